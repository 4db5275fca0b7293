"""Fill the (x, y, φ) field of allowed pair states; the Monte-Carlo estimator.

:func:`iter_slices` produces the field chunk by chunk over φ with the chosen
engine; :func:`reduce` drives any set of streaming reductions
(:mod:`sesp.reductions`) from one pass; :func:`scan` is the reduction that
keeps the field. :func:`monte_carlo` is the source paper's method (random
placements), kept as a baseline and cross-check.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
import xarray as xr

from .checks import check_choice, check_finite, check_positive, check_samples
from .dataset import base_attrs, coords, grid_attrs, pair_attrs, pair_variables
from .grid import Grid
from .kernels import hull, overlap
from .pair import Pair, as_pair
from .progress import progress_bar
from .reductions import StoredField
from .shape import DEFAULT_SEGMENTS
from .units import link_errors, quantity

__all__ = [
    "TruncatedBoxWarning",
    "scan",
    "reduce",
    "iter_slices",
    "Slices",
    "resolve_grid",
    "computed_slices",
    "working_bytes",
    "monte_carlo",
    "overlaps",
    "ENGINES",
]

ENGINES = overlap.ENGINES

# Working buffer for one chunk of orientations (uint16 counts), at most this.
CHUNK_BYTES = 1 << 27

# Bytes per state of one chunk that a pass holds while computing a field (counts, flags, hull field, mirror
# copies), by field computed; an upper bound of the measured peak (tests/test_reliability.py).
WORKING_BYTES_PER_STATE = {"allowed": 4, "crossings": 4, "entangled": 8}
# Bytes a pass holds whatever its grid: its coordinates, attributes, checksum and the interpreter's own allocations
# (a 1024² × 1 scan's peak rose 0.06-0.21 MB above its arrays' 5 MiB, tests/test_reliability.py).
PASS_OVERHEAD = 1 << 20


@dataclass(frozen=True)
class Slices:
    """One chunk of orientations k0..k1-1 of a field (arrays shaped (k1 - k0, ny, nx))."""

    k0: int
    k1: int
    allowed: np.ndarray
    crossings: np.ndarray | None = None
    entangled: np.ndarray | None = None


class TruncatedBoxWarning(UserWarning):
    """The grid's box is smaller than the reach of the pair: excluded positions outside it are not counted."""


def resolve_grid(pair: Pair, grid: Grid | None) -> Grid:
    """``grid`` (default ``Grid()``) with its box set from the pair's reach if unset.

    A box given smaller than the reach r₁ + r₂ + contact truncates the excluded
    set (A_ex comes out too small): that is warned about, not refused, since
    a zoomed map is a legitimate use.
    """
    resolved = (grid if grid is not None else Grid()).resolve(pair.reach)
    if resolved.half_width < pair.reach:
        warnings.warn(
            f"grid half_width {resolved.half_width:g} b is smaller than the pair's reach {pair.reach:g} b: "
            "positions outside the box are not scanned, so A_ex is truncated",
            TruncatedBoxWarning,
            stacklevel=3,
        )
    return resolved


def mirrored(pair: Pair, engine: str) -> bool:
    """Whether slices past φ = π are computed as mirror images.

    For a mirror-symmetric pair, the grid's y coordinates and the rotations
    for ±φ are exactly mirror-symmetric too, so the state (x, y, −φ) is the
    state (x, −y, φ) mirrored and the raster engine computes only φ in
    [0, π]. The direct engine computes every slice and the tests compare the two.
    """
    return engine == "raster" and pair.mirror_symmetric


def computed_slices(pair: Pair, grid: Grid, engine: str = "raster") -> int:
    """Slices k = 0 .. computed_slices − 1 are computed; the rest, if any, are their mirror images."""
    return grid.nphi // 2 + 1 if mirrored(pair, engine) else grid.nphi


def _phi_chunk(grid: Grid) -> int:
    per_slice = 2 * grid.nx * grid.ny
    return max(1, min(grid.nphi, CHUNK_BYTES // per_slice))


def working_bytes(grid: Grid, computed=("allowed",), per_position: int = 0) -> int:
    """Bytes a pass over ``grid`` holds besides its stored fields: one chunk of slices of the ``computed``
    fields with their mirror images, ``per_position`` bytes of running sums per (x, y), and PASS_OVERHEAD."""
    per_state = sum(WORKING_BYTES_PER_STATE[f] for f in computed)
    return grid.nx * grid.ny * (_phi_chunk(grid) * per_state + per_position) + PASS_OVERHEAD


def _compute(pair: Pair, grid: Grid, k0, k1, engine, crossings, entangled) -> Slices:
    cos_phi, sin_phi = (r[k0:k1] for r in grid.rotations())
    v1, v2 = pair.vertices1, pair.vertices2
    counts = overlap.crossing_field(
        v1, v2, cos_phi, sin_phi, grid.x, grid.y, pair.tolerance,
        contact=pair.contact, engine=engine, count=crossings, reach=pair.reach,
    )  # fmt: skip
    allowed = counts == 0
    tangled = None
    if entangled:
        hull1, hull2 = pair.hulls()
        tangled = hull.mutual_hull_field(
            v1, hull1, v2, hull2, cos_phi, sin_phi, grid.x, grid.y, pair.tolerance, pair.contact
        )
        tangled &= allowed
    return Slices(k0, k1, allowed, counts if crossings else None, tangled)


def _mirror(part: Slices, nphi: int) -> Slices | None:
    """The slices at −φ of ``part``'s slices (y flipped), leaving out φ = 0 and φ = π."""
    ks = [k for k in range(part.k0, part.k1) if k > 0 and 2 * k != nphi]
    if not ks:
        return None
    pick = slice(ks[0] - part.k0, ks[-1] - part.k0 + 1)

    def flip(array):
        return None if array is None else np.ascontiguousarray(array[pick][::-1, ::-1, :])

    return Slices(nphi - ks[-1], nphi - ks[0] + 1, flip(part.allowed), flip(part.crossings), flip(part.entangled))


def iter_slices(
    pair: Pair, grid: Grid, *, engine="raster", crossings=False, entangled=False, chunk=None, progress=False
):
    """Yield the field chunk by chunk over φ, never holding the whole field.

    ``grid`` must have its box set (:func:`resolve_grid`). Memory stays
    O(nx · ny · chunk). Each chunk is a :class:`Slices`.
    """
    check_choice("engine", engine, ENGINES)
    chunk = _phi_chunk(grid) if chunk is None else max(1, int(chunk))
    stop = computed_slices(pair, grid, engine)
    with progress_bar(grid.nphi, progress, f"scan ({engine})", unit="φ") as bar:
        for k0 in range(0, stop, chunk):
            part = _compute(pair, grid, k0, min(k0 + chunk, stop), engine, crossings, entangled)
            for piece in (part, _mirror(part, grid.nphi) if mirrored(pair, engine) else None):
                if piece is not None:
                    yield piece
                    bar.update(piece.k1 - piece.k0)


def reduce(
    pair: Pair, grid: Grid, reductions, *, engine="raster", kind="sesp.scan", chunk=None, progress=False
) -> xr.Dataset:
    """Run ``reductions`` (:mod:`sesp.reductions`) over one pass of the field; one labelled Dataset.

    The result holds every reduction's variables, the grid's coordinates
    along the dimensions they use, and attributes that reproduce the pass
    (format ``kind``, the pair, the grid, the engine).
    """
    wanted = {name for r in reductions for name in r.fields}
    for r in reductions:
        r.start(pair, grid)
    parts = iter_slices(
        pair,
        grid,
        engine=engine,
        crossings="crossings" in wanted,
        entangled="entangled" in wanted,
        chunk=chunk,
        progress=progress,
    )
    for part in parts:
        for r in reductions:
            r.add(part)
    variables = pair_variables(pair)
    attrs = {**base_attrs(kind), **pair_attrs(pair), **grid_attrs(grid), "engine": engine}
    for r in reductions:
        variables.update(r.finish())
        attrs.update(r.attrs())
    dims = [d for d in ("phi", "y", "x") if any(d in v[0] for v in variables.values())]
    return xr.Dataset(variables, coords=coords(grid, dims), attrs=attrs)


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
    particle : SeSP or Polyline or Pair
        The fixed particle, or a prepared pair.
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
    reduce, iter_slices : the same field chunk by chunk, for reductions of
        grids larger than memory.

    Examples
    --------
    >>> import numpy as np
    >>> from sesp import Grid, SeSP, scan
    >>> ds = scan(SeSP(n=2, opening=np.pi / 2), Grid(64, nphi=16), segments=64)
    >>> ds.allowed.dims
    ('phi', 'y', 'x')
    """
    check_choice("engine", engine, ENGINES)
    pair = as_pair(particle, other, segments)
    grid = resolve_grid(pair, grid)
    fields = ("allowed",) + ("crossings",) * crossings + ("entangled",) * entangled
    grid.check_memory(fields, memory_limit, working_bytes(grid, fields))
    return reduce(pair, grid, [StoredField(fields)], engine=engine, progress=progress)


def overlaps(particle, other, x, y, phi, *, segments: int = DEFAULT_SEGMENTS) -> np.ndarray:
    """Whether ``other``, turned by ``phi`` (rad) and moved by (``x``, ``y``) (b), overlaps ``particle`` at the
    origin: a boolean array over the states, of the broadcast shape of ``x``, ``y`` and ``phi``.

    The test sesp's scans make, state by state: the polylines meet (a segment of one crosses or touches one of
    the other, within the pair's contact tolerance), or for thick particles come closer than their contact
    distance (D₁ + D₂)/2. It is exact for the polylines; a SeSP is its polyline of ``segments`` segments (its
    departure from the smooth curve is :attr:`sesp.Pair.departure`). ``other`` None: a copy of ``particle``.
    ``particle`` may be a :class:`~sesp.Pair` (``other`` then None), whose polylines are used as they are.
    States run in parallel on numba's threads; the answer does not depend on their number.

    Examples
    --------
    >>> import numpy as np
    >>> from sesp import Polyline, overlaps
    >>> needle = Polyline([[-1, 0], [1, 0]])
    >>> overlaps(needle, None, [0.0, 0.0, 3.0], [0.5, 1.5, 0.0], np.pi / 2)  # crossing, above, beside
    array([ True, False, False])
    """
    pair = as_pair(particle, other, segments)
    states = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, phi)))
    for name, values in zip(("x", "y", "phi"), states, strict=True):
        check_finite(name, values, " (b)" if name != "phi" else " (rad)")
    x, y, phi = (np.ascontiguousarray(v).ravel() for v in states)
    near = x * x + y * y <= (pair.reach + pair.tolerance) ** 2  # farther, the curves cannot meet
    out = np.zeros(x.shape, dtype=bool)
    if near.any():
        out[near] = overlap.states_overlap(
            pair.vertices1, pair.vertices2, x[near], y[near], phi[near], pair.tolerance, contact=pair.contact
        )
    return out.reshape(states[0].shape)


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
    >>> import numpy as np
    >>> from sesp import SeSP
    >>> from sesp.measures import monte_carlo
    >>> mc = monte_carlo(SeSP(n=2, opening=np.pi / 2), samples=1000, seed=1)
    >>> float(mc.excluded_area) > 0
    True
    """
    samples = check_samples(samples)
    pair = as_pair(particle, other, segments)
    side = 2.0 * (pair.reach if half_width is None else check_positive("half_width", half_width))
    rng = _rng(seed)
    x, y = rng.uniform(-side / 2, side / 2, size=(2, samples))
    phi = rng.uniform(0.0, 2 * math.pi, size=samples)
    overlap_ = overlaps(pair, None, x, y, phi)
    p = overlap_.mean()
    attrs = {**base_attrs("sesp.monte_carlo"), **pair_attrs(pair), "half_width": side / 2, "samples": samples}
    return link_errors(
        xr.Dataset(
            {
                **pair_variables(pair),
                "x": ("sample", x, quantity(1, "x of particle 2's centre")),
                "y": ("sample", y, quantity(1, "y of particle 2's centre")),
                "phi": ("sample", phi, {"units": "rad", "long_name": "orientation of particle 2 (φ)"}),
                "overlap": ("sample", overlap_, {"units": "1", "long_name": "the particles overlap"}),
                "excluded_area": ((), p * side**2, quantity(2, "excluded area A_ex")),
                "excluded_area_error": (
                    (),
                    side**2 * math.sqrt(p * (1 - p) / samples),
                    quantity(2, "standard error of A_ex"),
                ),
            },
            attrs=attrs,
        )
    )
