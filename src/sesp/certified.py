"""Components of the excluded set at a stated resolution, certified on both sides, exact in φ.

Definition. The depth p(t) of a translation t is its distance (b) to the
nearest allowed translation (one at which some orientation φ leaves the two
particles apart). At resolution ε the excluded set is eroded by ε:
E_ε = {t : p(t) ≥ ε}. The count is the number of components of E_ε that
reach a depth of ε + rim: a single-point pinch (the ASP's centre) always
separates, a neck narrower than 2ε separates, and a component whose deepest
point is shallower than ε + rim is not counted. In the language of
persistence: the components born deeper than ε + rim that have not died at
ε. ``rim`` (b) is 1e-3 b by default, or ε or the polylines' departure from
the smooth curves (:attr:`sesp.Pair.departure`) where either is larger: a
body thinner than the departure may be the polylines' own and not the
particle's. A lower rim counts shallower components at a cost (below).

Certificates. Space is cut into a quadtree of square cells (base × base on
the particles' reach box, refined by halving). Each cell is

* **allowed-centred** when some φ leaves the particles apart at its centre
  (exact windows in φ; :mod:`sesp.kernels.orientations`), with a clearance
  that bounds the depth of every point of the cell from above;
* **in** when the depth certificate (:mod:`sesp.kernels.depth`: curves that
  cross with odd parity and stay crossed under every shorter translation, at
  every φ, in closed form; or two end points held through opposite sides of
  the other curve) proves its centre at least ε + h deep, h its
  half-diagonal: then the whole cell lies in E_ε;
* **out** when an upper bound on the depth anywhere in the cell (from allowed
  centres nearby) is below ε: no point of the cell lies in E_ε;
* **undecided** otherwise.

Every component of E_ε lies in one component of in ∪ undecided cells (a
candidate), and every certified part (in-cells joined where they touch or
where their certified disks meet) lies in one component of E_ε. Each cell
also has an upper bound on the depth anywhere in it (from the allowed points
nearby), so a candidate is **shallow**, holding no counted component, where
the largest bound on its cells is below ε + rim, and **counted** where the
depth certificate proves a point of it at least ε + rim deep. A counted
component of a candidate holds a point at least ε + rim deep, so it joins a
part to a cell whose bound reaches ε + rim without passing another part: only
parts so placed may be components of their own. ``low`` counts the counted
candidates, ``high`` adds up those parts of the candidates not shallow (and 1
for a candidate without any). Cells are split only where an undecided cell
could change the bracket: between two such parts of one candidate, in a
candidate without a part, in a candidate neither counted nor shallow where a
cell's bound reaches ε + rim, or on a candidate's rim where some point of the
cell lies farther than rim from every certified disk and may be deeper than
ε + rim (a point deeper than ε + its distance d to a certified disk joins that
disk's part: the disk of radius p − ε about it lies in E_ε, the depth being
1-Lipschitz, and reaches d; a point within ε + rim of an allowed disk, an
allowed point's clearance, is shallower than ε + rim). So every component
deeper than ε + rim is found, and the count does not depend on the cells.
Refinement stops at cells of side ε/4. Cells between two parts whose diagonal is below
ε are tried at their corners too, before they are split: an allowed corner
then bounds the depth of every point of the cell below ε, and the narrow
allowed wedge of a pinch on x = 0 runs along cell edges, between centres.
The centres of split cells stay known allowed points. A centre (or a corner
tried) that is not allowed at its first orientation is proved excluded by the
depth certificate (at a depth of 1e-9 b) where it can be within a few
intervals of φ (:data:`~sesp.kernels.depth.FALLBACK_STEPS`), which costs a
fraction of the exact windows; the windows decide the rest, with the same
answer. (The first orientation also finds allowed points whose windows are
narrower than the windows' ANGLE_GAP, 1e-9 rad: the apex of a pinch's allowed
wedge.)

Closed curves (Ψ = 0) have no end points: the depth certificate lets their
sub-arcs pass the polyline's first vertex (:mod:`sesp.kernels.depth`).

Symmetry. A SeSP is symmetric about the x axis, and so is its polyline,
exactly: (t, φ) overlaps where (Mt, −φ) does (M: y → −y), so the depth and
the allowed set are symmetric too. For a pair of SeSPs each leaf below the
axis is decided as its mirror image above it (the centres are exact images;
orientations turn to −φ), which halves the certificates made. A Polyline is
not assumed symmetric.

Why a second length: beside a part, a sliver of E_ε parted from it by an
allowed finger needs only about 3ε across (ε, finger, ε, sliver, ε), so it
fits inside one cell and between the points at which certificates are made;
only cells about ε wide along the whole rim could rule it out. The cells
along every edge are about the rim wide, so the cost grows as the rim falls
(n = 2 at Ψ = 90°: 4.3 s at a rim of 1e-3 b, 40.9 s at 1e-4 b). A sliver
shallower than ε + rim is not counted, so the search of the rims to ``rim``
finds every component that is counted, and a sliver it may miss is left out
on every grid alike. (Before, every component of E_ε was counted and the
rims were searched to 100 ε: n = 10 at Ψ = 169.2° counted an axis strip
7.4e-4 b deep on some base grids and not on others.)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

from .kernels import cells as cell_kernels
from .kernels import depth as depth_kernels
from .kernels.common import small_chunks
from .kernels.orientations import chunk_boxes, chunk_count, clearance_at, radial_spans, windows_at
from .orientations import ANGLE_GAP, SCREEN_SLACK
from .pair import as_pair
from .progress import progress_bar
from .shape import DEFAULT_SEGMENTS

__all__ = ["RESOLUTION", "Certified", "CertifiedComponent", "certified_components"]

RESOLUTION = 1e-5  # b: the default ε, the erosion length of the count
RIM = 1e-3  # b: the default rim, at least (a component is counted from ε + rim deep; rims are searched to it)
BASE = 64  # cells along each side of the reach box before refinement
STEPS_PER_VERTEX = 4  # intervals of φ a depth certificate may use at first, per vertex of the longer polyline
MOST_STEPS = 4096  # ... and at most (or the first budget, if larger), after retries at four times as many
CANDIDATES = 4  # in-cells per component at which its depth is certified: the tallest (largest bound on the depth)
TURNS = (0.1, 0.03, 0.01, 0.003, 0.001)  # rad: steps of the search for a larger clearance (cost only)
SUBCELLS = 4  # a rim leaf is shown searched on this many squares per side, each inside one disk (cost only)
NEAREST = 6  # ... of the nearest certified and allowed disks of each square's leaf; and the allowed points that
# bound a leaf's depth from above (cost only)
TALLEST = 16  # leaves per candidate from which allowed points are sought at each refinement (cost only)
RAYS = 32  # ... along this many directions (cost only)
PROBES = 12  # ... each bisected this many times (cost only)
DEPTH_RATIO = 1.001  # a depth is proved to within this factor of the largest the certificate proves (cost only)
SEARCH_RATIO = 1.003  # ... and a search for a deeper point moves where it gains this factor (cost only)
PROOF_DEPTH = 1e-9  # b: the depth proved at a centre to show it excluded (any length > 0 would; far above rounding)
OUT, IN, UNDECIDED = 0, 1, 2  # a cell's status


def _tallest_per_group(values, groups, most):
    """Indices (ascending) of the ``most`` largest entries of ``values`` in each value of ``groups``, and of every
    entry equal to the smallest of those (a tie at the cut is kept, for the caller to break)."""
    by = np.lexsort((-values, groups))  # by group, largest first
    g, v = groups[by], values[by]
    start = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])
    size = np.diff(np.r_[start, len(g)])
    cut = np.repeat(v[start + np.minimum(size, most) - 1], size)
    return np.sort(by[v >= cut])


def _first_per_group(groups, most):
    """Indices (ascending) of the first ``most`` entries of each value in ``groups``."""
    by = np.argsort(groups, kind="stable")
    g = groups[by]
    start = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])  # where each group begins, in ``by``
    rank = np.arange(len(g)) - np.repeat(start, np.diff(np.r_[start, len(g)]))
    return np.sort(by[rank < most])


@dataclass
class _Leaves:
    level: np.ndarray
    i: np.ndarray
    j: np.ndarray
    x: np.ndarray
    y: np.ndarray
    h: np.ndarray  # half-diagonal, b
    allowed: np.ndarray  # the centre is allowed
    clearance: np.ndarray  # b: a translation this short keeps the centre's orientation allowed
    middle: np.ndarray  # radians: an allowed orientation at the centre where it is allowed, else one allowed nearby
    deep: np.ndarray  # certified: every point of the cell is at least ε deep
    steps: np.ndarray  # intervals of φ the depth certificate may use
    ran_out: np.ndarray  # the certificate used them all without an answer
    radius: np.ndarray  # b: the disk of this radius about the centre is at least ε deep (0 if not deep)
    bound: np.ndarray  # b: an upper bound on the depth anywhere in the cell, from the parent's centre

    def take(self, keep):
        return _Leaves(**{k: v[keep] for k, v in self.__dict__.items()})

    @staticmethod
    def joined(parts):
        return _Leaves(**{k: np.concatenate([getattr(p, k) for p in parts]) for k in parts[0].__dict__})


@dataclass(frozen=True)
class CertifiedComponent:
    """One component of in ∪ undecided cells.

    ``parts``: certified parts (seeds) it holds: 1 is one component of E_ε, 0
    one that may be empty, more an undecided split. ``depth``: a certified lower
    bound on its largest depth (inscribed radius, b). ``area``: b² of its
    in-cells (a lower bound on the area of E_ε there) and ``area_bound`` of
    all its cells (an upper bound). ``box``: (xmin, xmax, ymin, ymax), b."""

    parts: int
    depth: float
    area: float
    area_bound: float
    box: tuple
    departure: float = 0.0  # b: the polylines' departure from the smooth curves
    top: float = math.inf  # b: an upper bound on its largest depth
    bar: float = 0.0  # b: the depth from which a component is counted (resolution + rim)

    @property
    def counted(self) -> bool:
        """Certified at least ``bar`` deep: it holds a counted component."""
        return self.parts > 0 and self.depth >= self.bar

    @property
    def shallow(self) -> bool:
        """Certified shallower than ``bar`` everywhere: it holds no counted component."""
        return self.top < self.bar

    @property
    def decided(self) -> bool:
        return self.shallow or (self.parts == 1 and self.counted)

    def tag(self) -> str:
        """A few words for a legend: "" for one counted component, else what is undecided or why it is not
        counted; † where it is shallower than the polylines' departure from the curves."""
        if self.shallow:
            said = "not counted: shallow"
        elif self.decided:
            said = ""
        elif not self.parts:
            said = "undecided: no certified part"
        elif self.parts > 1:
            said = f"undecided: {self.parts} parts"
        else:
            said = "undecided: depth"
        return " ".join(w for w in (said, "†" if self.depth < self.departure else "") if w)

    def why(self) -> str:
        if self.shallow:
            said = f"not counted: at most {self.top:.3e} b deep, less than resolution + rim ({self.bar:.3e} b)"
        elif not self.parts:
            said = "no cell of it is certified deeper than the resolution: at most about the resolution deep, or none"
        elif self.parts > 1:
            said = f"{self.parts} certified parts whose joins were not decided down to the floor"
        elif not self.counted:
            said = (
                f"{self.depth:.3e} to {self.top:.3e} b deep: whether it reaches resolution + rim "
                f"({self.bar:.3e} b) was not decided down to the floor"
            )
        else:
            said = "one component"
        if self.depth < self.departure and not self.shallow:
            said += (
                f"; shallower than the polylines' departure from the curves ({self.departure:.1e} b): a feature of "
                "the polylines, not resolved for the smooth particle (more segments resolve it)"
            )
        return said


@dataclass
class Certified:
    """The count of excluded components at resolution ``resolution`` (b), as a bracket ``low`` ≤ count ≤ ``high``.

    ``rim`` (b): a component is counted where it reaches ``resolution +
    rim`` in depth (and rims are searched to ``rim``, so none that deep is
    missed); shallower ones are not counted (listed where a cell of them is
    certified at least ``resolution`` deep). ``floor`` (b): the smallest cell
    side. ``components``: one :class:`CertifiedComponent` per candidate
    listed, deepest first."""

    low: int
    high: int
    resolution: float
    rim: float
    floor: float
    components: list = field(default_factory=list)
    evaluations: int = 0
    seconds: float = 0.0
    cells: dict = field(default_factory=dict, repr=False)  # leaf arrays: x, y, side (b), status, component

    def to_dict(self) -> dict:
        """The result as plain numbers (lengths in b, areas in b²), for JSON."""
        return {
            "count": self.count, "count_low": self.low, "count_high": self.high,
            "resolution": self.resolution, "rim": self.rim, "floor": self.floor,
            "units": {"lengths": "b", "areas": "b^2"}, "cells": self.evaluations, "seconds": self.seconds,
            "components": [
                {"parts": c.parts, "depth": c.depth, "area": c.area, "area_bound": c.area_bound, "box": list(c.box),
                 "status": c.why()}
                for c in self.components
            ],
        }  # fmt: skip

    @property
    def count(self):
        """The count where the bracket is one number, else None."""
        return self.low if self.low == self.high else None

    @property
    def bracket(self) -> str:
        """The count as text: "2", or "1-2" where undecided."""
        return f"{self.low}" if self.count is not None else f"{self.low}-{self.high}"

    @property
    def headline(self) -> str:
        """The bracket with "(undecided)" where it is not one number: the head of a report or a map's title."""
        return self.bracket + (" (undecided)" if self.count is None else "")

    @property
    def searched(self) -> str:
        """What the count leaves out, in words (the rim beside ε)."""
        return (f"  (counted: components at least {self.resolution + self.rim:.2e} b deep (resolution + rim, rim "
                f"{self.rim:.1e} b); shallower ones are not counted; --rim or rim= lowers the rim)")  # fmt: skip

    def __str__(self):
        lines = [f"excluded components at resolution {self.resolution:.1e} b: {self.headline}", self.searched]
        for k, c in enumerate(self.components, 1):
            x0, x1, y0, y1 = c.box
            lines.append(
                f"  {k}: depth >= {c.depth:.3e} b, area {c.area:.4e} b^2 (<= {c.area_bound:.4e}), "
                f"x {x0:+.4f}..{x1:+.4f}, y {y0:+.4f}..{y1:+.4f} b: {c.why()}"
            )
        return "\n".join(lines)


def check_resolution(resolution, rim=None, base=BASE) -> None:
    """Raise ValueError unless ``resolution`` is a finite length > 0 (b), ``rim`` None or a finite length
    ≥ ``resolution`` (b), and ``base`` a whole number of cells in [4, 4096]."""
    if not (isinstance(resolution, int | float | np.floating) and resolution > 0 and math.isfinite(resolution)):
        raise ValueError(f"resolution must be a length > 0 (b), got {resolution!r}")
    if rim is not None and not (rim >= resolution and math.isfinite(rim)):
        raise ValueError(f"rim must be a length >= resolution ({resolution:g} b), got {rim!r}")
    if not (isinstance(base, int | np.integer) and 4 <= base <= 4096):
        raise ValueError(f"base must be a whole number of cells in [4, 4096], got {base!r}")


def certified_components(
    particle,
    other=None,
    *,
    resolution: float = RESOLUTION,
    rim: float | None = None,
    base: int = BASE,
    segments: int = DEFAULT_SEGMENTS,
    progress: bool = False,
) -> Certified:
    """The excluded components of a pair at resolution ``resolution`` (b), certified on both sides, exact in φ.

    ``particle``/``other`` as for :func:`sesp.scan` (a Pair is taken as is);
    ``segments`` per polyline; ``rim`` (b; default 1e-3 b, or ``resolution``
    or the polylines' departure from the curves where either is larger): a
    component is counted where it is at least ``resolution + rim`` deep (a
    lower rim counts shallower components and costs more); ``base``:
    cells along each side at first. See the module text for the definition.

    Examples
    --------
    >>> import math
    >>> from sesp import SeSP
    >>> found = certified_components(SeSP(n=2, opening=math.radians(200)), resolution=1e-3)
    >>> found.count
    0
    """
    check_resolution(resolution, rim, base)
    pair = as_pair(particle, other, segments=segments)
    rim = max(resolution, RIM, pair.departure) if rim is None else rim
    return _Engine(pair, resolution, rim, int(base)).run(progress)


class _Engine:
    def __init__(self, pair, resolution, rim, base):
        self.pair, self.eps, self.base = pair, resolution, base
        self.floor = resolution / 4
        self.half = pair.reach
        # a part is a seed of its own where its certified disk reaches the rim length: every part holding a base
        # cell must be one, so the rim is at most half a base cell's half-diagonal
        self.rim = max(resolution, min(rim, self.half * math.sqrt(2.0) / base / 2))
        self.bar = resolution + self.rim  # b: a component is counted where it is at least this deep
        v1, v2 = pair.vertices1, pair.vertices2
        self.spans2 = radial_spans(v2)
        self.boxes1 = chunk_boxes(v1, np.empty((chunk_count(v1), 4)))
        self.curves = depth_kernels.prepared(v1, v2)
        # a walk around φ needs an interval each time a vertex passes a crossing: a closed N-gon at a shallow
        # overlap takes N to 3N (fewer at first would only be retried)
        self.steps = STEPS_PER_VERTEX * max(len(v1), len(v2))
        self.most_steps = max(MOST_STEPS, self.steps)
        self.evaluations = 0
        self.mirror = pair.mirror_symmetric  # each leaf below the x axis is decided as its mirror image
        self.depth_cache = {}
        self.best = {}  # component root -> the leaf where its depth was proved largest
        # b: allowed points that are no leaf's centre (x, y, clearance): the centres of split leaves, and allowed
        # corners of floor cells between parts (clearance 0)
        self.points = np.empty((0, 3))
        self.probed = set()  # corners tried, as whole multiples of the smallest cell side
        self.sought = set()  # leaves (level, i, j) from which allowed points were sought
        # refinement levels to the floor: no leaf is finer, cells of the last level are no wider than the floor
        self.levels = max(1, math.ceil(math.log2(2 * self.half / base / self.floor)))

    def evaluate(self, level, i, j, bound, steps=None, hint=None):
        """Leaves (level, i, j): whether each centre is allowed (and how far that lasts), or certified deep.

        ``hint``: an orientation to try first at each centre (NaN for none): where it leaves the curves apart,
        the centre is allowed and the exact windows are not needed. For a mirror-symmetric pair a leaf below
        the x axis whose mirror image is among the leaves is decided as that image is (:meth:`_mirrored`)."""
        n = len(i)
        steps = np.full(n, self.steps) if steps is None else steps
        hint = np.full(n, np.nan) if hint is None else hint
        self.evaluations += n
        if not self.mirror:
            return self._decided(level, i, j, bound, steps, hint)
        return self._mirrored(level, i, j, bound, steps, hint)

    def _mirrored(self, level, i, j, bound, steps, hint):
        """:meth:`evaluate` for a pair symmetric about the x axis: (t, φ) overlaps where (Mt, −φ) does, M the
        mirror y → −y, so the depth and the allowed set are symmetric and a leaf's mirror image is decided as it
        is, its orientations turned to −φ. The centres are exact mirror images (:meth:`centres`), and so are the
        polylines (:attr:`sesp.Pair.mirror_symmetric`). Each pair of images is decided once, above the axis."""
        flip = self.base * (1 << level) - 1 - j  # the row of the mirror image
        below = j < flip
        key = np.column_stack([level, i, np.where(below, flip, j)])
        _, first, back = np.unique(key, axis=0, return_index=True, return_inverse=True)
        back = back.ravel()
        once = self._decided(
            level[first], i[first], key[first, 2], bound[first], steps[first], np.where(below, -hint, hint)[first]
        )
        L = once.take(back)
        L.j, L.bound = j, bound
        L.y = np.where(below, -L.y, L.y)
        L.middle = np.where(below, -L.middle, L.middle)
        return L

    def centres(self, level, i, j):
        """The centres (b) of leaves (level, i, j) and their half-diagonals (b): exact mirror images of each
        other about both axes (a whole number times half a cell side)."""
        cells = self.base * np.exp2(level)
        step = self.half / cells  # half a cell side
        return (2 * i + 1 - cells) * step, (2 * j + 1 - cells) * step, step * math.sqrt(2.0)

    def _decided(self, level, i, j, bound, steps, hint):
        """:meth:`evaluate` of every leaf."""
        x, y, h = self.centres(level, i, j)
        n = len(x)
        clearance = np.zeros(n)
        middle = np.where(np.isnan(hint), 0.0, hint)
        tried = np.nonzero(~np.isnan(hint))[0]
        if len(tried):
            clearance[tried], middle[tried] = self._widest(x[tried], y[tried], hint[tried], h[tried])
        allowed = clearance > 0
        deep, ran_out, radius, excluded = np.zeros(n, bool), np.zeros(n, bool), np.zeros(n), np.zeros(n, bool)
        met = np.nonzero(~allowed)[0]  # where the hint failed (or there was none): certify depth first, from the hint
        deep[met], radius[met], ran_out[met], excluded[met] = self._deep(
            x[met], y[met], h[met], steps[met], middle[met]
        )
        rest = np.nonzero(~allowed & ~excluded)[0]  # neither allowed nor proved excluded: the exact windows decide
        if len(rest):
            ok, mid = self._windows(x[rest], y[rest])
            sel = rest[ok]
            allowed[sel], middle[sel] = True, mid[ok]
            clearance[sel] = np.maximum(self._clearance(x[sel], y[sel], mid[ok], h[sel]), 0.0)
        clearance = np.where(allowed, clearance, 0.0)
        return _Leaves(level, i, j, x, y, h, allowed, clearance, middle, deep, steps, ran_out, radius, bound)

    def _clearance(self, x, y, phi, h):
        """b: how far each centre may move with curve 2 turned by ``phi`` before the pair meets (≤ 0: it meets)."""
        got = np.empty(len(x))
        p = self.pair
        with small_chunks():
            clearance_at(p.vertices1, self.boxes1, p.vertices2, x, y, phi, 2 * h + p.contact, got)
        return got - p.contact

    def _widest(self, x, y, phi, h):
        """The clearance (b) at each centre, raised by a pattern search over φ from ``phi`` where it is positive
        (steps of TURNS, each tried on both sides, kept where the clearance grows), and the orientation reached
        (radians). A larger clearance bounds the depth near the centre more tightly: fewer cells are split."""
        clearance, phi = self._clearance(x, y, phi, h), phi.copy()
        for turn in TURNS:
            for side in (turn, -turn):
                k = np.nonzero((clearance > 0) & (clearance < 2 * h))[0]  # 2h: as far as a clearance is measured
                if not len(k):
                    return clearance, phi
                got = self._clearance(x[k], y[k], phi[k] + side, h[k])
                better = got > clearance[k]
                clearance[k[better]], phi[k[better]] = got[better], phi[k[better]] + side
        return clearance, phi

    def _windows(self, x, y):
        """Whether each position is allowed, exactly in φ, and the middle of its widest window (radians)."""
        p, n = self.pair, len(x)
        width, mid, clear = np.empty(n), np.empty(n), np.empty(n)
        with small_chunks():
            windows_at(
                p.vertices1, p.vertices2, self.spans2, self.boxes1, x, y, SCREEN_SLACK, ANGLE_GAP, p.contact,
                np.zeros(n), width, mid, clear,
            )  # fmt: skip
        return width > 0, mid

    def _deep(self, x, y, h, steps, start):
        """Cells certified at least ε deep throughout, the radius about their centres so certified (wider than
        the cell where it is under ``rim``), where the certificate ran out of intervals, and the centres proved
        excluded (at least ``PROOF_DEPTH`` deep where not deep: no allowed window to look for there). The walks
        around φ begin at ``start`` (radians): an orientation allowed nearby, where a walk that fails fails first.
        Two end points (:func:`~sesp.kernels.depth.two_tips`) are tried at ε + h, not for the wider disks: near
        the depth they can show they step in ever shorter turns, and the wider disks only save cells (cost). The
        depths that decide whether a candidate is counted try them too (:meth:`_proved_depth`)."""
        if not len(x):
            return np.zeros(0, bool), np.zeros(0), np.zeros(0, bool), np.zeros(0, bool)
        got = self._cover(x, y, self.eps + h, steps, PROOF_DEPTH, start, tips=True)
        deep, ran_out = got == 1, got == -1
        radius = np.where(deep, h, 0.0)
        thin = np.nonzero(deep & (h < self.rim))[0]
        if len(thin):
            wider = np.maximum(3 * h[thin], self.rim)
            ok = self._cover(x[thin], y[thin], self.eps + wider, steps[thin], start=start[thin]) == 1
            radius[thin[ok]] = wider[ok]
            # a disk of the rim's radius makes a part a seed of its own: try it where the wider disk failed
            short = thin[~ok & (wider > self.rim)]
            if len(short):
                r = np.full(len(short), self.eps + self.rim)
                ok = self._cover(x[short], y[short], r, steps[short], start=start[short]) == 1
                radius[short[ok]] = self.rim
        return deep, radius, ran_out, got > 0

    def _cover(self, x, y, r, steps, fallback=0.0, start=0.0, tips=False, stops=None):
        r = np.maximum(r - self.pair.contact, 1e-300)
        return depth_kernels.certified_deep(self.curves, x, y, r, steps, fallback, start, tips, stops=stops)

    def classify(self, L):
        """IN, OUT or UNDECIDED per leaf, with an upper bound on the depth anywhere in it (b)."""
        ea, eb = cell_kernels.leaf_edges(L.level, L.i, L.j, self.base)
        hi = np.where(L.allowed, np.maximum(0.0, L.h - L.clearance), L.bound)
        via = L.allowed[eb]
        a, b = ea[via], eb[via]
        reach = np.hypot(L.x[a] - L.x[b], L.y[a] - L.y[b]) + L.h[a] - L.clearance[b]
        np.minimum.at(hi, a, np.maximum(0.0, reach))
        far = ~L.allowed & (hi >= self.eps)  # in-cells too: a candidate's largest bound decides it shallow
        allowed = self._allowed_points(L)
        if far.any() and len(allowed):  # the nearest allowed point anywhere bounds the depth too
            near = min(NEAREST, len(allowed))
            gap, k = cKDTree(allowed[:, :2]).query(np.column_stack([L.x[far], L.y[far]]), k=near, workers=-1)
            reach = gap.reshape(-1, near) - allowed[k.reshape(-1, near), 2]
            hi[far] = np.minimum(hi[far], np.maximum(0.0, reach.min(axis=1) + L.h[far]))
        if self.mirror:  # the depth is symmetric: each bound holds at the mirror image too (and ties stay alike)
            hi = np.minimum(hi, hi[self._images(L)])
        status = np.full(len(L.x), UNDECIDED)
        status[L.deep] = IN
        status[(status == UNDECIDED) & (hi < self.eps)] = OUT
        return status, hi, ea, eb

    def _images(self, L):
        """Per leaf: the index of its mirror image about the x axis (itself where that is no leaf)."""

        def key(j):
            return (L.level << 50) | (L.i << 25) | j

        keys = key(L.j)
        order = np.argsort(keys)
        flipped = key(self.base * (1 << L.level) - 1 - L.j)
        at = np.minimum(np.searchsorted(keys, flipped, sorter=order), len(keys) - 1)
        image = order[at]
        return np.where(keys[image] == flipped, image, np.arange(len(keys)))

    def run(self, progress=False):
        start = time.perf_counter()
        b = self.base
        i, j = np.meshgrid(np.arange(b, dtype=np.int64), np.arange(b, dtype=np.int64), indexing="ij")
        L = self.evaluate(np.zeros(b * b, np.int64), i.ravel(), j.ravel(), np.full(b * b, np.inf))
        with progress_bar(self.levels, progress, "certified components", unit="level") as bar:
            deepest = 0
            while True:
                status, hi, ea, eb = self.classify(L)
                split, retry, between, seed, U = self._to_refine(L, status, hi, ea, eb)
                if self._probe_corners(L, between & (2 * L.h < self.eps)):
                    continue  # classified again, with the allowed corners found, before any is split
                if not split.any() and not retry.any():
                    break
                L = self._split(self._retry(L, retry), split)
                if (now := int(L.level.max())) > deepest:
                    bar.update(now - deepest)
                    deepest = now
        found = self._result(L, status, hi, U, seed)
        found.seconds = time.perf_counter() - start
        return found

    def _to_refine(self, L, status, hi, ea, eb):
        """The leaves to split and those to certify again with more intervals, the undecided leaves between two
        certified parts, the seed (certified part) of each in-leaf that may be counted and the candidate
        component (root) of each leaf not out. Allowed points are sought near the tallest leaves of candidates
        neither counted nor shallow (:meth:`_seek_allowed`), for the next classification."""
        und, inn = status == UNDECIDED, status == IN
        U = cell_kernels.components(status != OUT, ea, eb)
        near = cell_kernels.adjacency(len(L.x), ea, eb)
        parts = cell_kernels.disk_components(inn, L.x, L.y, L.radius, L.h, *near)
        has_part = np.zeros(len(L.x), bool)
        has_part[U[inn]] = True
        seed = np.where(inn, parts, -1)
        # parts that may each be a counted component of their own: two in one candidate are refined between
        seed = np.where(self._capable(seed, und, hi, ea, eb)[np.maximum(seed, 0)], seed, -1)
        between = und & cell_kernels.corridors(seed, und | inn, *near, 2)
        root = np.maximum(U, 0)
        empty = und & ~has_part[root]
        depth, top = self._depths(L, status, hi, U), self._tops(hi, U)
        shallow = (U >= 0) & (top[root] < self.bar)  # in a candidate proved shallower than ε + rim: not counted
        for r in np.unique(U[(U >= 0) & ~shallow & (depth[root] < self.bar)]):
            if r in self.best:  # not proved that deep at the leaves tried: search for a deeper point from the best
                depth[r] = self._deepest_cached(L, self.best[r], depth[r], top[r])
        # a leaf that may be that deep, split where its children's bounds may fall below ε + rim: the bound at
        # a child's centre is at least the parent's less h (the depth is 1-Lipschitz)
        tall = (U >= 0) & ~shallow & (depth[root] < self.bar) & (hi >= self.bar)
        unsure = tall & (hi - 2 * L.h < self.bar)
        self._seek_allowed(L, hi, U, tall)
        on_rim = und & ~shallow & (hi >= self.bar)
        searched = np.zeros(len(L.x), bool)
        searched[on_rim] = self._searched(L, inn, on_rim, np.full(int(on_rim.sum()), self.rim))
        if self.mirror:  # a leaf shown searched shows its mirror image searched too (nearest disks may tie)
            searched |= searched[self._images(L)]
        on_rim &= ~searched
        above_floor = L.h * math.sqrt(2.0) > self.floor
        split = ((between | empty) & ~shallow | on_rim | unsure) & above_floor
        retry = und & L.ran_out & (L.steps < self.most_steps)
        return split & ~retry, retry, between, seed, U

    def _seek_allowed(self, L, hi, U, tall):
        """Allowed points near the ``tall`` leaves (in candidates neither counted nor shallow, their bounds
        reaching ε + rim), for the bounds of the next classification: from the TALLEST such leaves of each
        candidate not tried before, along RAYS directions, the allowed point nearest the leaf's centre that a
        bisection of PROBES halvings meets, on rays as long as twice the bound at the centre that end in an
        allowed point. A split leaf's children are excluded centres, so splitting alone does not bring the
        allowed points nearer, and a bound may stay far above the depth (benchmarks/README.md)."""
        if self.mirror:  # the images below the axis come as mirror images of the points found above it
            tall = tall & (L.y >= 0)
        k = np.nonzero(tall & ~L.allowed)[0]
        k = k[[(L.level[a], L.i[a], L.j[a]) not in self.sought for a in k]] if len(k) else k
        if not len(k):
            return
        k = k[np.lexsort((-hi[k], U[k]))]  # by candidate, tallest first
        k = k[_first_per_group(U[k], TALLEST)]
        self.sought.update(zip(L.level[k], L.i[k], L.j[k]))
        turns = np.linspace(0.0, 2.0 * math.pi, RAYS, endpoint=False)
        x0, y0 = np.repeat(L.x[k], RAYS), np.repeat(L.y[k], RAYS)
        reach = np.repeat(2.0 * np.maximum(hi[k] - L.h[k], L.h[k]), RAYS)
        dx, dy = reach * np.tile(np.cos(turns), len(k)), reach * np.tile(np.sin(turns), len(k))
        ends, hint = self._allowed(x0 + dx, y0 + dy, self._nearest_middle(L, x0 + dx, y0 + dy))
        x0, y0, dx, dy, hint = x0[ends], y0[ends], dx[ends], dy[ends], hint[ends]
        lo, up = np.zeros(len(x0)), np.ones(len(x0))  # not allowed at lo (the leaf's centre), allowed at up
        for _ in range(PROBES):  # each probe tries first the orientation allowed at the ray's last allowed point
            t = (lo + up) / 2
            ok, phi = self._allowed(x0 + t * dx, y0 + t * dy, hint)
            lo, up, hint = np.where(ok, lo, t), np.where(ok, t, up), np.where(ok, phi, hint)
        found = np.column_stack([x0 + up * dx, y0 + up * dy])
        if self.mirror:
            found = np.concatenate([found, found * np.array([1.0, -1.0])])
        self.points = np.concatenate([self.points, np.column_stack([found, np.zeros(len(found))])])

    def _capable(self, seed, und, hi, ea, eb):
        """Per seed (a leaf index): whether its part may be a counted component of its own. Such a component
        holds a point at least ``bar`` deep, so a leaf whose bound ``hi`` reaches ``bar`` (tall), joined to the
        part within E_ε and without passing another part (that part would be in the same component): the tall
        leaf is the part's own, or lies in a run of undecided leaves that touches the part."""
        tall = hi >= self.bar
        run = cell_kernels.components(und, ea, eb)  # per undecided leaf: its run of undecided leaves
        tall_run = np.zeros(len(hi), bool)
        tall_run[run[und & tall]] = True
        capable = np.zeros(len(hi), bool)
        capable[seed[(seed >= 0) & tall]] = True
        touch = (seed[ea] >= 0) & und[eb]
        capable[seed[ea[touch]][tall_run[run[eb[touch]]]]] = True
        return capable

    def _probe_corners(self, L, left):
        """Whether allowed corners were found for the ``left`` leaves: undecided, between two parts, and with a
        diagonal below ε. A narrow allowed wedge (the pinch of lens and body at small Ψ lies on x = 0, a line of
        cell edges) passes between cell centres; the corners of a cell are its points too, and an allowed one
        bounds the depth of every point of the cell below ε (and of every cell near it)."""
        if not left.any():
            return False
        finest = self.levels
        scale = np.exp2(finest - L.level[left])  # corners in units of the finest cell side
        i0, j0 = L.i[left] * scale, L.j[left] * scale
        cells = self.base * 2**finest
        keys = {(a + da * s, b + db * s) for a, b, s in zip(i0, j0, scale) for da in (0, 1) for db in (0, 1)}
        if self.mirror:  # a corner below the axis is decided as its mirror image (:meth:`_mirrored`)
            keys = {(a, max(b, cells - b)) for a, b in keys}
        keys = sorted(k for k in keys if k not in self.probed)
        if not keys:
            return False
        self.probed.update(keys)
        corners = (2 * np.array(keys, dtype=float) - cells) * (self.half / cells)  # exact mirror images, as centres
        x, y = corners[:, 0].copy(), corners[:, 1].copy()
        ok, _ = self._allowed(x, y, self._nearest_middle(L, x, y))
        found = corners[ok]
        if self.mirror:
            images = found[found[:, 1] > 0] * np.array([1.0, -1.0])
            self.probed.update((a, cells - b) for a, b in keys)
            found = np.concatenate([found, images])
        self.points = np.concatenate([self.points, np.column_stack([found, np.zeros(len(found))])])
        return bool(ok.any())

    def _allowed(self, x, y, hint):
        """Whether each position is allowed, as a centre is decided: allowed where the curves keep apart at
        ``hint`` (radians; NaN for none), excluded where the depth certificate proves it (at ``PROOF_DEPTH``,
        within FALLBACK_STEPS intervals from the hint), the exact windows deciding the rest. Every position the
        windows allow is allowed; a hint also finds the apex of a pinch's allowed wedge, where the curves keep
        apart by about 1e-11 b in windows narrower than ANGLE_GAP (1e-9 rad), which the windows close. The first
        two cost a fraction of the windows (at the pinch of n = 10 at Ψ = 1.2°, 7 of 16,663 corners were left
        to them). Also an allowed orientation (radians) at each allowed position, NaN elsewhere."""
        ok, rest, phi = np.zeros(len(x), bool), np.ones(len(x), bool), hint.copy()
        tried = np.nonzero(~np.isnan(hint))[0]
        if len(tried):
            ok[tried] = self._clearance(x[tried], y[tried], hint[tried], np.full(len(tried), self.floor)) > 0
            rest[tried[ok[tried]]] = False
        k = np.nonzero(rest)[0]
        if len(k):
            start = np.where(np.isnan(hint[k]), 0.0, hint[k])
            proved = self._cover(x[k], y[k], PROOF_DEPTH, depth_kernels.FALLBACK_STEPS, start=start) == 1
            k = k[~proved]
        if len(k):
            ok[k], phi[k] = self._windows(x[k], y[k])
        return ok, np.where(ok, phi, np.nan)

    def _allowed_points(self, L):
        """(k, 3): x, y (b) and clearance (b) of every allowed point known: leaf centres and ``points``."""
        a = L.allowed
        return np.concatenate([np.column_stack([L.x[a], L.y[a], L.clearance[a]]), self.points])

    def _searched(self, L, inn, which, rim):
        """Per ``which`` leaf: whether no component deeper than ε + ``rim`` (b; per leaf) can hide in it apart
        from the certified parts. That holds where each of its points q lies within ``rim`` of a certified disk
        (an in-leaf's) or within ε + ``rim`` of an allowed disk (an allowed point's clearance):

        * a point q with p(q) ≥ ε + d, d its distance to a certified disk, joins that disk's part: the disk
          of radius p(q) − ε about q lies in E_ε (the depth is 1-Lipschitz) and reaches the certified disk;
        * within ε + rim of an allowed disk, p(q) < ε + rim.

        So the deepest point of a hidden component deeper than ε + rim is in neither. Shown on SUBCELLS ×
        SUBCELLS squares per leaf, each inside one disk of the NEAREST of each kind (fewer shown: more split)."""
        k = SUBCELLS
        offsets = ((np.arange(k) + 0.5) / k * 2.0 - 1.0) / math.sqrt(2.0)  # square centres, in half-diagonals
        x, y, h = L.x[which], L.y[which], L.h[which]
        allowed = self._allowed_points(L)
        disks = []  # per leaf: the centres and radii (b) of its NEAREST disks of each kind
        for cx, cy, cr, extra in ((L.x[inn], L.y[inn], L.radius[inn], rim), (*allowed.T, self.eps + rim)):
            near = min(NEAREST, len(cx))
            if near:
                _, idx = cKDTree(np.column_stack([cx, cy])).query(np.column_stack([x, y]), k=near, workers=-1)
                idx = idx.reshape(len(x), near)
                disks.append((cx[idx], cy[idx], cr[idx] + extra[:, None]))
        if not disks:
            return np.zeros(len(x), bool)
        cx, cy, reach = (np.ascontiguousarray(np.concatenate(d, axis=1)) for d in zip(*disks))
        return cell_kernels.squares_in_disks(x, y, h, offsets, cx, cy, reach)

    def _depths(self, L, status, hi, U):
        """Per component root: a certified lower bound on its depth (b), by bisection at its CANDIDATES tallest
        in-cells (below each cell's bound ``hi``; among equal bounds, those farthest from every other leaf). A
        point deeper than d lies in a cell whose bound reaches d: a long ridge is searched where it may be deepest
        (n = 4's island at 171.6°), not where it is widest."""
        depth = np.zeros(len(L.x))
        inn = np.nonzero(status == IN)[0]
        if not len(inn):
            return depth
        inn = inn[_tallest_per_group(hi[inn], U[inn], CANDIDATES)]  # ties at the cut too: broken by ``far``
        rest = np.nonzero(status != IN)[0]
        if len(rest):
            far, _ = cKDTree(np.column_stack([L.x[rest], L.y[rest]])).query(
                np.column_stack([L.x[inn], L.y[inn]]), workers=-1
            )
        else:
            far = L.h[inn]
        order = inn[np.lexsort((far, hi[inn]))[::-1]]
        self.best = {}
        for k in order[_first_per_group(U[order], CANDIDATES)]:
            got = self._depth_at(L, k, hi[k])
            if got > depth[U[k]]:
                depth[U[k]], self.best[U[k]] = got, k
        return depth

    @staticmethod
    def _tops(hi, U):
        """Per component root: an upper bound on its depth (b), the largest bound on any of its leaves."""
        top = np.zeros(len(hi))
        member = U >= 0
        np.maximum.at(top, U[member], hi[member])
        return top

    def _depth_at(self, L, k, bound):
        """b: the largest depth the certificate proves at leaf k's centre, within a factor DEPTH_RATIO; ``bound``
        (b): an upper bound on the depth there."""
        key = (L.level[k], L.i[k], L.j[k])
        if key not in self.depth_cache:
            self.depth_cache[key] = self._proved_depth(L.x[k], L.y[k], self.eps + L.radius[k], bound, L.middle[k])[0]
        return self.depth_cache[key]

    def _proved_depth(self, x, y, lo, bound, start):
        """(depth, φ): the largest depth (b, ≥ ``lo``, known proved) the certificate proves at (x, y), within a
        factor DEPTH_RATIO, by geometric bisection up to ``bound`` (b, an upper bound on the depth there), and
        the orientation (radians) at which the last walk that failed failed (else ``start``). Each walk begins
        at the orientation where the last one failed: one that fails again fails there, at once."""
        hi = min(bound, 2.0 * self.half) * DEPTH_RATIO  # a little above the bound: a depth at the bound is found
        stop = np.zeros(1)
        while hi > lo * DEPTH_RATIO:
            mid = math.sqrt(lo * hi)
            ok = self._cover(np.array([x]), np.array([y]), np.array([mid]), np.array([self.most_steps]), 0.0, start,
                             True, stop)[0]  # fmt: skip
            if ok == 1:
                lo = mid
            else:
                hi, start = mid, float(stop[0])
        return lo, start

    def _deepest_cached(self, L, k, depth, top):
        """:meth:`_deepest` from leaf k, once per leaf."""
        key = ("deepest", L.level[k], L.i[k], L.j[k])
        if key not in self.depth_cache:
            self.depth_cache[key] = self._deepest(L, k, depth, top)
        return self.depth_cache[key]

    def _deepest(self, L, k, depth, top):
        """b: the depth proved at leaf k's centre, raised by a pattern search from it (16 directions, steps from
        half that depth, halved ten times, at most 8 moves each): the inscribed radius of the component, from
        below. ``top`` (b): an upper bound on the depth anywhere in the component (a point proved deeper than
        the step lies in the same component). The walks begin where the last one failed (:meth:`_proved_depth`)."""
        x, y, step, start = L.x[k], L.y[k], depth / 2, L.middle[k]
        turns = np.linspace(0.0, 2.0 * math.pi, 16, endpoint=False)
        stops = np.zeros(16)
        for _ in range(10):
            for _ in range(8):
                if depth * DEPTH_RATIO >= top:
                    return depth
                xs, ys = x + step * np.cos(turns), y + step * np.sin(turns)
                r = np.full(16, depth * SEARCH_RATIO)
                deeper = self._cover(xs, ys, r, np.full(16, self.most_steps), 0.0, start, True, stops) == 1
                if not deeper.any():
                    start = float(stops[0])
                    break
                x, y = xs[np.argmax(deeper)], ys[np.argmax(deeper)]
                depth, start = self._proved_depth(x, y, depth * SEARCH_RATIO, top, start)
            step /= 2
        return depth

    def _hints(self, L, parent):
        """An orientation to try first in each child of ``parent``: the parent's allowed one, or that of the
        nearest leaf whose centre is allowed (windows move continuously with the position)."""
        hint = np.where(parent.allowed, parent.middle, np.nan)
        lost = np.nonzero(~parent.allowed)[0]
        hint[lost] = self._nearest_middle(L, parent.x[lost], parent.y[lost])
        return hint

    @staticmethod
    def _nearest_middle(L, x, y):
        """The allowed orientation (radians) of the leaf nearest each point (x, y) whose centre is allowed; NaN
        where no leaf's is."""
        donors = np.nonzero(L.allowed)[0]
        if not len(x) or not len(donors):
            return np.full(len(x), np.nan)
        _, nearest = cKDTree(np.column_stack([L.x[donors], L.y[donors]])).query(np.column_stack([x, y]), workers=-1)
        return L.middle[donors[nearest]]

    def _retry(self, L, retry):
        """Cells whose certificate ran out of intervals, certified again with four times as many."""
        idx = np.nonzero(retry)[0]
        if len(idx):
            L.steps[idx] *= 4
            got = self._deep(L.x[idx], L.y[idx], L.h[idx], L.steps[idx], L.middle[idx])
            L.deep[idx], L.radius[idx], L.ran_out[idx], _ = got
        return L

    def _split(self, L, split):
        parent, rest = L.take(split), L.take(~split)
        a = parent.allowed
        self.points = np.concatenate([self.points, np.column_stack([parent.x[a], parent.y[a], parent.clearance[a]])])
        m = len(parent.x)
        level = np.repeat(parent.level + 1, 4)
        i = np.repeat(parent.i * 2, 4) + np.tile(np.array([0, 1, 0, 1]), m)
        j = np.repeat(parent.j * 2, 4) + np.tile(np.array([0, 0, 1, 1]), m)
        # the parent's centre is a corner of each child: its clearance bounds the child's depth
        child_h = np.repeat(parent.h / 2, 4)
        was_allowed = np.repeat(parent.allowed, 4)
        bound = np.where(was_allowed, np.maximum(0.0, 2 * child_h - np.repeat(parent.clearance, 4)), np.inf)
        steps = np.repeat(parent.steps, 4)
        hint = np.repeat(self._hints(L, parent), 4)
        children = [rest]
        for lv in np.unique(level):
            sel = level == lv
            children.append(self.evaluate(level[sel], i[sel], j[sel], bound[sel], steps[sel], hint[sel]))
        return _Leaves.joined(children)

    def _result(self, L, status, hi, U, seed):
        area = (L.h * math.sqrt(2.0)) ** 2
        depth, top = self._depths(L, status, hi, U), self._tops(hi, U)
        for root, k in self.best.items():
            depth[root] = self._deepest_cached(L, k, depth[root], top[root])
        member = np.nonzero(U >= 0)[0]
        member = member[np.argsort(U[member], kind="stable")]  # the leaves of each candidate, one run per root
        roots, first = np.unique(U[member], return_index=True)
        departure = self.pair.departure  # b; measured on the dense arc table: once, not per component
        found = []
        kept = []
        for r, m in zip(roots, np.split(member, first[1:])):
            parts = len(np.unique(seed[m][seed[m] >= 0]))
            inn = m[status[m] == IN]
            if top[r] < self.bar and not len(inn):
                continue  # shallow, and no cell of it certified in E_ε: nothing to list
            kept.append(r)
            box = (float(L.x[m].min()), float(L.x[m].max()), float(L.y[m].min()), float(L.y[m].max()))
            found.append(CertifiedComponent(
                parts, float(depth[r]), float(area[inn].sum()), float(area[m].sum()), box, departure,
                float(top[r]), self.bar,
            ))  # fmt: skip
        order = np.argsort([-c.depth for c in found], kind="stable")
        rank = np.full(len(L.x), -1)
        rank[np.array(kept, dtype=np.int64)[order]] = np.arange(len(kept))
        cells = {
            "x": L.x, "y": L.y, "side": L.h * math.sqrt(2.0), "status": status,
            "component": np.where(U >= 0, rank[np.maximum(U, 0)], -1),
        }  # fmt: skip
        found = [found[k] for k in order]
        low = sum(1 for c in found if c.counted)
        high = sum(max(c.parts, 1) for c in found if not c.shallow)
        floor = 2.0 * self.half / (self.base * 2.0 ** int(L.level.max()))
        return Certified(low, high, self.eps, self.rim, floor, found, self.evaluations, cells=cells)
