"""What every kernel family shares: the jit options and small geometric helpers."""

import math
from contextlib import contextmanager

import numba
from numba import njit

# One set of options for every kernel: compiled once and cached on disk; no fastmath.
JIT = dict(cache=True, nogil=True)
# positions a thread takes at a time from a parallel loop over positions (cost only: a position near the
# curves costs a hundred times one far from them, and they come in runs, so equal shares leave a thread idle)
POSITIONS_PER_CHUNK = 8


@contextmanager
def small_chunks():
    """Within: ``prange`` loops hand out POSITIONS_PER_CHUNK iterations at a time to whichever thread is free
    (numba's parallel chunk size; 0: one equal share per thread, numba's default). Results are unchanged: each
    iteration is still written by one thread."""
    old = numba.set_parallel_chunksize(POSITIONS_PER_CHUNK)
    try:
        yield
    finally:
        numba.set_parallel_chunksize(old)


@njit(**JIT)
def rotate(vertices, c, s, out):
    """out = R vertices, R the rotation with cosine c and sine s."""
    for k in range(vertices.shape[0]):
        x = vertices[k, 0]
        y = vertices[k, 1]
        out[k, 0] = c * x - s * y
        out[k, 1] = s * x + c * y


@njit(**JIT)
def segment_lengths(vertices, out):
    for k in range(vertices.shape[0] - 1):
        dx = vertices[k + 1, 0] - vertices[k, 0]
        dy = vertices[k + 1, 1] - vertices[k, 1]
        out[k] = math.sqrt(dx * dx + dy * dy)


@njit(**JIT)
def index_range(lo, hi, origin, inv_step, size):
    """Indices i with origin + i·step in [lo, hi], clipped to the grid.

    Filters widen [lo, hi] by MARGIN_FACTOR·delta, far more than the rounding
    of this index arithmetic, so no node the predicate accepts is missed.
    """
    i0 = int(math.ceil((lo - origin) * inv_step))
    i1 = int(math.floor((hi - origin) * inv_step))
    return max(i0, 0), min(i1, size - 1)


@njit(**JIT)
def point_segment_distance2(x, y, ax, ay, bx, by):
    """Squared distance from (x, y) to the segment a–b."""
    ex = bx - ax
    ey = by - ay
    length2 = ex * ex + ey * ey
    lam = 0.0 if length2 == 0.0 else min(1.0, max(0.0, ((x - ax) * ex + (y - ay) * ey) / length2))
    dx = ax + lam * ex - x
    dy = ay + lam * ey - y
    return dx * dx + dy * dy


@njit(**JIT)
def sort_first(values, m):
    """Sort values[:m] in place (insertion sort: for the few roots of one interval of φ)."""
    for k in range(1, m):
        value = values[k]
        i = k - 1
        while i >= 0 and values[i] > value:
            values[i + 1] = values[i]
            i -= 1
        values[i + 1] = value


@njit(**JIT)
def find_root(parent, a):
    """The root of ``a`` in the union-find forest ``parent``, halving the path on the way (the one union-find
    of the code base: lattice labels and quadtree cells)."""
    while parent[a] != a:
        parent[a] = parent[parent[a]]
        a = parent[a]
    return a


CHUNK = 16  # segments per bounding box of a polyline's runs (cost only: a run whose box is far is skipped whole)


@njit(**JIT)
def chunk_boxes(v, out):
    """Write to ``out`` (xmin, xmax, ymin, ymax) of each run of ``CHUNK`` segments of the polyline ``v``."""
    for c in range(out.shape[0]):
        lo = c * CHUNK
        hi = min(lo + CHUNK, v.shape[0] - 1)
        out[c, 0] = out[c, 1] = v[lo, 0]
        out[c, 2] = out[c, 3] = v[lo, 1]
        for k in range(lo + 1, hi + 1):
            out[c, 0] = min(out[c, 0], v[k, 0])
            out[c, 1] = max(out[c, 1], v[k, 0])
            out[c, 2] = min(out[c, 2], v[k, 1])
            out[c, 3] = max(out[c, 3], v[k, 1])
    return out


@njit(**JIT)
def chunk_count(v):
    """Runs of ``CHUNK`` segments in the polyline ``v`` (the last may be shorter)."""
    return (v.shape[0] - 2) // CHUNK + 1
