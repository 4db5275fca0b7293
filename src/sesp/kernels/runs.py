"""Run kernels: pairs of runs of two polylines that cross oddly, and how long, in φ, their ends stay apart.

A run is a stretch of consecutive segments of one polyline. Two runs that
cross an odd number of times keep crossing under every motion during which
no end point of one touches the other (the parity of the crossing number
changes only there; Guillemin and Pollack, *Differential Topology*, ch. 2).
At a fixed translation t each end point moves on a circle as φ turns, and
its distance to a segment of the other run reaches r only at roots of
sinusoids in φ: :func:`certified_interval` finds, in closed form, the
interval of φ over which every end point stays at least r from the other
run. :func:`widest_odd_runs` picks the pair of odd runs whose ends lie
farthest from the other run at one φ.

Structured arguments (named tuples, read by name inside the kernels):

* :data:`Curves` — the two polylines as the kernels store them: ``v1`` and
  ``boxes1`` (curve 1 and the boxes of its runs of ``CHUNK`` segments),
  ``v2`` and ``frame_boxes2`` (curve 2 in its own frame), ``rin2``,
  ``rout2`` (each segment's least and greatest distance from curve 2's
  centre) and ``p1``, ``p2`` (segments of a closed curve stored twice over so
  that runs may pass its first vertex; 0 for an open one);
* :data:`Moved` — curve 2 at (t, φ): ``w``, its chunk boxes ``boxes2`` and
  room ``cross`` for the crossing segment pairs;
* :data:`Walk` — one position's walk around φ: ``curves``, ``near1`` and
  ``far1`` (curve 1's segments' distances from t), ``tx``, ``ty``, the depth
  ``r`` (b) at which the curves must stay crossed, the ``margin`` (b) by which
  thick particles may come apart and still overlap (contact distance less the
  particles' depth sought; ≤ 0: none), scratch ``roots`` and the walk's
  ``options`` (:data:`sesp.kernels.depth.Options`).
"""

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .common import CHUNK, JIT, chunk_boxes, point_segment_distance2, sort_first
from .orientations import TWO_PI, boxes_distance2, sinusoid_roots

Curves = namedtuple("Curves", "v1 boxes1 v2 frame_boxes2 rin2 rout2 p1 p2")
Moved = namedtuple("Moved", "w boxes2 cross")
Walk = namedtuple("Walk", "curves near1 far1 tx ty r margin roots options")


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
                if point_box2(0.5 * (px + qx), 0.5 * (py + qy), boxes2[b]) > 0.26 * ((qx - px) ** 2 + (qy - py) ** 2):
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
def point_box2(x, y, box):
    """Squared distance from (x, y) to the box (xmin, xmax, ymin, ymax)."""
    dx = max(0.0, box[0] - x, x - box[1])
    dy = max(0.0, box[2] - y, y - box[3])
    return dx * dx + dy * dy


@njit(**JIT)
def nearest_index(x, y, v, boxes, lo, hi, best2):
    """(k, d²): the segment k of polyline v (lo <= k < hi) nearest to (x, y) and its squared distance, where it
    is nearer than ``best2`` (else −1, best2); runs of ``CHUNK`` segments whose box (``boxes``) is farther than
    the best so far are skipped."""
    best = -1
    for c in range(lo // CHUNK, (hi - 1) // CHUNK + 1):
        if point_box2(x, y, boxes[c]) >= best2:
            continue
        for k in range(max(lo, c * CHUNK), min(hi, (c + 1) * CHUNK)):
            d2 = point_segment_distance2(x, y, v[k, 0], v[k, 1], v[k + 1, 0], v[k + 1, 1])
            if d2 < best2:
                best2, best = d2, k
    return best, best2


@njit(**JIT)
def nearest2(x, y, v, boxes, lo, hi, best2):
    """min(best2, squared distance from (x, y) to segments lo..hi-1 of polyline v)."""
    return nearest_index(x, y, v, boxes, lo, hi, best2)[1]


@njit(**JIT)
def ends_clearance(one, two, runs, most2=np.inf):
    """Distance of the nearest end point of run i0..i1 of ``one`` to run j0..j1 of ``two``, or of an end of
    ``two``'s run to ``one``'s, at most √``most2`` (a bound skips the segments farther than it). ``one``,
    ``two``: (vertices, chunk boxes); ``runs``: (i0, i1, j0, j1)."""
    v1, boxes1 = one
    w, boxes2 = two
    i0, i1, j0, j1 = runs
    m2 = nearest2(v1[i0, 0], v1[i0, 1], w, boxes2, j0, j1, most2)
    m2 = nearest2(v1[i1, 0], v1[i1, 1], w, boxes2, j0, j1, m2)
    m2 = nearest2(w[j0, 0], w[j0, 1], v1, boxes1, i0, i1, m2)
    m2 = nearest2(w[j1, 0], w[j1, 1], v1, boxes1, i0, i1, m2)
    return math.sqrt(m2)


@njit(**JIT)
def run_about(i, half, period, n):
    """Vertices (i0, i1) of the run of up to 2·half segments about segment i, and whether it can grow no more: an
    open curve's run is clipped at its ends; a closed curve (``period`` segments, stored twice) has no ends, and
    its runs grow to ``period`` − 1 segments."""
    if period:
        h = min(half, period // 2)
        return i - h + 1, i + h, h == period // 2
    i0, i1 = max(0, i - half + 1), min(n, i + half)
    return i0, i1, i0 == 0 and i1 == n


@njit(**JIT)
def parity_table(cross, count, n1, n2):
    """(n1 + 1, n2 + 1) uint8: entry (a, b) is the parity of the crossings (i, j) with i < a and j < b, so the parity
    of those inside runs [i0, i1) × [j0, j1) is four look-ups (:func:`inside_parity`)."""
    table = np.zeros((n1 + 1, n2 + 1), np.uint8)
    for k in range(count):
        table[cross[k, 0] + 1, cross[k, 1] + 1] ^= 1
    for a in range(1, n1 + 1):
        for b in range(1, n2 + 1):
            table[a, b] ^= table[a - 1, b] ^ table[a, b - 1] ^ table[a - 1, b - 1]
    return table


@njit(**JIT)
def inside_parity(cross, count, table, runs):
    """Parity of the crossings with i0 <= i < i1 and j0 <= j < j1 (``runs``: (i0, i1, j0, j1)): from ``table``
    where it is built (many crossings), else counted."""
    i0, i1, j0, j1 = runs
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
def _no_wider(v1, w, runs, i, j, best):
    """True where :func:`ends_clearance` of ``runs`` (i0, i1, j0, j1, holding the crossing segments i and j)
    cannot exceed ``best``: an end lies within ``best`` of the other run's first, crossing or last segment (the
    same arithmetic as the full measure; the square root of fl(best²) is best itself, so the test is exact)."""
    if best < 0.0:
        return False
    i0, i1, j0, j1 = runs
    b2 = best * best
    return (
        _nearer(v1[i0, 0], v1[i0, 1], w, j0, j, j1 - 1, b2)
        or _nearer(v1[i1, 0], v1[i1, 1], w, j0, j, j1 - 1, b2)
        or _nearer(w[j0, 0], w[j0, 1], v1, i0, i, i1 - 1, b2)
        or _nearer(w[j1, 0], w[j1, 1], v1, i0, i, i1 - 1, b2)
    )


@njit(**JIT)
def parities(cross, count, n1, n2):
    """The parity table of :func:`parity_table` where the crossings are many (counting them run by run would
    cost more), else an empty one: :func:`inside_parity` then counts."""
    levels = int(math.log2(max(n1, n2))) + 1
    if count * count * levels > (n1 + 1) * (n2 + 1):
        return parity_table(cross, count, n1, n2)
    return np.zeros((1, 1), np.uint8)


@njit(**JIT)
def widest_odd_runs(curves, moved, count, table):
    """(i0, i1, j0, j1, margin): the runs of segments (vertices i0..i1 of curve 1, j0..j1 of curve 2 at (t, φ),
    ``moved.w``) with an odd number of crossings whose ends are farthest from the other run; margin −1 if none:
    the whole curves, and runs of 1, 2, 4, ... segments about each crossing (a closed curve's may pass its
    first vertex). ``count`` crossings are in ``moved.cross``; ``table``: :func:`parities`. A run whose ends lie
    no farther from a few of the other run's segments than the best margin so far is not measured (its margin
    cannot be wider)."""
    v1, boxes1, p1, p2 = curves.v1, curves.boxes1, curves.p1, curves.p2
    w, boxes2, cross = moved
    n1, n2 = v1.shape[0] - 1, w.shape[0] - 1
    g1 = p1 if p1 else n1
    g2 = p2 if p2 else n2
    best = -1.0
    bi0 = bi1 = bj0 = bj1 = 0
    if inside_parity(cross, count, table, (0, g1, 0, g2)) == 1:
        best = ends_clearance((v1, boxes1), (w, boxes2), (0, g1, 0, g2))
        bi0, bi1, bj0, bj1 = 0, g1, 0, g2
    for c in range(count):
        i, j = cross[c, 0], cross[c, 1]
        if (p1 and not (p1 // 2 <= i < p1 // 2 + p1)) or (p2 and not (p2 // 2 <= j < p2 // 2 + p2)):
            continue  # a copy of a crossing seen in the middle of the stored curves
        half = 1
        while True:
            i0, i1, full1 = run_about(i, half, p1, n1)
            j0, j1, full2 = run_about(j, half, p2, n2)
            if full1 and full2 and not p1 and not p2:
                break  # the whole curves, tried above
            runs = (i0, i1, j0, j1)
            if inside_parity(cross, count, table, runs) == 1 and not _no_wider(v1, w, runs, i, j, best):
                margin = ends_clearance((v1, boxes1), (w, boxes2), runs)
                if margin > best:
                    best = margin
                    bi0, bi1, bj0, bj1 = i0, i1, j0, j1
            if full1 and full2:
                break
            half *= 2
    return bi0, bi1, bj0, bj1, best


@njit(**JIT)
def _approach(circle, segment, r, phi0, roots, interval):
    """Shrink ``interval`` (ahead, behind): how far φ may turn from ``phi0`` before the point
    o + a cos φ + b sin φ (``circle``: (ox, oy, ax, ay, bx, by); |a| = |b|, a ⊥ b) comes within ``r`` of
    ``segment`` (px, py, qx, qy). (0, 0) if it is within r at ``phi0``."""
    ox, oy, ax, ay, bx, by = circle
    px, py, qx, qy = segment
    ahead, behind = interval
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
def _point_interval(circle, run, r, phi0, roots, interval):
    """Shrink ``interval`` (ahead, behind) by the first φ on either side of ``phi0`` at which the point
    o + a cos φ + b sin φ (``circle``, as :func:`_approach`) comes within ``r`` of a segment of ``run``:
    (v, boxes, near, far, lo, hi), segments lo..hi-1 of polyline v with the boxes of its chunks and each
    segment's distances from the circle's centre o. Runs of segments are visited nearest first, and the rest
    skipped once they are too far to be reached within the interval: the point moves at most |a| per radian; a
    segment that keeps out of the annulus |a| ± r is never reached."""
    ox, oy, ax, ay, bx, by = circle
    v, boxes, near, far, lo, hi = run
    ahead, behind = interval
    c, s = math.cos(phi0), math.sin(phi0)
    x0, y0 = ox + ax * c + bx * s, oy + ay * c + by * s
    speed = math.hypot(ax, ay)
    first, last = lo // CHUNK, (hi - 1) // CHUNK
    gaps = np.empty(last - first + 1)
    for k in range(first, last + 1):
        gaps[k - first] = math.sqrt(point_box2(x0, y0, boxes[k]))
    for k in np.argsort(gaps):
        if gaps[k] - r >= speed * max(ahead, behind):
            break
        chunk = first + k
        for i in range(max(lo, chunk * CHUNK), min(hi, (chunk + 1) * CHUNK)):
            if speed < near[i] - r or speed > far[i] + r:
                continue
            segment = (v[i, 0], v[i, 1], v[i + 1, 0], v[i + 1, 1])
            ahead, behind = _approach(circle, segment, r, phi0, roots, (ahead, behind))
            if ahead == 0.0:
                return 0.0, 0.0
    return ahead, behind


@njit(**JIT)
def certified_interval(walk, runs, phi0, behind, skip=-1, least=-1.0):
    """(ahead, behind): the interval of φ about ``phi0`` over which every end point of the two ``runs``
    (i0, i1, j0, j1) stays at least ``walk.r`` from the other run. ``behind``: 2π to find how far back the
    interval reaches, 0 where only ahead matters. ``skip``: an end not to follow (0 to 3: i0, i1, j0, j1; −1
    none). Where ahead + behind falls to ``least`` or below, it is returned at once (shorter than an interval
    found already)."""
    curves, r, tx, ty = walk.curves, walk.r, walk.tx, walk.ty
    v1, v2 = curves.v1, curves.v2
    i0, i1, j0, j1 = runs
    ahead = TWO_PI
    run2 = (v2, curves.frame_boxes2, curves.rin2, curves.rout2, j0, j1)
    for a in (i0, i1):  # a fixed end of run 1, seen from curve 2's frame, turns by −φ about the origin
        if skip == (0 if a == i0 else 1) or ahead + behind <= least:
            continue
        gx, gy = v1[a, 0] - tx, v1[a, 1] - ty
        ahead, behind = _point_interval((0.0, 0.0, gx, gy, gy, -gx), run2, r, phi0, walk.roots, (ahead, behind))
    run1 = (v1, curves.boxes1, walk.near1, walk.far1, i0, i1)
    for b in (j0, j1):  # a moving end of run 2 turns by φ about t
        if skip == (2 if b == j0 else 3) or ahead + behind <= least:
            continue
        wx, wy = v2[b, 0], v2[b, 1]
        ahead, behind = _point_interval((tx, ty, wx, wy, -wy, wx), run1, r, phi0, walk.roots, (ahead, behind))
    return ahead, behind


@njit(**JIT)
def segment_radii(v, cx, cy, near, far):
    """Nearest and farthest distance of each segment of polyline ``v`` from (cx, cy)."""
    for k in range(v.shape[0] - 1):
        near[k] = math.sqrt(point_segment_distance2(cx, cy, v[k, 0], v[k, 1], v[k + 1, 0], v[k + 1, 1]))
        far[k] = max(math.hypot(v[k, 0] - cx, v[k, 1] - cy), math.hypot(v[k + 1, 0] - cx, v[k + 1, 1] - cy))


@njit(**JIT)
def runs_at(curves, tx, ty, phi, moved, max_crossings):
    """(count, i0, i1, j0, j1, margin): :func:`widest_odd_runs` with curve 2 turned by ``phi`` and moved to
    (tx, ty) (written to ``moved``); count −1 where a pair meets degenerately, margin −1 where the curves cross
    more than ``max_crossings`` times or no runs cross oddly."""
    v1, v2 = curves.v1, curves.v2
    w, boxes2, cross = moved
    c, s = math.cos(phi), math.sin(phi)
    for k in range(v2.shape[0]):
        w[k, 0] = tx + c * v2[k, 0] - s * v2[k, 1]
        w[k, 1] = ty + s * v2[k, 0] + c * v2[k, 1]
    chunk_boxes(w, boxes2)
    count = crossings(v1, curves.boxes1, w, boxes2, cross, curves.p1, curves.p2)
    if count < 0 or count > max_crossings:
        return count, 0, 0, 0, 0, -1.0
    table = parities(cross, count, v1.shape[0] - 1, w.shape[0] - 1)
    i0, i1, j0, j1, margin = widest_odd_runs(curves, moved, count, table)
    return count, i0, i1, j0, j1, margin
