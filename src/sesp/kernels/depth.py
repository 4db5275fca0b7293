"""Depth kernels: a lower bound on how deep a position lies in the excluded set, exact in φ.

The depth p(t) is the distance from t to the nearest allowed position. A
position is at least r deep when, at every orientation φ, the curves meet so
robustly that no translation shorter than r parts them. This module proves
that without sampling φ:

* Two arcs α (of curve 1) and β (of curve 2 at t, φ) that cross an odd
  number of times keep crossing under any motion during which no end point of
  one touches the other (the parity of the crossing number changes only
  there). So if every end point of α is at least r from β and every end point
  of β at least r from α, every translation of curve 2 shorter than r leaves
  them crossing: the pair overlaps on the whole disk of radius r about t.
* At a fixed t, each end point moves on a circle as φ turns, and its distance
  to a segment of the other arc reaches r only at roots of sinusoids in φ
  (its distance to the segment's line, its projection reaching the
  segment's ends, its distance to the segment's end points). Between those
  roots the end points stay at least r away, so the parity is constant: one
  chain pair certifies a whole interval of φ, found in closed form.

* A closed curve has no end points: it is stored twice over, and its runs
  (of fewer segments than the curve) may pass the polyline's first vertex.
* A run may end anywhere on the curve, not only at a vertex. Where a lens
  between the curves spans about one segment (a rounded corner across a flat
  side), every vertex near it lies close to a crossing and no vertex-ended
  run is r apart; at such a φ the runs are also tried on the polylines with
  each segment cut at its middle (the same curves), whose ends can lie in
  the middle of the lens.

* Two contacts at once. Where one end point of an open curve pokes through a
  side of the other curve and a second end point through (or close to) the
  opposite side, a short translation frees either alone but not both, and no
  single pair of runs is r apart. Each such end point, near a run of the other
  curve that is a graph over a line across the disk, keeps a pair of runs
  crossing oddly for every translation in a half-plane (the side of the run
  its parity gives); two half-planes that cover the disk of radius r certify
  it (:func:`two_tips`). Turning φ by δ moves the end point towards the
  run's line by A·sin δ + B·(cos δ − 1), A and B from its offset from the
  centre of rotation, so each half-plane, moved by at most that, holds over
  an interval of φ. The rate A is the end point's speed across the line, not
  along it: where both ends of curve 2 slide along the flat sides of curve 1,
  the interval is many times longer than the end point's whole speed allows.

:func:`cover` walks around the circle of orientations: at the first φ not yet
certified it looks for an arc pair with an odd crossing number and end points
at least r from the other arc (the whole curves first, then runs of 1, 2, 4,
... segments about each crossing; the widest apart), finds the interval of φ
over which that pair stays certified, and continues from its end. Where the
curves run close about a crossing (a shallow lens), pairs short on both sides
keep apart only while a vertex of each lies in the lens, one interval per
vertex passing it; the same pair with one run lengthened to its whole curve
holds until the turning curve sweeps over an end of the short run, and the
longer interval is taken (:func:`_longest`). Deep in the excluded set a
widest pair that keeps apart still stops each time an end point passes the
other curve, while the lengthened pair often holds nearly all the way
round: from its second interval on, a walk tries the lengthened pair there
too, until once it gives no longer interval. Where no pair keeps apart, two
end points of the open curves may (:func:`two_tips`). The position is certified
r deep when the intervals close around the circle. The bound is one-sided: a
position whose certificate fails may still be that deep (for instance where
the curves nearly coincide and cross many times within a short run).

References: the mod-2 intersection number of curves and its invariance under
homotopy (Guillemin and Pollack, *Differential Topology*, ch. 2).
"""

import math

import numpy as np
from numba import njit, prange

from .common import JIT, point_segment_distance2, small_chunks, sort_first
from .orientations import CHUNK, TWO_PI, boxes_distance2, chunk_boxes, chunk_count, sinusoid_roots

MAX_CROSSINGS = 1024  # crossings of the two stored polylines at one φ at most; more and the certificate gives up
# a turn of φ over which two end points move curve 2 by less than this many r is given up as a step of their
# walk: it nears an orientation where their half-planes stop covering the disk, in ever shorter steps (cost only)
LEAST_TIP_STEP = 1e-6
LONG_CROSSINGS = 16  # a run is lengthened to its whole curve only where the curves cross at most this often (cost only)
# intervals of φ a walk may take at its ``fallback`` depth before it gives up (returns 0); the caller then decides
# the position by its exact windows, which give the same answer (cost only: where the curves run within a hair
# of each other, the ASP near a closed circle, a walk at 1e-9 b takes hundreds of intervals, the windows fewer)
FALLBACK_STEPS = 64


@njit(**JIT)
def _orient(px, py, qx, qy, ax, ay):
    return (qx - px) * (ay - py) - (qy - py) * (ax - px)


@njit(**JIT)
def crossings(v1, boxes1, w, boxes2, out, p1, p2):
    """Write the segment pairs (i, j) of ``v1`` and ``w`` whose interiors cross to ``out``; return how many, or -1
    where a pair meets degenerately (an end point exactly on the other's line), where parity is not defined.
    ``p1``, ``p2``: segments of a closed curve stored twice over (0: open); its crossings are found on the first
    copy and written for both."""
    g1 = p1 if p1 else v1.shape[0] - 1
    g2 = p2 if p2 else w.shape[0] - 1
    n = 0
    for a in range((g1 - 1) // CHUNK + 1):
        for b in range((g2 - 1) // CHUNK + 1):
            if boxes_distance2(boxes1[a], boxes2[b]) > 0.0:
                continue
            for i in range(a * CHUNK, min((a + 1) * CHUNK, g1)):
                px, py, qx, qy = v1[i, 0], v1[i, 1], v1[i + 1, 0], v1[i + 1, 1]
                if _point_box2(0.5 * (px + qx), 0.5 * (py + qy), boxes2[b]) > 0.26 * ((qx - px) ** 2 + (qy - py) ** 2):
                    continue  # the segment keeps out of the other run's box (0.25: half its length, squared)
                for j in range(b * CHUNK, min((b + 1) * CHUNK, g2)):
                    ax, ay, bx, by = w[j, 0], w[j, 1], w[j + 1, 0], w[j + 1, 1]
                    d1 = _orient(px, py, qx, qy, ax, ay)
                    d2 = _orient(px, py, qx, qy, bx, by)
                    if d1 * d2 > 0.0:
                        continue
                    d3 = _orient(ax, ay, bx, by, px, py)
                    d4 = _orient(ax, ay, bx, by, qx, qy)
                    if d3 * d4 > 0.0:
                        continue
                    if d1 == 0.0 or d2 == 0.0 or d3 == 0.0 or d4 == 0.0:
                        return -1
                    for ci in range(2 if p1 else 1):
                        for cj in range(2 if p2 else 1):
                            if n < out.shape[0]:
                                out[n, 0] = i + ci * p1
                                out[n, 1] = j + cj * p2
                            n += 1
    return n


@njit(**JIT)
def _point_box2(x, y, box):
    dx = max(0.0, box[0] - x, x - box[1])
    dy = max(0.0, box[2] - y, y - box[3])
    return dx * dx + dy * dy


@njit(**JIT)
def _nearest_index(x, y, v, boxes, lo, hi, best2):
    """(k, d²): the segment k of polyline v (lo <= k < hi) nearest to (x, y) and its squared distance, where it
    is nearer than ``best2`` (else −1, best2); runs of ``CHUNK`` segments whose box (``boxes``) is farther than
    the best so far are skipped."""
    best = -1
    for c in range(lo // CHUNK, (hi - 1) // CHUNK + 1):
        if _point_box2(x, y, boxes[c]) >= best2:
            continue
        for k in range(max(lo, c * CHUNK), min(hi, (c + 1) * CHUNK)):
            d2 = point_segment_distance2(x, y, v[k, 0], v[k, 1], v[k + 1, 0], v[k + 1, 1])
            if d2 < best2:
                best2, best = d2, k
    return best, best2


@njit(**JIT)
def _nearest2(x, y, v, boxes, lo, hi, best2):
    """min(best2, squared distance from (x, y) to segments lo..hi-1 of polyline v)."""
    return _nearest_index(x, y, v, boxes, lo, hi, best2)[1]


@njit(**JIT)
def _ends_clearance(v1, boxes1, i0, i1, w, boxes2, j0, j1, most2=np.inf):
    """Distance of the nearest end point of run i0..i1 of v1 to run j0..j1 of w, or of an end of w's run to v1's;
    at most √``most2`` (a bound skips the segments farther than it)."""
    m2 = _nearest2(v1[i0, 0], v1[i0, 1], w, boxes2, j0, j1, most2)
    m2 = _nearest2(v1[i1, 0], v1[i1, 1], w, boxes2, j0, j1, m2)
    m2 = _nearest2(w[j0, 0], w[j0, 1], v1, boxes1, i0, i1, m2)
    m2 = _nearest2(w[j1, 0], w[j1, 1], v1, boxes1, i0, i1, m2)
    return math.sqrt(m2)


@njit(**JIT)
def _run(i, half, period, n):
    """Vertices (i0, i1) of the run of up to 2·half segments about segment i, and whether it can grow no more: an
    open curve's run is clipped at its ends; a closed curve (``period`` segments, stored twice) has no ends, and
    its runs grow to ``period`` − 1 segments."""
    if period:
        h = min(half, period // 2)
        return i - h + 1, i + h, h == period // 2
    i0, i1 = max(0, i - half + 1), min(n, i + half)
    return i0, i1, i0 == 0 and i1 == n


@njit(**JIT)
def _parity_table(cross, count, n1, n2):
    """(n1 + 1, n2 + 1) uint8: entry (a, b) is the parity of the crossings (i, j) with i < a and j < b, so the parity
    of those inside runs [i0, i1) × [j0, j1) is four look-ups (:func:`_inside_parity`)."""
    table = np.zeros((n1 + 1, n2 + 1), np.uint8)
    for k in range(count):
        table[cross[k, 0] + 1, cross[k, 1] + 1] ^= 1
    for a in range(1, n1 + 1):
        for b in range(1, n2 + 1):
            table[a, b] ^= table[a - 1, b] ^ table[a, b - 1] ^ table[a - 1, b - 1]
    return table


@njit(**JIT)
def _inside_parity(cross, count, table, i0, i1, j0, j1):
    """Parity of the crossings with i0 <= i < i1 and j0 <= j < j1: from ``table`` where it is built (many
    crossings), else counted."""
    if table.shape[0] > 1:
        return table[i1, j1] ^ table[i0, j1] ^ table[i1, j0] ^ table[i0, j0]
    inside = 0
    for k in range(count):
        inside += i0 <= cross[k, 0] < i1 and j0 <= cross[k, 1] < j1
    return inside % 2


@njit(**JIT)
def _nearer(x, y, v, k0, k1, k2, bound2):
    """Whether (x, y) lies within squared distance ``bound2`` of segment k0, k1 or k2 of polyline v."""
    for k in (k0, k1, k2):
        if point_segment_distance2(x, y, v[k, 0], v[k, 1], v[k + 1, 0], v[k + 1, 1]) <= bound2:
            return True
    return False


@njit(**JIT)
def _no_wider(v1, i0, i1, i, w, j0, j1, j, best):
    """True where :func:`_ends_clearance` of runs i0..i1 and j0..j1 (holding the crossing segments i and j) cannot
    exceed ``best``: an end lies within ``best`` of the other run's first, crossing or last segment (the same
    arithmetic as the full measure; the square root of fl(best²) is best itself, so the test is exact)."""
    if best < 0.0:
        return False
    b2 = best * best
    return (
        _nearer(v1[i0, 0], v1[i0, 1], w, j0, j, j1 - 1, b2)
        or _nearer(v1[i1, 0], v1[i1, 1], w, j0, j, j1 - 1, b2)
        or _nearer(w[j0, 0], w[j0, 1], v1, i0, i, i1 - 1, b2)
        or _nearer(w[j1, 0], w[j1, 1], v1, i0, i, i1 - 1, b2)
    )


@njit(**JIT)
def _parities(cross, count, n1, n2):
    """The parity table of :func:`_parity_table` where the crossings are many (counting them run by run would
    cost more), else an empty one: :func:`_inside_parity` then counts."""
    levels = int(math.log2(max(n1, n2))) + 1
    if count * count * levels > (n1 + 1) * (n2 + 1):
        return _parity_table(cross, count, n1, n2)
    return np.zeros((1, 1), np.uint8)


@njit(**JIT)
def _odd_runs(v1, boxes1, w, boxes2, cross, count, table, p1, p2):
    """(i0, i1, j0, j1, margin): the runs of segments (vertices i0..i1 of v1, j0..j1 of w) with an odd number of
    crossings whose ends are farthest from the other run; margin -1 if none: the whole curves, and runs of 1, 2,
    4, ... segments about each crossing. ``p1``, ``p2``:
    segments of a closed curve, stored twice over (0: open), whose runs may pass its first vertex. ``table``:
    :func:`_parities`. A run whose ends lie no farther from a few of the other run's segments than the best
    margin so far is not measured (its margin cannot be wider)."""
    n1 = v1.shape[0] - 1
    n2 = w.shape[0] - 1
    g1 = p1 if p1 else n1
    g2 = p2 if p2 else n2
    best = -1.0
    bi0 = bi1 = bj0 = bj1 = 0
    if _inside_parity(cross, count, table, 0, g1, 0, g2) == 1:
        best = _ends_clearance(v1, boxes1, 0, g1, w, boxes2, 0, g2)
        bi0, bi1, bj0, bj1 = 0, g1, 0, g2
    for c in range(count):
        i = cross[c, 0]
        j = cross[c, 1]
        if (p1 and not (p1 // 2 <= i < p1 // 2 + p1)) or (p2 and not (p2 // 2 <= j < p2 // 2 + p2)):
            continue  # a copy of a crossing seen in the middle of the stored curves
        half = 1
        while True:
            i0, i1, full1 = _run(i, half, p1, n1)
            j0, j1, full2 = _run(j, half, p2, n2)
            if full1 and full2 and not p1 and not p2:
                break  # the whole curves, tried above
            if _inside_parity(cross, count, table, i0, i1, j0, j1) == 1 and not _no_wider(
                v1, i0, i1, i, w, j0, j1, j, best
            ):
                margin = _ends_clearance(v1, boxes1, i0, i1, w, boxes2, j0, j1)
                if margin > best:
                    best = margin
                    bi0, bi1, bj0, bj1 = i0, i1, j0, j1
            if full1 and full2:
                break
            half *= 2
    return bi0, bi1, bj0, bj1, best


@njit(**JIT)
def _approach(ox, oy, ax, ay, bx, by, px, py, qx, qy, r, phi0, roots, ahead, behind):
    """Shrink (ahead, behind): how far φ may turn from ``phi0`` before the point o + a cos φ + b sin φ (on a
    circle: |a| = |b|, a ⊥ b) comes within ``r`` of segment p–q. (0, 0) if it is within r at ``phi0``."""
    dx, dy = qx - px, qy - py
    length = math.hypot(dx, dy)
    gx, gy = ox - px, oy - py
    m = 0
    side, side_a, side_b = dx * gy - dy * gx, dx * ay - dy * ax, dx * by - dy * bx  # |d| × distance to the line
    m = sinusoid_roots(side - r * length, side_a, side_b, roots, m)
    m = sinusoid_roots(side + r * length, side_a, side_b, roots, m)
    along, along_a, along_b = dx * gx + dy * gy, dx * ax + dy * ay, dx * bx + dy * by  # projection × |d|
    m = sinusoid_roots(along, along_a, along_b, roots, m)
    m = sinusoid_roots(along - length * length, along_a, along_b, roots, m)
    radius2 = ax * ax + ay * ay
    for ex, ey in ((px, py), (qx, qy)):  # distance to the end points
        hx, hy = ox - ex, oy - ey
        m = sinusoid_roots(
            hx * hx + hy * hy + radius2 - r * r, 2 * (hx * ax + hy * ay), 2 * (hx * bx + hy * by), roots, m
        )
    if m == 0:  # the distance never crosses r: near at every φ or at none
        c, s = math.cos(phi0), math.sin(phi0)
        if point_segment_distance2(ox + ax * c + bx * s, oy + ay * c + by * s, px, py, qx, qy) <= r * r:
            return 0.0, 0.0
        return ahead, behind
    sort_first(roots, m)
    for k in range(m):
        lo = roots[k]
        hi = roots[k + 1] if k + 1 < m else roots[0] + TWO_PI
        if hi <= lo:
            continue
        mid = 0.5 * (lo + hi)
        c, s = math.cos(mid), math.sin(mid)
        if point_segment_distance2(ox + ax * c + bx * s, oy + ay * c + by * s, px, py, qx, qy) <= r * r:
            if (phi0 - lo) % TWO_PI < hi - lo:
                return 0.0, 0.0
            ahead = min(ahead, (lo - phi0) % TWO_PI)
            behind = min(behind, (phi0 - hi) % TWO_PI)
    return ahead, behind


@njit(**JIT)
def _point_interval(ox, oy, ax, ay, bx, by, v, boxes, near, far, lo, hi, r, phi0, roots, ahead, behind):
    """Shrink (ahead, behind) by the first φ on either side of ``phi0`` at which the point o + a cos φ + b sin φ
    comes within ``r`` of segments lo..hi-1 of ``v``. Runs of segments are visited nearest first, and the rest
    skipped once they are too far to be reached within the interval: the point moves at most |a| per radian.
    ``near``, ``far``: each segment's distances from the circle's centre o; a segment that keeps out of the
    annulus |a| ± r is never reached."""
    c, s = math.cos(phi0), math.sin(phi0)
    x0, y0 = ox + ax * c + bx * s, oy + ay * c + by * s
    speed = math.hypot(ax, ay)
    first, last = lo // CHUNK, (hi - 1) // CHUNK
    gaps = np.empty(last - first + 1)
    for k in range(first, last + 1):
        gaps[k - first] = math.sqrt(_point_box2(x0, y0, boxes[k]))
    for k in np.argsort(gaps):
        if gaps[k] - r >= speed * max(ahead, behind):
            break
        chunk = first + k
        for i in range(max(lo, chunk * CHUNK), min(hi, (chunk + 1) * CHUNK)):
            if speed < near[i] - r or speed > far[i] + r:
                continue
            ahead, behind = _approach(
                ox, oy, ax, ay, bx, by, v[i, 0], v[i, 1], v[i + 1, 0], v[i + 1, 1], r, phi0, roots, ahead, behind
            )
            if ahead == 0.0:
                return 0.0, 0.0
    return ahead, behind


@njit(**JIT)
def _certified_interval(
    v1, boxes1, near1, far1, i0, i1, v2, frame_boxes2, rin2, rout2, j0, j1, tx, ty, r, phi0, roots, behind, skip=-1,
    least=-1.0
):  # fmt: skip
    """(ahead, behind): the interval of φ about ``phi0`` over which every end point of the two runs stays at
    least ``r`` from the other run. ``frame_boxes2``: chunk boxes of curve 2 in its own frame; ``near1``,
    ``far1``: the distances of curve 1's segments from t; ``rin2``, ``rout2``: of curve 2's from its centre.
    ``behind``: 2π to find how far back the interval reaches, 0 where only ahead matters. ``skip``: an end not
    to follow (0 to 3: i0, i1, j0, j1; −1 none). Where ahead + behind falls to ``least`` or below, it is returned
    at once (shorter than an interval found already)."""
    ahead = TWO_PI
    for a in (i0, i1):  # a fixed end of run 1, seen from curve 2's frame, turns by −φ about the origin
        if skip == (0 if a == i0 else 1) or ahead + behind <= least:
            continue
        gx, gy = v1[a, 0] - tx, v1[a, 1] - ty
        ahead, behind = _point_interval(
            0.0, 0.0, gx, gy, gy, -gx, v2, frame_boxes2, rin2, rout2, j0, j1, r, phi0, roots, ahead, behind
        )
    for b in (j0, j1):  # a moving end of run 2 turns by φ about t
        if skip == (2 if b == j0 else 3) or ahead + behind <= least:
            continue
        wx, wy = v2[b, 0], v2[b, 1]
        ahead, behind = _point_interval(
            tx, ty, wx, wy, -wy, wx, v1, boxes1, near1, far1, i0, i1, r, phi0, roots, ahead, behind
        )
    return ahead, behind


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
def _tip_runs(curves, w, boxes2, cross, count, side, tip, c0, c1, reach):
    """(i0, i1, j0, j1, skip, odd) for a tip near the graph c0..c1 of the other curve (:func:`two_tips`):
    the runs from the tip and about the graph whose other three ends, and the tip to the run outside the graph,
    are farther than ``reach`` from the other run, the tip's end (as :func:`_certified_interval` skips it) and
    whether the runs cross oddly; skip −1 where there are none."""
    v1, boxes1, _, _, _, _, _, _ = curves
    own, own_boxes, other, other_boxes = (v1, boxes1, w, boxes2) if side == 1 else (w, boxes2, v1, boxes1)
    ex, ey = own[tip, 0], own[tip, 1]
    n_own, n_other = own.shape[0] - 1, other.shape[0] - 1
    half = 1
    while True:  # runs: ``half`` segments from the tip, and the graph with ``half`` more segments on either side
        t0, t1 = (0, min(half, n_own)) if tip == 0 else (max(0, n_own - half), n_own)
        o0, o1 = max(0, c0 - half), min(n_other, c1 + half)
        far = t1 if tip == 0 else t0
        m2 = _nearest2(own[far, 0], own[far, 1], other, other_boxes, o0, o1, np.inf)
        m2 = _nearest2(other[o0, 0], other[o0, 1], own, own_boxes, t0, t1, m2)
        m2 = _nearest2(other[o1, 0], other[o1, 1], own, own_boxes, t0, t1, m2)
        if o0 < c0:
            m2 = min(m2, _nearest2(ex, ey, other, other_boxes, o0, c0, np.inf))
        if c1 < o1:
            m2 = min(m2, _nearest2(ex, ey, other, other_boxes, c1, o1, np.inf))
        if m2 >= reach * reach:
            break
        if t1 - t0 == n_own and o1 - o0 == n_other:
            return 0, 0, 0, 0, -1, False
        half *= 2
    if side == 1:
        i0, i1, j0, j1, skip = t0, t1, o0, o1, 0 if tip == 0 else 1
    else:
        i0, i1, j0, j1, skip = o0, o1, t0, t1, 2 if tip == 0 else 3
    return i0, i1, j0, j1, skip, _inside_parity(cross, count, np.zeros((1, 1), np.uint8), i0, i1, j0, j1) == 1


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
def _covered(plane, a, odd_a, slack_a, b, odd_b, slack_b, r):
    """Whether the half-planes of tips a and b, on their parities' sides and moved by their slacks (b), hold
    every translation shorter than r."""
    ax, ay, ca = _half_plane(plane, a, odd_a, slack_a)
    bx, by, cb = _half_plane(plane, b, odd_b, slack_b)
    return _least_norm(ax, ay, ca, bx, by, cb) >= r


@njit(**JIT)
def _shift(turning, q, odd, direction, turn):
    """b: how far tip q's half-plane moves against its parity's side while φ turns by at most ``turn`` (rad) in
    ``direction`` (±1). ``turning[q]``: (A, B, extra, |d|) of :func:`two_tips`: the tip moves towards its run's
    line by A·sin δ + B·(cos δ − 1) (δ the signed turn), and by at most extra·|δ| more; over every turn up to
    ``turn`` that is at most max(±A, 0)·turn + max(∓B, 0)·turn²/2 + extra·turn."""
    rate, bend, extra = direction * turning[q, 0], turning[q, 1], turning[q, 2]
    if not odd:  # the half-plane of an even parity lies on the other side: the height moves it the other way
        rate, bend = -rate, -bend
    return max(rate, 0.0) * turn + max(-bend, 0.0) * 0.5 * turn * turn + extra * turn


@njit(**JIT)
def _largest_turn(plane, turning, a, odd_a, b, odd_b, r, most, lateral, below, direction):
    """The largest turn of φ (rad, at most ``most``; 0 if none) in ``direction`` over which both half-planes,
    moved by their shifts (:func:`_shift`, each at most ``below``), still cover the disk of radius r, and
    each tip moves along its run by at most ``lateral`` (b) less r (the slab about it)."""
    hi = most
    for q in (a, b):
        speed = turning[q, 3] + turning[q, 2]  # b per radian, at most (0: a tip at the centre of rotation)
        if speed * hi > lateral:
            hi = lateral / speed
    lo = 0.0
    for k in range(31):
        turn = hi if k == 0 else 0.5 * (lo + hi)
        slack_a, slack_b = _shift(turning, a, odd_a, direction, turn), _shift(turning, b, odd_b, direction, turn)
        if slack_a <= below and slack_b <= below and _covered(plane, a, odd_a, slack_a, b, odd_b, slack_b, r):
            if k == 0:
                return hi
            lo = turn
        else:
            hi = turn
    return lo


@njit(**JIT)
def two_tips(curves, w, boxes2, cross, count, tx, ty, phi, r, near1, far1, roots, first):
    """(ahead, behind): an interval of φ about ``phi`` over which every translation of curve 2 shorter than ``r``
    overlaps, shown by two end points of the open curves; (0, 0) where none is found. Where one end point pokes
    through a side of the other curve and a second through (or close to) the opposite side, a short translation
    frees either alone but not both: no single pair of runs shows that depth.

    A tip e (of curve 1 or 2) near a run α of the other curve that is a graph over a line across the slab of
    half-width r + 2·s about e (:func:`_graph`; s = ρδ, ρ curve 2's radius, δ the turn of φ allowed), with runs
    from e and about α whose other three ends lie farther than that from the other run (:func:`_tip_runs`): the
    parity of their crossings changes only where e crosses α. Within the disk |v| < r it is one parity P for
    every v that leaves e below α (the side of e's foot on the line), the other above. So where P is odd the
    runs cross for every v that puts e lower than α's least height in the slab, where it is even higher than
    its greatest: a half-plane of translations. As φ turns by at most δ, e moves at most s relative to α and α
    turns by at most δ: the half-plane, its heights moved by e's motion across α's line (:func:`_shift`: as
    φ turns, e turns about t, seen from curve 2's frame where e is curve 1's), holds while the far ends stay r
    from the other run (:func:`_certified_interval`). Two tips whose half-planes cover the disk certify it. The
    graphs and runs are found for δ at most r/ρ (then 1/16 of that), and δ, ahead and behind, is the largest
    that keeps the disk covered (:func:`_largest_turn`).
    ``w``, ``boxes2``, ``cross``, ``count``: curve 2 at (t, φ) and its crossings."""
    v1, boxes1, v2, frame_boxes2, rin2, rout2, p1, p2 = curves
    if p1 or p2:
        return 0.0, 0.0  # a closed curve has no end points
    rho = 0.0
    for k in range(rout2.shape[0]):
        rho = max(rho, rout2[k])
    most = r / rho  # the widest turn tried
    sides, tips, nearest = np.empty(4, np.int64), np.empty(4, np.int64), np.empty(4, np.int64)
    m = 0
    for side, tip in ((1, 0), (1, v1.shape[0] - 1), (2, 0), (2, v2.shape[0] - 1)):
        own, other, other_boxes = (v1, w, boxes2) if side == 1 else (w, v1, boxes1)
        k, d2 = _nearest_index(own[tip, 0], own[tip, 1], other, other_boxes, 0, other.shape[0] - 1, np.inf)
        if d2 < (r + 2.0 * rho * most) ** 2:  # a tip farther than the widest slab from the other curve shows nothing
            sides[m], tips[m], nearest[m] = side, tip, k
            m += 1
    if m < 2:
        return 0.0, 0.0
    plane = np.empty((m, 4))  # per tip: the normal (a_x, a_y) in translations of curve 2, least and greatest heights
    turning = np.empty((m, 4))  # per tip: how its height above its run changes as φ turns (:func:`_shift`)
    graph = np.empty((m, 3), np.int64)  # per tip: c0, c1, and 1 where e lies above α (−1: no graph)
    runs = np.empty((2, 5), np.int64)
    odd = np.empty(2, np.bool_)
    for _ in range(2):
        reach = r + 2.0 * rho * most
        for q in range(m):
            own = v1 if sides[q] == 1 else w
            other = w if sides[q] == 1 else v1
            c0, c1, nx, ny, low, high, at_e = _graph(own[tips[q], 0], own[tips[q], 1], other, nearest[q], reach, most)
            sign = 1.0 if sides[q] == 2 else -1.0  # e moves by v (curve 2) or by −v (curve 1) relative to α
            plane[q, 0], plane[q, 1], plane[q, 2], plane[q, 3] = sign * nx, sign * ny, low, high
            # turning φ by δ moves e relative to α by (R(sign·δ) − I)·d, d = e − t (curve 2 turns about t); a
            # tip of curve 1 is seen from curve 2's frame, where the translation v turns too: at most r·|δ| more
            dx, dy = own[tips[q], 0] - tx, own[tips[q], 1] - ty
            turning[q, 0], turning[q, 1] = sign * (ny * dx - nx * dy), nx * dx + ny * dy
            turning[q, 2], turning[q, 3] = (0.0 if sides[q] == 2 else r), math.hypot(dx, dy)
            # no graph, or e too close to α to tell its side
            graph[q, 0], graph[q, 1], graph[q, 2] = c0, c1, (-1 if c0 < 0 or abs(at_e) < 1e-13 else at_e < 0.0)
        for a in range(m):
            for b in range(a + 1, m):
                if graph[a, 2] < 0 or graph[b, 2] < 0:
                    continue
                hope = False
                for oa in (False, True):
                    for ob in (False, True):
                        hope = hope or _covered(plane, a, oa, 0.0, b, ob, 0.0, r)
                if not hope:
                    continue  # no parities would do: the runs need not be found
                for k in range(2):
                    q = a if k == 0 else b
                    got = _tip_runs(curves, w, boxes2, cross, count, sides[q], tips[q], graph[q, 0], graph[q, 1], reach)
                    runs[k, 0], runs[k, 1], runs[k, 2], runs[k, 3], runs[k, 4] = got[0], got[1], got[2], got[3], got[4]
                    odd[k] = got[5] != (graph[q, 2] == 1)  # the parity below α: flipped where e lies above it
                if runs[0, 4] < 0 or runs[1, 4] < 0:
                    continue
                # a point of the disk stays below each α (its height less than the least, moved): the parity
                # below is the same all along
                below = min(plane[a, 2], plane[b, 2]) + 0.99 * r
                ahead = _largest_turn(plane, turning, a, odd[0], b, odd[1], r, most, 2.0 * rho * most, below, 1.0)
                if ahead * rho <= LEAST_TIP_STEP * r:
                    continue
                behind = 0.0
                if first:
                    behind = _largest_turn(plane, turning, a, odd[0], b, odd[1], r, most, 2.0 * rho * most, below, -1.0)
                for k in range(2):
                    got = _certified_interval(
                        v1, boxes1, near1, far1, runs[k, 0], runs[k, 1], v2, frame_boxes2, rin2, rout2, runs[k, 2],
                        runs[k, 3], tx, ty, r, phi, roots, TWO_PI if first else 0.0, runs[k, 4],
                    )  # fmt: skip
                    ahead, behind = min(ahead, got[0]), min(behind, got[1])
                if ahead * rho > LEAST_TIP_STEP * r:
                    return ahead, behind
        most /= 16.0
    return 0.0, 0.0


@njit(**JIT)
def segment_radii(v, cx, cy, near, far):
    """Nearest and farthest distance of each segment of polyline ``v`` from (cx, cy)."""
    for k in range(v.shape[0] - 1):
        near[k] = math.sqrt(point_segment_distance2(cx, cy, v[k, 0], v[k, 1], v[k + 1, 0], v[k + 1, 1]))
        far[k] = max(math.hypot(v[k, 0] - cx, v[k, 1] - cy), math.hypot(v[k + 1, 0] - cx, v[k + 1, 1] - cy))


@njit(**JIT)
def _runs_at(curves, tx, ty, phi, w, boxes2, cross):
    """(count, i0, i1, j0, j1, margin): :func:`_odd_runs` of ``curves`` with curve 2 turned by ``phi`` and moved
    to (tx, ty) (written to ``w``, ``boxes2``); count −1 where a pair meets degenerately."""
    v1, boxes1, v2, _, _, _, p1, p2 = curves
    c, s = math.cos(phi), math.sin(phi)
    for k in range(v2.shape[0]):
        w[k, 0] = tx + c * v2[k, 0] - s * v2[k, 1]
        w[k, 1] = ty + s * v2[k, 0] + c * v2[k, 1]
    chunk_boxes(w, boxes2)
    count = crossings(v1, boxes1, w, boxes2, cross, p1, p2)
    if count < 0 or count > MAX_CROSSINGS:
        return count, 0, 0, 0, 0, -1.0
    table = _parities(cross, count, v1.shape[0] - 1, w.shape[0] - 1)
    i0, i1, j0, j1, margin = _odd_runs(v1, boxes1, w, boxes2, cross, count, table, p1, p2)
    return count, i0, i1, j0, j1, margin


@njit(**JIT)
def _longest(curves, near1, far1, w, boxes2, cross, got, tx, ty, r, phi, roots, first, lengthen=1):
    """(ahead, behind, found, longer): the longest interval of φ about ``phi`` (behind only where ``first``)
    certified by the widest pair of ``got`` (:func:`_runs_at`; curve 2 in ``w``, crossings in ``cross``) where its
    ends are ``r`` apart, or by that pair with one run lengthened to the whole of its curve (a closed curve's longest
    run), where they cross oddly with their ends r apart; ``found`` False where none is. The ends of a whole
    curve lie far from the crossing, so a lengthened pair stays certified until the turning curve sweeps over
    an end of the short run: where the curves run close about a crossing (a shallow lens), pairs short on both
    sides keep apart only while a vertex of each lies in the lens, one interval per vertex passing it. Tried
    (``lengthen`` 1) where the curves cross at most LONG_CROSSINGS times and the widest pair is not r apart,
    or, for a closed curve 2, gives an interval shorter than a vertex takes to pass (2π / its segments);
    ``lengthen`` 2 tries it also where the widest pair of open curves is r apart, 0 never. ``longer``: the
    lengthened pair gave the interval. Deep in the excluded set a lengthened pair often holds nearly all
    the way round, where the widest pair stops each time an end point passes the other curve (cost only: the
    walk decides when to ask, :func:`cover`)."""
    v1, boxes1, v2, frame_boxes2, rin2, rout2, p1, p2 = curves
    count, i0, i1, j0, j1, margin = got
    behind0 = TWO_PI if first else 0.0
    ahead, behind, found = 0.0, 0.0, margin >= r
    if found:
        ahead, behind = _certified_interval(
            v1, boxes1, near1, far1, i0, i1, v2, frame_boxes2, rin2, rout2, j0, j1, tx, ty, r, phi, roots, behind0
        )
    n1, n2 = v1.shape[0] - 1, v2.shape[0] - 1
    if not lengthen or margin < 0.0 or count > LONG_CROSSINGS:
        return ahead, behind, found, False
    if found and lengthen < 2 and (not p2 or ahead + behind >= TWO_PI / p2):
        return ahead, behind, found, False
    longer = False
    no_table = np.zeros((1, 1), np.uint8)
    for side in (1, 2):  # about the run's middle: a closed curve's crossing, its longest run in the stored range
        a0, a1, b0, b1 = i0, i1, j0, j1
        if side == 1:  # curve 2's run lengthened
            b0, b1, _ = _run((j0 + j1) // 2, n2, p2, n2)
        else:
            a0, a1, _ = _run((i0 + i1) // 2, n1, p1, n1)
        if (a0, a1, b0, b1) == (i0, i1, j0, j1) or _inside_parity(cross, count, no_table, a0, a1, b0, b1) != 1:
            continue
        if _ends_clearance(v1, boxes1, a0, a1, w, boxes2, b0, b1, 4.0 * r * r) < r:
            continue
        a, b = _certified_interval(
            v1, boxes1, near1, far1, a0, a1, v2, frame_boxes2, rin2, rout2, b0, b1, tx, ty, r, phi, roots, behind0,
            -1, ahead + behind if found else -1.0,
        )  # fmt: skip
        if not found or a + b > ahead + behind:
            ahead, behind, found, longer = a, b, True, True
    return ahead, behind, found, longer


@njit(**JIT)
def cover(plain, halved, tx, ty, r, fallback, max_steps, start, tips, lengthen_apart=True):
    """(status, φ): status 1 if position (tx, ty) is certified at least ``r`` deep in the excluded set (module
    notes) within ``max_steps`` intervals of φ; 2 if not, but at least ``fallback`` deep (0 < ``fallback`` <
    ``r``; 0: not asked); 0 if at some φ no pair of runs crosses with its ends that far apart (the position may still be
    that deep: the certificate is one-sided), or if the walk at ``fallback`` took more than FALLBACK_STEPS
    intervals; −1 if ``max_steps`` were not enough at ``r``. Where the walk at ``r`` fails it goes on at
    ``fallback`` from there: what is certified at ``r`` is certified at any smaller depth.
    ``plain``, ``halved``: :func:`prepared`; the runs of ``halved`` may end at the middle of a segment, and are
    tried at a φ where no widest pair of ``plain`` is r apart. At each φ the pair that certifies the longest interval
    is taken (:func:`_longest`); from the second interval on also lengthened where the widest pair is r apart,
    until once that gives no longer interval (at ε + h in the rims of the ASP at Ψ = 45°: a median of 4
    intervals instead of 24; a try that fails costs a shallow walk). The walk begins at φ = ``start``
    (radians): where the position is least deep there (an orientation allowed nearby), a walk that fails fails
    at once. ``tips``: where no pair of runs is r apart, try two end points of the open curves (:func:`two_tips`).
    ``lengthen_apart``: False never lengthens a pair that is r apart (for comparison: ``benchmarks/depth_walk.py``).
    φ (radians): where the walk stopped, the orientation at which a walk that fails failed (nearby positions at
    a like depth fail there too: a walk begun there fails at once)."""
    near1, far1 = np.empty(plain[0].shape[0] - 1), np.empty(plain[0].shape[0] - 1)
    near1h, far1h = np.empty(halved[0].shape[0] - 1), np.empty(halved[0].shape[0] - 1)
    segment_radii(plain[0], tx, ty, near1, far1)
    segment_radii(halved[0], tx, ty, near1h, far1h)
    w, wh = np.empty_like(plain[2]), np.empty_like(halved[2])
    boxes2, boxes2h = np.empty((chunk_count(plain[2]), 4)), np.empty((chunk_count(halved[2]), 4))
    cross, cross_h = np.empty((MAX_CROSSINGS, 2), dtype=np.int64), np.empty((MAX_CROSSINGS, 2), dtype=np.int64)
    roots = np.empty(16)
    phi = start
    first, first_behind = True, 0.0
    proved, at_fallback = 1, 0
    lengthen = False  # also lengthen a pair that is r apart: from the second interval on, while it pays
    for _ in range(max_steps):
        got = _runs_at(plain, tx, ty, phi, w, boxes2, cross)
        for _ in range(2):  # beside a degenerate touch the parity is defined
            if got[0] >= 0:
                break
            phi += 1e-9
            got = _runs_at(plain, tx, ty, phi, w, boxes2, cross)
        if got[0] < 0 or got[0] > MAX_CROSSINGS:
            return 0, phi
        ahead, behind, found, longer = _longest(
            plain, near1, far1, w, boxes2, cross, got, tx, ty, r, phi, roots, first, 2 if lengthen else 1
        )
        if lengthen and got[5] >= r and not longer:
            lengthen = False
        if got[5] < r:  # no widest pair: runs that may end at the middle of a segment
            finer = _runs_at(halved, tx, ty, phi, wh, boxes2h, cross_h)
            if 0 <= finer[0] <= MAX_CROSSINGS:
                a, b, f, _ = _longest(
                    halved, near1h, far1h, wh, boxes2h, cross_h, finer, tx, ty, r, phi, roots, first, 0
                )
                if f and (not found or a + b > ahead + behind):
                    ahead, behind, found = a, b, True
        if not found and tips and proved == 1:  # two end points, each through or near a side of the other curve
            ahead, behind = two_tips(plain, w, boxes2, cross, got[0], tx, ty, phi, r, near1, far1, roots, first)
            found = ahead > 0.0
        if not found and proved == 1 and fallback > 0.0:  # go on at ``fallback`` from this φ
            r, proved = fallback, 2
            ahead, behind, found, _ = _longest(plain, near1, far1, w, boxes2, cross, got, tx, ty, r, phi, roots, first)
        if not found:
            return 0, phi
        if first:
            first, first_behind = False, behind
            lengthen = lengthen_apart
        if phi + ahead >= start + TWO_PI - first_behind:
            return proved, phi
        if proved == 2:
            at_fallback += 1
            if at_fallback > FALLBACK_STEPS:
                return 0, phi
        phi += ahead + 1e-12  # the interval is closed: its end is certified
    return (-1 if proved == 1 else 0), phi  # out of steps at ``fallback``: nothing proved


@njit(**JIT, parallel=True)
def cover_at(plain, halved, xs, ys, rs, fallback, max_steps, starts, tips, lengthen, out, stops):
    """``out[p]``, ``stops[p]``: :func:`cover` of (xs[p], ys[p]) at depth ``rs[p]`` (else ``fallback``) with
    ``max_steps[p]`` intervals, its walk begun at φ = ``starts[p]``. Each position is written by one thread."""
    for p in prange(xs.shape[0]):
        out[p], stops[p] = cover(plain, halved, xs[p], ys[p], rs[p], fallback, max_steps[p], starts[p], tips, lengthen)


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
    return v1, boxes1, v2, chunk_boxes(v2, np.empty((chunk_count(v2), 4))), rin2, rout2, p1, p2


def prepared(v1, v2):
    """The arguments of :func:`cover` that depend on the curves only: the polylines as they are, and halved."""
    return _curves(v1, v2), _curves(_halved(v1), _halved(v2))


def certified_deep(
    prepared_curves, xs, ys, rs, max_steps, fallback=0.0, start=0.0, tips=True, lengthen=True, stops=None
):
    """(p,) int8, :func:`cover` of each position (b) at depth ``rs`` (b), else ``fallback`` (b; 0: not asked),
    with ``max_steps`` intervals of φ, each walk begun at φ = ``start`` (radians; all broadcast), trying two end
    points where one pair of runs falls short if ``tips``, lengthening pairs that are r apart if ``lengthen``
    (:func:`cover`); ``prepared_curves``: :func:`prepared`. ``stops``: a (p,) float array to receive the
    orientation (radians) at which each walk stopped (where it failed, for one that failed), or None."""
    xs = np.ascontiguousarray(xs, dtype=float)
    ys = np.ascontiguousarray(ys, dtype=float)
    rs = np.ascontiguousarray(np.broadcast_to(np.asarray(rs, dtype=float), xs.shape))
    steps = np.ascontiguousarray(np.broadcast_to(np.asarray(max_steps, dtype=np.int64), xs.shape))
    starts = np.ascontiguousarray(np.broadcast_to(np.asarray(start, dtype=float), xs.shape))
    out = np.zeros(xs.shape[0], dtype=np.int8)
    where = np.empty(xs.shape[0]) if stops is None else stops
    with small_chunks():
        cover_at(*prepared_curves, xs, ys, rs, float(fallback), steps, starts, bool(tips), bool(lengthen), out, where)
    return out
