"""Excluded area and the exact integrals it is checked against.

Quadrature on the grid of a scan: cell-centred nodes with weight
dx · dy · Δφ / 2π each, so the orientation-averaged excluded area is
A_ex = (1/2π) ∫ A_ex(φ) dφ = dx · dy · (excluded states) / nphi, in b².
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import xarray as xr

from .checks import check_choice, check_count, check_positive, check_rtol
from .dataset import base_attrs, cell_area, grid_attrs, grid_of, pair_attrs, pair_of
from .exact import superellipse_area, superellipse_perimeter
from .field import computed_slices, monte_carlo, resolve_grid, scan
from .grid import Grid
from .kernels import overlap, scanline
from .pair import Pair, as_pair
from .progress import progress_bar
from .shape import DEFAULT_SEGMENTS, Polyline, SeSP
from .units import link_errors, quantity

__all__ = [
    "excluded_area",
    "monte_carlo",
    "lattice_excluded_area",
    "lattice_excluded_area_error",
    "shifted_excluded_area",
    "scanline_excluded_area",
    "smooth_excluded_area",
    "lattice_shifts",
    "normalized_excluded_area",
    "closed_excluded_area",
    "convex_excluded_area",
    "kinematic_integral",
    "excluded_perimeter",
]


def _excluded_states(allowed, axis=None):
    allowed = np.asarray(allowed)
    total = allowed.size if axis is None else np.prod([allowed.shape[a] for a in axis])
    return total - np.count_nonzero(allowed, axis=axis)


def lattice_excluded_area(ds: xr.Dataset, *, by: str | None = None):
    """The excluded area a stored field counts: the excluded states of its lattice times their cell, b².

    This is the field's own measure, with the lattice's bias (mostly shared by all orientations, of order
    a cell times the excluded set's perimeter); the best estimate of A_ex, with error bars, is
    :func:`excluded_area`, which takes the particles.

    Parameters
    ----------
    ds : xarray.Dataset
        A scan with ``allowed(phi, y, x)``, or a summary / analysis with
        ``excluded_area(phi)``.
    by : {None, "phi"}
        None: the orientation average A_ex = (1/2π) ∫ A_ex(φ) dφ, a float.
        "phi": A_ex(φ) = ∫∫ [overlap] dx dy at each orientation, a DataArray.

    Examples
    --------
    >>> import numpy as np
    >>> from sesp import Grid, SeSP, scan
    >>> from sesp.measures import lattice_excluded_area
    >>> ds = scan(SeSP(n=2), Grid(128, nphi=4), segments=128)
    >>> round(lattice_excluded_area(ds) / (4 * np.pi), 2)
    1.0
    """
    check_choice("by", by, (None, "phi"))
    if "allowed" not in ds:
        if "excluded_area" not in ds or ds.excluded_area.dims != ("phi",):
            raise ValueError("lattice_excluded_area needs a scan (allowed field) or a summary with excluded_area(phi)")
        return float(ds.excluded_area.mean()) if by is None else ds.excluded_area
    if by is None:
        return cell_area(ds) * float(_excluded_states(ds.allowed.values)) / ds.sizes["phi"]
    per_phi = _excluded_states(ds.allowed.values, axis=(1, 2)) * cell_area(ds)
    return xr.DataArray(
        per_phi,
        coords={"phi": ds.phi},
        dims="phi",
        name="excluded_area",
        attrs=quantity(2, "excluded area at fixed orientation A_ex(φ)"),
    )


def lattice_excluded_area_error(ds: xr.Dataset) -> float:
    """Indication of the quadrature error of :func:`lattice_excluded_area`, in b².

    |A_ex(h) − A_ex(2h)|: the difference from a second scan of the same box
    at half the resolution in x, y and φ, rebuilt from the attributes. The
    coarse grid's error is the larger, so this usually exceeds the error at
    h; it is an indication, not a bound (``tests/test_measures.py`` compares
    it with the true error on exact cases). Costs one scan at half
    resolution. (Sub-grids of the scan itself would be free but useless: for
    mirror-symmetric fields the parity sub-grids are each other's mirror
    images and agree exactly.)
    """
    grid = grid_of(ds)
    coarse_grid = Grid(max(grid.nx // 2, 3), max(grid.ny // 2, 3), max(grid.nphi // 2, 1), half_width=grid.half_width)
    return abs(lattice_excluded_area(ds) - lattice_excluded_area(scan(pair_of(ds), coarse_grid)))


# R2 low-discrepancy sequence: steps 1/g and 1/g² with g the plastic number
_PLASTIC = 1.324717957244746025960908854
_R2_STEP = np.array([1.0 / _PLASTIC, 1.0 / _PLASTIC**2])


def lattice_shifts(nphi: int) -> np.ndarray:
    """Per-orientation lattice shifts of :func:`shifted_excluded_area`, in cells.

    Shape (nphi, 2), each in [−½, ½)². Orientations k ≤ nphi/2 take the
    points of the R2 sequence (k = 0: no shift); φ_{nphi−k} = −φ_k takes
    the y-mirror (u, −v) of φ_k's shift, so for mirror-symmetric pairs the
    slice at −φ is the mirror image of the slice at φ, exactly.
    """
    k = np.arange(int(nphi))
    j = np.minimum(k, nphi - k)
    shifts = np.mod(0.5 + j[:, None] * _R2_STEP, 1.0) - 0.5
    shifts[k > nphi - k, 1] *= -1.0
    return shifts


def shifted_excluded_area(particle, grid: Grid | None = None, *, other=None, segments: int = DEFAULT_SEGMENTS):
    """A_ex(φ) counted on a lattice shifted afresh at each orientation, in b².

    The stored ``allowed`` field uses one cell-centred lattice for every φ,
    and its error in A_ex is mostly a bias shared by all orientations:
    boundary arcs that stay put as φ turns (for the ASP, the circle |t| = 2
    around the centre) cut the same lattice at every φ, so the errors add
    instead of averaging out. Here slice k's lattice is moved by
    ``lattice_shifts(nphi)[k]`` cells (a low-discrepancy sequence), which
    turns that bias into an average over shifts; the average over all shifts
    of a lattice count is the area exactly. At the cost of a scan, the
    orientation average comes much closer to the true value
    (``tests/test_measures.py``; ``benchmarks/time_to_accuracy.py`` has the
    figures). No field is stored: use :func:`sesp.scan` for the allowed
    states themselves.

    Parameters
    ----------
    particle, other, segments
        As for :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    grid : Grid, optional
        Default ``Grid(256, nphi=128)``. Its box must reach half a cell beyond
        r₁ + r₂ (the default box reaches one cell beyond).

    Returns
    -------
    xarray.DataArray
        ``excluded_area(phi)`` in b². Its mean over phi is the orientation
        average A_ex. Attribute ``error_estimate`` (b²) is half the difference
        between the averages over even and odd k: an indication, not a bound.
    """
    pair = as_pair(particle, other, segments)
    grid = resolve_grid(pair, grid)
    if grid.half_width < pair.reach + 0.5 * max(grid.dx, grid.dy):
        raise ValueError("shifted_excluded_area needs a box reaching half a cell beyond r1 + r2: use the default box")
    cos_phi, sin_phi = grid.rotations()
    shifts = lattice_shifts(grid.nphi) * [grid.dx, grid.dy]
    stop = computed_slices(pair, grid)
    counts = np.zeros(grid.nphi, dtype=np.int64)
    counts[:stop] = overlap.lattice_overlap_counts(
        pair.vertices1, pair.vertices2, cos_phi[:stop], sin_phi[:stop], grid.x, grid.y, shifts[:stop],
        pair.tolerance, pair.contact,
    )  # fmt: skip
    if stop < grid.nphi:  # the mirror images of the computed slices
        counts[stop:] = counts[1 : grid.nphi - stop + 1][::-1]
    per_phi = counts * (grid.dx * grid.dy)
    error = abs(per_phi[0::2].mean() - per_phi[1::2].mean()) / 2 if grid.nphi > 1 else math.nan
    attrs = {
        **quantity(2, "excluded area at fixed orientation A_ex(φ), lattice shifted per φ"),
        "error_estimate": error,
        **base_attrs("sesp.scan"),
        **pair_attrs(pair),
        **grid_attrs(grid),
        "engine": "raster",
    }
    attrs["sesp_format"] = "sesp.measures.shifted_excluded_area"
    return xr.DataArray(
        per_phi, coords={"phi": ("phi", grid.phi, {"units": "rad"})}, dims="phi", name="excluded_area", attrs=attrs
    )


def scan_directions(phi) -> np.ndarray:
    """Direction θ (rad) of the scanlines at each orientation: as far as can be, modulo π/2, from both
    particles' axes (0 and φ), along which flat sides of SeSPs lie; a flat side parallel to the lines would
    make the length a step function of the line's height."""
    a = np.mod(phi, np.pi / 2)
    return np.where(a > np.pi / 4, a / 2, (a + np.pi / 2) / 2)


# Order of the trapezoidal error across scanlines: where a line grazes a curved part of the excluded set's
# boundary the length grows as the square root of the distance, and the error falls as h^1.5.
SCANLINE_ORDER = 1.5


# Line spacings across the excluded set by default: a line costs a few crossings, not N² cuts, so many are cheap.
# The smooth particle's extrapolation in N magnifies the lines' error, so it takes more.
SCANLINE_ROWS = 512
SMOOTH_ROWS = 2048


def scanline_excluded_area(
    particle, *, other=None, segments: int = DEFAULT_SEGMENTS, nphi: int = 128, rows: int = SCANLINE_ROWS
) -> xr.Dataset:
    """A_ex(φ) by scanlines: exact along each line, extrapolated across them, with an error estimate; b².

    At each orientation φ the pair is turned so that the lines avoid the particles' axes
    (:func:`scan_directions`), ``rows`` + 1 equally spaced lines span the excluded set, and on each the
    overlapping translations, a union of intervals, are measured exactly (:mod:`sesp.kernels.scanline`: the
    count of segment pairs over each point of the line, from the crossings of the few edges that change it).
    At the default 512 spacings A_ex(φ) of SeSPs with n = 2 to 10 at Ψ = 90° and 180° is within 2e-4 of a
    converged reference at every φ, in less time than ``shifted_excluded_area`` on its 256² lattice
    (``benchmarks/accuracy.py``).
    The lengths are integrated by the trapezoidal rule on the lines at spacings h, 2h, 4h and 8h (every
    line, every other, ...), and each two neighbouring results extrapolated with the error order
    :data:`SCANLINE_ORDER` (Richardson): the finest is the value, the changes between them the error.

    Parameters
    ----------
    particle, other, segments
        As for :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    nphi : int
        Orientations φ = 2πk/nphi.
    rows : int
        Line spacings across the excluded set, a multiple of 8 (the coarser levels drop lines).

    Returns
    -------
    xarray.Dataset
        ``excluded_area(phi)`` and ``excluded_area_error(phi)``, and the orientation averages
        ``mean_excluded_area`` and ``mean_excluded_area_error`` (b²). The error of each A_ex(φ) is
        |R(h) − R(2h)| + |R(2h) − R(4h)| for the extrapolations R (``benchmarks/accuracy.py`` prints how
        often it covers the actual error). The average's error is the same formula applied to the
        averages of R, plus the φ-quadrature error (half the difference between the averages over even
        and odd k).
    """
    return _scanline_dataset(as_pair(particle, other, segments), *_checked_lines(nphi, rows), {})


def _checked_lines(nphi, rows) -> tuple[int, int]:
    """``nphi`` and ``rows`` as whole numbers, or ValueError: nphi ≥ 1, rows ≥ 8 and a multiple of 8."""
    nphi = check_count("nphi", nphi, 1, 1 << 20)
    rows = check_count("rows", rows, 8, 1 << 20)
    if rows % 8:
        raise ValueError(f"rows must be a multiple of 8 (coarser levels drop every other line), got {rows}")
    return nphi, rows


def _trapezoids(pair: Pair, nphi: int, rows: int, memo: dict) -> np.ndarray:
    """(4, stop): the trapezoidal rule on the line lengths at spacings h, 2h, 4h and 8h, per orientation
    φ_k = 2πk/nphi, k < stop (half the turn and one for a mirror-symmetric pair), b².

    ``memo`` holds those of earlier calls for the same particles, by (segments, nphi, rows): each orientation's
    lines are measured on their own, so a call at twice an earlier nphi measures only the odd k (the even ones
    are the earlier φ, bit for bit), and a repeated call measures nothing."""
    key = (pair.segments, nphi, rows)
    if key in memo:
        return memo[key]
    stop = nphi // 2 + 1 if pair.mirror_symmetric else nphi
    phi = 2 * np.pi * np.arange(stop) / nphi
    half = memo.get((pair.segments, nphi // 2, rows)) if nphi % 2 == 0 else None
    new = np.arange(stop) if half is None else np.arange(1, stop, 2)
    theta = scan_directions(phi[new])
    lengths, _, h = scanline.scanline_table(
        pair.vertices1, pair.vertices2, -theta, phi[new] - theta, pair.contact, rows
    )
    # trapezoids at spacings h, 2h, 4h, 8h (the end lines have length 0, or nearly, within contact)
    sums = np.empty((4, stop))
    sums[:, new] = [lengths[:, ::m].sum(axis=1) * m * h for m in (1, 2, 4, 8)]
    if half is not None:
        sums[:, 0::2] = half
    memo[key] = sums
    return sums


def _scanline_dataset(pair: Pair, nphi: int, rows: int, memo: dict) -> xr.Dataset:
    """:func:`scanline_excluded_area` of ``pair``, its trapezoids kept in (and taken from) ``memo``."""
    trapezoid = _trapezoids(pair, nphi, rows, memo)
    q = 2.0**SCANLINE_ORDER
    extrapolated = [(q * fine - coarse) / (q - 1) for fine, coarse in zip(trapezoid, trapezoid[1:], strict=False)]
    levels = [_unmirrored(values, nphi) for values in extrapolated]  # every φ, for the means
    area = levels[0]
    error = np.abs(levels[0] - levels[1]) + np.abs(levels[1] - levels[2])
    # the mean's error from the means of the levels (their errors share a sign across φ), and the φ quadrature
    mean_error = abs(levels[0].mean() - levels[1].mean()) + abs(levels[1].mean() - levels[2].mean())
    attrs = {**base_attrs("sesp.summary"), **pair_attrs(pair), "nphi": nphi, "rows": rows}
    attrs["sesp_format"] = "sesp.measures.scanline_excluded_area"
    attrs.update(mean_error_lines=mean_error, mean_error_phi=_phi_quadrature_error(area))
    phi = 2 * np.pi * np.arange(nphi) / nphi
    return _area_dataset(phi, area, error, mean_error + attrs["mean_error_phi"], attrs)


def _unmirrored(computed, nphi: int) -> np.ndarray:
    """Values at every φ_k from those at k = 0 .. len(computed) − 1, A(−φ) = A(φ) supplying the rest."""
    stop = len(computed)
    return np.concatenate([computed, computed[1 : nphi - stop + 1][::-1]]) if stop < nphi else np.asarray(computed)


def _phi_quadrature_error(area) -> float:
    """Half the difference between the averages over even and odd k: the error of the mean over φ."""
    return abs(area[0::2].mean() - area[1::2].mean()) / 2 if len(area) > 1 else math.nan


def _area_dataset(phi, area, error, mean_error, attrs) -> xr.Dataset:
    """A_ex(φ) with error bars, and their orientation average with its error bar ``mean_error``."""
    return xr.Dataset(
        {
            "excluded_area": ("phi", area, quantity(2, "excluded area at fixed orientation A_ex(φ)")),
            "excluded_area_error": ("phi", error, quantity(2, "error estimate of A_ex(φ)")),
            "mean_excluded_area": ((), area.mean(), quantity(2, "orientation-averaged A_ex")),
            "mean_excluded_area_error": ((), mean_error, quantity(2, "its error estimate")),
        },
        coords={"phi": ("phi", phi, {"units": "rad", "long_name": "orientation of particle 2 (φ)"})},
        attrs=attrs,
    )


def smooth_excluded_area(
    particle, *, other=None, segments: int = DEFAULT_SEGMENTS, nphi: int = 128, rows: int = SMOOTH_ROWS
) -> xr.Dataset:
    """A_ex(φ) of the smooth SeSPs (not their polygons) by scanlines, with an error estimate; b².

    A polygon of N (nearly) equal-arc-length segments misses the smooth curve's A_ex(φ) by an error that falls as
    N⁻². :func:`scanline_excluded_area` at N = ``segments``, N/2 and N/4 gives two Richardson
    extrapolations in N; the finer is the value, its change from the coarser is the polygon's share of the
    error bar, added to the scanline error at N. Checked against the smooth ASP's A_ex(φ), computed
    semi-analytically (``tests/test_measures.py``), and closed superellipses (2A + P²/2π with the smooth
    curve's area and perimeter).

    Parameters and result as for :func:`scanline_excluded_area`; both particles must be SeSPs, and
    ``segments`` a multiple of 4.
    """
    if not isinstance(particle, SeSP) or not isinstance(other, (SeSP, type(None))):
        raise ValueError("smooth_excluded_area needs SeSPs: a Polyline is its own shape, there is nothing to refine")
    if segments % 4 or segments < 16:
        raise ValueError(f"segments must be a multiple of 4 and at least 16, got {segments}")
    return _smooth_dataset(particle, other, segments, *_checked_lines(nphi, rows), {})


def _smooth_dataset(particle, other, segments: int, nphi: int, rows: int, memo: dict) -> xr.Dataset:
    """:func:`smooth_excluded_area` of the SeSPs, the trapezoids of each polygon kept in (and taken from)
    ``memo``: a refinement that doubles the segments measures only the new, finest polygon."""
    levels = [_scanline_dataset(as_pair(particle, other, segments // m), nphi, rows, memo) for m in (1, 2, 4)]
    areas = [ds.excluded_area.values for ds in levels]
    fine, coarse = ((4 * a - b) / 3 for a, b in zip(areas, areas[1:], strict=False))
    error = levels[0].excluded_area_error.values + np.abs(fine - coarse)
    attrs = {**levels[0].attrs, "sesp_format": "sesp.measures.smooth_excluded_area"}
    attrs["mean_error_polygon"] = abs(fine.mean() - coarse.mean())
    mean_error = float(levels[0].mean_excluded_area_error) + attrs["mean_error_polygon"]
    return _area_dataset(levels[0].phi.values, fine, error, mean_error, attrs)


# sesp's A_ex: the relative error of ⟨A_ex⟩ it refines to by default, where it starts, and how far it goes
RTOL = 1e-5
START = {"segments": 256, "nphi": 128}
LARGEST = {"segments": 4096, "nphi": 4096, "rows": 1 << 15}
# which setting to double for each part of the error budget (the attributes mean_error_*)
_REFINES = {"mean_error_lines": "rows", "mean_error_phi": "nphi", "mean_error_polygon": "segments"}


def _smooth_possible(pair: Pair, segments: int) -> bool:
    """Whether the smooth curves' A_ex can be had: two SeSPs, and N, N/2, N/4 segments."""
    sesps = isinstance(pair.particle, SeSP) and isinstance(pair.other, SeSP)
    return sesps and segments % 4 == 0 and segments >= 16


def _measured(pair: Pair, segments: int, nphi: int, rows: int | None, memo: dict) -> xr.Dataset:
    """One evaluation of the best estimate: the smooth curves' A_ex(φ) where possible, else the polygons';
    ``memo``: the trapezoids of the refinement's earlier evaluations (:func:`_trapezoids`)."""
    if _smooth_possible(pair, segments):
        other = None if pair.other is pair.particle else pair.other
        rows = SMOOTH_ROWS if rows is None else rows
        ds = _smooth_dataset(pair.particle, other, segments, *_checked_lines(nphi, rows), memo)
        ds.attrs["excluded_area_of"] = "smooth curves"
        return ds
    ds = _scanline_dataset(pair, *_checked_lines(nphi, SCANLINE_ROWS if rows is None else rows), memo)
    sesps = [isinstance(p, SeSP) for p in (pair.particle, pair.other)]
    polygons = f"polygons of {pair.segments} segments"
    of = polygons if all(sesps) else "polylines as given" + (f", the SeSP as {polygons}" if any(sesps) else "")
    ds.attrs["excluded_area_of"] = of
    return ds


def _next_setting(ds: xr.Dataset, settings: dict, free: set, target: float) -> str | None:
    """The setting to double: the free one (not yet at its largest) whose part of the error budget is largest;
    None when the parts of the others already exceed ``target`` (b²), so no refinement can meet it."""
    parts = {name: ds.attrs.get(part, 0.0) for part, name in _REFINES.items()}
    growing = [name for name in free if parts[name] > 0 and settings[name] * 2 <= LARGEST[name]]
    held = sum(size for name, size in parts.items() if name not in growing)
    if not growing or held > target:
        return None
    return max(growing, key=parts.get)


def _warn_not_met(ds, settings, rtol, mean, error) -> None:
    parts = ", ".join(f"{name} {ds.attrs.get(part, 0.0):.1g}" for part, name in _REFINES.items())
    warnings.warn(
        f"excluded_area: rtol {rtol:g} not met: <A_ex> = {mean:.9g} ± {error:.2g} b^2 (relative "
        f"{error / abs(mean):.2g}) at {settings}; the error's parts by setting: {parts} b^2, and the "
        f"settings given stay as given (largest refined: {LARGEST})",
        stacklevel=3,
    )


def excluded_area(
    particle,
    other=None,
    *,
    rtol: float | None = RTOL,
    segments: int | None = None,
    nphi: int | None = None,
    rows: int | None = None,
    progress: bool = True,
) -> xr.Dataset:
    """A_ex(φ) and its orientation mean ⟨A_ex⟩ with error bars, b²: sesp's answer to "what is A_ex?".

    The best estimate sesp has: of the smooth curves for two SeSPs (:func:`smooth_excluded_area`: scanlines
    exact along each line, extrapolated across lines and in the number of segments), of the polygons
    otherwise (:func:`scanline_excluded_area`). The settings left unset are refined, each step doubling
    the one whose part of the error budget is largest (``rows`` for the lines, ``nphi`` for the mean over
    φ, ``segments`` for the polygon), until the error bar of ⟨A_ex⟩ is at most ``rtol`` · ⟨A_ex⟩; settings
    that are given stay as given. A step measures only what is new (the odd orientations where nphi doubles,
    the finest polygon where the segments do): the result is bit for bit that of one evaluation at the
    settings reached. Where that cannot be reached (a given setting's part dominates, or the
    largest settings are reached) the result says so (attribute ``converged`` 0) and a warning tells how
    far it got. The integral of a stored field is the field's own measure,
    :func:`lattice_excluded_area`.

    Parameters
    ----------
    particle, other
        As for :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`, whose polylines are then
        measured as given).
    rtol : float or None
        Relative error bar of ⟨A_ex⟩ to reach (default 1e-5); None: one evaluation at the settings.
    segments : int, optional
        Polyline segments N of SeSPs (a multiple of 4 for the smooth curves), refined from 256 if unset.
    nphi : int, optional
        Orientations φ = 2πk/nphi, refined from 128 if unset.
    rows : int, optional
        Scanline spacings (a multiple of 8), refined from 2048 (smooth curves) or 512 (polygons).
    progress : bool
        A progress bar over the refinement steps, showing each step's settings, ⟨A_ex⟩ and its error bar, once
        the work has run 2 s (default; no call runs silently for minutes); False: none.

    Returns
    -------
    xarray.Dataset
        ``excluded_area(phi)`` and ``excluded_area_error(phi)``, ``mean_excluded_area`` and
        ``mean_excluded_area_error`` (b²); attributes ``excluded_area_of``, the settings used
        (``segments``, ``nphi``, ``rows``), ``rtol``, ``converged`` and the error budget
        ``mean_error_lines``, ``mean_error_phi`` (and ``mean_error_polygon`` for smooth curves), b².
        :mod:`sesp.onsager` takes it as it is.

    Examples
    --------
    >>> import math
    >>> from sesp import SeSP, excluded_area
    >>> ds = excluded_area(SeSP(n=2, opening=0.0), rtol=1e-4)  # the closed circle: 4π
    >>> abs(float(ds.mean_excluded_area) / (4 * math.pi) - 1) < 1e-4
    True
    """
    if isinstance(particle, xr.Dataset | xr.DataArray):
        raise TypeError("excluded_area takes particles; the count of a stored field is lattice_excluded_area(ds)")
    rtol = check_rtol(rtol, "<A_ex>")
    free = {name for name, value in (("segments", segments), ("nphi", nphi), ("rows", rows)) if value is None}
    settings = {
        "segments": check_count("segments", segments, 3, LARGEST["segments"]) if segments else START["segments"],
        "nphi": check_count("nphi", nphi, 1, LARGEST["nphi"]) if nphi else START["nphi"],
        "rows": rows,
    }
    if isinstance(particle, Pair):
        free.discard("segments")
        settings["segments"] = particle.segments
    memo = {}  # the trapezoids of every evaluation: each refinement step measures only what is new
    with progress_bar(None, progress, "excluded_area", unit="step") as bar:
        while True:
            pair = as_pair(particle, other, settings["segments"])
            ds = _measured(pair, settings["segments"], settings["nphi"], settings["rows"], memo)
            settings["rows"] = int(ds.attrs["rows"])
            mean, error = float(ds.mean_excluded_area), float(ds.mean_excluded_area_error)
            bar.set_postfix_str(f"{settings} <A_ex> = {mean:.9g} ± {error:.2g} b^2", refresh=False)
            bar.update(1)
            if rtol is None or error <= rtol * abs(mean):
                converged = True
                break
            step = _next_setting(ds, settings, free, rtol * abs(mean))
            if step is None:
                converged = False
                _warn_not_met(ds, settings, rtol, mean, error)
                break
            settings[step] *= 2
    ds.attrs.update(segments=settings["segments"], rtol=np.nan if rtol is None else rtol, converged=int(converged))
    return link_errors(ds)


def convex_excluded_area(curve: Polyline, other: Polyline | None = None) -> float:
    """Orientation-averaged excluded area of two closed convex curves, in b².

    A_ex = A₁ + A₂ + P₁ P₂ / 2π (for identical curves 2A + P²/2π), with the
    polygons' own areas and perimeters. For two curves that cannot contain
    one another (identical shapes), the curves meet exactly when the filled
    shapes do, so this is also the curves' excluded area.
    """
    other = curve if other is None else other
    for c in (curve, other):
        if not c.is_closed:
            raise ValueError("convex_excluded_area needs closed curves")
    return curve.area + other.area + curve.length * other.length / (2 * math.pi)


def _convex_mean(area: float, perimeter: float, contact: float) -> float:
    """⟨A_ex⟩ (b²) of two copies of a convex body of ``area`` and ``perimeter`` that meet at ``contact`` (b):
    2·Area + P²/2π, and 2·P·D + π·D² more at D = ``contact`` (Steiner's formula)."""
    return 2 * area + perimeter**2 / (2 * math.pi) + 2 * perimeter * contact + math.pi * contact**2


def closed_excluded_area(source, *, rtol: float = RTOL) -> float:
    """⟨A_ex⟩ (b²) of the pair's particles closed (Ψ = 0), measured as the quantity it normalises.

    ``source`` a stored field (a scan or summary): the closed polygons with the file's segments, as the field's
    lattice count measures them: for identical convex shapes the exact 2·Area + P²/2π of the closed polygon
    (with 2·P·D + π·D² at thickness D, Steiner's formula), otherwise a lattice count of the closed shapes at
    the file's grid. ``source`` particles or a :class:`~sesp.Pair`: the smooth curves, as
    :func:`excluded_area` measures SeSPs: the exact 2·Area + P²/2π of the superellipse for identical convex
    shapes, otherwise :func:`excluded_area` of the closed SeSPs at ``rtol``; NaN for polylines, which have no
    closed shape. The reference :func:`sesp.analyze` divides its A_ex by, and
    :func:`normalized_excluded_area` a field's."""
    if isinstance(source, xr.Dataset):
        return _closed_polygons(pair_of(source), grid_of(source))
    pair = as_pair(source)
    if not (isinstance(pair.particle, SeSP) and isinstance(pair.other, SeSP)):
        return math.nan
    closed = pair.closed()
    if closed.identical and closed.particle.is_convex_closed:
        particle = closed.particle
        return _convex_mean(superellipse_area(particle), superellipse_perimeter(particle), pair.contact)
    found = excluded_area(closed.particle, None if closed.identical else closed.other, rtol=rtol, progress=False)
    return float(found.mean_excluded_area)


def _closed_polygons(pair: Pair, grid: Grid) -> float:
    """:func:`closed_excluded_area` of a stored field's pair on its grid."""
    closed = pair.closed()
    if pair.identical and pair.particle.is_convex_closed:
        curve = closed.curve1
        return _convex_mean(curve.area, curve.length, pair.contact)
    return lattice_excluded_area(scan(closed, Grid(grid.nx, grid.ny, grid.nphi)))


def normalized_excluded_area(ds: xr.Dataset, *, by: str | None = None, reference: float | None = None):
    """Excluded area divided by that of the closed shape (dimensionless).

    ``reference`` overrides the closed shape's A_ex (b²). For the ASP the
    closed value is π D² = 4π up to the polygon's error.
    """
    reference = closed_excluded_area(ds) if reference is None else float(reference)
    value = lattice_excluded_area(ds, by=by)
    if by is None:
        return value / reference
    out = value / reference
    out.name = "normalized_excluded_area"
    out.attrs = {"units": "1", "long_name": "A_ex(φ) / A_ex of the closed shape", "reference": reference}
    return out


def kinematic_integral(ds: xr.Dataset) -> tuple[float, float]:
    """∫∫∫ n dx dy dφ over the grid, and its exact value 4 L₁ L₂ (Poincaré).

    Poincaré's kinematic formula holds for any two curves (polylines
    included) and any shapes, so the relative difference measures the
    quadrature error alone. Needs a scan with ``crossings=True``.

    Returns
    -------
    measured, exact : float
        In b² · rad.
    """
    if "crossings" not in ds:
        raise ValueError("kinematic_integral needs the crossings field: scan with crossings=True")
    total = float(ds.crossings.values.sum(dtype=np.uint64))
    measured = total * cell_area(ds) * 2 * math.pi / ds.sizes["phi"]
    exact = 4.0 * float(ds.attrs["particle_length"]) * float(ds.attrs["other_length"])
    return measured, exact


def excluded_perimeter(particle, grid: Grid | None = None, *, other=None, segments: int = DEFAULT_SEGMENTS,
                       step: float | None = None):  # fmt: skip
    """P_ex(φ) = dA_ex(φ)/dD: the perimeter of the excluded set at each orientation, in b.

    Thickening both particles by D adds a band of width D around the
    excluded set, so A_ex(D) = A_ex(0) + P_ex D + O(D²): P_ex is the
    first-order thickness correction of a thin result, and the perimeter of
    the excluded set (holes included). It is measured from A_ex(φ) on
    shifted lattices (:func:`shifted_excluded_area`) at the pair's own
    contact distance and at ``step`` and 2 ``step`` more, by the
    second-order one-sided difference (4 A(ε) − A(2ε) − 3 A(0)) / 2ε, which
    removes the D² term. ``tests/test_thickness.py`` compares it with the
    exact perimeter of the union of the Minkowski parallelograms.

    Parameters
    ----------
    particle, other, segments, grid
        As for :func:`shifted_excluded_area`.
    step : float, optional
        Thickness increment ε (b); default 16 cells of the grid (lattice noise in
        the differences falls as 1/ε, the neglected D³ term grows as ε²).

    Returns
    -------
    xarray.DataArray
        ``excluded_perimeter(phi)`` in b.
    """
    pair = as_pair(particle, other, segments)
    base = grid if grid is not None else Grid()
    if step is None:
        step = 16 * 2 * resolve_grid(pair, base).half_width / min(base.nx, base.ny or base.nx)
    step = check_positive("step", step)
    grid = resolve_grid(pair.thickened(2 * step), base)  # one box for all three, wide enough for the thickest
    areas = [shifted_excluded_area(pair.thickened(extra), grid) for extra in (0.0, step, 2 * step)]
    slope = (4 * areas[1] - areas[2] - 3 * areas[0]) / (2 * step)
    return slope.rename("excluded_perimeter").assign_attrs(
        **quantity(1, "perimeter of the excluded set P_ex(φ) = dA_ex/dD"), step=step
    )
