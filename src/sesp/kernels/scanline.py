"""Scanline kernels: the overlapping translations on lines y = const, measured exactly in x.

At orientation φ the translations t at which segments i and j meet form the
parallelogram P_ij = {c + λ d_i + μ f_j} (:mod:`sesp.kernels.overlap`); the
overlapping translations O are their union. On a line y = const the number of
parallelograms over a point changes only where the line crosses an edge, and
most edges are shared by two parallelograms on opposite sides, where the count
does not change: only the edges at the curves' ends and the folds (where one
curve's tangent turns through the direction of the other's segment) step it,
of the order of N edges instead of N² parallelograms. Sorting a line's
crossings and summing where the count is positive gives the length of O on
the line, exactly. For thick particles the set is O dilated by the contact
distance D, which is O together with the D-neighbourhood of its boundary, and
the boundary lies on those same edges: the line's length is that of the union
of O's pieces and the cuts of the edges' capsules (points within D of an
edge). Integrating the length over y gives A_ex(φ) with a quadrature that is
exact in x: no lattice in x, so no error from flat sides lining up with one.

Parallel kernels run ``prange`` over φ; each φ is computed by one thread, in a
fixed order, so results do not depend on the thread count.
"""

import math

import numpy as np
from numba import njit, prange

from .common import JIT, rotate


@njit(**JIT)
def _cut_edge(ax, ay, ex, ey, y, lo, hi):
    """Widen [lo, hi] by where the edge from a to a + e meets the line at height y."""
    t = y - ay
    if ey == 0.0:  # along the line, or apart from it
        if t != 0.0:
            return lo, hi
        return min(lo, ax, ax + ex), max(hi, ax, ax + ex)
    s = t / ey
    if s < 0.0 or s > 1.0:
        return lo, hi
    x = ax + ex * s
    return min(lo, x), max(hi, x)


@njit(**JIT)
def _cut_disk(cx, cy, r, y, lo, hi):
    """Widen [lo, hi] by the chord of the disk (centre c, radius r) at height y."""
    h2 = r * r - (y - cy) * (y - cy)
    if h2 < 0.0:
        return lo, hi
    h = math.sqrt(h2)
    return min(lo, cx - h), max(hi, cx + h)


@njit(**JIT)
def capsule_cut(px, py, qx, qy, contact, y):
    """The interval of x at which the line at height y meets the points within ``contact`` of the edge from
    p to q (empty: lo > hi): the hull of the cuts of the end disks and of the rectangle between them."""
    lo, hi = _cut_disk(px, py, contact, y, math.inf, -math.inf)
    lo, hi = _cut_disk(qx, qy, contact, y, lo, hi)
    ex, ey = qx - px, qy - py
    length = math.hypot(ex, ey)
    if length == 0.0:
        return lo, hi
    nx, ny = -ey / length * contact, ex / length * contact
    ox, oy = px - nx, py - ny  # the rectangle o + λe + μ·2n, λ, μ ∈ [0, 1]
    lo, hi = _cut_edge(ox, oy, ex, ey, y, lo, hi)
    lo, hi = _cut_edge(ox, oy, 2.0 * nx, 2.0 * ny, y, lo, hi)
    lo, hi = _cut_edge(ox + ex, oy + ey, 2.0 * nx, 2.0 * ny, y, lo, hi)
    return _cut_edge(ox + 2.0 * nx, oy + 2.0 * ny, ex, ey, y, lo, hi)


@njit(**JIT)
def _sign(value):
    return (value > 0.0) - (value < 0.0)


@njit(**JIT)
def _record(table, size, line, a, b):
    """Append (line, a, b) to ``table`` (3, capacity), growing it when full."""
    if size == table.shape[1]:
        grown = np.empty((3, 2 * size))
        grown[:, :size] = table
        table = grown
    table[0, size], table[1, size], table[2, size] = line, a, b
    return table, size + 1


@njit(**JIT)
def _lines_near(low, high, y0, h, rows):
    """(first, last): the lines r (heights y0 + r·h) that may lie in [low, high], one more each way than
    (low − y0)/h and (high − y0)/h say: rounding can put y0 + r·h inside while the quotient says outside (a
    line through a corner, a line tangent to a contact disk, whose chord there is sqrt(2·contact·rounding),
    about 1e-8 b). The caller tests each line exactly."""
    return max(0, int(math.ceil((low - y0) / h)) - 1), min(rows - 1, int(math.floor((high - y0) / h)) + 1)


@njit(**JIT)
def _cross_edge(crossings, size, y0, h, rows, px, py, qx, qy, step):
    """Record where the edge from p to q crosses the lines, with the step of the count of parallelograms as
    x grows past it: (line, x, step) appended to ``crossings``.

    An edge holds the heights min ≤ y < max (half-open), so a line through a corner shared by two edges
    crosses one of them, and every parallelogram is crossed twice or not at all; the corners are the same
    numbers a_i − b_j in every edge that has them. Edges along the lines hold no height."""
    low, high = min(py, qy), max(py, qy)
    first, last = _lines_near(low, high, y0, h, rows)
    for r in range(first, last + 1):
        y = y0 + r * h  # the range may be one line too wide; the test below is exact
        if low <= y < high:
            crossings, size = _record(crossings, size, r, px + (qx - px) * ((y - py) / (qy - py)), step)
    return crossings, size


@njit(**JIT)
def _stepping_edges(a1, b2, y0, h, rows, keep):
    """The crossings of the lines with the edges of the parallelograms P_ij that step the count, and, if
    ``keep``, those edges themselves: ``(crossings (3, m): line, x, step; m; edges (4, e): p, q; e)``.

    P_ij, spanned by d = a_i+1 − a_i and f = b_j − b_j+1 from a_i − b_j, lies on the side σ_ij =
    sign(d × f) of its edges (a_i .. a_i+1) − b_j and a_i+1 − (b_j .. b_j+1), and on the other side of the
    two opposite ones; an edge steps the count by the difference of the σ of its two parallelograms (0 past
    the curves' ends), signed by the direction it is crossed in. One sign per pair fixes every step. A flat
    P_ij (σ_ij = 0, as when two segments are parallel at φ = π) has no area and steps nothing, but a
    segment of O may stick out there, so its edges are kept too.
    """
    n1, n2 = a1.shape[0] - 1, b2.shape[0] - 1
    crossings = np.empty((3, 16 * (n1 + n2) + 16))
    size = 0
    edges = np.empty((4, 4 * (n1 + n2) + 16 if keep else 0))
    kept = 0
    fx = b2[:-1, 0] - b2[1:, 0]  # f_j
    fy = b2[:-1, 1] - b2[1:, 1]
    previous = np.zeros(n2 + 2, dtype=np.int64)  # σ_i-1,j at j + 1; 0 past the ends
    current = np.zeros(n2 + 2, dtype=np.int64)
    for i in range(n1 + 1):  # vertex i of curve 1, and segment i if i < n1
        ax, ay = a1[i, 0], a1[i, 1]
        if i < n1:
            dx, dy = a1[i + 1, 0] - ax, a1[i + 1, 1] - ay
            for j in range(n2):
                current[j + 1] = _sign(dx * fy[j] - dy * fx[j])
        else:
            dx, dy = 0.0, 0.0
            current[:] = 0
        for j in range(n2 + 1):
            here = current[j + 1]
            if here == previous[j + 1] and here == current[j] and (here != 0 or not keep):
                continue
            px, py = ax - b2[j, 0], ay - b2[j, 1]  # a_i − b_j
            if j < n2 and here != previous[j + 1]:  # a_i − (b_j .. b_j+1): P_i-1,j on side σ, P_ij on side −σ
                qx, qy = ax - b2[j + 1, 0], ay - b2[j + 1, 1]
                if fy[j] != 0.0:
                    step = -_sign(fy[j]) * (previous[j + 1] - here)
                    crossings, size = _cross_edge(crossings, size, y0, h, rows, px, py, qx, qy, step)
                if keep:
                    edges, kept = _keep(edges, kept, px, py, qx, qy)
            if here != current[j]:  # (a_i .. a_i+1) − b_j: P_ij on side σ, P_i,j-1 on side −σ
                qx, qy = a1[i + 1, 0] - b2[j, 0], a1[i + 1, 1] - b2[j, 1]  # a_i+1 − b_j, as in every edge
                if dy != 0.0:
                    step = -_sign(dy) * (here - current[j])
                    crossings, size = _cross_edge(crossings, size, y0, h, rows, px, py, qx, qy, step)
                if keep:
                    edges, kept = _keep(edges, kept, px, py, qx, qy)
            if keep and here == 0 and j < n2 and i < n1:  # P_ij flat (d ∥ f): a segment, maybe sticking out of O
                edges, kept = _keep_flat(edges, kept, a1, b2, i, j)
        previous, current = current, previous
    return crossings, size, edges, kept


@njit(**JIT)
def _keep(edges, kept, px, py, qx, qy):
    """Append the edge from p to q to ``edges`` (4, capacity), growing it when full."""
    if kept == edges.shape[1]:
        grown = np.empty((4, 2 * kept))
        grown[:, :kept] = edges
        edges = grown
    edges[0, kept], edges[1, kept], edges[2, kept], edges[3, kept] = px, py, qx, qy
    return edges, kept + 1


@njit(**JIT)
def _keep_flat(edges, kept, a1, b2, i, j):
    """Keep the flat P_ij as edges from its corners a_i+u − b_j+v to a_i+1 − b_j+1 (they cover the segment)."""
    qx, qy = a1[i + 1, 0] - b2[j + 1, 0], a1[i + 1, 1] - b2[j + 1, 1]
    for u, v in ((0, 0), (1, 0), (0, 1)):
        edges, kept = _keep(edges, kept, a1[i + u, 0] - b2[j + v, 0], a1[i + u, 1] - b2[j + v, 1], qx, qy)
    return edges, kept


@njit(**JIT)
def _by_line(table, size, rows):
    """Group the records (line, a, b) of ``table[:, :size]`` by line, keeping their order within a line
    (counting sort): ``(start (rows + 1), a, b)``, line r's records at start[r] .. start[r + 1]."""
    start = np.zeros(rows + 1, dtype=np.int64)
    for k in range(size):
        start[int(table[0, k]) + 1] += 1
    for r in range(rows):
        start[r + 1] += start[r]
    fill = start[:rows].copy()
    a, b = np.empty(size), np.empty(size)
    for k in range(size):
        r = int(table[0, k])
        a[fill[r]], b[fill[r]] = table[1, k], table[2, k]
        fill[r] += 1
    return start, a, b


@njit(**JIT)
def _sort_together(keys, values, lo, hi):
    """Sort ``keys[lo:hi]``, and ``values`` with them, in place (stable; insertion sort for the few crossings a
    line of a SeSP pair holds)."""
    if hi - lo > 64:
        order = np.argsort(keys[lo:hi], kind="mergesort")
        keys[lo:hi], values[lo:hi] = keys[lo:hi][order], values[lo:hi][order]
        return
    for k in range(lo + 1, hi):
        key, value = keys[k], values[k]
        m = k
        while m > lo and keys[m - 1] > key:
            keys[m], values[m] = keys[m - 1], values[m - 1]
            m -= 1
        keys[m], values[m] = key, value


@njit(**JIT)
def _union_length(lows, highs):
    """Total length of the union of the intervals [lows[k], highs[k]]."""
    order = np.argsort(lows, kind="mergesort")
    total = 0.0
    lo, hi = math.inf, -math.inf
    for k in order:
        if lows[k] > hi:
            if hi > lo:
                total += hi - lo
            lo, hi = lows[k], highs[k]
        elif highs[k] > hi:
            hi = highs[k]
    return total + hi - lo if hi > lo else total


@njit(**JIT)
def row_lengths(a1, b2, y0, h, contact, out):
    """``out[r]`` = length of the overlapping translations on the line y = y0 + r·h, for curve 1 at ``a1`` and
    curve 2 at ``b2`` (both already rotated), at contact distance ``contact``.

    The count of parallelograms over each point of the line steps at the crossings of
    :func:`_stepping_edges`; where it is positive the point is in O. With a contact distance the pieces of
    O and the cuts of the stepping edges' capsules are joined instead.
    """
    rows = out.shape[0]
    crossings, size, edges, kept = _stepping_edges(a1, b2, y0, h, rows, contact > 0.0)
    start, xs, steps = _by_line(crossings, size, rows)
    pieces = np.empty((3, size + 16 if contact > 0.0 else 0))
    count_pieces = 0
    for r in range(rows):
        _sort_together(xs, steps, start[r], start[r + 1])
        total, count, opened = 0.0, 0, 0.0
        for k in range(start[r], start[r + 1]):
            if count == 0:
                opened = xs[k]
            count += int(steps[k])
            if count == 0 and xs[k] > opened:  # a piece of O ends
                total += xs[k] - opened
                if contact > 0.0:
                    pieces, count_pieces = _record(pieces, count_pieces, r, opened, xs[k])
        out[r] = total
    if contact == 0.0:
        return
    for k in range(kept):
        px, py, qx, qy = edges[0, k], edges[1, k], edges[2, k], edges[3, k]
        low, high = min(py, qy) - contact, max(py, qy) + contact
        first, last = _lines_near(low, high, y0, h, rows)
        for r in range(first, last + 1):  # capsule_cut is the exact test
            lo, hi = capsule_cut(px, py, qx, qy, contact, y0 + r * h)
            if lo <= hi:
                pieces, count_pieces = _record(pieces, count_pieces, r, lo, hi)
    start, lows, highs = _by_line(pieces, count_pieces, rows)
    for r in range(rows):
        out[r] = _union_length(lows[start[r] : start[r + 1]], highs[start[r] : start[r + 1]])


@njit(**JIT, parallel=True)
def scanline_lengths(v1, v2, cos_a, sin_a, cos_b, sin_b, contact, out):
    """``out[k, r]``, r = 0 .. rows: overlapping length on the r-th of rows + 1 equally spaced lines across the
    excluded set, with curve 1 rotated by (cos_a[k], sin_a[k]) and curve 2 by (cos_b[k], sin_b[k]);
    ``out[k, rows + 1]`` and ``out[k, rows + 2]`` are the first line's height and the spacing."""
    rows = out.shape[1] - 3
    for k in prange(cos_a.shape[0]):
        a1 = np.empty_like(v1)
        rotate(v1, cos_a[k], sin_a[k], a1)
        b2 = np.empty_like(v2)
        rotate(v2, cos_b[k], sin_b[k], b2)
        y0 = a1[:, 1].min() - b2[:, 1].max() - contact
        h = (a1[:, 1].max() - b2[:, 1].min() + contact - y0) / rows
        row_lengths(a1, b2, y0, h, contact, out[k, : rows + 1])
        out[k, rows + 1] = y0
        out[k, rows + 2] = h


# --- the wrapper: arrays in, arrays out ---------------------------------------------------


def scanline_table(v1, v2, angle1, angle2, contact, rows):
    """Lengths on ``rows`` + 1 lines across the excluded set, curve 1 turned by ``angle1[k]`` and curve 2 by
    ``angle2[k]`` (rad): ``(lengths (k, rows + 1), first line's height (k,), spacing h (k,))``, in b."""
    out = np.zeros((len(angle1), rows + 3))
    scanline_lengths(v1, v2, np.cos(angle1), np.sin(angle1), np.cos(angle2), np.sin(angle2), contact, out)
    return out[:, : rows + 1], out[:, rows + 1], out[:, rows + 2]
