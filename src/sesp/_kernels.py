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
def pair_setup(dx, dy, fx, fy, dlen, flen, delta):
    """Per-pair constants of the membership test :func:`pair_contains`.

    With D = d × f and w = λ d + μ f: λ D = w × f and μ D = d × w. The sign
    makes D >= 0; the tolerances turn "within delta of an edge" into bounds
    on those cross products; (lo, hi) bound the projection of w on d.
    """
    big_d = dx * fy - dy * fx
    sign = 1.0 if big_d >= 0.0 else -1.0
    inv_dlen = 1.0 / dlen
    q = (fx * dx + fy * dy) * inv_dlen
    lo = min(q, 0.0) - delta
    hi = dlen + max(q, 0.0) + delta
    return sign * big_d, sign, delta * flen, delta * dlen, inv_dlen, lo, hi


@njit(**_JIT)
def pair_contains(wx, wy, dx, dy, fx, fy, big_d, sign, tol_f, tol_d, inv_dlen, lo, hi):
    """True when w = t − c lies within delta of {λ d + μ f : λ, μ ∈ [0, 1]}.

    The two strip tests bound the distance to each pair of opposite edges;
    the projection test on d bounds the extent along d, which keeps a
    (near-)degenerate parallelogram, i.e. two (nearly) parallel segments,
    from growing long tolerance tails: when d ∥ f the set is a segment and
    the tests reduce to "within delta of it".
    """
    u = sign * (wx * fy - wy * fx)
    if u < -tol_f or u > big_d + tol_f:
        return False
    v = sign * (dx * wy - dy * wx)
    if v < -tol_d or v > big_d + tol_d:
        return False
    p = (wx * dx + wy * dy) * inv_dlen
    return p >= lo and p <= hi


@njit(**_JIT)
def in_pair_set(wx, wy, dx, dy, fx, fy, dlen, flen, delta):
    """:func:`pair_contains` with its set-up: one pair, one point."""
    big_d, sign, tol_f, tol_d, inv_dlen, lo, hi = pair_setup(dx, dy, fx, fy, dlen, flen, delta)
    return pair_contains(wx, wy, dx, dy, fx, fy, big_d, sign, tol_f, tol_d, inv_dlen, lo, hi)


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
def _index_range(lo, hi, origin, inv_step, size):
    """Indices i with origin + i·step in [lo, hi], clipped to the grid.

    Filters widen [lo, hi] by MARGIN_FACTOR·delta, far more than the rounding
    of this index arithmetic, so no node the predicate accepts is missed.
    """
    i0 = int(math.ceil((lo - origin) * inv_step))
    i1 = int(math.floor((hi - origin) * inv_step))
    return max(i0, 0), min(i1, size - 1)


@njit(**_JIT)
def raster_slice(v1, dlen, b2, flen, xs, ys, delta, count, out):
    """Minkowski raster of one orientation: add P_ij's nodes to ``out`` (ny, nx).

    ``out`` must be zero on entry. When ``count`` is False a node already
    marked is not tested again (only overlap, not the count, is wanted).
    """
    margin = MARGIN_FACTOR * delta
    inv_hx = 1.0 / (xs[1] - xs[0])
    inv_hy = 1.0 / (ys[1] - ys[0])
    for j in range(b2.shape[0] - 1):
        for i in range(v1.shape[0] - 1):
            cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
            xmin, xmax, ymin, ymax = pair_bounds(cx, cy, dx, dy, fx, fy, margin)
            iy0, iy1 = _index_range(ymin, ymax, ys[0], inv_hy, ys.shape[0])
            if iy0 > iy1:
                continue
            ix0, ix1 = _index_range(xmin, xmax, xs[0], inv_hx, xs.shape[0])
            if ix0 > ix1:
                continue
            big_d, sign, tol_f, tol_d, inv_dlen, lo, hi = pair_setup(dx, dy, fx, fy, dlen[i], flen[j], delta)
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
                    if pair_contains(tx - cx, ty - cy, dx, dy, fx, fy, big_d, sign, tol_f, tol_d, inv_dlen, lo, hi):
                        if out[iy, ix] < COUNT_MAX:
                            out[iy, ix] += 1


@njit(**_JIT)
def raster_phi(v1, dlen, v2, c, s, xs, ys, delta, count, out):
    """Raster engine for one orientation (cosine c, sine s) into ``out`` (ny, nx), zeroed."""
    b2 = np.empty_like(v2)
    rotate(v2, c, s, b2)
    flen = np.empty(b2.shape[0] - 1)
    segment_lengths(b2, flen)
    raster_slice(v1, dlen, b2, flen, xs, ys, delta, count, out)


@njit(**_JIT, parallel=True)
def raster_slices(v1, v2, cos_phi, sin_phi, xs, ys, delta, count, out):
    """Raster engine: ``out[k]`` = crossings at φ_k over the grid (out zeroed), one thread per φ."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in prange(cos_phi.shape[0]):
        raster_phi(v1, dlen, v2, cos_phi[k], sin_phi[k], xs, ys, delta, count, out[k])


@njit(**_JIT)
def raster_slices_serial(v1, v2, cos_phi, sin_phi, xs, ys, delta, count, out):
    """:func:`raster_slices` in one thread: for small grids, where loading the
    parallel kernel costs more than it saves. Same slices, same results."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in range(cos_phi.shape[0]):
        raster_phi(v1, dlen, v2, cos_phi[k], sin_phi[k], xs, ys, delta, count, out[k])


@njit(**_JIT, parallel=True)
def shifted_overlap_counts(v1, v2, cos_phi, sin_phi, xs, ys, shifts, delta, out):
    """``out[k]`` = overlapping nodes at φ_k on the lattice moved by ``shifts[k]``.

    Counts only: each thread rasterises one slice into its own scratch array.
    """
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in prange(cos_phi.shape[0]):
        field = np.zeros((ys.shape[0], xs.shape[0]), dtype=np.uint16)
        raster_phi(v1, dlen, v2, cos_phi[k], sin_phi[k], xs + shifts[k, 0], ys + shifts[k, 1], delta, False, field)
        out[k] = np.count_nonzero(field)


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
def _widen_rows(x1, y1, x2, y2, ys, inv_hy, delta, lo, hi):
    """Extend each row's [lo, hi] by where segment (x1, y1)-(x2, y2) crosses it.

    ``inv_hy`` is 1 / (ys[1] − ys[0]). Returns the range of rows touched
    (empty: first > last).
    """
    ymin = min(y1, y2) - delta
    ymax = max(y1, y2) + delta
    i0, i1 = _index_range(ymin - delta, ymax + delta, ys[0], inv_hy, ys.shape[0])
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


@njit(**_JIT)
def _hull_rows(hull, px, py, ys, inv_hy, delta, lo, hi):
    """Row spans of the convex polygon hull + (px, py); returns the rows touched."""
    nh = hull.shape[0]
    first, last = ys.shape[0], -1
    for v in range(nh):
        w = (v + 1) % nh
        f, l_ = _widen_rows(
            hull[v, 0] + px, hull[v, 1] + py, hull[w, 0] + px, hull[w, 1] + py, ys, inv_hy, delta, lo, hi
        )
        first, last = min(first, f), max(last, l_)
    return first, last


@njit(**_JIT)
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


@njit(**_JIT)
def swept_hull_cover(hull, path, xs, ys, delta, diff):
    """Add the nodes of ∪_k hull ⊕ [path_k, path_k+1] to the row-difference array.

    ``hull`` (H, 2) is a convex polygon (H >= 2), ``path`` (P, 2) a polyline.
    Each piece is the convex hull of two translated copies of ``hull``; its
    boundary lies on the copies' edges and on the sweep paths of the two
    vertices extreme across the sweep direction, so the row span is the
    extent of those. ``diff`` (ny, nx + 1) int32 receives +1 / −1 at each
    covered run's ends. Nodes within ``delta`` of a piece count as covered.
    """
    ny = ys.shape[0]
    inv_hx = 1.0 / (xs[1] - xs[0])
    inv_hy = 1.0 / (ys[1] - ys[0])
    lo_a, hi_a = np.full(ny, np.inf), np.full(ny, -np.inf)
    lo_b, hi_b = np.full(ny, np.inf), np.full(ny, -np.inf)
    lo, hi = np.full(ny, np.inf), np.full(ny, -np.inf)
    a0, a1 = _hull_rows(hull, path[0, 0], path[0, 1], ys, inv_hy, delta, lo_a, hi_a)
    for k in range(path.shape[0] - 1):
        px, py, qx, qy = path[k, 0], path[k, 1], path[k + 1, 0], path[k + 1, 1]
        b0, b1 = _hull_rows(hull, qx, qy, ys, inv_hy, delta, lo_b, hi_b)
        r0, r1 = min(a0, b0), max(a1, b1)
        for iy in range(r0, r1 + 1):
            lo[iy] = min(lo_a[iy], lo_b[iy])
            hi[iy] = max(hi_a[iy], hi_b[iy])
        for v in _tangent_vertices(hull, qx - px, qy - py):
            f, l_ = _widen_rows(
                hull[v, 0] + px, hull[v, 1] + py, hull[v, 0] + qx, hull[v, 1] + qy, ys, inv_hy, delta, lo, hi
            )
            r0, r1 = min(r0, f), max(r1, l_)
        for iy in range(r0, r1 + 1):
            if lo[iy] <= hi[iy]:
                i0, i1 = _index_range(lo[iy] - 2 * delta, hi[iy] + 2 * delta, xs[0], inv_hx, xs.shape[0])
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
        diff = np.zeros((ny, nx + 1), dtype=np.int32)
        # curve 2 meets hull 1: hull1 ⊕ (−R C2)
        path2 = np.empty_like(v2)
        rotate(v2, -c, -s, path2)
        swept_hull_cover(hull1, path2, xs, ys, delta, diff)
        first = np.empty((ny, nx), dtype=np.bool_)
        _covered(diff, first)
        # curve 1 meets hull 2: C1 ⊕ (−R hull2)
        diff[:] = 0
        neg_hull2 = np.empty_like(hull2)
        rotate(hull2, -c, -s, neg_hull2)
        swept_hull_cover(neg_hull2, v1, xs, ys, delta, diff)
        second = np.empty((ny, nx), dtype=np.bool_)
        _covered(diff, second)
        for iy in range(ny):
            for ix in range(nx):
                out[k, iy, ix] = first[iy, ix] and second[iy, ix]


# --- persistence of the distance-to-complement field (robust components) -----------


@njit(**_JIT)
def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(**_JIT)
def _neighbour(node, k, nz, ny, nx, periodic):
    """Flat index of the k-th of the 26 (3D) or 8 (nz == 1) neighbours, or −1."""
    dz, rest = divmod(k, 9)
    dy, dx = divmod(rest, 3)
    dz, dy, dx = dz - 1, dy - 1, dx - 1
    if (dz == 0 and dy == 0 and dx == 0) or (nz == 1 and dz != 0):
        return -1
    z, rem = divmod(node, ny * nx)
    y, x = divmod(rem, nx)
    z, y, x = z + dz, y + dy, x + dx
    if y < 0 or y >= ny or x < 0 or x >= nx:
        return -1
    if z < 0 or z >= nz:
        if not periodic:
            return -1
        z %= nz
    return (z * ny + y) * nx + x


@njit(**_JIT)
def persistent_components(dist, order, shape, periodic, ratio, min_peak, labels):
    """Label the significant components of the superlevel sets of ``dist``.

    ``dist`` is flat over a grid of ``shape`` (nz, ny, nx) (nz = 1 in the
    plane); axis 0 wraps when ``periodic``. Nodes (flat indices, ``order`` by
    decreasing ``dist``, only nodes of the set) are added one by one and
    joined to their already-added neighbours (full connectivity). When two
    components meet at a node of value s, the one with the lower peak p
    stays separate if s < ratio · p and
    p >= min_peak (a narrow neck or a pinch between two bodies), else it is
    absorbed (a bump or a fragment). Writes each node's final component
    number (1, 2, ...; 0: in none) to ``labels`` and returns the count.
    """
    n = dist.shape[0]
    parent = np.arange(n)
    peak = np.zeros(n)
    merged_into = np.full(n, -1)  # root absorbed into another root (not compressed)
    kept = np.zeros(n, dtype=np.bool_)  # root that survived a merge as its own component
    owner = np.full(n, -1)  # root a node joined when it was added
    added = np.zeros(n, dtype=np.bool_)
    for node in order:
        added[node] = True
        best = -1
        for k in range(27):
            nb = _neighbour(node, k, shape[0], shape[1], shape[2], periodic)
            if nb < 0 or not added[nb]:
                continue
            r = _find(parent, nb)
            if best < 0:
                best = r
            elif r != best:
                hi, lo = (best, r) if peak[best] >= peak[r] else (r, best)
                if dist[node] < ratio * peak[lo] and peak[lo] >= min_peak:
                    kept[lo] = True
                else:
                    merged_into[lo] = hi
                parent[lo] = hi
                best = hi
        if best < 0:
            peak[node] = dist[node]
            owner[node] = node
        else:
            parent[node] = best
            owner[node] = best
    # final roots with a high enough peak are components too
    for i in range(n):
        if added[i] and parent[i] == i and peak[i] >= min_peak:
            kept[i] = True
    number = np.zeros(n, dtype=np.int64)
    count = 0
    for node in order:  # number components by decreasing peak: the order they were born
        if owner[node] == node and kept[node]:
            count += 1
            number[node] = count
    for node in order:
        r = owner[node]
        while r >= 0 and not kept[r]:
            r = merged_into[r]
        labels[node] = number[r] if r >= 0 else 0
    return count


# --- orientations at a fixed translation, exact in φ --------------------------------------

TWO_PI = 2.0 * math.pi


@njit(**_JIT)
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


@njit(**_JIT)
def _pair_signs(phi, k1, k2, k3, k4):
    """Whether the segments meet at φ: both pairs of orientation values change sign (or vanish)."""
    c = math.cos(phi)
    s = math.sin(phi)
    s1 = k1[0] + k1[1] * c + k1[2] * s
    s2 = k2[0] + k2[1] * c + k2[2] * s
    s3 = k3[0] + k3[1] * c + k3[2] * s
    s4 = k4[0] + k4[1] * c + k4[2] * s
    return s1 * s2 <= 0.0 and s3 * s4 <= 0.0


@njit(**_JIT)
def _pair_angles(px, py, qx, qy, ux, uy, vx, vy, tx, ty, starts, ends, n):
    """Append the φ intervals where fixed segment pq meets t + R_φ[uv]; return the new count.

    Segments meet exactly when each one's end points lie on opposite sides of
    (or on) the other's line. Every such orientation value is a sinusoid
    c + α cos φ + β sin φ in φ, so between consecutive roots of the four the
    answer is constant: one midpoint test per piece.
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
    roots = np.empty(10)
    m = 0
    for k in (k1, k2, k3, k4):
        m = _sinusoid_roots(k[0], k[1], k[2], roots, m)
    roots[m] = 0.0
    roots[m + 1] = TWO_PI
    cuts = np.sort(roots[: m + 2])
    for i in range(m + 1):
        lo = cuts[i]
        hi = cuts[i + 1]
        if hi > lo and _pair_signs(0.5 * (lo + hi), k1, k2, k3, k4):
            if n > 0 and ends[n - 1] == lo:  # continues the piece before
                ends[n - 1] = hi
            else:
                starts[n] = lo
                ends[n] = hi
                n += 1
    return n


@njit(**_JIT)
def _segment_distances(vx0, vy0, vx1, vy1, x, y):
    """(nearest, farthest) distance from (x, y) to the segment."""
    ex = vx1 - vx0
    ey = vy1 - vy0
    length2 = ex * ex + ey * ey
    lam = 0.0 if length2 == 0.0 else min(1.0, max(0.0, ((x - vx0) * ex + (y - vy0) * ey) / length2))
    near = math.hypot(vx0 + lam * ex - x, vy0 + lam * ey - y)
    far = max(math.hypot(vx0 - x, vy0 - y), math.hypot(vx1 - x, vy1 - y))
    return near, far


@njit(**_JIT)
def blocked_angles(v1, v2, tx, ty, slack):
    """Sorted (starts, ends) of the φ intervals in [0, 2π) where curve 2 at t meets curve 1.

    Pairs are screened first: rotated about its centre, segment j of curve 2
    stays in the annulus of radii [nearest, farthest distance of the segment
    from the centre] about t, so it can meet segment i only if segment i
    reaches that annulus (widened by ``slack``).
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
            if near1[i] > rout + slack or far1[i] < rin - slack:
                continue
            if n + 5 > cap:  # one pair adds at most 5 intervals (9 pieces, adjacent ones merged)
                cap *= 2
                grown_s = np.empty(cap)
                grown_e = np.empty(cap)
                grown_s[:n] = starts[:n]
                grown_e[:n] = ends[:n]
                starts, ends = grown_s, grown_e
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


@njit(**_JIT)
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


@njit(**_JIT, parallel=True)
def allowed_angle_at(v1, v2, xs, ys, slack, gap, out):
    """``out[p]`` = measure (radians) of the orientations allowed at translation (xs[p], ys[p]).

    Each point is written by one thread, so results do not depend on the thread count.
    """
    for p in prange(xs.shape[0]):
        starts, ends = blocked_angles(v1, v2, xs[p], ys[p], slack)
        out[p] = free_measure(starts, ends, gap)
