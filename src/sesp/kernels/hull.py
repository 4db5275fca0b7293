"""Convex-hull kernels: where each curve meets the other's filled convex hull (entanglement).

"Curve 2 meets hull(curve 1)" holds at translation t exactly when t lies in
hull(C1) ⊕ (−R C2), a union over segments j of the convex polygons
hull(C1) ⊕ (−R s_j); likewise "curve 1 meets hull(R C2 + t)" when t lies in
C1 ⊕ (−R hull(C2)). Both are a convex polygon Q swept along a polyline, one
convex piece per segment. A piece's row span is found from segments that
cover its boundary: Q's edges at both ends of the sweep and the sweep path
of every vertex of Q.
"""

import math

import numpy as np
from numba import njit, prange

from .common import JIT, index_range, rotate


@njit(**JIT)
def _segment_rows(x1, y1, x2, y2, ys, inv_hy, delta, lo, hi):
    """Extend each row's [lo, hi] by where segment (x1, y1)-(x2, y2) crosses it.

    ``inv_hy`` is 1 / (ys[1] − ys[0]). Returns the range of rows touched
    (empty: first > last).
    """
    ymin = min(y1, y2) - delta
    ymax = max(y1, y2) + delta
    i0, i1 = index_range(ymin - delta, ymax + delta, ys[0], inv_hy, ys.shape[0])
    dy = y2 - y1
    first, last = ys.shape[0], -1
    for iy in range(i0, i1 + 1):
        y = ys[iy]
        if y < ymin or y > ymax:
            continue
        if dy == 0.0:
            xa, xb = min(x1, x2), max(x1, x2)
        else:
            s = min(max((y - y1) / dy, 0.0), 1.0)
            xa = xb = x1 + s * (x2 - x1)
        if xa < lo[iy]:
            lo[iy] = xa
        if xb > hi[iy]:
            hi[iy] = xb
        first = min(first, iy)
        last = max(last, iy)
    return first, last


@njit(**JIT)
def _disk_rows(cx, cy, radius, ys, inv_hy, delta, lo, hi):
    """Extend each row's [lo, hi] by where the disk of ``radius`` about (cx, cy) crosses it."""
    i0, i1 = index_range(cy - radius - 2 * delta, cy + radius + 2 * delta, ys[0], inv_hy, ys.shape[0])
    first, last = ys.shape[0], -1
    for iy in range(i0, i1 + 1):
        dy = ys[iy] - cy
        if abs(dy) > radius + delta:
            continue
        half = math.sqrt(max(radius * radius - dy * dy, 0.0))
        lo[iy] = min(lo[iy], cx - half)
        hi[iy] = max(hi[iy], cx + half)
        first = min(first, iy)
        last = max(last, iy)
    return first, last


@njit(**JIT)
def _widen_rows(x1, y1, x2, y2, ys, inv_hy, delta, contact, lo, hi):
    """Extend each row's [lo, hi] by where the segment, dilated by a disk of radius ``contact``, crosses it.

    The dilated segment's boundary lies on the two segments offset by
    ±contact and on the two end disks, so its row span is theirs.
    """
    if contact == 0.0:
        return _segment_rows(x1, y1, x2, y2, ys, inv_hy, delta, lo, hi)
    first, last = _disk_rows(x1, y1, contact, ys, inv_hy, delta, lo, hi)
    f, l_ = _disk_rows(x2, y2, contact, ys, inv_hy, delta, lo, hi)
    first, last = min(first, f), max(last, l_)
    length = math.hypot(x2 - x1, y2 - y1)
    if length > 0.0:
        nx = -(y2 - y1) / length * contact
        ny = (x2 - x1) / length * contact
        for side in (1.0, -1.0):
            f, l_ = _segment_rows(
                x1 + side * nx, y1 + side * ny, x2 + side * nx, y2 + side * ny, ys, inv_hy, delta, lo, hi
            )
            first, last = min(first, f), max(last, l_)
    return first, last


@njit(**JIT)
def _hull_rows(hull, px, py, ys, inv_hy, delta, contact, lo, hi):
    """Row spans of the convex polygon hull + (px, py); returns the rows touched."""
    nh = hull.shape[0]
    first, last = ys.shape[0], -1
    for v in range(nh):
        w = (v + 1) % nh
        f, l_ = _widen_rows(
            hull[v, 0] + px, hull[v, 1] + py, hull[w, 0] + px, hull[w, 1] + py, ys, inv_hy, delta, contact, lo, hi
        )
        first, last = min(first, f), max(last, l_)
    return first, last


@njit(**JIT)
def _tangent_vertices(hull, ex, ey):
    """Vertices of the hull extreme on either side of direction (ex, ey)."""
    best_hi, best_lo = -np.inf, np.inf
    k_hi = k_lo = 0
    for v in range(hull.shape[0]):
        side = ex * hull[v, 1] - ey * hull[v, 0]
        if side > best_hi:
            best_hi, k_hi = side, v
        if side < best_lo:
            best_lo, k_lo = side, v
    return k_hi, k_lo


@njit(**JIT)
def swept_hull_cover(hull, path, xs, ys, delta, contact, diff):
    """Add the nodes of ∪_k hull ⊕ [path_k, path_k+1] to the row-difference array.

    ``hull`` (H, 2) is a convex polygon (H >= 2), ``path`` (P, 2) a polyline.
    Each piece is the convex hull of two translated copies of ``hull``; its
    boundary lies on the copies' edges and on the sweep paths of the two
    vertices extreme across the sweep direction, so the row span is the
    extent of those. ``diff`` (ny, nx + 1) int32 receives +1 / −1 at each
    covered run's ends. Nodes within ``delta`` of a piece, dilated by a disk of
    radius ``contact`` (thick particles), count as covered.
    """
    ny = ys.shape[0]
    inv_hx = 1.0 / (xs[1] - xs[0])
    inv_hy = 1.0 / (ys[1] - ys[0])
    lo_a, hi_a = np.full(ny, np.inf), np.full(ny, -np.inf)
    lo_b, hi_b = np.full(ny, np.inf), np.full(ny, -np.inf)
    lo, hi = np.full(ny, np.inf), np.full(ny, -np.inf)
    a0, a1 = _hull_rows(hull, path[0, 0], path[0, 1], ys, inv_hy, delta, contact, lo_a, hi_a)
    for k in range(path.shape[0] - 1):
        px, py, qx, qy = path[k, 0], path[k, 1], path[k + 1, 0], path[k + 1, 1]
        b0, b1 = _hull_rows(hull, qx, qy, ys, inv_hy, delta, contact, lo_b, hi_b)
        r0, r1 = min(a0, b0), max(a1, b1)
        for iy in range(r0, r1 + 1):
            lo[iy] = min(lo_a[iy], lo_b[iy])
            hi[iy] = max(hi_a[iy], hi_b[iy])
        for v in _tangent_vertices(hull, qx - px, qy - py):
            f, l_ = _widen_rows(
                hull[v, 0] + px, hull[v, 1] + py, hull[v, 0] + qx, hull[v, 1] + qy, ys, inv_hy, delta, contact, lo, hi
            )
            r0, r1 = min(r0, f), max(r1, l_)
        for iy in range(r0, r1 + 1):
            if lo[iy] <= hi[iy]:
                i0, i1 = index_range(lo[iy] - 2 * delta, hi[iy] + 2 * delta, xs[0], inv_hx, xs.shape[0])
                while i0 <= i1 and xs[i0] < lo[iy] - delta:
                    i0 += 1
                while i1 >= i0 and xs[i1] > hi[iy] + delta:
                    i1 -= 1
                if i0 <= i1:
                    diff[iy, i0] += 1
                    diff[iy, i1 + 1] -= 1
            lo[iy], hi[iy] = np.inf, -np.inf
        for iy in range(a0, a1 + 1):  # copy a is done with; copy b becomes a
            lo_a[iy], hi_a[iy] = np.inf, -np.inf
        lo_a, lo_b = lo_b, lo_a
        hi_a, hi_b = hi_b, hi_a
        a0, a1 = b0, b1


@njit(**JIT)
def _covered(diff, out):
    """out[iy, ix] = True where the running sum of diff's row is positive."""
    for iy in range(out.shape[0]):
        run = 0
        for ix in range(out.shape[1]):
            run += diff[iy, ix]
            out[iy, ix] = run > 0


@njit(**JIT, parallel=True)
def mutual_hull_slices(v1, hull1, v2, hull2, cos_phi, sin_phi, xs, ys, delta, contact, out):
    """out[k] = True where each curve meets the other's filled convex hull at φ_k."""
    ny, nx = ys.shape[0], xs.shape[0]
    for k in prange(cos_phi.shape[0]):
        c, s = cos_phi[k], sin_phi[k]
        diff = np.zeros((ny, nx + 1), dtype=np.int32)
        # curve 2 meets hull 1: hull1 ⊕ (−R C2)
        path2 = np.empty_like(v2)
        rotate(v2, -c, -s, path2)
        swept_hull_cover(hull1, path2, xs, ys, delta, contact, diff)
        first = np.empty((ny, nx), dtype=np.bool_)
        _covered(diff, first)
        # curve 1 meets hull 2: C1 ⊕ (−R hull2)
        diff[:] = 0
        neg_hull2 = np.empty_like(hull2)
        rotate(hull2, -c, -s, neg_hull2)
        swept_hull_cover(neg_hull2, v1, xs, ys, delta, contact, diff)
        second = np.empty((ny, nx), dtype=np.bool_)
        _covered(diff, second)
        for iy in range(ny):
            for ix in range(nx):
                out[k, iy, ix] = first[iy, ix] and second[iy, ix]


def mutual_hull_field(v1, hull1, v2, hull2, cos_phi, sin_phi, xs, ys, delta, contact=0.0):
    """(k, ny, nx) bool: where each curve comes within ``contact`` of the other's filled convex hull at φ_k."""
    out = np.empty((len(cos_phi), len(ys), len(xs)), dtype=bool)
    mutual_hull_slices(v1, hull1, v2, hull2, cos_phi, sin_phi, xs, ys, delta, contact, out)
    return out
