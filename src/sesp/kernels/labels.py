"""Component-labelling kernel: persistence of the distance-to-complement field (robust components)."""

import numpy as np
from numba import njit

from .common import JIT


@njit(**JIT)
def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@njit(**JIT)
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


@njit(**JIT)
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


def persistent_labels(dist, order, shape, periodic, ratio, min_peak):
    """(labels, count): :func:`persistent_components` on flat arrays, labels int64 like ``dist``."""
    labels = np.zeros(dist.shape[0], dtype=np.int64)
    count = persistent_components(dist, order, shape, periodic, ratio, min_peak, labels)
    return labels, count
