"""Scanline kernels: the overlapping translations on lines y = const, measured exactly in x.

At orientation φ the translations t at which segments i and j meet form the
parallelogram P_ij = {c + λ d_i + μ f_j} (:mod:`sesp.kernels.overlap`), or, for
thick particles, P_ij dilated by a disk of radius ``contact``. Each is
convex, so a line y = const cuts it in one interval; the overlapping
translations on the line are the union of those intervals, whose length is
computed exactly (sorted and merged). Integrating that length over y gives
A_ex(φ) with a quadrature that is exact in x: no lattice in x, so no error
from flat sides lining up with one.

Parallel kernels run ``prange`` over φ; each φ is computed by one thread, so
results do not depend on the thread count.
"""

import math

import numpy as np
from numba import njit, prange

from .common import JIT, rotate


@njit(**JIT)
def _cut_segment(ax, ay, bx, by, y, lo, hi):
    """Widen [lo, hi] by where the segment a–b meets the line at height y."""
    if (ay - y) * (by - y) > 0.0:
        return lo, hi
    if ay == by:  # on the line
        return min(lo, ax, bx), max(hi, ax, bx)
    x = ax + (bx - ax) * (y - ay) / (by - ay)
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
def _cut_polygon4(px, py, y, lo, hi):
    """Widen [lo, hi] by the cut of the convex quadrilateral (px[k], py[k]), k = 0..3, at height y."""
    for k in range(4):
        m = (k + 1) % 4
        lo, hi = _cut_segment(px[k], py[k], px[m], py[m], y, lo, hi)
    return lo, hi


@njit(**JIT)
def pair_cut(cx, cy, dx, dy, fx, fy, contact, y, px, py, qx, qy):
    """The interval of x at which the line at height y meets P_ij dilated by ``contact`` (empty: lo > hi).

    P_ij ⊕ disk is the union of P_ij, each edge's rectangle of half-width ``contact`` and the four corner
    disks; being convex, its cut is the hull of the pieces' cuts. ``px, py, qx, qy`` are scratch arrays of 4.
    """
    px[0], py[0] = cx, cy
    px[1], py[1] = cx + dx, cy + dy
    px[2], py[2] = cx + dx + fx, cy + dy + fy
    px[3], py[3] = cx + fx, cy + fy
    lo, hi = _cut_polygon4(px, py, y, math.inf, -math.inf)
    if contact == 0.0:
        return lo, hi
    for k in range(4):
        lo, hi = _cut_disk(px[k], py[k], contact, y, lo, hi)
        m = (k + 1) % 4
        ex, ey = px[m] - px[k], py[m] - py[k]
        length = math.hypot(ex, ey)
        if length == 0.0:
            continue
        nx, ny = -ey / length * contact, ex / length * contact
        qx[0], qy[0] = px[k] + nx, py[k] + ny
        qx[1], qy[1] = px[m] + nx, py[m] + ny
        qx[2], qy[2] = px[m] - nx, py[m] - ny
        qx[3], qy[3] = px[k] - nx, py[k] - ny
        lo, hi = _cut_polygon4(qx, qy, y, lo, hi)
    return lo, hi


@njit(**JIT)
def union_length(starts, ends):
    """Total length of the union of the intervals [starts[k], ends[k]] (empty ones, start > end, ignored)."""
    order = np.argsort(starts)
    total = 0.0
    lo, hi = math.inf, -math.inf
    for k in order:
        if starts[k] > ends[k]:
            continue
        if starts[k] > hi:
            if hi > lo:
                total += hi - lo
            lo, hi = starts[k], ends[k]
        elif ends[k] > hi:
            hi = ends[k]
    return total + hi - lo if hi > lo else total


@njit(**JIT)
def _pair_rows(a1, b2, i, j, y0, h, contact, rows):
    """The lines r0 .. r1 that may cut P_ij (dilated by ``contact``)."""
    cy = a1[i, 1] - b2[j, 1]
    dy, fy = a1[i + 1, 1] - a1[i, 1], b2[j, 1] - b2[j + 1, 1]
    ymin = cy + min(0.0, dy) + min(0.0, fy) - contact
    ymax = cy + max(0.0, dy) + max(0.0, fy) + contact
    return max(0, int(math.ceil((ymin - y0) / h))), min(rows - 1, int(math.floor((ymax - y0) / h)))


@njit(**JIT)
def _emit(pieces, size, r, lo, hi):
    """Append the piece [lo, hi] of line r to ``pieces`` (3, capacity), growing it when full."""
    if size == pieces.shape[1]:
        grown = np.empty((3, 2 * size))
        grown[:, :size] = pieces
        pieces = grown
    pieces[0, size], pieces[1, size], pieces[2, size] = r, lo, hi
    return pieces, size + 1


@njit(**JIT)
def row_lengths(a1, b2, y0, h, contact, out):
    """``out[r]`` = length of the overlapping translations on the line y = y0 + r·h, for curve 1 at ``a1`` and
    curve 2 at ``b2`` (both already rotated).

    For one segment i of curve 1 the parallelograms of consecutive segments j share an edge, so their cuts
    of a line mostly overlap: they are merged as they come (a running interval per line), and only the
    merged pieces are grouped by line, sorted and joined.
    """
    n1, n2 = a1.shape[0] - 1, b2.shape[0] - 1
    rows = out.shape[0]
    pieces = np.empty((3, 4 * n1 * rows + 16))  # line, start, end of each merged piece
    size = 0
    run_lo = np.full(rows, math.inf)
    run_hi = np.full(rows, -math.inf)
    px, py, qx, qy = np.empty(4), np.empty(4), np.empty(4), np.empty(4)
    for i in range(n1):
        dx, dy = a1[i + 1, 0] - a1[i, 0], a1[i + 1, 1] - a1[i, 1]
        for j in range(n2):
            cx, cy = a1[i, 0] - b2[j, 0], a1[i, 1] - b2[j, 1]
            fx, fy = b2[j, 0] - b2[j + 1, 0], b2[j, 1] - b2[j + 1, 1]
            ymin = cy + min(0.0, dy) + min(0.0, fy) - contact
            ymax = cy + max(0.0, dy) + max(0.0, fy) + contact
            r0 = max(0, int(math.ceil((ymin - y0) / h)))
            r1 = min(rows - 1, int(math.floor((ymax - y0) / h)))
            for r in range(r0, r1 + 1):
                lo, hi = pair_cut(cx, cy, dx, dy, fx, fy, contact, y0 + r * h, px, py, qx, qy)
                if lo > hi:
                    continue
                if lo <= run_hi[r] and hi >= run_lo[r]:  # overlaps the running piece: extend it
                    run_lo[r] = min(run_lo[r], lo)
                    run_hi[r] = max(run_hi[r], hi)
                    continue
                if run_lo[r] <= run_hi[r]:
                    pieces, size = _emit(pieces, size, r, run_lo[r], run_hi[r])
                run_lo[r], run_hi[r] = lo, hi
        for r in range(rows):  # the next segment i starts its own pieces
            if run_lo[r] <= run_hi[r]:
                pieces, size = _emit(pieces, size, r, run_lo[r], run_hi[r])
                run_lo[r], run_hi[r] = math.inf, -math.inf
    # group the pieces by line (counting sort), then join each line's
    start = np.zeros(rows + 1, dtype=np.int64)
    for k in range(size):
        start[int(pieces[0, k]) + 1] += 1
    for r in range(rows):
        start[r + 1] += start[r]
    fill = start[:rows].copy()
    lows, highs = np.empty(size), np.empty(size)
    for k in range(size):
        r = int(pieces[0, k])
        lows[fill[r]], highs[fill[r]] = pieces[1, k], pieces[2, k]
        fill[r] += 1
    for r in range(rows):
        out[r] = union_length(lows[start[r] : start[r + 1]], highs[start[r] : start[r + 1]])


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
