"""numba kernels: segment-pair tests and Minkowski rasterisation.

Conventions shared by every kernel:

* Curve 1 is fixed; curve 2 is rotated by φ about its centre, then translated
  by t = (x, y). ``b2`` is curve 2's vertices already rotated.
* Segment i of curve 1 runs from a_i by d_i; rotated segment j of curve 2 runs
  from b_j by e_j. They meet at translation t exactly when t lies in the
  parallelogram P_ij = {c + λ d_i + μ f_j : λ, μ ∈ [0, 1]}, with c = a_i − b_j
  and f_j = −e_j (DESIGN.md §6). Both engines evaluate that one predicate,
  :func:`in_pair_set`, on the same floating-point inputs, so they agree state
  for state, including at ties and on degenerate (parallel) pairs.
* Touching counts as meeting: the predicate accepts points within ``delta``
  of P_ij (closed sets, one tolerance for every engine).
* Parallel kernels run ``prange`` over φ (or over samples); each slice is
  written by one thread, so results do not depend on the thread count.
"""

import math

import numpy as np
from numba import njit, prange

_JIT = dict(cache=True, nogil=True)

COUNT_MAX = 65535  # crossing counts saturate at the uint16 maximum

# The accepted region lies within delta·√2 of P_ij's bounding box; filters
# use a wider margin so they never reject a state the predicate accepts.
MARGIN_FACTOR = 3.0


@njit(**_JIT)
def rotate(vertices, c, s, out):
    """out = R vertices, R the rotation with cosine c and sine s."""
    for k in range(vertices.shape[0]):
        x = vertices[k, 0]
        y = vertices[k, 1]
        out[k, 0] = c * x - s * y
        out[k, 1] = s * x + c * y


@njit(**_JIT)
def segment_lengths(vertices, out):
    for k in range(vertices.shape[0] - 1):
        dx = vertices[k + 1, 0] - vertices[k, 0]
        dy = vertices[k + 1, 1] - vertices[k, 1]
        out[k] = math.sqrt(dx * dx + dy * dy)


@njit(**_JIT)
def pair_geometry(v1, b2, i, j):
    """(c, d, f) of the parallelogram P_ij, as six scalars."""
    ax = v1[i, 0]
    ay = v1[i, 1]
    dx = v1[i + 1, 0] - ax
    dy = v1[i + 1, 1] - ay
    cx = ax - b2[j, 0]
    cy = ay - b2[j, 1]
    fx = b2[j, 0] - b2[j + 1, 0]
    fy = b2[j, 1] - b2[j + 1, 1]
    return cx, cy, dx, dy, fx, fy


@njit(**_JIT)
def in_pair_set(wx, wy, dx, dy, fx, fy, dlen, flen, delta):
    """True when w = t − c lies within ``delta`` of {λ d + μ f : λ, μ ∈ [0, 1]}.

    With D = d × f, λ D = w × f and μ D = d × w. The two strip tests bound the
    distance to each pair of opposite edges; the projection test on d bounds
    the extent along d, which keeps a (near-)degenerate parallelogram, i.e.
    two (nearly) parallel segments, from growing long tolerance tails: when
    d ∥ f the set is a segment and the tests reduce to "within delta of it".
    """
    big_d = dx * fy - dy * fx
    u = wx * fy - wy * fx
    v = dx * wy - dy * wx
    if big_d < 0.0:
        big_d = -big_d
        u = -u
        v = -v
    tol_f = delta * flen
    if u < -tol_f or u > big_d + tol_f:
        return False
    tol_d = delta * dlen
    if v < -tol_d or v > big_d + tol_d:
        return False
    p = (wx * dx + wy * dy) / dlen
    q = (fx * dx + fy * dy) / dlen
    lo = q if q < 0.0 else 0.0
    hi = dlen + (q if q > 0.0 else 0.0)
    return p >= lo - delta and p <= hi + delta


@njit(**_JIT)
def pair_bounds(cx, cy, dx, dy, fx, fy, margin):
    """Axis-aligned bounding box of P_ij, widened by ``margin``."""
    xmin = cx + min(0.0, dx) + min(0.0, fx) - margin
    xmax = cx + max(0.0, dx) + max(0.0, fx) + margin
    ymin = cy + min(0.0, dy) + min(0.0, fy) - margin
    ymax = cy + max(0.0, dy) + max(0.0, fy) + margin
    return xmin, xmax, ymin, ymax


@njit(**_JIT)
def crossings_at(v1, dlen, b2, flen, tx, ty, delta, count):
    """Number of segment pairs that meet at translation (tx, ty).

    The direct test: every pair, with bounding-box rejection. When ``count``
    is False it stops at the first pair found (the result is then 0 or 1).
    """
    margin = MARGIN_FACTOR * delta
    found = 0
    for j in range(b2.shape[0] - 1):
        for i in range(v1.shape[0] - 1):
            cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
            xmin, xmax, ymin, ymax = pair_bounds(cx, cy, dx, dy, fx, fy, margin)
            if tx < xmin or tx > xmax or ty < ymin or ty > ymax:
                continue
            if in_pair_set(tx - cx, ty - cy, dx, dy, fx, fy, dlen[i], flen[j], delta):
                found += 1
                if not count:
                    return found
    return found


@njit(**_JIT, parallel=True)
def direct_slices(v1, v2, cos_phi, sin_phi, xs, ys, delta, reach, count, out):
    """Direct engine: ``out[k, iy, ix]`` = crossings at (xs[ix], ys[iy], φ_k).

    ``reach`` = r₁ + r₂: states further apart cannot meet and are skipped.
    """
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    far = (reach + MARGIN_FACTOR * delta) ** 2
    for k in prange(cos_phi.shape[0]):
        b2 = np.empty_like(v2)
        rotate(v2, cos_phi[k], sin_phi[k], b2)
        flen = np.empty(b2.shape[0] - 1)
        segment_lengths(b2, flen)
        for iy in range(ys.shape[0]):
            for ix in range(xs.shape[0]):
                if xs[ix] * xs[ix] + ys[iy] * ys[iy] > far:
                    out[k, iy, ix] = 0
                    continue
                n = crossings_at(v1, dlen, b2, flen, xs[ix], ys[iy], delta, count)
                out[k, iy, ix] = min(n, COUNT_MAX)


@njit(**_JIT)
def _index_range(lo, hi, origin, step, size):
    """Indices i with origin + i·step possibly in [lo, hi], clipped to the grid."""
    i0 = int(math.ceil((lo - origin) / step)) - 1
    i1 = int(math.floor((hi - origin) / step)) + 1
    return max(i0, 0), min(i1, size - 1)


@njit(**_JIT)
def raster_slice(v1, dlen, b2, flen, xs, ys, delta, count, out):
    """Minkowski raster of one orientation: add P_ij's nodes to ``out`` (ny, nx).

    ``out`` must be zero on entry. When ``count`` is False a node already
    marked is not tested again (only overlap, not the count, is wanted).
    """
    margin = MARGIN_FACTOR * delta
    hx = xs[1] - xs[0]
    hy = ys[1] - ys[0]
    for j in range(b2.shape[0] - 1):
        for i in range(v1.shape[0] - 1):
            cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
            xmin, xmax, ymin, ymax = pair_bounds(cx, cy, dx, dy, fx, fy, margin)
            ix0, ix1 = _index_range(xmin, xmax, xs[0], hx, xs.shape[0])
            iy0, iy1 = _index_range(ymin, ymax, ys[0], hy, ys.shape[0])
            for iy in range(iy0, iy1 + 1):
                ty = ys[iy]
                if ty < ymin or ty > ymax:
                    continue
                for ix in range(ix0, ix1 + 1):
                    tx = xs[ix]
                    if tx < xmin or tx > xmax:
                        continue
                    if not count and out[iy, ix] != 0:
                        continue
                    if in_pair_set(tx - cx, ty - cy, dx, dy, fx, fy, dlen[i], flen[j], delta):
                        if out[iy, ix] < COUNT_MAX:
                            out[iy, ix] += 1


@njit(**_JIT, parallel=True)
def raster_slices(v1, v2, cos_phi, sin_phi, xs, ys, delta, count, out):
    """Raster engine: ``out[k]`` = crossings at φ_k over the grid (out zeroed)."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in prange(cos_phi.shape[0]):
        b2 = np.empty_like(v2)
        rotate(v2, cos_phi[k], sin_phi[k], b2)
        flen = np.empty(b2.shape[0] - 1)
        segment_lengths(b2, flen)
        raster_slice(v1, dlen, b2, flen, xs, ys, delta, count, out[k])


@njit(**_JIT, parallel=True)
def crossings_at_states(v1, v2, xs, ys, phis, delta, count, out):
    """Direct test at arbitrary states (xs[s], ys[s], phis[s]): the Monte-Carlo path."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for s in prange(xs.shape[0]):
        b2 = np.empty_like(v2)
        rotate(v2, math.cos(phis[s]), math.sin(phis[s]), b2)
        flen = np.empty(b2.shape[0] - 1)
        segment_lengths(b2, flen)
        out[s] = min(crossings_at(v1, dlen, b2, flen, xs[s], ys[s], delta, count), COUNT_MAX)


# --- convex-hull tests (entanglement) -------------------------------------------
#
# "Curve 2 meets hull(curve 1)" holds at translation t exactly when t lies in
# hull(C1) ⊕ (−R C2), a union over segments j of the convex polygons
# hull(C1) ⊕ (−R s_j); likewise "curve 1 meets hull(R C2 + t)" when t lies in
# C1 ⊕ (−R hull(C2)). Both are a convex polygon Q swept along a polyline, one
# convex piece per segment. A piece's row span is found from segments that
# cover its boundary: Q's edges at both ends of the sweep and the sweep path
# of every vertex of Q.


@njit(**_JIT)
def _widen_rows(x1, y1, x2, y2, ys, delta, lo, hi):
    """Extend each row's [lo, hi] by where segment (x1, y1)-(x2, y2) crosses it."""
    hy = ys[1] - ys[0]
    ymin = min(y1, y2) - delta
    ymax = max(y1, y2) + delta
    i0, i1 = _index_range(ymin, ymax, ys[0], hy, ys.shape[0])
    dy = y2 - y1
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


@njit(**_JIT)
def swept_hull_cover(hull, path, xs, ys, delta, lo, hi, diff):
    """Add the nodes of ∪_k hull ⊕ [path_k, path_k+1] to the row-difference array.

    ``hull`` (H, 2) is a convex polygon (any H >= 1), ``path`` (P, 2) a
    polyline. ``diff`` (ny, nx + 1) int32 receives +1 / −1 at each covered
    run's ends; ``lo`` and ``hi`` (ny,) are scratch. Nodes within ``delta``
    of a piece count as covered (closed sets).
    """
    hx = xs[1] - xs[0]
    nh = hull.shape[0]
    for k in range(path.shape[0] - 1):
        px, py, qx, qy = path[k, 0], path[k, 1], path[k + 1, 0], path[k + 1, 1]
        lo[:] = np.inf
        hi[:] = -np.inf
        for v in range(nh):
            w = (v + 1) % nh
            ax, ay, bx, by = hull[v, 0], hull[v, 1], hull[w, 0], hull[w, 1]
            _widen_rows(ax + px, ay + py, bx + px, by + py, ys, delta, lo, hi)
            _widen_rows(ax + qx, ay + qy, bx + qx, by + qy, ys, delta, lo, hi)
            _widen_rows(ax + px, ay + py, ax + qx, ay + qy, ys, delta, lo, hi)
        for iy in range(ys.shape[0]):
            if lo[iy] > hi[iy]:
                continue
            i0, i1 = _index_range(lo[iy] - delta, hi[iy] + delta, xs[0], hx, xs.shape[0])
            while i0 <= i1 and xs[i0] < lo[iy] - delta:
                i0 += 1
            while i1 >= i0 and xs[i1] > hi[iy] + delta:
                i1 -= 1
            if i0 <= i1:
                diff[iy, i0] += 1
                diff[iy, i1 + 1] -= 1


@njit(**_JIT)
def _covered(diff, out):
    """out[iy, ix] = True where the running sum of diff's row is positive."""
    for iy in range(out.shape[0]):
        run = 0
        for ix in range(out.shape[1]):
            run += diff[iy, ix]
            out[iy, ix] = run > 0


@njit(**_JIT, parallel=True)
def mutual_hull_slices(v1, hull1, v2, hull2, cos_phi, sin_phi, xs, ys, delta, out):
    """out[k] = True where each curve meets the other's filled convex hull at φ_k."""
    ny, nx = ys.shape[0], xs.shape[0]
    for k in prange(cos_phi.shape[0]):
        c, s = cos_phi[k], sin_phi[k]
        lo = np.empty(ny)
        hi = np.empty(ny)
        diff = np.zeros((ny, nx + 1), dtype=np.int32)
        # curve 2 meets hull 1: hull1 ⊕ (−R C2)
        path2 = np.empty_like(v2)
        rotate(v2, -c, -s, path2)
        swept_hull_cover(hull1, path2, xs, ys, delta, lo, hi, diff)
        first = np.empty((ny, nx), dtype=np.bool_)
        _covered(diff, first)
        # curve 1 meets hull 2: C1 ⊕ (−R hull2)
        diff[:] = 0
        neg_hull2 = np.empty_like(hull2)
        rotate(hull2, -c, -s, neg_hull2)
        swept_hull_cover(neg_hull2, v1, xs, ys, delta, lo, hi, diff)
        second = np.empty((ny, nx), dtype=np.bool_)
        _covered(diff, second)
        for iy in range(ny):
            for ix in range(nx):
                out[k, iy, ix] = first[iy, ix] and second[iy, ix]
