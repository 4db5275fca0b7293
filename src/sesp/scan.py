"""Fill the (x, y, φ) field of allowed pair states; the Monte-Carlo estimator.

``scan`` returns the Dataset of DESIGN.md §5. ``monte_carlo`` is the source
paper's method (random placements), kept as a baseline and cross-check.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

from . import _kernels
from ._version import __version__
from .grid import Grid
from .shape import DEFAULT_SEGMENTS, Polyline, SeSP, as_polyline, check_positive, particle_attrs

__all__ = ["scan", "iter_slices", "prepare", "monte_carlo", "ENGINES", "field_sha256"]

ENGINES = ("raster", "direct")

# Touching counts as overlap: states within this distance (relative to r₁ + r₂)
# of touching are overlaps, identically in every engine.
TOUCH_TOLERANCE = 1e-9

# Working buffer for one chunk of orientations (uint16 counts), at most this.
CHUNK_BYTES = 1 << 27

# Chunks with fewer states than this run in one thread (no parallel start-up cost).
SERIAL_STATES = 1 << 20


def field_sha256(allowed) -> str:
    """SHA-256 of a boolean field's C-ordered bytes (one byte per state)."""
    data = np.ascontiguousarray(np.asarray(allowed, dtype=bool))
    return hashlib.sha256(data.view(np.uint8)).hexdigest()


def _check_engine(engine: str) -> str:
    if engine not in ENGINES:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    return engine


def _curves(particle, other, segments) -> tuple[Polyline, Polyline]:
    """The two polylines of a pair: particle 2 is particle 1 unless ``other`` is given."""
    curve1 = as_polyline(particle, segments)
    curve2 = curve1 if other is None else as_polyline(other, segments)
    return curve1, curve2


def _phi_chunk(grid: Grid) -> int:
    per_slice = 2 * grid.nx * grid.ny
    return max(1, min(grid.nphi, CHUNK_BYTES // per_slice))


def _fill_counts(curve1, curve2, grid, k0, k1, engine, count, delta):
    """Crossing counts for orientations k0..k1-1, shape (k1 - k0, ny, nx)."""
    cos_phi, sin_phi = grid.rotations()
    out = np.zeros((k1 - k0, grid.ny, grid.nx), dtype=np.uint16)
    args = (curve1.vertices, curve2.vertices, cos_phi[k0:k1], sin_phi[k0:k1], grid.x, grid.y, delta)
    if engine == "raster":
        small = out.size < SERIAL_STATES
        (_kernels.raster_slices_serial if small else _kernels.raster_slices)(*args, count, out)
    else:
        reach = curve1.max_radius + curve2.max_radius
        _kernels.direct_slices(*args, reach, count, out)
    return out


def _fill_mutual_hulls(curve1, curve2, grid, k0, k1, delta):
    """Where each curve meets the other's convex hull, orientations k0..k1-1."""
    cos_phi, sin_phi = grid.rotations()
    out = np.empty((k1 - k0, grid.ny, grid.nx), dtype=bool)
    _kernels.mutual_hull_slices(
        curve1.vertices,
        curve1.hull(),
        curve2.vertices,
        curve2.hull(),
        cos_phi[k0:k1],
        sin_phi[k0:k1],
        grid.x,
        grid.y,
        delta,
        out,
    )
    return out


class _NoProgress:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def update(self, n=1):
        pass


def _progress(total: int, enabled: bool, desc: str):
    """A tqdm bar, imported only when shown (the import costs a visible part of start-up)."""
    if not enabled:
        return _NoProgress()
    from tqdm.auto import tqdm

    return tqdm(total=total, unit="φ", desc=desc, leave=False)


@dataclass(frozen=True)
class Slices:
    """One chunk of orientations k0..k1-1 of a scan (arrays shaped (k1 - k0, ny, nx))."""

    k0: int
    k1: int
    allowed: np.ndarray
    crossings: np.ndarray | None = None
    entangled: np.ndarray | None = None


@dataclass(frozen=True)
class Setup:
    """A checked scan request: the two polylines, the resolved grid, the tolerance."""

    particle: object
    other: object
    curve1: Polyline
    curve2: Polyline
    grid: Grid
    engine: str
    delta: float

    @property
    def mirrored(self) -> bool:
        """Whether slices past φ = π are computed as mirror images.

        SeSPs are mirror-symmetric about the x axis, and so are their
        polylines, the grid's y coordinates and the rotations for ±φ, exactly;
        so the state (x, y, −φ) is the state (x, −y, φ) mirrored and the raster
        engine computes only φ in [0, π]. The direct engine computes every
        slice and the tests compare the two.
        """
        return self.engine == "raster" and isinstance(self.particle, SeSP) and isinstance(self.other, SeSP)

    @property
    def computed_slices(self) -> int:
        """Slices k = 0 .. computed_slices − 1 are computed; the rest, if any, are their mirror images."""
        return self.grid.nphi // 2 + 1 if self.mirrored else self.grid.nphi

    def attrs(self) -> dict:
        """Dataset attributes that reproduce this scan."""
        attrs = {"sesp_format": "sesp.scan", "sesp_format_version": 1, "sesp_version": __version__}
        attrs.update(particle_attrs(self.particle, self.curve1, "particle"))
        attrs.update(particle_attrs(self.other, self.curve2, "other"))
        attrs["identical_particles"] = int(self.curve1 == self.curve2)
        attrs.update(self.grid.to_attrs())
        attrs.update({"engine": self.engine, "touch_tolerance": self.delta})
        return attrs


def prepare(particle, grid=None, *, other=None, segments=DEFAULT_SEGMENTS, engine="raster") -> Setup:
    """Check a scan request and build its polylines and grid, before any heavy work."""
    engine = _check_engine(engine)
    curve1, curve2 = _curves(particle, other, segments)
    reach = curve1.max_radius + curve2.max_radius
    grid = (grid if grid is not None else Grid()).resolve(reach)
    other = particle if other is None else other
    return Setup(particle, other, curve1, curve2, grid, engine, TOUCH_TOLERANCE * reach)


def iter_slices(setup: Setup, *, crossings=False, entangled=False, chunk=None, progress=False):
    """Yield the scan chunk by chunk over φ, never holding the whole field.

    Memory stays O(nx · ny · chunk). Each chunk is a :class:`Slices`.
    """
    grid = setup.grid
    chunk = _phi_chunk(grid) if chunk is None else max(1, int(chunk))
    stop = setup.computed_slices
    with _progress(grid.nphi, progress, f"scan ({setup.engine})") as bar:
        for k0 in range(0, stop, chunk):
            k1 = min(k0 + chunk, stop)
            counts = _fill_counts(setup.curve1, setup.curve2, grid, k0, k1, setup.engine, crossings, setup.delta)
            allowed = counts == 0
            tangled = None
            if entangled:
                tangled = _fill_mutual_hulls(setup.curve1, setup.curve2, grid, k0, k1, setup.delta)
                tangled &= allowed
            part = Slices(k0, k1, allowed, counts if crossings else None, tangled)
            for piece in (part, _mirror(part, grid.nphi) if setup.mirrored else None):
                if piece is not None:
                    yield piece
                    bar.update(piece.k1 - piece.k0)


def _mirror(part: Slices, nphi: int) -> Slices | None:
    """The slices at −φ of ``part``'s slices (y flipped), leaving out φ = 0 and φ = π."""
    ks = [k for k in range(part.k0, part.k1) if k > 0 and 2 * k != nphi]
    if not ks:
        return None
    pick = slice(ks[0] - part.k0, ks[-1] - part.k0 + 1)

    def flip(array):
        return None if array is None else np.ascontiguousarray(array[pick][::-1, ::-1, :])

    return Slices(nphi - ks[-1], nphi - ks[0] + 1, flip(part.allowed), flip(part.crossings), flip(part.entangled))


def scan(
    particle,
    grid: Grid | None = None,
    *,
    other=None,
    segments: int = DEFAULT_SEGMENTS,
    engine: str = "raster",
    crossings: bool = False,
    entangled: bool = False,
    memory_limit: int | None = None,
    progress: bool = False,
) -> xr.Dataset:
    """Allowed pair states of two thin particles on a regular (x, y, φ) grid.

    Particle 1 sits at the origin with orientation +x. Particle 2 (``other``,
    or a copy of ``particle``) is rotated by φ about its centre, then moved by
    (x, y). A state is allowed when the two curves share no point.

    Parameters
    ----------
    particle : SeSP or Polyline
        The fixed particle.
    grid : Grid, optional
        Resolution; its box defaults to r₁ + r₂ plus one cell (no truncation).
        Default ``Grid(256, nphi=128)``.
    other : SeSP or Polyline, optional
        The moving particle, if it differs from ``particle``.
    segments : int
        Polyline segments N for each SeSP (a Polyline is used as given).
    engine : {"raster", "direct"}
        ``"raster"`` rasterises the Minkowski parallelograms (fast);
        ``"direct"`` tests every segment pair at every state (reference).
        Both give identical fields.
    crossings : bool
        Also store ``crossings``, the number of segment pairs that meet.
    entangled : bool
        Also store ``entangled``: allowed states in which each curve meets the
        other's filled convex hull (mutual entanglement).
    memory_limit : int, optional
        Bytes the stored fields may take; default half the available memory.
        A larger grid is refused before anything is allocated.
    progress : bool
        Show a progress bar over orientations.

    Returns
    -------
    xarray.Dataset
        ``allowed(phi, y, x)`` bool, optionally ``crossings(phi, y, x)``
        uint16 and ``entangled(phi, y, x)`` bool, coordinates in units of b
        and radians, and attributes that reproduce the scan.

    See Also
    --------
    iter_slices : the same field chunk by chunk, for reductions of grids
        larger than memory.

    Examples
    --------
    >>> ds = scan(SeSP(n=2, opening=np.pi / 2), Grid(64, nphi=16), segments=64)
    >>> ds.allowed.dims
    ('phi', 'y', 'x')
    """
    setup = prepare(particle, grid, other=other, segments=segments, engine=engine)
    grid = setup.grid
    fields = ("allowed",) + ("crossings",) * crossings + ("entangled",) * entangled
    grid.check_memory(fields, memory_limit)
    shape = (grid.nphi, grid.ny, grid.nx)
    data = {name: np.empty(shape, dtype=np.uint16 if name == "crossings" else bool) for name in fields}
    for part in iter_slices(setup, crossings=crossings, entangled=entangled, progress=progress):
        for name, array in data.items():
            array[part.k0 : part.k1] = getattr(part, name)
    attrs = setup.attrs()
    attrs["allowed_sha256"] = field_sha256(data["allowed"])
    return _package(data, grid, attrs)


def _coords(grid: Grid) -> dict:
    return {
        "phi": ("phi", grid.phi, {"units": "rad", "long_name": "orientation of particle 2 (φ)"}),
        "y": ("y", grid.y, {"units": "b", "long_name": "y of particle 2's centre"}),
        "x": ("x", grid.x, {"units": "b", "long_name": "x of particle 2's centre"}),
    }


LONG_NAMES = {
    "allowed": "state allowed (curves do not meet)",
    "crossings": "segment pairs that meet (n)",
    "entangled": "allowed and mutually entangled (each curve meets the other's convex hull)",
}


def _package(data, grid, attrs) -> xr.Dataset:
    dims = ("phi", "y", "x")
    variables = {name: (dims, array, {"long_name": LONG_NAMES[name]}) for name, array in data.items()}
    return xr.Dataset(variables, coords=_coords(grid), attrs=attrs)


def _rng(seed) -> np.random.Generator:
    return seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)


def monte_carlo(
    particle,
    samples: int = 100_000,
    *,
    other=None,
    segments: int = DEFAULT_SEGMENTS,
    half_width: float | None = None,
    seed: np.random.Generator | int | None = None,
) -> xr.Dataset:
    """Excluded area by random placements, the source paper's method.

    States are drawn uniformly from the box [-L, L]² × [0, 2π); the estimate
    is A_ex = (N_overlap / N_total) · (2L)², with standard error
    (2L)² · sqrt(p (1 − p) / N_total).

    Parameters
    ----------
    particle, other, segments
        As in :func:`scan`.
    samples : int
        Number of placements, >= 1.
    half_width : float, optional
        Box half-width L in units of b; default r₁ + r₂ (nothing is truncated).
    seed : numpy.random.Generator or int or None
        Source of randomness; the same seed gives the same placements.

    Returns
    -------
    xarray.Dataset
        ``x, y, phi, overlap`` over dimension ``sample``, and 0-d variables
        ``excluded_area`` and ``excluded_area_error`` (units b²).

    Examples
    --------
    >>> mc = monte_carlo(SeSP(n=2, opening=np.pi / 2), samples=1000, seed=1)
    >>> float(mc.excluded_area) > 0
    True
    """
    if isinstance(samples, bool) or int(samples) != samples or samples < 1:
        raise ValueError(f"samples must be an integer >= 1, got {samples!r}")
    setup = prepare(particle, other=other, segments=segments)
    reach = setup.curve1.max_radius + setup.curve2.max_radius
    side = 2.0 * (reach if half_width is None else check_positive("half_width", half_width))
    rng = _rng(seed)
    x, y = rng.uniform(-side / 2, side / 2, size=(2, int(samples)))
    phi = rng.uniform(0.0, 2 * math.pi, size=int(samples))
    counts = np.empty(int(samples), dtype=np.uint16)
    _kernels.crossings_at_states(setup.curve1.vertices, setup.curve2.vertices, x, y, phi, setup.delta, False, counts)
    overlap = counts > 0
    p = overlap.mean()
    attrs = {k: v for k, v in setup.attrs().items() if k not in ("nx", "ny", "nphi", "engine")}
    attrs.update({"sesp_format": "sesp.monte_carlo", "half_width": side / 2, "samples": int(samples)})
    area = {"units": "b^2"}
    return xr.Dataset(
        {
            "x": ("sample", x, {"units": "b"}),
            "y": ("sample", y, {"units": "b"}),
            "phi": ("sample", phi, {"units": "rad"}),
            "overlap": ("sample", overlap),
            "excluded_area": ((), p * side**2, {**area, "long_name": "excluded area A_ex"}),
            "excluded_area_error": ((), side**2 * math.sqrt(p * (1 - p) / samples), area),
        },
        attrs=attrs,
    )
