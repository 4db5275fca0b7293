"""Connected components of sets of positions or states, robust to the grid.

Robust count
------------
Sets in this problem touch themselves at single points: for the ASP the
excluded set is two bodies that meet at the particle's centre, separated
near it by allowed wedges whose opening angle is Ψ. On a grid such a pinch
is a junction of excluded nodes about h/Ψ across, so a pixel count, or a
count of an eroded set, joins the bodies at every resolution once Ψ is small.

sesp therefore counts components by **persistence of the distance to the
set's complement**. Let d be, for each node of the set, its distance (in node
spacings) to the nearest node outside the set. Components are the
superlevel-set components of d, grown from their peaks; when two meet at a
node of value s (the width of the neck between them), the one with the
lower peak p (its inscribed radius) stays a component of its own if
s < ``ratio`` · p, and merges otherwise. Components whose peak is below
``min_peak`` are noise and are not counted. The two judged are the bodies
the node touches: where a connected part already holds bodies kept apart
(two wings and the tip they meet at), a body that reaches it at the tip is
judged against the tip, not against the part's largest body; where a node
touches several, the verdict that joins most wins. Consequences:

* a pinch (s ≈ h, p ≫ h) separates two bodies, and ever more surely as h
  shrinks, whatever the grid's parity;
* a bump or a cusp-tip fragment joined by a neck nearly as wide as itself
  is part of the body it hangs on;
* a component thinner than about ``2 · min_peak`` nodes is not resolved, so
  one that is born thin (an island appearing from a point) is first seen at
  slightly different Ψ on different grids; :func:`find_transitions` reports
  brackets at two resolutions so the convergence is visible, and flags a
  transition as grid-limited (``Transition.resolved`` False) when a component
  at either end of its bracket is thinner than ``RESOLVED_PEAK`` nodes. A
  component that shrinks continuously to nothing (the ASP's island as Ψ → π)
  is always lost this way: its bracket is where the grid stops seeing it,
  which moves with h (for the ASP, toward the exact Ψ = π as h shrinks);
* a pinch behind an allowed wedge of small angle Ψ is a junction about h/Ψ
  nodes across, so a split as Ψ → 0⁺ is seen once the wedge is resolved,
  at a Ψ that depends on the grid even though both bodies are thick
  (``benchmarks/topology_parity.py`` measures it on even and odd grids).

φ is periodic: a component that wraps through φ = 0 is one component.

Following thin components: the symmetry axis
--------------------------------------------
For a SeSP with itself the pair is mirror-symmetric about the x axis, and
every component that is its own mirror image meets the axis. Along the axis,
:func:`axis_profile` measures the excluded set's half-thickness exactly in φ
(:func:`sesp.regions.allowed_orientations`, no orientation grid) and in y
down to 1e-9 b, and :func:`axis_transitions` counts its persistent components
over Ψ, ranked like the grid count by the inscribed radius of the sampled
set |y| <= w(x) (:meth:`AxisProfile.radii`), and always sampling the centre
x = 0, where the excluded set touches itself. That count follows components
thinner than any grid's node, such as the ASP's island, 1 − sin(Ψ/2) thick,
to their end; it does not see components that come in mirror pairs off the
axis, which only the grid count does. It also brackets the split at 0⁺ and
the end at π identically on even and odd samplings, where the grid count
is misled by thin allowed wedges and slits (``benchmarks/axis_slit.py``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
import xarray as xr
from scipy import ndimage

from .dataset import cell_area
from .field import scan
from .grid import Grid
from .kernels import labels as label_kernels
from .orientations import allowed_orientations
from .pair import as_pair
from .progress import progress_bar, progress_iter
from .regions import summarize
from .shape import DEFAULT_SEGMENTS, SeSP

__all__ = [
    "Components",
    "components",
    "distance_to_complement",
    "excluded_components",
    "state_components",
    "find_transitions",
    "opening_family",
    "QUANTITIES",
    "AxisProfile",
    "axis_profile",
    "axis_transitions",
]

QUANTITIES = ("excluded", "allowed", "entangled")

# Inscribed radius, in node spacings, below which a component is near the
# grid's reach: twice the default ``min_peak`` of :func:`components`.
RESOLVED_PEAK = 4.0
PINCH_RATIO = 0.5  # a neck under this times the smaller body's inscribed radius parts two bodies


@dataclass(frozen=True)
class Components:
    """Labelled components of a set on the grid.

    Attributes
    ----------
    labels : ndarray of int32
        0 outside every component, k = 1..count inside component k (every
        node of the set belongs to the component it was grown into, except
        nodes of components too thin to count).
    sizes : (count,) ndarray
        Nodes in each component, largest first (labels are numbered so).
    measure : float
        Area (b²) or hypervolume (b²·rad) of one node.
    unassigned : int
        Nodes of the set in no component (parts too thin to count).
    peaks : (count,) ndarray
        Inscribed radius of each component, in node spacings (the largest
        distance from one of its nodes to the set's complement).
    necks : (k, 4) ndarray
        Undecided necks, when asked for (``neck`` > 0 in :func:`components`):
        flat node index, the two components' labels, the neck's width s
        (node spacings).
    """

    labels: np.ndarray
    sizes: np.ndarray
    measure: float
    unassigned: int
    peaks: np.ndarray
    necks: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))

    @property
    def count(self) -> int:
        return len(self.sizes)

    @property
    def areas(self) -> np.ndarray:
        """Area (or hypervolume) of each component, largest first."""
        return self.sizes * self.measure


def distance_to_complement(mask, periodic=(), outside: bool = False):
    """Euclidean distance, in node spacings, from each node of the set to the nearest node outside it."""
    pad = [(1, 1)] * mask.ndim
    for axis in periodic:
        pad[axis] = (0, 0)
    padded = np.pad(mask, pad, mode="constant", constant_values=outside)
    if outside:  # the set continues beyond the box: only nodes inside it are outside the set (the array's edge
        padded = mask  # is not background to the transform)
    reps = [3 if a in periodic else 1 for a in range(mask.ndim)]
    tiled = np.tile(padded, reps)
    dist = ndimage.distance_transform_edt(tiled)
    crop = []
    for a in range(mask.ndim):
        start = mask.shape[a] if a in periodic else (padded.shape[a] - mask.shape[a]) // 2
        crop.append(slice(start, start + mask.shape[a]))
    return dist[tuple(crop)]


def components(
    mask,
    *,
    periodic=(),
    outside: bool = False,
    measure: float = 1.0,
    ratio: float = PINCH_RATIO,
    min_peak: float = 2.0,
    neck: float = 0.0,
    distance=None,
) -> Components:
    """Robust connected components of a boolean set (see the module notes).

    Parameters
    ----------
    mask : (ny, nx) or (nphi, ny, nx) bool array_like
    periodic : tuple of int
        Axes that wrap around; only axis 0 (φ of a (phi, y, x) field) may.
    outside : bool
        Whether the set continues beyond the grid's box along non-periodic
        axes (True for allowed states, False for excluded positions).
    measure : float
        Area or hypervolume of one node.
    ratio : float
        A component stays separate where the neck joining it to a larger one
        is narrower than ``ratio`` times its own inscribed radius.
    min_peak : float
        Smallest inscribed radius, in node spacings, of a counted component.
    neck : float
        Where two components with inscribed radii of at least ``RESOLVED_PEAK``
        meet at a neck s with ratio · p <= s < neck · p (p the smaller radius),
        keep them apart and list the neck in ``Components.necks``, for a finer
        look (the adaptive maps do); 0: no such necks.
    distance : ndarray, optional
        The distance field to rank by, shaped like ``mask`` (node spacings);
        default :func:`distance_to_complement` of ``mask``.

    Returns
    -------
    Components
    """
    mask = np.asarray(mask, dtype=bool)
    periodic = tuple(sorted({a % mask.ndim for a in periodic}))
    if periodic not in ((), (0,)):
        raise ValueError(f"only axis 0 can be periodic, got {periodic}")
    dist = distance_to_complement(mask, periodic, outside) if distance is None else np.asarray(distance, dtype=float)
    dist = dist.ravel()
    nodes = np.flatnonzero(mask.ravel())
    order = nodes[np.argsort(-dist[nodes], kind="stable")]
    shape = np.array((1,) * (3 - mask.ndim) + mask.shape, dtype=np.int64)
    labels, _, necks = label_kernels.persistent_labels(
        dist, order, shape, bool(periodic), float(ratio), float(min_peak), float(neck), RESOLVED_PEAK, MAX_NECKS
    )
    return renumbered(labels.reshape(mask.shape), mask, measure, dist.reshape(mask.shape), necks)


MAX_NECKS = 4096  # undecided necks listed at most, per call of :func:`components`


def renumbered(labels, mask, measure, dist, necks) -> Components:
    """Components of ``labels`` (0: none) numbered by decreasing size, with their inscribed radii (``dist``,
    node spacings) and ``necks`` relabelled; ``mask`` is the set they are components of. Used to rebuild
    :class:`Components` after joining some of them."""
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    keep = np.flatnonzero(sizes > 0)
    keep = keep[np.argsort(-sizes[keep], kind="stable")]
    mapping = np.zeros(len(sizes), dtype=np.int32)
    mapping[keep] = np.arange(1, len(keep) + 1, dtype=np.int32)
    new = mapping[labels]
    peaks = np.asarray(ndimage.maximum(dist, new, np.arange(1, len(keep) + 1)), dtype=float).reshape(-1)
    unassigned = int(np.count_nonzero(mask) - np.count_nonzero(new))
    necks = necks.copy()
    necks[:, 1:3] = mapping[necks[:, 1:3].astype(np.int64)]
    return Components(new, sizes[keep], float(measure), unassigned, peaks, necks)


def excluded_components(ds: xr.Dataset, **kwargs) -> Components:
    """Components of the excluded positions (no orientation allowed), in the plane.

    ``ds`` is a scan or a summary (:func:`sesp.regions.summarize`).
    """
    if "allowed_fraction" in ds:
        excluded = ds.allowed_fraction.values == 0
    else:
        excluded = ~ds.allowed.values.any(axis=0)
    return components(excluded, outside=False, measure=cell_area(ds), **kwargs)


def state_components(ds: xr.Dataset, which: str = "allowed", **kwargs) -> Components:
    """Components in the (x, y, φ) hypervolume, φ periodic; measure in b²·rad.

    ``which`` is "allowed" or "entangled" (the latter needs a scan with
    ``entangled=True``).
    """
    if which not in ("allowed", "entangled"):
        raise ValueError(f"which must be 'allowed' or 'entangled', got {which!r}")
    if which not in ds:
        raise ValueError(f"the dataset has no {which!r} field: scan with {which}=True")
    measure = cell_area(ds) * 2 * math.pi / ds.sizes["phi"]
    return components(ds[which].values, periodic=(0,), outside=(which == "allowed"), measure=measure, **kwargs)


# --- transitions over the opening Ψ ----------------------------------------------------


def opening_family(family):
    """opening -> particle: a SeSP's opening varied, or the callable itself."""
    if isinstance(family, SeSP):
        return lambda opening: dataclasses.replace(family, opening=float(opening))
    if callable(family):
        return family
    raise TypeError("family must be a SeSP (its opening is varied) or a callable opening -> particle")


def _count(make, opening, quantity, grid, segments) -> Components:
    particle = make(opening)
    if quantity == "excluded":
        return excluded_components(summarize(particle, grid, segments=segments, entangled=False))
    ds = scan(particle, grid, segments=segments, entangled=(quantity == "entangled"))
    return state_components(ds, quantity)


def _thinnest(found: Components) -> float:
    """Smallest inscribed radius (node spacings) of the counted components; inf if none."""
    return float(found.peaks.min()) if found.count else math.inf


def _state(found: Components) -> tuple:
    """What a transition search keeps of a count: (count, thinnest component)."""
    return found.count, _thinnest(found)


@dataclass
class Transition:
    """A change of the component count between two openings (radians).

    ``thinnest`` is the smallest inscribed radius, in node spacings, of the
    components counted at either end of the bracket. Below ``RESOLVED_PEAK``
    the change may be the grid losing (or first seeing) a thin component
    rather than the component vanishing (or appearing): such a bracket moves
    with resolution, and ``resolved`` is False. ``resolved`` says nothing
    about the necks: a split at a pinch that the grid resolves late (an
    allowed wedge of small angle) can still differ between grids with thick
    components on both sides.
    """

    low: float
    high: float
    count_low: int
    count_high: int
    resolution: tuple = ()
    thinnest: float = math.inf

    @property
    def opening(self) -> float:
        return 0.5 * (self.low + self.high)

    @property
    def resolved(self) -> bool:
        return self.thinnest >= RESOLVED_PEAK


@dataclass
class TopologyResult:
    """Counts over a Ψ sweep and the refined transitions at each resolution."""

    quantity: str
    openings: np.ndarray
    counts: np.ndarray
    areas: list
    transitions: dict = field(default_factory=dict)  # resolution -> [Transition]
    thinnest: np.ndarray | None = None  # per opening, node spacings


def _profile(make, openings, quantity, grid, segments, progress) -> list:
    return [_count(make, o, quantity, grid, segments) for o in progress_iter(openings, progress, "Ψ")]


def _memoised(measure, summary, cache, bar=None):
    """opening -> summary(measure(opening)), measuring each opening once (``cache`` holds the measures).

    ``bar`` (a progress bar) counts the openings measured.
    """

    def state(opening):
        if opening not in cache:
            cache[opening] = measure(opening)
            if bar is not None:
                bar.update(1)
        return summary(cache[opening])

    return state


def _counter(make, quantity, grid, segments, cache, bar=None):
    """opening -> (count, thinnest component) on ``grid``; ``cache`` maps openings to Components."""
    return _memoised(lambda opening: _count(make, opening, quantity, grid, segments), _state, cache, bar)


def _first_pass_transitions(state, openings, tolerance, resolution):
    """Each change of ``state``'s count between consecutive openings, bisected."""
    return [
        t
        for a, b in zip(openings[:-1], openings[1:])
        for t in _refine(state, float(a), float(b), tolerance, resolution)
    ]


def _refine(state, low, high, tolerance, resolution):
    """Bisect [low, high] to brackets no wider than 2·tolerance around each change."""
    (c_low, t_low), (c_high, t_high) = state(low), state(high)
    if c_low == c_high:
        return []
    if high - low <= 2 * tolerance:
        return [Transition(low, high, c_low, c_high, resolution, min(t_low, t_high))]
    mid = 0.5 * (low + high)
    return _refine(state, low, mid, tolerance, resolution) + _refine(state, mid, high, tolerance, resolution)


def _openings(opening_range, step, tolerance):
    """The first pass's openings: ``step`` apart from the range's start, below 2π; checked."""
    lo, hi = (float(v) for v in opening_range)
    if not (0 <= lo < hi) or step <= 0 or tolerance <= 0:
        raise ValueError(f"opening_range must satisfy 0 <= low < high and step, tolerance > 0, got {opening_range}")
    openings = lo + step * np.arange(int(math.floor((hi - lo) / step + 1e-9)) + 1)
    return openings[openings < 2 * math.pi]


def find_transitions(
    family,
    quantity: str = "excluded",
    opening_range=(0.0, 2 * math.pi),
    *,
    grid: Grid | None = None,
    segments: int = DEFAULT_SEGMENTS,
    step: float = math.radians(5),
    tolerance: float = 0.02,
    refine_factor: int = 2,
    progress: bool = False,
) -> TopologyResult:
    """Where a topological count changes as the opening Ψ varies.

    Scans Ψ over ``opening_range`` in steps of ``step`` on ``grid``, finds the
    steps where the count changes and bisects each to a bracket of at most
    ``2 · tolerance`` (radians). The brackets are then re-bisected on a grid
    ``refine_factor`` times finer in x, y and φ, so the user can see whether
    they converge. Each transition says whether it is resolved: a component
    thinner than ``RESOLVED_PEAK`` node spacings at either end of the bracket
    means the grid may be losing a component that still exists (or first
    seeing one born earlier); such brackets move with resolution.

    Parameters
    ----------
    family : SeSP or callable
        A SeSP whose opening is varied, or a function opening -> particle.
    quantity : {"excluded", "allowed", "entangled"}
        "excluded": components of the excluded positions in the plane;
        "allowed" / "entangled": components of those states in (x, y, φ).
    opening_range : (float, float)
        Ψ range in radians; Ψ >= 2π is left out.

    Returns
    -------
    TopologyResult
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {QUANTITIES}, got {quantity!r}")
    openings = _openings(opening_range, step, tolerance)
    make = opening_family(family)
    grid = grid if grid is not None else Grid(256, nphi=256)
    found = _profile(make, openings, quantity, grid, segments, progress)
    result = TopologyResult(
        quantity,
        openings,
        np.array([c.count for c in found]),
        [c.areas for c in found],
        thinnest=np.array([_thinnest(c) for c in found]),
    )
    resolution = (grid.nx, grid.ny, grid.nphi)
    with progress_bar(None, progress, f"bisect ({grid.nx}x{grid.ny}x{grid.nphi})", unit="Ψ") as bar:
        state = _counter(make, quantity, grid, segments, dict(zip(openings.tolist(), found)), bar)
        coarse = _first_pass_transitions(state, openings, tolerance, resolution)
    result.transitions[resolution] = coarse
    if refine_factor > 1:
        fine = Grid(grid.nx * refine_factor, grid.ny * refine_factor, grid.nphi * refine_factor)
        with progress_bar(None, progress, f"re-bracket ({fine.nx}x{fine.ny}x{fine.nphi})", unit="Ψ") as bar:
            result.transitions[(fine.nx, fine.ny, fine.nphi)] = _rebracket(
                make, coarse, quantity, fine, segments, step, tolerance, bar
            )
    return result


def _windows(coarse, step, factor):
    """One search window per coarse transition, widened by ``factor`` steps, overlaps merged."""
    spans = sorted((max(t.low - factor * step, 0.0), min(t.high + factor * step, 2 * math.pi - 1e-9)) for t in coarse)
    merged = []
    for low, high in spans:
        if merged and low <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], high))
        else:
            merged.append((low, high))
    return merged


def _rebracket(make, coarse, quantity, grid, segments, step, tolerance, bar=None):
    """Re-bisect the coarse transitions on a finer grid.

    Each is searched in a window of one coarse step on either side, widened
    (2, then 4 steps) while the counts at the window's ends are equal, so a
    transition that moved with resolution is followed, not lost.
    """
    state = _counter(make, quantity, grid, segments, {}, bar)
    resolution = (grid.nx, grid.ny, grid.nphi)
    out = []
    for factor in (1, 2, 4):
        pending = [
            t
            for t in coarse
            if not any(f.low <= t.high + factor * step and f.high >= t.low - factor * step for f in out)
        ]
        for low, high in _windows(pending, step, factor):
            out += _refine(state, low, high, tolerance, resolution)
        if len(out) >= len(coarse):
            break
    return sorted(out, key=lambda t: t.low)


# --- the symmetry axis, exact in φ ------------------------------------------------------
#
# A SeSP pair is mirror-symmetric about the x axis, and so is every component of
# the excluded set that is its own mirror image; such a component meets the
# axis (a path from a point to its mirror image crosses it). Along the axis its
# half-thickness w(x) is measured exactly in φ and adaptively in y, so thin
# components (the island as it closes up) are followed far below any grid's
# node spacing.

AXIS_WIDTH_FLOOR = 1e-9  # b: thinner than this counts as no thickness
_WIDTH_RATIO = 16.0  # geometric search steps for the half-thickness
_WIDTH_BISECTIONS = 8  # then bisection, to 1/256 of the bracket
AXIS_REFINE = 16  # runs of excluded axis nodes shorter than this are resampled this many times finer


@dataclass(frozen=True)
class AxisProfile:
    """Half-thickness of the excluded set along the symmetry axis y = 0.

    Attributes
    ----------
    opening : float
        Ψ, radians.
    x : (k,) ndarray
        Axis nodes, b: cell centres of [-reach, reach] and the centre x = 0
        (where the excluded set can touch itself), plus nodes ``AXIS_REFINE``
        times denser over each run of excluded nodes shorter than ``AXIS_REFINE``.
    half_width : (k,) ndarray
        For each node, the largest w (b) such that the points (x, y) with
        0 <= y <= w found by the search are all excluded, capped at
        ``RESOLVED_PEAK`` coarse axis spacings (thicker parts are the 2D
        grid's business); 0 where (x, 0) is allowed. Exact in φ; in y the
        search tests y = 1e-9 · 16^j up to the cap, then bisects the last
        bracket 8 times (to 1/16 of w).
    """

    opening: float
    x: np.ndarray
    half_width: np.ndarray

    def radii(self) -> np.ndarray:
        """Inscribed radius (b) at each axis node of the set |y| <= w(x) it samples.

        r(x) = min over nodes x' of sqrt((x − x')² + w(x')²): the distance from
        (x, 0) to the nearest sampled boundary point, the axis form of the
        distance to the complement that the grid count ranks by. It is small
        wherever the set is short along the axis, however tall it is there.
        """
        return _axis_radii(self.x, self.half_width)

    def components(self, ratio: float = PINCH_RATIO, min_nodes: int = 2) -> list:
        """Robust components along the axis: list of (x_low, x_high, peak radius, nodes).

        The 1D form of the persistence count (module notes) on the inscribed
        radii r (:meth:`radii`): along the axis a component is a run of nodes
        with w > ``AXIS_WIDTH_FLOOR``; two runs that meet at a neck of radius s
        stay separate if s < ``ratio`` times the smaller peak radius. Runs
        shorter than ``min_nodes`` nodes are not counted.
        """
        return _axis_persistence(self.x, self.radii(), ratio, min_nodes)


def _axis_radii(x, w):
    """min over x' of hypot(x − x', w(x')), per run of w > floor and its two bounding allowed nodes."""
    r = np.where(w > AXIS_WIDTH_FLOOR, w, 0.0)
    for a, b in _runs(w):
        near = slice(max(a - 1, 0), min(b + 1, len(w)))  # the run and the allowed nodes around it
        bound = np.where(w[near] > AXIS_WIDTH_FLOOR, w[near], 0.0)
        r[a:b] = np.hypot(x[a:b, None] - x[None, near], bound[None, :]).min(axis=1)
    return r


def _axis_persistence(x, w, ratio, min_nodes):
    """Superlevel-set components of w along a line, merged at necks as in :func:`components`."""
    parent = np.full(len(w), -1)
    peak, size = np.zeros(len(w)), np.zeros(len(w), dtype=int)
    first, last = np.arange(len(w)), np.arange(len(w))

    def root(i):
        while parent[i] != i:
            i = parent[i]
        return i

    for i in np.argsort(-w, kind="stable"):
        if w[i] <= AXIS_WIDTH_FLOOR:
            break
        near = sorted({root(j) for j in (i - 1, i + 1) if 0 <= j < len(w) and parent[j] >= 0}, key=lambda r: -peak[r])
        if not near:
            parent[i], peak[i], size[i] = i, w[i], 1
            continue
        big = near[0]
        parent[i] = big
        size[big] += 1
        first[big], last[big] = min(first[big], i), max(last[big], i)
        for small in near[1:]:
            if w[i] >= ratio * peak[small]:  # a neck as wide as the smaller side: one component
                parent[small] = big
                size[big] += size[small]
                first[big], last[big] = min(first[big], first[small]), max(last[big], last[small])
    roots = [i for i in range(len(w)) if parent[i] == i and size[i] >= min_nodes]
    return [
        (float(x[first[r]]), float(x[last[r]]), float(peak[r]), int(size[r]))
        for r in sorted(roots, key=lambda r: first[r])
    ]


def _axis_nodes(particle, nodes, segments):
    """(axis nodes, their spacing), b: cell centres of [-r₁ - r₂, r₁ + r₂] and the centre x = 0."""
    reach = as_pair(particle, segments=segments).reach
    spacing = 2 * reach / nodes
    cells = (np.arange(nodes) - (nodes - 1) / 2) * spacing
    return np.union1d(cells, [0.0]), spacing  # the centre, where the excluded set can touch itself, on any parity


def axis_profile(particle, *, nodes: int = 512, segments: int = DEFAULT_SEGMENTS) -> AxisProfile:
    """The excluded set's half-thickness along the symmetry axis, exact in φ.

    Only for a mirror-symmetric pair (a SeSP with itself); components that
    are not their own mirror image (mirror pairs off the axis) are not seen.

    Parameters
    ----------
    particle : SeSP
    nodes : int
        Axis nodes over [-r₁ - r₂, r₁ + r₂].
    segments : int
        Polyline segments.
    """
    if not isinstance(particle, SeSP):
        raise TypeError(f"axis_profile needs a SeSP (mirror-symmetric), got {type(particle).__name__}")
    x, spacing = _axis_nodes(particle, int(nodes), segments)
    cap = RESOLVED_PEAK * spacing
    w = _axis_widths(particle, x, segments, cap)
    for first, last in _short_runs(w, AXIS_REFINE):  # resample short runs AXIS_REFINE times finer
        count = AXIS_REFINE * (last - first + 2)
        fine = x[first] - spacing + (np.arange(1, count) / count) * (last - first + 2) * spacing
        x = np.concatenate([x, fine])
        w = np.concatenate([w, _axis_widths(particle, fine, segments, cap)])
    x, first = np.unique(x, return_index=True)  # sorted; a fine node may repeat a coarse one
    return AxisProfile(float(particle.opening), x, w[first])


def _axis_widths(particle, x, segments, cap):
    w = np.zeros(len(x))
    inside = np.flatnonzero(allowed_orientations(particle, x, 0.0, segments=segments) == 0)
    if len(inside):
        w[inside] = _half_widths(particle, x[inside], segments, cap)
    return w


def _runs(w):
    """(start, stop) of each run of nodes with w > ``AXIS_WIDTH_FLOOR``, as slice bounds."""
    inside = np.concatenate([[False], w > AXIS_WIDTH_FLOOR, [False]]).astype(np.int8)
    return np.flatnonzero(np.diff(inside)).reshape(-1, 2)


def _short_runs(w, shorter_than):
    """(first, last) node of each run of w > ``AXIS_WIDTH_FLOOR`` with fewer than ``shorter_than`` nodes."""
    return [(int(a), int(b) - 1) for a, b in _runs(w) if b - a < shorter_than]


def _half_widths(particle, xs, segments, cap):
    """For excluded axis points: the extent in y, up to ``cap``, of the excluded run from the axis."""
    steps = AXIS_WIDTH_FLOOR * _WIDTH_RATIO ** np.arange(
        1, 1 + math.ceil(math.log(cap / AXIS_WIDTH_FLOOR, _WIDTH_RATIO))
    )
    steps = np.append(steps[steps < cap], cap)
    grid_x, grid_y = np.meshgrid(xs, steps, indexing="ij")
    excluded = allowed_orientations(particle, grid_x, grid_y, segments=segments) == 0
    first_allowed = np.where(excluded.all(axis=1), len(steps), np.argmin(excluded, axis=1))
    low = np.where(first_allowed > 0, steps[np.maximum(first_allowed - 1, 0)], 0.0)
    high = np.where(first_allowed < len(steps), steps[np.minimum(first_allowed, len(steps) - 1)], steps[-1])
    for _ in range(_WIDTH_BISECTIONS):
        mid = 0.5 * (low + high)
        ok = allowed_orientations(particle, xs, mid, segments=segments) == 0
        low, high = np.where(ok, mid, low), np.where(ok, high, mid)
    return low


def _axis_summary(found) -> tuple:
    """What a transition search keeps of axis components: (count, shortest component in axis nodes)."""
    return len(found), min((c[3] for c in found), default=math.inf)


def axis_transitions(
    family,
    opening_range=(0.0, math.pi + 0.35),
    *,
    nodes: int = 512,
    segments: int = DEFAULT_SEGMENTS,
    step: float = math.radians(5),
    tolerance: float = 0.02,
    progress: bool = False,
) -> TopologyResult:
    """Where the count of axis components (:func:`axis_profile`) changes with Ψ.

    Like :func:`find_transitions`, but each count is exact in φ and resolves
    thicknesses down to ``AXIS_WIDTH_FLOOR``: it follows thin components (the
    island as Ψ → π) that every grid loses early. ``thinnest`` is here the
    shortest counted component, in axis nodes; below ``RESOLVED_PEAK`` the
    bracket is near the axis sampling's reach; ``areas`` holds each
    component's peak inscribed radius (b, :meth:`AxisProfile.radii`) instead
    of an area.

    Parameters
    ----------
    family : SeSP or callable opening -> SeSP
    opening_range, step, tolerance
        As in :func:`find_transitions` (radians).
    nodes, segments
        As in :func:`axis_profile`.
    """
    openings = _openings(opening_range, step, tolerance)
    make = opening_family(family)
    cache = {}  # opening -> axis components
    state = _memoised(
        lambda opening: axis_profile(make(opening), nodes=nodes, segments=segments).components(), _axis_summary, cache
    )
    states = [state(float(o)) for o in progress_iter(openings, progress, "Ψ (axis)")]
    areas = [np.array([c[2] for c in cache[float(o)]]) for o in openings]
    result = TopologyResult(
        "excluded (axis)", openings, np.array([s[0] for s in states]), areas, thinnest=np.array([s[1] for s in states])
    )
    resolution = (nodes, 1, 0)
    with progress_bar(None, progress, f"bisect ({nodes} axis nodes)", unit="Ψ") as bar:
        state = _memoised(
            lambda opening: axis_profile(make(opening), nodes=nodes, segments=segments).components(),
            _axis_summary,
            cache,
            bar,
        )
        result.transitions[resolution] = _first_pass_transitions(state, openings, tolerance, resolution)
    return result
