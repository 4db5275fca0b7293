"""Orientation kernels: the φ intervals in which two curves meet at a fixed translation, exact in φ."""

import math

import numpy as np
from numba import njit, prange

from .common import JIT, point_segment_distance2

TWO_PI = 2.0 * math.pi


@njit(**JIT)
def _sinusoid_roots(c, a, b, roots, n):
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
    """The m roots with 0 and 2π added, sorted: the ends of the pieces on which a pair's answer is constant."""
    roots[m] = 0.0
    roots[m + 1] = TWO_PI
    return np.sort(roots[: m + 2])


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
def _pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, starts, ends, n):
    """Append the φ intervals where fixed segment pq meets t + R_φ[uv]; return the new count.

    Segments meet exactly when each one's end points lie on opposite sides of
    (or on) the other's line. Every such orientation value is a sinusoid
    c + α cos φ + β sin φ in φ, so between consecutive roots of the four the
    answer is constant: one midpoint test per piece.
    """
    k1, k2, k3, k4 = _crossing_sinusoids(px, py, qx, qy, ux, uy, vx, vy, tx, ty)
    roots = np.empty(10)
    m = 0
    for k in (k1, k2, k3, k4):
        m = _sinusoid_roots(k[0], k[1], k[2], roots, m)
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
def _thick_pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, contact, starts, ends, n):
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
    roots = np.empty(50)
    m = 0
    for k in (k1, k2):
        for shift in (0.0, contact * dlen, -contact * dlen):
            m = _sinusoid_roots(k[0] + shift, k[1], k[2], roots, m)
    for k in (k3, k4):
        for shift in (0.0, contact * elen, -contact * elen):
            m = _sinusoid_roots(k[0] + shift, k[1], k[2], roots, m)
    along = (tx - px) * dx + (ty - py) * dy
    for wx, wy in ((ux, uy), (vx, vy)):  # moving end points' projections on p–q reach its ends
        a = wx * dx + wy * dy
        b = wx * dy - wy * dx
        m = _sinusoid_roots(along, a, b, roots, m)
        m = _sinusoid_roots(along - dlen * dlen, a, b, roots, m)
    for gx, gy in ((gpx, gpy), (gqx, gqy)):  # fixed end points' projections on the moving segment
        c0 = -(ux * ex + uy * ey)
        a = gx * ex + gy * ey
        b = gy * ex - gx * ey
        m = _sinusoid_roots(c0, a, b, roots, m)
        m = _sinusoid_roots(c0 - elen * elen, a, b, roots, m)
        for wx, wy in ((ux, uy), (vx, vy)):  # end point to end point at distance contact
            m = _sinusoid_roots(
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
def blocked_angles(v1, v2, tx, ty, slack, contact):
    """Sorted (starts, ends) of the φ intervals in [0, 2π) where curve 2 at t comes within ``contact`` of curve 1.

    Pairs are screened first: rotated about its centre, segment j of curve 2
    stays in the annulus of radii [nearest, farthest distance of the segment
    from the centre] about t, so it can meet segment i only if segment i
    reaches that annulus (widened by ``slack`` + ``contact``).
    """
    n1 = v1.shape[0] - 1
    n2 = v2.shape[0] - 1
    near1 = np.empty(n1)
    far1 = np.empty(n1)
    for i in range(n1):
        near1[i], far1[i] = _segment_distances(v1[i, 0], v1[i, 1], v1[i + 1, 0], v1[i + 1, 1], tx, ty)
    cap = 64
    starts = np.empty(cap)
    ends = np.empty(cap)
    n = 0
    for j in range(n2):
        rin, rout = _segment_distances(v2[j, 0], v2[j, 1], v2[j + 1, 0], v2[j + 1, 1], 0.0, 0.0)
        for i in range(n1):
            if near1[i] > rout + slack + contact or far1[i] < rin - slack - contact:
                continue
            if n + 26 > cap:  # one pair adds at most 25 intervals (49 pieces, adjacent ones merged)
                cap *= 2
                grown_s = np.empty(cap)
                grown_e = np.empty(cap)
                grown_s[:n] = starts[:n]
                grown_e[:n] = ends[:n]
                starts, ends = grown_s, grown_e
            if contact > 0.0:
                n = _thick_pair_angles(
                    v1[i, 0], v1[i, 1], v1[i + 1, 0], v1[i + 1, 1], v2[j, 0], v2[j, 1], v2[j + 1, 0], v2[j + 1, 1],
                    tx, ty, contact, starts, ends, n,
                )  # fmt: skip
                continue
            n = _pair_angles(
                v1[i, 0],
                v1[i, 1],
                v1[i + 1, 0],
                v1[i + 1, 1],
                v2[j, 0],
                v2[j, 1],
                v2[j + 1, 0],
                v2[j + 1, 1],
                tx,
                ty,
                starts,
                ends,
                n,
            )
    order = np.argsort(starts[:n], kind="mergesort")
    return starts[:n][order], ends[:n][order]


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


@njit(**JIT, parallel=True)
def allowed_angle_at(v1, v2, xs, ys, slack, gap, contact, out):
    """``out[p]`` = measure (radians) of the orientations allowed at translation (xs[p], ys[p]).

    Each point is written by one thread, so results do not depend on the thread count.
    """
    for p in prange(xs.shape[0]):
        starts, ends = blocked_angles(v1, v2, xs[p], ys[p], slack, contact)
        out[p] = free_measure(starts, ends, gap)


def blocked_intervals(v1, v2, tx, ty, slack, contact=0.0):
    """Sorted (starts, ends) of the φ intervals where curve 2 at (tx, ty) meets curve 1, radians."""
    return blocked_angles(v1, v2, float(tx), float(ty), slack, float(contact))


def allowed_measures(v1, v2, xs, ys, slack, gap, contact=0.0):
    """(p,) measure in radians of the orientations allowed at each translation (xs[p], ys[p])."""
    out = np.empty(len(xs))
    allowed_angle_at(v1, v2, xs, ys, slack, gap, float(contact), out)
    return out
