"""Tip kernels: a depth shown by two end points held through opposite sides of the other curve.

Where one end point (a tip) of an open curve pokes through a side of the
other curve and a second tip through (or close to) the opposite side, a
short translation frees either alone but not both, and no single pair of
runs shows the depth. A tip e near a run α of the other curve that is a
graph over a line across the disk keeps a pair of runs crossing oddly for
every translation in a half-plane (the side of α its parity gives); two
half-planes that cover the disk of radius r certify it. Turning φ by δ moves
e towards α's line by A·sin δ + B·(cos δ − 1) (A, B from e's offset from the
centre of rotation), so each half-plane, moved by at most that, holds over an
interval of φ. The rate A is e's speed across the line, not along it: where
both ends of curve 2 slide along the flat sides of curve 1 the interval is
many times longer than e's whole speed allows.

Per tip q the kernels keep, in :data:`Tips`: ``sides[q]`` (1 or 2: whose end
it is), ``ends[q]`` (its vertex), ``nearest[q]`` (the other curve's segment
nearest to it), ``plane[q]`` (the normal (a_x, a_y) of its half-plane in
translations of curve 2, and the run's least and greatest heights),
``turning[q]`` (A, B, a bound on any further motion per radian, and e's
distance from the centre of rotation) and ``graph[q]`` (the run's first and
last vertex, and 1 where e lies above α, 0 below, −1 where there is no run).
"""

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .common import JIT
from .orientations import TWO_PI
from .runs import certified_interval, inside_parity, nearest2, nearest_index

Tips = namedtuple("Tips", "sides ends nearest plane turning graph")
TIGHT = 1e-12  # b: the widest strip between two opposite half-planes that still hold every translation (_gap)


@njit(**JIT)
def _steep(o, i, mx, my, least):
    """Whether segment i of polyline o runs along m = (mx, my), at an angle of more than asin(least) to its normal."""
    dx, dy = o[i + 1, 0] - o[i, 0], o[i + 1, 1] - o[i, 1]
    return dx * mx + dy * my > least * math.hypot(dx, dy)


@njit(**JIT)
def _graph(ex, ey, o, k, reach, turn):
    """The run of polyline o about its segment k that is a graph over the line of segment k across the slab of
    half-width ``reach`` about (ex, ey), each segment at more than ``turn`` to the line's normal:
    (c0, c1, nx, ny, low, high, at_e), vertices c0..c1, n the unit normal pointing from e towards the line, low
    and high the least and greatest height along n of the run inside the slab and ``at_e`` its height beside e,
    all from e. c0 = −1 where there is none."""
    mx, my = o[k + 1, 0] - o[k, 0], o[k + 1, 1] - o[k, 1]
    length = math.hypot(mx, my)
    mx, my = mx / length, my / length
    nx, ny = (-my, mx) if mx * (o[k, 1] - ey) - my * (o[k, 0] - ex) > 0.0 else (my, -mx)
    least = math.sin(turn)
    c0, c1 = k, k + 1
    while (o[c0, 0] - ex) * mx + (o[c0, 1] - ey) * my > -reach:
        if c0 == 0 or not _steep(o, c0 - 1, mx, my, least):
            return -1, 0, 0.0, 0.0, 0.0, 0.0, 0.0
        c0 -= 1
    while (o[c1, 0] - ex) * mx + (o[c1, 1] - ey) * my < reach:
        if c1 == o.shape[0] - 1 or not _steep(o, c1, mx, my, least):
            return -1, 0, 0.0, 0.0, 0.0, 0.0, 0.0
        c1 += 1
    low, high, at_e = np.inf, -np.inf, 0.0
    for i in range(c0, c1):  # the run clipped to the slab: heights at the clipped ends
        ax, ay = o[i, 0] - ex, o[i, 1] - ey
        dx, dy = o[i + 1, 0] - o[i, 0], o[i + 1, 1] - o[i, 1]
        a, d = ax * mx + ay * my, dx * mx + dy * my  # d > 0: the run is steep
        s0, s1 = max(0.0, (-reach - a) / d), min(1.0, (reach - a) / d)
        for s in (s0, s1):
            height = (ax + s * dx) * nx + (ay + s * dy) * ny
            low, high = min(low, height), max(high, height)
        if a <= 0.0 <= a + d:
            at_e = (ax - a / d * dx) * nx + (ay - a / d * dy) * ny
    return c0, c1, nx, ny, low, high, at_e


@njit(**JIT)
def _tip_runs(curves, moved, count, tip, graph, reach):
    """(i0, i1, j0, j1, skip, odd) for ``tip`` (side, vertex) near the run ``graph`` (c0, c1) of the other curve:
    the runs from the tip and about the graph whose other three ends, and the tip to the run outside the graph,
    are farther than ``reach`` from the other run, the tip's end (as :func:`certified_interval` skips it) and
    whether the runs cross oddly; skip −1 where there are none. ``moved``: curve 2 at (t, φ) and its ``count``
    crossings."""
    side, at = tip
    c0, c1 = graph
    v1, boxes1 = curves.v1, curves.boxes1
    w, boxes2, cross = moved
    own, own_boxes, other, other_boxes = (v1, boxes1, w, boxes2) if side == 1 else (w, boxes2, v1, boxes1)
    ex, ey = own[at, 0], own[at, 1]
    n_own, n_other = own.shape[0] - 1, other.shape[0] - 1
    half = 1
    while True:  # runs: ``half`` segments from the tip, and the graph with ``half`` more segments on either side
        t0, t1 = (0, min(half, n_own)) if at == 0 else (max(0, n_own - half), n_own)
        o0, o1 = max(0, c0 - half), min(n_other, c1 + half)
        far = t1 if at == 0 else t0
        m2 = nearest2(own[far, 0], own[far, 1], other, other_boxes, o0, o1, np.inf)
        m2 = nearest2(other[o0, 0], other[o0, 1], own, own_boxes, t0, t1, m2)
        m2 = nearest2(other[o1, 0], other[o1, 1], own, own_boxes, t0, t1, m2)
        if o0 < c0:
            m2 = min(m2, nearest2(ex, ey, other, other_boxes, o0, c0, np.inf))
        if c1 < o1:
            m2 = min(m2, nearest2(ex, ey, other, other_boxes, c1, o1, np.inf))
        if m2 >= reach * reach:
            break
        if t1 - t0 == n_own and o1 - o0 == n_other:
            return 0, 0, 0, 0, -1, False
        half *= 2
    if side == 1:
        i0, i1, j0, j1, skip = t0, t1, o0, o1, 0 if at == 0 else 1
    else:
        i0, i1, j0, j1, skip = o0, o1, t0, t1, 2 if at == 0 else 3
    return i0, i1, j0, j1, skip, inside_parity(cross, count, np.zeros((1, 1), np.uint8), (i0, i1, j0, j1)) == 1


@njit(**JIT)
def _least_norm(ax, ay, b, cx, cy, d):
    """The least |v| with a·v >= b and c·v >= d (|a| = |c| = 1); inf where no v has both."""
    if b <= 0.0 and d <= 0.0:
        return 0.0
    cos = ax * cx + ay * cy
    best = np.inf
    if b > 0.0 and b * cos >= d:
        best = b
    if d > 0.0 and d * cos >= b:
        best = min(best, d)
    if best < np.inf:
        return best
    det = ax * cy - ay * cx
    if det == 0.0:
        return np.inf
    return math.hypot((b * cy - ay * d) / det, (ax * d - b * cx) / det)


@njit(**JIT)
def _half_plane(plane, q, odd, slack):
    """(a_x, a_y, c): tip q's half-plane of overlapping translations {v : a·v < c}, on its parity's side, its
    heights moved by ``slack`` against it."""
    if odd:
        return plane[q, 0], plane[q, 1], plane[q, 2] - slack
    return -plane[q, 0], -plane[q, 1], -plane[q, 3] - slack


@njit(**JIT)
def _covered(plane, pair, slacks, r):
    """Whether the half-planes of the tips ``pair`` (a, odd_a, b, odd_b), on their parities' sides and moved by
    their ``slacks`` (b), hold every translation shorter than r."""
    a, odd_a, b, odd_b = pair
    ax, ay, ca = _half_plane(plane, a, odd_a, slacks[0])
    bx, by, cb = _half_plane(plane, b, odd_b, slacks[1])
    return _least_norm(ax, ay, ca, bx, by, cb) >= r


@njit(**JIT)
def _shift(turning, q, odd, direction, turn):
    """b: how far tip q's half-plane moves against its parity's side while φ turns by at most ``turn`` (rad) in
    ``direction`` (±1). The tip moves towards its run's line by A·sin δ + B·(cos δ − 1) (δ the signed turn), and
    by at most extra·|δ| more; over every turn up to ``turn`` that is at most max(±A, 0)·turn +
    max(∓B, 0)·turn²/2 + extra·turn."""
    rate, bend, extra = _motion(turning, q, odd, direction)
    return max(rate, 0.0) * turn + max(-bend, 0.0) * 0.5 * turn * turn + extra * turn


@njit(**JIT)
def _largest_turn(tips, pair, r, bounds, direction, joint):
    """The largest turn of φ (rad, at most ``most``; 0 if none) in ``direction`` over which both half-planes of
    ``pair`` (a, odd_a, b, odd_b), moved by their shifts (:func:`_shift`, each at most ``below``), still cover
    the disk of radius r, and each tip moves along its run by at most ``lateral`` (b) less r (the slab about
    it). ``bounds``: (most, lateral, below). ``joint``: two half-planes with opposite normals, which cover while
    their overlap, moved by the sum of their two motions, stays at least −TIGHT (:func:`_gap`); 0 for any other
    two. Where both tips move alike (as the two ends of a staple's arms, across two parallel sides of the other)
    the overlap hardly changes, and the turn passes the orientation at which it is 0: each half-plane with its
    own worst motion takes ever shorter turns there."""
    a, odd_a, b, odd_b = pair
    most, lateral, below = bounds
    turning = tips.turning
    gap, rate, bend, extra = 0.0, 0.0, 0.0, 0.0
    if joint:
        gap = _gap(tips.plane, pair)
        if gap < -TIGHT:
            return 0.0
        for q, odd in ((a, odd_a), (b, odd_b)):
            rq, bq, eq = _motion(turning, q, odd, direction)
            rate, bend, extra = rate + rq, bend + bq, extra + eq
    hi = most
    for q in (a, b):
        speed = turning[q, 3] + turning[q, 2]  # b per radian, at most (0: a tip at the centre of rotation)
        if speed * hi > lateral:
            hi = lateral / speed
    lo = 0.0
    for k in range(31):
        turn = hi if k == 0 else 0.5 * (lo + hi)
        slack_a, slack_b = _shift(turning, a, odd_a, direction, turn), _shift(turning, b, odd_b, direction, turn)
        if joint:
            holds = gap - _sinusoid_most(rate, bend, turn) - extra * turn >= -TIGHT
        else:
            holds = _covered(tips.plane, pair, (slack_a, slack_b), r)
        if slack_a <= below and slack_b <= below and holds:
            if k == 0:
                return hi
            lo = turn
        else:
            hi = turn
    return lo


@njit(**JIT)
def _gap(plane, pair) -> float:
    """b: for two half-planes with opposite normals (on their parities' sides), how far they overlap along the
    normal (negative: the width of the strip of translations neither holds); −inf for any other two. Two such
    half-planes, closed, hold every translation where it is at least −1e-12 b (TIGHT): on their edges each tip
    lies on its run's line, and within the strip both lie within 1e-12 b of them, touching to within the
    floating point of coordinates of order 1 b (:data:`~sesp.kernels.depth.LEAST_DEPTH` is 1e-9 b)."""
    a, odd_a, b, odd_b = pair
    ax, ay, ca = _half_plane(plane, a, odd_a, 0.0)
    bx, by, cb = _half_plane(plane, b, odd_b, 0.0)
    if ax * bx + ay * by > -1.0 + 1e-12:
        return -np.inf
    return ca + cb


@njit(**JIT)
def _motion(turning, q, odd, direction):
    """(rate, bend, extra): tip q's half-plane moves against its parity's side by rate·sin δ + bend·(cos δ − 1),
    and by at most extra·δ more, while φ turns by δ in ``direction``."""
    rate, bend, extra = direction * turning[q, 0], turning[q, 1], turning[q, 2]
    if not odd:  # the half-plane of an even parity lies on the other side: the height moves it the other way
        rate, bend = -rate, -bend
    return rate, bend, extra


@njit(**JIT)
def _sinusoid_most(rate, bend, turn):
    """The largest of rate·sin δ + bend·(cos δ − 1) over 0 ≤ δ ≤ ``turn`` (≤ 2π): at an end, or where its
    derivative rate·cos δ − bend·sin δ vanishes."""
    best = max(0.0, rate * math.sin(turn) + bend * (math.cos(turn) - 1.0))
    at = math.atan2(rate, bend)
    for d in (at, at + math.pi, at + 2.0 * math.pi):
        if 0.0 < d < turn:
            best = max(best, rate * math.sin(d) + bend * (math.cos(d) - 1.0))
    return best


@njit(**JIT)
def _tips_near(walk, moved, slab):
    """(sides, ends, nearest, m): the m end points of the open curves within r + ``slab`` (b) of the other curve
    (a tip farther than the widest slab shows nothing), with the other curve's segment nearest to each."""
    v1, boxes1, v2 = walk.curves.v1, walk.curves.boxes1, walk.curves.v2
    w, boxes2 = moved.w, moved.boxes2
    sides, ends, nearest = np.empty(4, np.int64), np.empty(4, np.int64), np.empty(4, np.int64)
    m = 0
    for side, tip in ((1, 0), (1, v1.shape[0] - 1), (2, 0), (2, v2.shape[0] - 1)):
        own, other, other_boxes = (v1, w, boxes2) if side == 1 else (w, v1, boxes1)
        k, d2 = nearest_index(own[tip, 0], own[tip, 1], other, other_boxes, 0, other.shape[0] - 1, np.inf)
        if d2 < (walk.r + slab) ** 2:
            sides[m], ends[m], nearest[m] = side, tip, k
            m += 1
    return sides, ends, nearest, m


@njit(**JIT)
def _tip_planes(walk, moved, near, reach, most):
    """:data:`Tips` of the tips ``near`` (:func:`_tips_near`): each tip's run of the other curve that is a graph
    across the slab of half-width ``reach`` about it (each segment at more than ``most`` rad to the line's
    normal), its half-plane and how that moves as φ turns."""
    sides, ends, nearest, m = near
    v1, w, r = walk.curves.v1, moved.w, walk.r
    plane, turning, graph = np.empty((m, 4)), np.empty((m, 4)), np.empty((m, 3), np.int64)
    for q in range(m):
        own = v1 if sides[q] == 1 else w
        other = w if sides[q] == 1 else v1
        c0, c1, nx, ny, low, high, at_e = _graph(own[ends[q], 0], own[ends[q], 1], other, nearest[q], reach, most)
        sign = 1.0 if sides[q] == 2 else -1.0  # e moves by v (curve 2) or by −v (curve 1) relative to α
        plane[q, 0], plane[q, 1], plane[q, 2], plane[q, 3] = sign * nx, sign * ny, low, high
        # turning φ by δ moves e relative to α by (R(sign·δ) − I)·d, d = e − t (curve 2 turns about t); a
        # tip of curve 1 is seen from curve 2's frame, where the translation v turns too: at most r·|δ| more
        dx, dy = own[ends[q], 0] - walk.tx, own[ends[q], 1] - walk.ty
        turning[q, 0], turning[q, 1] = sign * (ny * dx - nx * dy), nx * dx + ny * dy
        turning[q, 2], turning[q, 3] = (0.0 if sides[q] == 2 else r), math.hypot(dx, dy)
        # no graph, or e too close to α to tell its side
        graph[q, 0], graph[q, 1], graph[q, 2] = c0, c1, (-1 if c0 < 0 or abs(at_e) < 1e-13 else at_e < 0.0)
    return Tips(sides, ends, nearest, plane, turning, graph)


@njit(**JIT)
def _pair_interval(walk, moved, count, tips, ab, scale, phi, first):
    """(ahead, behind): the interval of φ about ``phi`` over which tips ``ab`` (a, b) hold every translation
    shorter than r, (0, 0) where they do not: their runs cross oddly on the sides that cover the disk, the
    half-planes cover it over the turn (:func:`_largest_turn`), and the runs' far ends stay r from the other
    run (:func:`certified_interval`). ``scale``: (reach, most, rho), the slab's half-width (b), the widest turn
    tried (rad) and curve 2's radius (b); ``behind`` only where ``first``."""
    a, b = ab
    reach, most, rho = scale
    graph, r = tips.graph, walk.r
    if graph[a, 2] < 0 or graph[b, 2] < 0:
        return 0.0, 0.0
    hope = False
    for oa in (False, True):
        for ob in (False, True):
            parities = (a, oa, b, ob)
            hope = hope or _covered(tips.plane, parities, (0.0, 0.0), r) or _gap(tips.plane, parities) >= -TIGHT
    if not hope:
        return 0.0, 0.0  # no parities would do: the runs need not be found
    ra = _tip_runs(walk.curves, moved, count, (tips.sides[a], tips.ends[a]), (graph[a, 0], graph[a, 1]), reach)
    rb = _tip_runs(walk.curves, moved, count, (tips.sides[b], tips.ends[b]), (graph[b, 0], graph[b, 1]), reach)
    if ra[4] < 0 or rb[4] < 0:
        return 0.0, 0.0
    # the parity below α: flipped where e lies above it
    pair = (a, ra[5] != (graph[a, 2] == 1), b, rb[5] != (graph[b, 2] == 1))
    # a point of the disk stays below each α (its height less than the least, moved): the parity below is the
    # same all along
    below = min(tips.plane[a, 2], tips.plane[b, 2]) + 0.99 * r
    bounds = (most, 2.0 * rho * most, below)
    # the longer of: each half-plane with its own worst motion, and two opposite ones with their joint motion
    ahead = max(_largest_turn(tips, pair, r, bounds, 1.0, False), _largest_turn(tips, pair, r, bounds, 1.0, True))
    if ahead * rho <= walk.options.least_tip_step * r:
        return 0.0, 0.0
    behind = 0.0
    if first:
        behind = max(
            _largest_turn(tips, pair, r, bounds, -1.0, False), _largest_turn(tips, pair, r, bounds, -1.0, True)
        )
    for got in (ra, rb):
        around = certified_interval(walk, got[:4], phi, TWO_PI if first else 0.0, got[4])
        ahead, behind = min(ahead, around[0]), min(behind, around[1])
    return ahead, behind


@njit(**JIT)
def two_tips(walk, moved, count, phi, first):
    """(ahead, behind): an interval of φ about ``phi`` over which every translation of curve 2 shorter than
    ``walk.r`` overlaps, shown by two end points of the open curves (module notes); (0, 0) where none is found.
    ``moved``: curve 2 at (t, φ) and its ``count`` crossings; ``behind`` only where ``first``.

    A tip e near a run α of the other curve that is a graph over a line across the slab of half-width r + 2·s
    about e (s = ρδ, ρ curve 2's radius, δ the turn of φ allowed), with runs from e and about α whose other three
    ends lie farther than that from the other run: the parity of their crossings changes only where e crosses
    α. Within the disk |v| < r it is one parity P for every v that leaves e below α, the other above: where P is
    odd the runs cross for every v that puts e lower than α's least height in the slab, where it is even higher
    than its greatest. As φ turns by at most δ, e moves at most s relative to α: the half-plane, moved by e's
    motion across α's line, holds while the far ends stay r from the other run. The graphs and runs are found
    for δ at most r/ρ (then 1/16 of that)."""
    curves, r = walk.curves, walk.r
    if curves.p1 or curves.p2:
        return 0.0, 0.0  # a closed curve has no end points
    rho = 0.0
    for k in range(curves.rout2.shape[0]):
        rho = max(rho, curves.rout2[k])
    most = r / rho  # the widest turn tried
    near = _tips_near(walk, moved, 2.0 * rho * most)
    m = near[3]
    if m < 2:
        return 0.0, 0.0
    for _ in range(2):
        reach = r + 2.0 * rho * most
        tips = _tip_planes(walk, moved, near, reach, most)
        for a in range(m):
            for b in range(a + 1, m):
                ahead, behind = _pair_interval(walk, moved, count, tips, (a, b), (reach, most, rho), phi, first)
                if ahead * rho > walk.options.least_tip_step * r:
                    return ahead, behind
        most /= 16.0
    return 0.0, 0.0
