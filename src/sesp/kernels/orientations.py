"""Orientation kernels: the φ intervals in which two curves meet at a fixed translation, exact in φ."""

import math

import numpy as np
from numba import njit, prange

from .common import CHUNK, JIT, chunk_boxes, chunk_count, point_segment_distance2, small_chunks, sort_first

TWO_PI = 2.0 * math.pi


@njit(**JIT)
def sinusoid_roots(c, a, b, roots, n):
    """Append to ``roots`` the φ in [0, 2π) where c + a cos φ + b sin φ = 0; return the new count."""
    r = math.hypot(a, b)
    if r == 0.0 or abs(c) > r:
        return n
    centre = math.atan2(b, a)
    half = math.acos(min(1.0, max(-1.0, -c / r)))
    for phi in (centre - half, centre + half):
        roots[n] = phi % TWO_PI
        n += 1
    return n


@njit(**JIT)
def _pair_signs(phi, k1, k2, k3, k4):
    """Whether the segments meet at φ: both pairs of orientation values change sign (or vanish)."""
    c = math.cos(phi)
    s = math.sin(phi)
    s1 = k1[0] + k1[1] * c + k1[2] * s
    s2 = k2[0] + k2[1] * c + k2[2] * s
    s3 = k3[0] + k3[1] * c + k3[2] * s
    s4 = k4[0] + k4[1] * c + k4[2] * s
    return s1 * s2 <= 0.0 and s3 * s4 <= 0.0


@njit(**JIT)
def _crossing_sinusoids(px, py, qx, qy, ux, uy, vx, vy, tx, ty):
    """(k1, k2, k3, k4): the orientation values of the four end points against the other segment's line.

    Each is (c, α, β) of the sinusoid c + α cos φ + β sin φ: k1, k2 for u, v
    against p–q (|d| × signed distance), k3, k4 for p, q against the moving
    segment (|e| × signed distance).
    """
    dx = qx - px
    dy = qy - py
    ex = vx - ux
    ey = vy - uy
    base = dx * (ty - py) - dy * (tx - px)
    k1 = (base, dx * uy - dy * ux, dx * ux + dy * uy)
    k2 = (base, dx * vy - dy * vx, dx * vx + dy * vy)
    offset = -(ex * uy - ey * ux)
    gx, gy = px - tx, py - ty
    k3 = (offset, -(gx * ey - gy * ex), -(gx * ex + gy * ey))
    gx, gy = qx - tx, qy - ty
    k4 = (offset, -(gx * ey - gy * ex), -(gx * ex + gy * ey))
    return k1, k2, k3, k4


@njit(**JIT)
def _cuts(roots, m):
    """Add 0 and 2π to the m roots and sort the m + 2 in place (insertion sort: at most 50): the ends of the
    pieces on which a pair's answer is constant."""
    roots[m] = 0.0
    roots[m + 1] = TWO_PI
    sort_first(roots, m + 2)
    return roots


@njit(**JIT)
def _append_piece(lo, hi, starts, ends, n):
    """Append the blocked piece [lo, hi], merging it with the previous one when they touch; return the count."""
    if n > 0 and ends[n - 1] == lo:  # continues the piece before
        ends[n - 1] = hi
        return n
    starts[n] = lo
    ends[n] = hi
    return n + 1


@njit(**JIT)
def _pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, starts, ends, n, roots):
    """Append the φ intervals where fixed segment pq meets t + R_φ[uv]; return the new count.

    Segments meet exactly when each one's end points lie on opposite sides of
    (or on) the other's line. Every such orientation value is a sinusoid
    c + α cos φ + β sin φ in φ, so between consecutive roots of the four the
    answer is constant: one midpoint test per piece.
    """
    k1, k2, k3, k4 = _crossing_sinusoids(px, py, qx, qy, ux, uy, vx, vy, tx, ty)
    m = 0
    for k in (k1, k2, k3, k4):
        m = sinusoid_roots(k[0], k[1], k[2], roots, m)
    cuts = _cuts(roots, m)
    for i in range(m + 1):
        lo = cuts[i]
        hi = cuts[i + 1]
        if hi > lo and _pair_signs(0.5 * (lo + hi), k1, k2, k3, k4):
            n = _append_piece(lo, hi, starts, ends, n)
    return n


@njit(**JIT)
def _within(px, py, qx, qy, ux, uy, vx, vy, crossing, contact):
    """Whether segments p–q and u–v come within ``contact``: they cross, or an end point is that close."""
    if crossing:
        return True
    r2 = contact * contact
    return (
        point_segment_distance2(px, py, ux, uy, vx, vy) <= r2
        or point_segment_distance2(qx, qy, ux, uy, vx, vy) <= r2
        or point_segment_distance2(ux, uy, px, py, qx, qy) <= r2
        or point_segment_distance2(vx, vy, px, py, qx, qy) <= r2
    )


@njit(**JIT)
def _thick_pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, contact, starts, ends, n, roots):
    """:func:`_pair_angles` for thick particles: the φ intervals where the segments come within ``contact``.

    Within ``contact`` means crossing, or an end point within ``contact`` of
    the other segment. Each of these conditions changes only where a
    sinusoid in φ vanishes: the four orientation values (crossing), the same
    shifted by ±contact · length (distance of an end point from the other
    line), the projections of each end point on the other segment reaching
    its ends, and the distances between end points reaching ``contact``. So
    between consecutive roots of those 24 sinusoids the answer is constant:
    one midpoint test per piece.
    """
    k1, k2, k3, k4 = _crossing_sinusoids(px, py, qx, qy, ux, uy, vx, vy, tx, ty)
    dx = qx - px
    dy = qy - py
    ex = vx - ux
    ey = vy - uy
    dlen = math.hypot(dx, dy)
    elen = math.hypot(ex, ey)
    gpx, gpy = px - tx, py - ty
    gqx, gqy = qx - tx, qy - ty
    m = 0
    for k in (k1, k2):
        for shift in (0.0, contact * dlen, -contact * dlen):
            m = sinusoid_roots(k[0] + shift, k[1], k[2], roots, m)
    for k in (k3, k4):
        for shift in (0.0, contact * elen, -contact * elen):
            m = sinusoid_roots(k[0] + shift, k[1], k[2], roots, m)
    along = (tx - px) * dx + (ty - py) * dy
    for wx, wy in ((ux, uy), (vx, vy)):  # moving end points' projections on p–q reach its ends
        a = wx * dx + wy * dy
        b = wx * dy - wy * dx
        m = sinusoid_roots(along, a, b, roots, m)
        m = sinusoid_roots(along - dlen * dlen, a, b, roots, m)
    for gx, gy in ((gpx, gpy), (gqx, gqy)):  # fixed end points' projections on the moving segment
        c0 = -(ux * ex + uy * ey)
        a = gx * ex + gy * ey
        b = gy * ex - gx * ey
        m = sinusoid_roots(c0, a, b, roots, m)
        m = sinusoid_roots(c0 - elen * elen, a, b, roots, m)
        for wx, wy in ((ux, uy), (vx, vy)):  # end point to end point at distance contact
            m = sinusoid_roots(
                gx * gx + gy * gy + wx * wx + wy * wy - contact * contact,
                -2.0 * (gx * wx + gy * wy),
                -2.0 * (gy * wx - gx * wy),
                roots,
                m,
            )
    cuts = _cuts(roots, m)
    for i in range(m + 1):
        lo = cuts[i]
        hi = cuts[i + 1]
        if hi <= lo:
            continue
        mid = 0.5 * (lo + hi)
        c = math.cos(mid)
        s = math.sin(mid)
        crossing = _pair_signs(mid, k1, k2, k3, k4)
        ax, ay = tx + c * ux - s * uy, ty + s * ux + c * uy
        bx, by = tx + c * vx - s * vy, ty + s * vx + c * vy
        if _within(px, py, qx, qy, ax, ay, bx, by, crossing, contact):
            n = _append_piece(lo, hi, starts, ends, n)
    return n


@njit(**JIT)
def _segment_distances(vx0, vy0, vx1, vy1, x, y):
    """(nearest, farthest) distance from (x, y) to the segment."""
    near = math.sqrt(point_segment_distance2(x, y, vx0, vy0, vx1, vy1))
    far = max(math.hypot(vx0 - x, vy0 - y), math.hypot(vx1 - x, vy1 - y))
    return near, far


@njit(**JIT)
def radial_spans(v):
    """(rin, rout, order, sorted rin, widest rout − rin): each segment's nearest and farthest distance from the
    curve's centre, and the segments sorted by ``rin``. Rotated about its centre, segment j sweeps the annulus
    [rin[j], rout[j]]."""
    n = v.shape[0] - 1
    rin = np.empty(n)
    rout = np.empty(n)
    widest = 0.0
    for j in range(n):
        rin[j], rout[j] = _segment_distances(v[j, 0], v[j, 1], v[j + 1, 0], v[j + 1, 1], 0.0, 0.0)
        widest = max(widest, rout[j] - rin[j])
    order = np.argsort(rin, kind="mergesort")
    return rin, rout, order, rin[order], widest


@njit(**JIT)
def _candidates(spans2, near, far, widen, out):
    """Write to ``out`` the segments j of curve 2 whose annulus comes within ``widen`` of the distances
    [near, far] of a segment of curve 1 from t (in order of rin); return how many.

    With curve 2's segments sorted by rin they are one run of that order (rin
    between near − widen − the widest annulus and far + widen): two binary
    searches and a check of each.
    """
    rin, rout, order, sorted_rin, widest = spans2
    first = np.searchsorted(sorted_rin, near - widen - widest, side="left")
    last = np.searchsorted(sorted_rin, far + widen, side="right")
    m = 0
    for k in range(first, last):
        j = order[k]
        if near > rout[j] + widen or far < rin[j] - widen:
            continue
        out[m] = j
        m += 1
    return m


@njit(**JIT)
def _grow(starts, ends, n, cap):
    """The interval buffers, doubled when fewer than 26 free places are left (one pair adds at most 25)."""
    if n + 26 <= cap:
        return starts, ends, cap
    cap *= 2
    grown_s = np.empty(cap)
    grown_e = np.empty(cap)
    grown_s[:n] = starts[:n]
    grown_e[:n] = ends[:n]
    return grown_s, grown_e, cap


@njit(**JIT)
def blocked_angles(v1, v2, spans2, tx, ty, slack, contact):
    """Sorted (starts, ends) of the φ intervals in [0, 2π) where curve 2 at t comes within ``contact`` of curve 1.

    Pairs are screened first: rotated about its centre, segment j of curve 2
    sweeps the annulus of radii [rin, rout] (``spans2`` = :func:`radial_spans`
    of curve 2) about t, so it can meet segment i only if segment i reaches
    that annulus (widened by ``slack`` + ``contact``). With curve 2's segments
    sorted by rin, the candidates for segment i are one run of that order
    (rin between the segment's nearest distance minus the widest annulus and
    its farthest distance), found by two binary searches: the work per
    position is O(N log N) plus the pairs that do meet at some φ.
    """
    widen = slack + contact
    cap = 64
    starts = np.empty(cap)
    ends = np.empty(cap)
    roots = np.empty(52)  # scratch for one pair's roots: at most 48, and 0 and 2π
    candidates = np.empty(spans2[0].shape[0], dtype=np.int64)
    n = 0
    for i in range(v1.shape[0] - 1):
        px, py, qx, qy = v1[i, 0], v1[i, 1], v1[i + 1, 0], v1[i + 1, 1]
        near, far = _segment_distances(px, py, qx, qy, tx, ty)
        for k in range(_candidates(spans2, near, far, widen, candidates)):
            j = candidates[k]
            starts, ends, cap = _grow(starts, ends, n, cap)
            ux, uy, vx, vy = v2[j, 0], v2[j, 1], v2[j + 1, 0], v2[j + 1, 1]
            if contact > 0.0:
                n = _thick_pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, contact, starts, ends, n, roots)
            else:
                n = _pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, starts, ends, n, roots)
    order_out = np.argsort(starts[:n], kind="mergesort")
    return starts[:n][order_out], ends[:n][order_out]


@njit(**JIT)
def free_measure(starts, ends, gap):
    """Measure of [0, 2π) outside the union of sorted intervals; gaps narrower than ``gap`` count as closed."""
    free = 0.0
    reach = 0.0
    for k in range(starts.shape[0]):
        if starts[k] - reach > gap:
            free += starts[k] - reach
        reach = max(reach, ends[k])
    if TWO_PI - reach > gap:
        free += TWO_PI - reach
    return free


@njit(**JIT)
def largest_window(starts, ends, gap):
    """(width, middle) of the widest allowed φ window, radians, φ periodic; (0, 0) if none is wider than ``gap``.

    ``starts``, ``ends``: sorted blocked intervals in [0, 2π]; no interval: (2π, 0).
    """
    n = starts.shape[0]
    if n == 0:
        return TWO_PI, 0.0
    best = 0.0
    middle = 0.0
    reach = ends[0]
    for k in range(1, n):
        if starts[k] - reach > best:
            best = starts[k] - reach
            middle = reach + 0.5 * best
        reach = max(reach, ends[k])
    across = TWO_PI - reach + starts[0]  # the window through φ = 0
    if across > best:
        best = across
        middle = (reach + 0.5 * across) % TWO_PI
    if best <= gap:
        return 0.0, 0.0
    return best, middle


@njit(**JIT)
def _segments_distance2(px, py, qx, qy, ax, ay, bx, by):
    """Squared distance between segments p–q and a–b: 0 when they cross."""
    d1 = (qx - px) * (ay - py) - (qy - py) * (ax - px)
    d2 = (qx - px) * (by - py) - (qy - py) * (bx - px)
    d3 = (bx - ax) * (py - ay) - (by - ay) * (px - ax)
    d4 = (bx - ax) * (qy - ay) - (by - ay) * (qx - ax)
    if d1 * d2 <= 0.0 and d3 * d4 <= 0.0:
        return 0.0
    return min(
        point_segment_distance2(ax, ay, px, py, qx, qy),
        point_segment_distance2(bx, by, px, py, qx, qy),
        point_segment_distance2(px, py, ax, ay, bx, by),
        point_segment_distance2(qx, qy, ax, ay, bx, by),
    )


@njit(**JIT)
def _gap2(ax0, ax1, ay0, ay1, bx0, bx1, by0, by1):
    """Squared distance between the boxes [ax0, ax1] × [ay0, ay1] and [bx0, bx1] × [by0, by1]."""
    dx = max(0.0, ax0 - bx1, bx0 - ax1)
    dy = max(0.0, ay0 - by1, by0 - ay1)
    return dx * dx + dy * dy


@njit(**JIT)
def boxes_distance2(a, b):
    """Squared distance between two boxes (xmin, xmax, ymin, ymax), as :func:`chunk_boxes` writes them."""
    return _gap2(a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3])


@njit(**JIT)
def placed(v2, tx, ty, phi, moved, boxes2):
    """Curve 2's vertices turned by φ and moved to t, written to ``moved``, and their boxes to ``boxes2``."""
    c = math.cos(phi)
    s = math.sin(phi)
    for k in range(v2.shape[0]):
        moved[k, 0] = tx + c * v2[k, 0] - s * v2[k, 1]
        moved[k, 1] = ty + s * v2[k, 0] + c * v2[k, 1]
    chunk_boxes(moved, boxes2)


@njit(**JIT)
def nearest_segments(v1, boxes1, moved, boxes2, cap):
    """(d², i, j): the squared distance, capped at cap², between curve 1 and curve 2 placed (``moved``, its
    boxes ``boxes2``), and a pair of segments at that distance (−1, −1 where none is nearer than ``cap``).

    A pair of segments is measured only where the boxes of their runs, the box
    of each against the other's run and their own boxes are all nearer than the
    nearest distance found so far (the others cannot be nearer, so the minimum
    is the same); where two segments meet it stops.
    """
    best2, bi, bj = cap * cap, -1, -1
    for a in range(boxes1.shape[0]):
        for b in range(boxes2.shape[0]):
            box = boxes2[b]
            if boxes_distance2(boxes1[a], box) > best2:
                continue
            for i in range(a * CHUNK, min((a + 1) * CHUNK, v1.shape[0] - 1)):
                px, py, qx, qy = v1[i, 0], v1[i, 1], v1[i + 1, 0], v1[i + 1, 1]
                x0, x1, y0, y1 = min(px, qx), max(px, qx), min(py, qy), max(py, qy)
                if _gap2(x0, x1, y0, y1, box[0], box[1], box[2], box[3]) > best2:
                    continue
                for j in range(b * CHUNK, min((b + 1) * CHUNK, moved.shape[0] - 1)):
                    ax, ay, bx, by = moved[j, 0], moved[j, 1], moved[j + 1, 0], moved[j + 1, 1]
                    if _gap2(x0, x1, y0, y1, min(ax, bx), max(ax, bx), min(ay, by), max(ay, by)) > best2:
                        continue
                    got = _segments_distance2(px, py, qx, qy, ax, ay, bx, by)
                    if got < best2 or bi < 0 and got <= best2:
                        best2, bi, bj = got, i, j
                    if best2 == 0.0:  # the curves meet: nothing is nearer
                        return 0.0, bi, bj
    return best2, bi, bj


@njit(**JIT)
def clearance(v1, boxes1, v2, tx, ty, phi, cap, moved, boxes2):
    """min(cap, distance between curve 1 and curve 2 turned by φ and moved to t), b. ``boxes1``:
    :func:`chunk_boxes` of curve 1; ``moved``, ``boxes2``: scratch for curve 2's vertices at (t, φ) and their
    boxes (:func:`nearest_segments`)."""
    placed(v2, tx, ty, phi, moved, boxes2)
    return math.sqrt(nearest_segments(v1, boxes1, moved, boxes2, cap)[0])


def _halving_fractions(levels):
    """k / 2^levels for k = 1 .. 2^levels - 1, coarse to fine: 1/2, then 1/4 and 3/4, then the eighths, ..."""
    out = []
    for level in range(1, levels + 1):
        out += [k / 2**level for k in range(1, 2**level, 2)]
    return np.array(out)


# Orientations tried for the clearance, as fractions of the widest window: its middle first, then ever finer
# halvings. The clearance is 0 at the window's ends and often largest near one of them (an arc's end clears the
# other curve just before the window closes), so the sample goes to 1/64 of the window from its ends.
CLEARANCE_FRACTIONS = _halving_fractions(6)


@njit(**JIT, parallel=True)
def windows_at(v1, v2, spans2, boxes1, xs, ys, slack, gap, contact, caps, width, middle, clear):
    """Per position p: the widest allowed window ``width[p]`` (radians), its ``middle[p]``, and the largest
    clearance (b) found at the orientations ``CLEARANCE_FRACTIONS`` across that window, capped at
    ``caps[p]`` + ``contact`` (``clear[p]``; 0 where no orientation is allowed or ``caps[p]`` is 0).

    Each position is written by one thread, so results do not depend on the thread count.
    """
    for p in prange(xs.shape[0]):
        starts, ends = blocked_angles(v1, v2, spans2, xs[p], ys[p], slack, contact)
        width[p], middle[p] = largest_window(starts, ends, gap)
        clear[p] = 0.0
        if width[p] == 0.0 or caps[p] <= 0.0:
            continue
        cap = caps[p] + contact
        moved = np.empty_like(v2)
        boxes2 = np.empty((chunk_count(v2), 4))
        for fraction in CLEARANCE_FRACTIONS:
            phi = middle[p] + (fraction - 0.5) * width[p]
            clear[p] = max(clear[p], clearance(v1, boxes1, v2, xs[p], ys[p], phi, cap, moved, boxes2))
            if clear[p] >= cap:
                break


@njit(**JIT, parallel=True)
def clearance_at(v1, boxes1, v2, xs, ys, phis, caps, out):
    """``out[p]``: :func:`clearance` of curve 2 at (xs[p], ys[p]) turned by ``phis[p]``, capped at ``caps[p]``; 0
    where they meet. Each position is written by one thread."""
    for p in prange(xs.shape[0]):
        moved = np.empty_like(v2)
        boxes2 = np.empty((chunk_count(v2), 4))
        out[p] = clearance(v1, boxes1, v2, xs[p], ys[p], phis[p], caps[p], moved, boxes2)


@njit(**JIT, parallel=True)
def allowed_angle_at(v1, v2, spans2, xs, ys, slack, gap, contact, out):
    """``out[p]`` = measure (radians) of the orientations allowed at translation (xs[p], ys[p]).

    Each point is written by one thread, so results do not depend on the thread count.
    """
    for p in prange(xs.shape[0]):
        starts, ends = blocked_angles(v1, v2, spans2, xs[p], ys[p], slack, contact)
        out[p] = free_measure(starts, ends, gap)


def blocked_intervals(v1, v2, tx, ty, slack, contact=0.0):
    """Sorted (starts, ends) of the φ intervals where curve 2 at (tx, ty) meets curve 1, radians."""
    return blocked_angles(v1, v2, radial_spans(v2), float(tx), float(ty), slack, float(contact))


def allowed_measures(v1, v2, xs, ys, slack, gap, contact=0.0):
    """(p,) measure in radians of the orientations allowed at each translation (xs[p], ys[p])."""
    out = np.empty(len(xs))
    with small_chunks():
        allowed_angle_at(v1, v2, radial_spans(v2), xs, ys, slack, gap, float(contact), out)
    return out


def widest_windows(v1, v2, xs, ys, slack, gap, contact=0.0, caps=None):
    """(width, middle, clearance) per translation: see :func:`windows_at`; ``caps`` None: no clearance."""
    xs = np.ascontiguousarray(xs, dtype=float)
    ys = np.ascontiguousarray(ys, dtype=float)
    caps = np.zeros(len(xs)) if caps is None else np.ascontiguousarray(caps, dtype=float)
    width, middle, clear = np.empty(len(xs)), np.empty(len(xs)), np.empty(len(xs))
    boxes1 = chunk_boxes(v1, np.empty((chunk_count(v1), 4)))
    with small_chunks():
        windows_at(v1, v2, radial_spans(v2), boxes1, xs, ys, slack, gap, float(contact), caps, width, middle, clear)
    return width, middle, clear
