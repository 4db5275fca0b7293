"""Overlap kernels: segment-pair tests, the Minkowski raster and the direct engine.

Conventions shared by every kernel:

* Curve 1 is fixed; curve 2 is rotated by φ about its centre, then translated
  by t = (x, y). ``b2`` is curve 2's vertices already rotated.
* Segment i of curve 1 runs from a_i by d_i; rotated segment j of curve 2 runs
  from b_j by e_j. They meet at translation t exactly when t lies in the
  parallelogram P_ij = {c + λ d_i + μ f_j : λ, μ ∈ [0, 1]}, with c = a_i − b_j
  and f_j = −e_j (docs/design.md, Engines). Both engines evaluate that one predicate,
  :func:`pair_contains`, on the same floating-point inputs, so they agree state
  for state, including at ties and on degenerate (parallel) pairs.
* Touching counts as meeting: the predicate accepts points within ``delta``
  of P_ij (closed sets, one tolerance for every engine).
* Thick particles meet when their centre curves come within the contact
  distance ``contact`` = (D₁ + D₂)/2. Two segments are that close exactly
  when they cross or an end point of one lies within that distance of the
  other (:func:`pair_meets`; geometrically, t lies within ``contact`` of
  P_ij). Each (end point, segment) distance is computed by one function with
  the same arguments whichever pair asks (:func:`vertex_near_segment`), so
  the raster can mark crossings first and then visit each (end point,
  segment) pair once (:func:`near_ends_slice`) and still agree with the
  direct engine state for state. ``contact`` = 0 takes the thin code path
  unchanged.
* Parallel kernels run ``prange`` over φ (or over samples); each slice is
  written by one thread, so results do not depend on the thread count.
"""

import math

import numpy as np
from numba import njit, prange

from .common import CHUNK, JIT, chunk_boxes, chunk_count, index_range, point_segment_distance2, rotate, segment_lengths

COUNT_MAX = 65535  # crossing counts saturate at the uint16 maximum

# The accepted region lies within delta·√2 of P_ij's bounding box; filters
# use a wider margin so they never reject a state the predicate accepts.
MARGIN_FACTOR = 3.0


@njit(**JIT)
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


@njit(**JIT)
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


@njit(**JIT)
def pair_contains(wx, wy, dx, dy, fx, fy, big_d, sign, tol_f, tol_d, inv_dlen, lo, hi):
    """True when w = t − c lies within delta of {λ d + μ f : λ, μ ∈ [0, 1]}: the thin segments i and j meet.

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
    return lo <= p <= hi


@njit(**JIT)
def in_pair_set(wx, wy, dx, dy, fx, fy, dlen, flen, delta):
    """:func:`pair_contains` with its set-up: one pair, one point."""
    big_d, sign, tol_f, tol_d, inv_dlen, lo, hi = pair_setup(dx, dy, fx, fy, dlen, flen, delta)
    return pair_contains(wx, wy, dx, dy, fx, fy, big_d, sign, tol_f, tol_d, inv_dlen, lo, hi)


@njit(**JIT)
def vertex_near_segment(px, py, s, k, reach2):
    """Whether the point (px, py) lies within √reach2 of segment k (s[k]–s[k+1]) of the polyline ``s``.

    Every engine evaluates a (vertex, segment) pair through this function with
    the same arguments, whichever segment pair asks: the thick predicate then
    has one value per state, and the engines agree bit for bit.
    """
    return point_segment_distance2(px, py, s[k, 0], s[k, 1], s[k + 1, 0], s[k + 1, 1]) <= reach2


@njit(**JIT)
def ends_near(v1, b2, i, j, tx, ty, reach2):
    """Whether an end point of segment i of curve 1 or of segment j of curve 2 (moved by t) lies within
    √reach2 of the other segment: with :func:`pair_contains` (the segments cross), segments within that
    distance of each other."""
    return (
        vertex_near_segment(tx + b2[j, 0], ty + b2[j, 1], v1, i, reach2)
        or vertex_near_segment(tx + b2[j + 1, 0], ty + b2[j + 1, 1], v1, i, reach2)
        or vertex_near_segment(v1[i, 0] - tx, v1[i, 1] - ty, b2, j, reach2)
        or vertex_near_segment(v1[i + 1, 0] - tx, v1[i + 1, 1] - ty, b2, j, reach2)
    )


@njit(**JIT)
def pair_meets(v1, b2, i, j, tx, ty, dlen, flen, delta, contact):
    """Segments i and j meet at translation t: they cross (within ``delta``), or, for thick particles, come
    within the contact distance (an end point of one within delta + contact of the other)."""
    cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
    if in_pair_set(tx - cx, ty - cy, dx, dy, fx, fy, dlen, flen, delta):
        return True
    reach = delta + contact
    return contact > 0.0 and ends_near(v1, b2, i, j, tx, ty, reach * reach)


@njit(**JIT)
def pair_bounds(cx, cy, dx, dy, fx, fy, margin):
    """Axis-aligned bounding box of P_ij, widened by ``margin``."""
    xmin = cx + min(0.0, dx) + min(0.0, fx) - margin
    xmax = cx + max(0.0, dx) + max(0.0, fx) + margin
    ymin = cy + min(0.0, dy) + min(0.0, fy) - margin
    ymax = cy + max(0.0, dy) + max(0.0, fy) + margin
    return xmin, xmax, ymin, ymax


@njit(**JIT)
def crossings_at(v1, dlen, b2, flen, tx, ty, delta, contact, count):
    """Number of segment pairs that meet at translation (tx, ty).

    The direct test: every pair, with bounding-box rejection. When ``count``
    is False it stops at the first pair found (the result is then 0 or 1).
    """
    margin = MARGIN_FACTOR * delta + contact
    found = 0
    for j in range(b2.shape[0] - 1):
        for i in range(v1.shape[0] - 1):
            cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
            xmin, xmax, ymin, ymax = pair_bounds(cx, cy, dx, dy, fx, fy, margin)
            if tx < xmin or tx > xmax or ty < ymin or ty > ymax:
                continue
            if pair_meets(v1, b2, i, j, tx, ty, dlen[i], flen[j], delta, contact):
                found += 1
                if not count:
                    return found
    return found


@njit(**JIT, parallel=True)
def direct_slices(v1, v2, cos_phi, sin_phi, xs, ys, delta, contact, reach, count, out):
    """Direct engine: ``out[k, iy, ix]`` = crossings at (xs[ix], ys[iy], φ_k).

    ``reach`` = r₁ + r₂ + contact: states further apart cannot meet and are skipped.
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
                n = crossings_at(v1, dlen, b2, flen, xs[ix], ys[iy], delta, contact, count)
                out[k, iy, ix] = min(n, COUNT_MAX)


@njit(**JIT)
def raster_constants(xs, ys, delta, contact):
    """(margin of the candidate boxes, squared contact reach, 1/dx, 1/dy) of a raster over (xs, ys)."""
    reach = delta + contact
    return MARGIN_FACTOR * delta + contact, reach * reach, 1.0 / (xs[1] - xs[0]), 1.0 / (ys[1] - ys[0])


@njit(**JIT)
def raster_slice(v1, dlen, b2, flen, xs, ys, delta, contact, count, out):
    """Minkowski raster of one orientation: add P_ij's nodes to ``out`` (ny, nx).

    ``out`` must be zero on entry. When ``count`` is False a node already
    marked is not tested again (only overlap, not the count, is wanted).
    """
    margin, reach2, inv_hx, inv_hy = raster_constants(xs, ys, delta, contact)
    for j in range(b2.shape[0] - 1):
        for i in range(v1.shape[0] - 1):
            cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
            xmin, xmax, ymin, ymax = pair_bounds(cx, cy, dx, dy, fx, fy, margin)
            iy0, iy1 = index_range(ymin, ymax, ys[0], inv_hy, ys.shape[0])
            if iy0 > iy1:
                continue
            ix0, ix1 = index_range(xmin, xmax, xs[0], inv_hx, xs.shape[0])
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
                    if pair_contains(tx - cx, ty - cy, dx, dy, fx, fy, big_d, sign, tol_f, tol_d, inv_dlen, lo, hi) or (
                        contact > 0.0 and ends_near(v1, b2, i, j, tx, ty, reach2)
                    ):  # pair_meets, with the pair's set-up hoisted out of the node loop
                        if out[iy, ix] < COUNT_MAX:
                            out[iy, ix] += 1


@njit(**JIT)
def free_node_table(out):
    """Summed-area table of the nodes of ``out`` still zero: ``table[iy, ix]`` counts them in [0, iy) × [0, ix)."""
    ny, nx = out.shape
    table = np.zeros((ny + 1, nx + 1), dtype=np.int32)
    for iy in range(ny):
        row = 0
        for ix in range(nx):
            row += out[iy, ix] == 0
            table[iy + 1, ix + 1] = table[iy, ix + 1] + row
    return table


@njit(**JIT)
def any_free(table, iy0, iy1, ix0, ix1):
    """Whether the box [iy0, iy1] × [ix0, ix1] of the table's field held a zero node."""
    return table[iy1 + 1, ix1 + 1] - table[iy0, ix1 + 1] - table[iy1 + 1, ix0] + table[iy0, ix0] > 0


@njit(**JIT)
def mark_near(px, py, s, k, sign, xs, ys, bounds, reach2, out):
    """Mark nodes t whose point p + sign·t lies within √reach2 of segment k of ``s`` (:func:`vertex_near_segment`
    evaluated as every engine does); ``bounds`` = (iy0, iy1, ix0, ix1) of the candidate nodes."""
    iy0, iy1, ix0, ix1 = bounds
    for iy in range(iy0, iy1 + 1):
        ty = ys[iy]
        for ix in range(ix0, ix1 + 1):
            if out[iy, ix] != 0:
                continue
            tx = xs[ix]
            hit = (
                vertex_near_segment(tx + px, ty + py, s, k, reach2)
                if sign > 0.0
                else vertex_near_segment(px - tx, py - ty, s, k, reach2)
            )
            if hit:
                out[iy, ix] = 1


@njit(**JIT)
def near_ends_slice(v1, b2, xs, ys, delta, contact, out):
    """Mark the nodes where an end point of one curve lies within delta + contact of a segment of the other.

    With the crossings already marked this completes the thick overlap field: each (vertex, segment) pair is
    visited once (a segment-pair raster would visit each twice), and one whose candidate box holds no
    unmarked node after the crossings (deep inside the excluded set) is skipped.
    """
    table = free_node_table(out)
    _near_ends_of(v1, b2, 1.0, xs, ys, delta, contact, table, out)  # vertices of curve 2 near segments of curve 1
    _near_ends_of(b2, v1, -1.0, xs, ys, delta, contact, table, out)  # and the other way round


@njit(**JIT)
def _near_ends_of(s, p, sign, xs, ys, delta, contact, table, out):
    """:func:`near_ends_slice` for the vertices of ``p`` (moved by sign·t) against the segments of ``s``."""
    margin, reach2, inv_hx, inv_hy = raster_constants(xs, ys, delta, contact)
    for k in range(s.shape[0] - 1):
        lox, hix = min(s[k, 0], s[k + 1, 0]), max(s[k, 0], s[k + 1, 0])
        loy, hiy = min(s[k, 1], s[k + 1, 1]), max(s[k, 1], s[k + 1, 1])
        for m in range(p.shape[0]):
            # nodes t with p_m + t (sign > 0) or p_m − t (sign < 0) near segment k, widened by the margin
            if sign > 0.0:
                xmin, xmax, ymin, ymax = lox - p[m, 0], hix - p[m, 0], loy - p[m, 1], hiy - p[m, 1]
            else:
                xmin, xmax, ymin, ymax = p[m, 0] - hix, p[m, 0] - lox, p[m, 1] - hiy, p[m, 1] - loy
            iy0, iy1 = index_range(ymin - margin, ymax + margin, ys[0], inv_hy, ys.shape[0])
            if iy0 > iy1:
                continue
            ix0, ix1 = index_range(xmin - margin, xmax + margin, xs[0], inv_hx, xs.shape[0])
            if ix0 > ix1 or not any_free(table, iy0, iy1, ix0, ix1):
                continue
            mark_near(p[m, 0], p[m, 1], s, k, sign, xs, ys, (iy0, iy1, ix0, ix1), reach2, out)


@njit(**JIT)
def raster_phi(v1, dlen, v2, c, s, xs, ys, delta, contact, count, out):
    """Raster engine for one orientation (cosine c, sine s) into ``out`` (ny, nx), zeroed."""
    b2 = np.empty_like(v2)
    rotate(v2, c, s, b2)
    flen = np.empty(b2.shape[0] - 1)
    segment_lengths(b2, flen)
    if contact > 0.0 and not count:  # overlap only: crossings, then the ends within reach (the same predicate)
        raster_slice(v1, dlen, b2, flen, xs, ys, delta, 0.0, False, out)
        near_ends_slice(v1, b2, xs, ys, delta, contact, out)
    else:
        raster_slice(v1, dlen, b2, flen, xs, ys, delta, contact, count, out)


@njit(**JIT, parallel=True)
def raster_slices(v1, v2, cos_phi, sin_phi, xs, ys, delta, contact, count, out):
    """Raster engine: ``out[k]`` = crossings at φ_k over the grid (out zeroed), one thread per φ."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in prange(cos_phi.shape[0]):
        raster_phi(v1, dlen, v2, cos_phi[k], sin_phi[k], xs, ys, delta, contact, count, out[k])


@njit(**JIT)
def raster_slices_serial(v1, v2, cos_phi, sin_phi, xs, ys, delta, contact, count, out):
    """:func:`raster_slices` in one thread: for small grids, where loading the
    parallel kernel costs more than it saves. Same slices, same results."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in range(cos_phi.shape[0]):
        raster_phi(v1, dlen, v2, cos_phi[k], sin_phi[k], xs, ys, delta, contact, count, out[k])


@njit(**JIT, parallel=True)
def shifted_overlap_counts(v1, v2, cos_phi, sin_phi, xs, ys, shifts, delta, contact, out):
    """``out[k]`` = overlapping nodes at φ_k on the lattice moved by ``shifts[k]``.

    Counts only: each thread rasterises one slice into its own scratch array.
    """
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for k in prange(cos_phi.shape[0]):
        field = np.zeros((ys.shape[0], xs.shape[0]), dtype=np.uint16)
        raster_phi(
            v1, dlen, v2, cos_phi[k], sin_phi[k], xs + shifts[k, 0], ys + shifts[k, 1], delta, contact, False, field
        )
        out[k] = np.count_nonzero(field)


@njit(**JIT)
def turned(v2, phi):
    """The polyline ``v2`` turned by ``phi`` (rad), and its segment lengths."""
    b2 = np.empty_like(v2)
    rotate(v2, math.cos(phi), math.sin(phi), b2)
    flen = np.empty(b2.shape[0] - 1)
    segment_lengths(b2, flen)
    return b2, flen


@njit(**JIT, parallel=True)
def crossings_at_states(v1, v2, xs, ys, phis, delta, contact, count, out):
    """Direct test at arbitrary states (xs[s], ys[s], phis[s]): the Monte-Carlo path."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    for s in prange(xs.shape[0]):
        b2, flen = turned(v2, phis[s])
        out[s] = min(crossings_at(v1, dlen, b2, flen, xs[s], ys[s], delta, contact, count), COUNT_MAX)


@njit(**JIT)
def meets_in_chunks(v1, dlen, box1, b2, flen, box2, tx, ty, delta, contact):
    """Whether any segment pair meets at translation (tx, ty): the pairs of :func:`crossings_at`, those of chunk
    pairs whose boxes, moved by (tx, ty) and widened by twice the pair margin, overlap (no other pair can meet:
    each segment pair's bounds lie within its chunks')."""
    margin = MARGIN_FACTOR * delta + contact
    wide = 2.0 * margin
    for cj in range(box2.shape[0]):
        for ci in range(box1.shape[0]):
            if tx < box1[ci, 0] - box2[cj, 1] - wide or tx > box1[ci, 1] - box2[cj, 0] + wide:
                continue
            if ty < box1[ci, 2] - box2[cj, 3] - wide or ty > box1[ci, 3] - box2[cj, 2] + wide:
                continue
            for j in range(cj * CHUNK, min((cj + 1) * CHUNK, b2.shape[0] - 1)):
                for i in range(ci * CHUNK, min((ci + 1) * CHUNK, v1.shape[0] - 1)):
                    cx, cy, dx, dy, fx, fy = pair_geometry(v1, b2, i, j)
                    xmin, xmax, ymin, ymax = pair_bounds(cx, cy, dx, dy, fx, fy, margin)
                    if tx < xmin or tx > xmax or ty < ymin or ty > ymax:
                        continue
                    if pair_meets(v1, b2, i, j, tx, ty, dlen[i], flen[j], delta, contact):
                        return True
    return False


@njit(**JIT, parallel=True)
def overlap_at_states(v1, v2, xs, ys, phis, delta, contact, out):
    """``out[s]``: whether the curves meet at state (xs[s], ys[s], phis[s]), by :func:`meets_in_chunks`."""
    dlen = np.empty(v1.shape[0] - 1)
    segment_lengths(v1, dlen)
    box1 = np.empty((chunk_count(v1), 4))
    chunk_boxes(v1, box1)
    for s in prange(xs.shape[0]):
        b2, flen = turned(v2, phis[s])
        box2 = np.empty((chunk_count(b2), 4))
        chunk_boxes(b2, box2)
        out[s] = meets_in_chunks(v1, dlen, box1, b2, flen, box2, xs[s], ys[s], delta, contact)


# --- the wrappers: arrays in, arrays out -------------------------------------------------

ENGINES = ("raster", "direct")

# Fields with fewer states than this run the serial raster kernel (no parallel start-up cost).
SERIAL_STATES = 1 << 20


def crossing_field(v1, v2, cos_phi, sin_phi, xs, ys, delta, *, contact=0.0, engine="raster", count=False, reach=0.0):
    """(k, ny, nx) uint16: segment pairs that meet at (xs[ix], ys[iy], φ_k).

    With ``count`` False only overlap is wanted and a node stops at its first
    pair (the value is then 0 or a lower bound). Segments within ``contact``
    (b) count as meeting (thick particles). ``reach`` (r₁ + r₂ + contact) lets the
    direct engine skip states that cannot meet. Both engines evaluate the same
    predicate and give identical fields.
    """
    out = np.zeros((len(cos_phi), len(ys), len(xs)), dtype=np.uint16)
    if engine == "raster":
        kernel = raster_slices_serial if out.size < SERIAL_STATES else raster_slices
        kernel(v1, v2, cos_phi, sin_phi, xs, ys, delta, contact, count, out)
    elif engine == "direct":
        direct_slices(v1, v2, cos_phi, sin_phi, xs, ys, delta, contact, reach, count, out)
    else:
        raise ValueError(f"engine must be one of {ENGINES}, got {engine!r}")
    return out


def lattice_overlap_counts(v1, v2, cos_phi, sin_phi, xs, ys, shifts, delta, contact=0.0):
    """(k,) int64: overlapping nodes at φ_k on the lattice (xs, ys) moved by ``shifts[k]``."""
    out = np.zeros(len(cos_phi), dtype=np.int64)
    shifted_overlap_counts(v1, v2, cos_phi, sin_phi, xs, ys, shifts, delta, contact, out)
    return out


def state_crossings(v1, v2, xs, ys, phis, delta, count=False, contact=0.0):
    """(s,) uint16: segment pairs that meet at each arbitrary state (xs[s], ys[s], phis[s])."""
    out = np.empty(len(xs), dtype=np.uint16)
    crossings_at_states(v1, v2, xs, ys, phis, delta, contact, count, out)
    return out


def states_overlap(v1, v2, xs, ys, phis, delta, contact=0.0):
    """(s,) bool: whether the curves meet at each arbitrary state (xs[s], ys[s], phis[s]); the same answer as
    ``state_crossings(...) > 0``, skipping chunks of segments whose boxes are apart."""
    out = np.empty(len(xs), dtype=np.bool_)
    overlap_at_states(v1, v2, xs, ys, phis, delta, contact, out)
    return out
