"""Depth kernels: a lower bound on how deep a position lies in the excluded set, exact in φ.

The depth p(t) is the distance from t to the nearest allowed position. A
position is at least r deep when, at every orientation φ, the curves meet so
robustly that no translation shorter than r parts them. :func:`cover` proves
that without sampling φ: it walks around the circle of orientations, and at
the first φ not yet certified takes the pair of runs that crosses oddly with
its ends at least r from the other run (:mod:`sesp.kernels.runs`) and holds
over the longest interval of φ, and continues from that interval's end. The
position is certified r deep when the intervals close around the circle.

* A run may end anywhere on the curve, not only at a vertex: where a lens
  between the curves spans about one segment (a rounded corner across a flat
  side) every vertex near it lies close to a crossing, so the runs are also
  tried on the polylines with each segment cut at its middle (the same curves).
* Where the curves run close about a crossing (a shallow lens) a pair short
  on both sides keeps apart only while a vertex of each lies in the lens; the
  same pair with one run lengthened to its whole curve holds until the turning
  curve sweeps over an end of the short run (:func:`_longest`).
* Where no pair keeps apart, two end points of the open curves may
  (:mod:`sesp.kernels.tips`); a walk asked to (``options.tips`` 2) tries
  them at every step and keeps the longer interval.
* Thick particles overlap where their curves come within the contact
  distance, crossed or not: they are near enough at φ while their distance
  stays within the margin (:func:`_near_interval`).
* A closed curve has no end points: it is stored twice over, and its runs may
  pass the polyline's first vertex.

The bound is one-sided: a position whose certificate fails may still be that
deep (for instance where the curves nearly coincide and cross many times
within a short run).
"""

import math
from collections import namedtuple

import numpy as np
from numba import njit, prange

from .common import JIT, chunk_boxes, chunk_count, small_chunks
from .orientations import TWO_PI, blocked_angles, nearest_segments, placed, radial_spans
from .runs import (
    Curves,
    Moved,
    Walk,
    certified_interval,
    ends_clearance,
    inside_parity,
    run_about,
    runs_at,
    segment_radii,
)
from .tips import two_tips

# How a walk works, none of it part of what it proves (:class:`sesp.certified.Settings` documents each):
# max_crossings, long_crossings, fallback_steps (counts), least_tip_step (a fraction of the depth), tips (0:
# two end points never tried, 1: where no pair of runs is r apart, 2: at every step, the longer kept) and
# lengthen (whether a pair r apart is also lengthened)
Options = namedtuple("Options", "max_crossings long_crossings fallback_steps least_tip_step tips lengthen")
OPTIONS = Options(1024, 16, 64, 1e-6, 1, True)
# b: the least depth at which the curves are walked crossed. Below it the two roots of an end point's passage
# through a segment, r apart, merge in floating point (coordinates are of order 1 b), the passage is missed and
# the walk would prove too much; a larger depth proves less, so raising a smaller one to it stays sound.
LEAST_DEPTH = 1e-9


@njit(**JIT)
def _longest(walk, moved, got, phi, first, lengthen=1):
    """(ahead, behind, found, longer): the longest interval of φ about ``phi`` (behind only where ``first``)
    certified by the widest pair of ``got`` (:func:`~sesp.kernels.runs.runs_at`, curve 2 and its crossings in
    ``moved``) where its ends are ``walk.r`` apart, or by that pair with one run lengthened to the whole of its
    curve (a closed curve's longest run), where they cross oddly with their ends r apart; ``found`` False where
    none is. Tried (``lengthen`` 1) where the curves cross at most ``long_crossings`` times and the widest pair
    is not r apart, or, for a closed curve 2, gives an interval shorter than a vertex takes to pass (2π / its
    segments); ``lengthen`` 2 tries it also where the widest pair of open curves is r apart, 0 never.
    ``longer``: the lengthened pair gave the interval."""
    curves, r = walk.curves, walk.r
    count, i0, i1, j0, j1, margin = got
    behind0 = TWO_PI if first else 0.0
    ahead, behind, found = 0.0, 0.0, margin >= r
    if found:
        ahead, behind = certified_interval(walk, (i0, i1, j0, j1), phi, behind0)
    n1, n2, p1, p2 = curves.v1.shape[0] - 1, curves.v2.shape[0] - 1, curves.p1, curves.p2
    if not lengthen or margin < 0.0 or count > walk.options.long_crossings:
        return ahead, behind, found, False
    if found and lengthen < 2 and (not p2 or ahead + behind >= TWO_PI / p2):
        return ahead, behind, found, False
    longer = False
    no_table = np.zeros((1, 1), np.uint8)
    for side in (1, 2):  # about the run's middle: a closed curve's crossing, its longest run in the stored range
        a0, a1, b0, b1 = i0, i1, j0, j1
        if side == 1:  # curve 2's run lengthened
            b0, b1, _ = run_about((j0 + j1) // 2, n2, p2, n2)
        else:
            a0, a1, _ = run_about((i0 + i1) // 2, n1, p1, n1)
        runs = (a0, a1, b0, b1)
        if runs == (i0, i1, j0, j1) or inside_parity(moved.cross, count, no_table, runs) != 1:
            continue
        if ends_clearance((curves.v1, curves.boxes1), (moved.w, moved.boxes2), runs, 4.0 * r * r) < r:
            continue
        a, b = certified_interval(walk, runs, phi, behind0, -1, ahead + behind if found else -1.0)
        if not found or a + b > ahead + behind:
            ahead, behind, found, longer = a, b, True, True
    return ahead, behind, found, longer


@njit(**JIT)
def _interval_at(walks, moved, got, phi, first, lengthen):
    """(ahead, behind, found, longer): :func:`_longest` at ``phi`` on the polylines, and where no widest pair of
    them is r apart also on the halved polylines, whose runs may end at the middle of a segment. ``walks``,
    ``moved``: (plain, halved) each."""
    walk, halved = walks
    ahead, behind, found, longer = _longest(walk, moved[0], got, phi, first, 2 if lengthen else 1)
    if got[5] < walk.r:  # no widest pair: runs that may end at the middle of a segment
        most = walk.options.max_crossings
        finer = runs_at(halved.curves, walk.tx, walk.ty, phi, moved[1], most)
        if 0 <= finer[0] <= most:
            a, b, f, _ = _longest(halved, moved[1], finer, phi, first, 0)
            if f and (not found or a + b > ahead + behind):
                ahead, behind, found = a, b, True
    return ahead, behind, found, longer


@njit(**JIT)
def _walk(curves, tx, ty, depth, roots, options):
    """A :data:`~sesp.kernels.runs.Walk` of position (tx, ty) at ``depth`` (r, margin), and room for curve 2
    placed."""
    v1, v2 = curves.v1, curves.v2
    near1, far1 = np.empty(v1.shape[0] - 1), np.empty(v1.shape[0] - 1)
    segment_radii(v1, tx, ty, near1, far1)
    cross = np.empty((options.max_crossings, 2), dtype=np.int64)
    moved = Moved(np.empty_like(v2), np.empty((chunk_count(v2), 4)), cross)
    return Walk(curves, near1, far1, tx, ty, depth[0], depth[1], roots, options), moved


@njit(**JIT)
def _deeper(walk, depth):
    """``walk`` at ``depth`` (r, margin)."""
    return Walk(walk.curves, walk.near1, walk.far1, walk.tx, walk.ty, depth[0], depth[1], walk.roots, walk.options)


@njit(**JIT)
def _nearer(walk, moved, phi, first, ahead, behind, found):
    """(ahead, behind, found): the interval found, or that of :func:`_near_interval` where thick particles come
    near enough (crossed or not) over a longer one."""
    if walk.margin > 0.0:
        a, b = _near_interval(walk, moved, phi, first)
        if a + b > ahead + behind:
            return a, b, True
    return ahead, behind, found


@njit(**JIT)
def _near_interval(walk, moved, phi, first):
    """(ahead, behind): an interval of φ about ``phi`` over which thick particles stay within their contact
    distance under every translation shorter than the depth sought: where the curves' distance d at ``phi`` is
    at most ``walk.margin`` (the contact distance less that depth), the longest of

    * (margin − d)/ρ each way: the distance grows by at most ρ per radian of turn, ρ the largest distance of
      curve 2's points from its centre;
    * the interval over which all of curve 2 stays within the margin of the segment of curve 1 nearest to it at
      ``phi``, and the one over which curve 1 stays within the margin of curve 2's nearest segment
      (:func:`_segment_within`): the curves are never farther apart than such a pair.

    (0, 0) where d is larger. The second holds far longer where the nearest points slide along the curves as
    they turn, as on two arcs about nearly the same centre."""
    curves, tx, ty, margin = walk.curves, walk.tx, walk.ty, walk.margin
    if margin <= 0.0:
        return 0.0, 0.0
    rho = 0.0
    for k in range(curves.rout2.shape[0]):
        rho = max(rho, curves.rout2[k])
    v1, v2 = curves.v1, curves.v2
    placed(v2, tx, ty, phi, moved.w, moved.boxes2)
    d2, i, j = nearest_segments(v1, curves.boxes1, moved.w, moved.boxes2, margin)
    d = math.sqrt(d2)
    if d >= margin:
        return 0.0, 0.0
    ahead = behind = (margin - d) / rho
    if i >= 0:
        for one, other in ((v1[i : i + 2], v2), (v1, v2[j : j + 2])):
            a, b = _segment_within(one, other, tx, ty, phi, margin)
            ahead, behind = max(ahead, a), max(behind, b)
    return ahead, (behind if first else 0.0)


@njit(**JIT)
def _segment_within(v1, v2, tx, ty, phi, margin):
    """(ahead, behind): the interval of φ about ``phi`` over which curve 2 (``v2``) at t comes within ``margin``
    (b) of curve 1 (``v1``), one of them a single segment: the union of the exact intervals of each pair of
    segments (:func:`~sesp.kernels.orientations.blocked_angles`), taken at a margin 1e-12 b smaller and
    shortened by 1e-12 rad at each end, for rounding; (0, 0) where ``phi`` lies in none."""
    starts, ends = blocked_angles(v1, v2, radial_spans(v2), tx, ty, 0.0, margin - 1e-12)
    at = phi - TWO_PI * math.floor(phi / TWO_PI)
    lo, hi = at, at
    grown = True
    while grown:  # the union's piece about ``at``, across 0 = 2π
        grown = False
        for k in range(starts.shape[0]):
            for shift in (-TWO_PI, 0.0, TWO_PI):
                s, e = starts[k] + shift, ends[k] + shift
                if s <= hi and e >= lo and (s < lo or e > hi):
                    lo, hi, grown = min(lo, s), max(hi, e), True
        if hi - lo >= TWO_PI:
            return TWO_PI, TWO_PI
    if lo == at and hi == at:
        return 0.0, 0.0
    return max(0.0, hi - at - 1e-12), max(0.0, at - lo - 1e-12)


@njit(**JIT)
def cover(prepared_curves, tx, ty, depth, fallback, max_steps, start, options):
    """(status, φ): status 1 if position (tx, ty) is certified deep in the excluded set (module notes) within
    ``max_steps`` intervals of φ: ``depth`` (r, margin), at every φ the curves stay crossed under translations
    shorter than r or (thick particles) come no farther apart than the margin (:func:`_near_interval`); 2 if
    not, but at least ``fallback`` (r, margin) deep (0 < its r < depth's; r 0: not asked); 0 if at some φ no
    pair of runs crosses with its ends that far apart (the position may still be that deep: the certificate is
    one-sided), or if the walk at ``fallback`` took more than ``options.fallback_steps`` intervals; −1 if
    ``max_steps`` were not enough at r. Where the walk at r fails it goes on at ``fallback`` from there: what is
    certified at r is certified at any smaller depth. ``prepared_curves``: :func:`prepared`. From the second
    interval on a pair r apart is also lengthened (``options.lengthen``), until once that gives no longer
    interval; ``options.tips``: where no pair of runs is r apart (1), or at every step (2), try two end points.
    The walk begins at φ = ``start`` (radians): where the position is least deep there (an orientation allowed
    nearby), a walk that fails fails at once. φ (radians): where the walk stopped, the orientation at which a
    walk that fails failed (nearby positions at a like depth fail there too)."""
    roots = np.empty(16)
    plain, moved = _walk(prepared_curves[0], tx, ty, depth, roots, options)
    halved, moved_h = _walk(prepared_curves[1], tx, ty, depth, roots, options)
    phi = start
    first, first_behind = True, 0.0
    proved, at_fallback = 1, 0
    lengthen = False  # also lengthen a pair that is r apart: from the second interval on, while it pays
    for _ in range(max_steps):
        got = runs_at(plain.curves, tx, ty, phi, moved, options.max_crossings)
        for _ in range(2):  # beside a degenerate touch the parity is defined
            if got[0] >= 0:
                break
            phi += 1e-9
            got = runs_at(plain.curves, tx, ty, phi, moved, options.max_crossings)
        if got[0] < 0 or got[0] > options.max_crossings:
            return 0, phi
        ahead, behind, found, longer = _interval_at((plain, halved), (moved, moved_h), got, phi, first, lengthen)
        if lengthen and got[5] >= plain.r and not longer:
            lengthen = False
        ahead, behind, found = _nearer(plain, moved, phi, first, ahead, behind, found)
        if options.tips and proved == 1 and not found:  # two end points, each through or near a side of the other
            ahead, behind = two_tips(plain, moved, got[0], phi, first)
            found = ahead > 0.0
        elif options.tips == 2 and proved == 1:  # and where they hold longer than the pair found
            a, b = two_tips(plain, moved, got[0], phi, first)
            if a > ahead:
                ahead, behind = a, b
        if not found and proved == 1 and fallback[0] > 0.0:  # go on at ``fallback`` from this φ
            plain, halved, proved = _deeper(plain, fallback), _deeper(halved, fallback), 2
            ahead, behind, found, _ = _longest(plain, moved, got, phi, first)
            ahead, behind, found = _nearer(plain, moved, phi, first, ahead, behind, found)
        if not found:
            return 0, phi
        if first:
            first, first_behind = False, behind
            lengthen = options.lengthen
        if phi + ahead >= start + TWO_PI - first_behind:
            return proved, phi
        if proved == 2:
            at_fallback += 1
            if at_fallback > options.fallback_steps:
                return 0, phi
        phi += ahead + 1e-12  # the interval is closed: its end is certified
    return (-1 if proved == 1 else 0), phi  # out of steps at ``fallback``: nothing proved


@njit(**JIT, parallel=True)
def cover_at(prepared_curves, positions, fallback, options, out, stops):
    """``out[p]``, ``stops[p]``: :func:`cover` of position p at depth (``rs[p]``, ``margins[p]``) (else
    ``fallback``: r, margin) with ``max_steps[p]`` intervals, its walk begun at φ = ``starts[p]``;
    ``positions``: (xs, ys, rs, margins, max_steps, starts). Each position is written by one thread."""
    xs, ys, rs, margins, max_steps, starts = positions
    v1, boxes1, v2, frame_boxes2, rin2, rout2, p1, p2 = prepared_curves[0]
    h1, hboxes1, h2, hframe_boxes2, hrin2, hrout2, hp1, hp2 = prepared_curves[1]
    for p in prange(xs.shape[0]):
        # rebuilt per position: numba's parallel loops take arrays, not tuples of them
        curves = (
            Curves(v1, boxes1, v2, frame_boxes2, rin2, rout2, p1, p2),
            Curves(h1, hboxes1, h2, hframe_boxes2, hrin2, hrout2, hp1, hp2),
        )
        depth = (rs[p], margins[p])
        out[p], stops[p] = cover(curves, xs[p], ys[p], depth, fallback, max_steps[p], starts[p], options)


def _stored(v):
    """A closed polyline (last vertex = first) stored twice over, so that runs may pass its first vertex, with
    its number of segments; an open one as it is, with 0. Always a new, writable array: a read-only one (a
    Pair's) would make numba compile every kernel a second time, for that type."""
    if len(v) > 3 and np.array_equal(v[0], v[-1]):
        return np.ascontiguousarray(np.concatenate([v, v[1:]])), len(v) - 1
    return np.array(v, dtype=float, order="C"), 0


def _halved(v):
    """Polyline ``v`` with each segment cut in two at its middle: the same curve, with more places to end a run."""
    out = np.empty((2 * len(v) - 1, 2))
    out[0::2], out[1::2] = v, 0.5 * (v[:-1] + v[1:])
    return out


def _curves(v1, v2):
    v1, p1 = _stored(v1)
    v2, p2 = _stored(v2)
    boxes1 = chunk_boxes(v1, np.empty((chunk_count(v1), 4)))
    rin2, rout2 = np.empty(v2.shape[0] - 1), np.empty(v2.shape[0] - 1)
    segment_radii(v2, 0.0, 0.0, rin2, rout2)
    return Curves(v1, boxes1, v2, chunk_boxes(v2, np.empty((chunk_count(v2), 4))), rin2, rout2, p1, p2)


def prepared(v1, v2):
    """The arguments of :func:`cover` that depend on the curves only: the polylines as they are, and halved
    (:data:`~sesp.kernels.runs.Curves` each)."""
    return _curves(v1, v2), _curves(_halved(v1), _halved(v2))


def certified_deep(
    prepared_curves, xs, ys, rs, max_steps, fallback=0.0, start=0.0, options=OPTIONS, stops=None, contact=0.0
):
    """(p,) int8, :func:`cover` of each position (b) at depth ``rs`` (b), else ``fallback`` (b; 0: not asked),
    with ``max_steps`` intervals of φ, each walk begun at φ = ``start`` (radians; all broadcast);
    ``prepared_curves``: :func:`prepared`; ``options``: :data:`Options` (``OPTIONS._replace(tips=False)``: no
    two end points). ``contact`` (b): the particles' contact distance (thick particles overlap where their
    curves come within it): the curves must then stay crossed to ``rs`` − ``contact`` only (at least
    LEAST_DEPTH), or come no farther apart than ``contact`` − ``rs``. ``stops``: a (p,) float array to receive
    the orientation (radians) at which each walk stopped (where it failed, for one that failed), or None."""
    xs = np.ascontiguousarray(xs, dtype=float)
    ys = np.ascontiguousarray(ys, dtype=float)
    depths = np.broadcast_to(np.asarray(rs, dtype=float), xs.shape)
    rs = np.ascontiguousarray(np.maximum(depths - contact, LEAST_DEPTH))
    margins = np.ascontiguousarray(contact - depths)
    steps = np.ascontiguousarray(np.broadcast_to(np.asarray(max_steps, dtype=np.int64), xs.shape))
    starts = np.ascontiguousarray(np.broadcast_to(np.asarray(start, dtype=float), xs.shape))
    out = np.zeros(xs.shape[0], dtype=np.int8)
    where = np.empty(xs.shape[0]) if stops is None else stops
    below = (max(fallback - contact, LEAST_DEPTH) if fallback > 0.0 else 0.0, contact - fallback)
    options = Options(*(int(v) for v in options[:3]), float(options[3]), int(options[4]), bool(options[5]))
    with small_chunks():
        cover_at(prepared_curves, (xs, ys, rs, margins, steps, starts), below, options, out, where)
    return out
