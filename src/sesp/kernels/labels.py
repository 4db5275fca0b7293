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
def persistent_components(dist, order, shape, periodic, ratio, min_peak, labels, neck, resolved, necks):
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

    Undecided necks: where the lower peak is at least ``resolved`` and
    ratio · p <= s < neck · p, the neck is narrower than the smaller body but
    wide enough to join them at this resolution; the two are kept apart and
    the meeting is written to ``necks`` (rows: node, the two components'
    numbers, s), as many as it holds, for a finer look (``neck`` = 0: none).
    Returns (count, number of necks found).
    """
    n = dist.shape[0]
    parent = np.arange(n)
    peak = np.zeros(n)
    merged_into = np.full(n, -1)  # root absorbed into another root (not compressed)
    kept = np.zeros(n, dtype=np.bool_)  # root that survived a merge as its own component
    owner = np.full(n, -1)  # root a node joined when it was added
    added = np.zeros(n, dtype=np.bool_)
    neck_node = np.empty(necks.shape[0], dtype=np.int64)
    neck_a = np.empty(necks.shape[0], dtype=np.int64)
    neck_b = np.empty(necks.shape[0], dtype=np.int64)
    found = 0
    for node in order:
        added[node] = True
        best = -1
        steepest = -1  # the added neighbour of largest distance: the node takes its component (steepest ascent)
        for k in range(27):
            nb = _neighbour(node, k, shape[0], shape[1], shape[2], periodic)
            if nb < 0 or not added[nb]:
                continue
            if steepest < 0 or dist[nb] > dist[steepest]:
                steepest = nb
            r = _find(parent, nb)
            if best < 0:
                best = r
            elif r != best:
                hi, lo = (best, r) if peak[best] >= peak[r] else (r, best)
                if dist[node] < ratio * peak[lo] and peak[lo] >= min_peak:
                    kept[lo] = True
                elif dist[node] < neck * peak[lo] and peak[lo] >= resolved:
                    kept[lo] = True
                    if found < neck_node.shape[0]:
                        neck_node[found], neck_a[found], neck_b[found] = node, hi, lo
                    found += 1
                else:
                    merged_into[lo] = hi
                parent[lo] = hi
                best = hi
        if best < 0:
            peak[node] = dist[node]
            owner[node] = node
        else:
            parent[node] = best
            owner[node] = owner[steepest]
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
        labels[node] = _number_of(owner[node], kept, merged_into, number)
    for k in range(min(found, necks.shape[0])):
        necks[k, 0] = neck_node[k]
        necks[k, 1] = _number_of(neck_a[k], kept, merged_into, number)
        necks[k, 2] = _number_of(neck_b[k], kept, merged_into, number)
        necks[k, 3] = dist[neck_node[k]]
    return count, found


@njit(**JIT)
def _number_of(root, kept, merged_into, number):
    """The component number of a root: its own if kept, else that of the root it was absorbed into (0: none)."""
    while root >= 0 and not kept[root]:
        root = merged_into[root]
    return number[root] if root >= 0 else 0


def persistent_labels(dist, order, shape, periodic, ratio, min_peak, neck=0.0, resolved=np.inf, max_necks=0):
    """(labels, count, necks): :func:`persistent_components` on flat arrays, labels int64 like ``dist``;
    ``necks`` (k, 4): node, the two components' numbers, neck value, at most ``max_necks`` rows."""
    labels = np.zeros(dist.shape[0], dtype=np.int64)
    necks = np.zeros((max_necks, 4))
    count, found = persistent_components(
        dist, order, shape, periodic, ratio, min_peak, labels, float(neck), float(resolved), necks
    )
    return labels, count, necks[: min(found, max_necks)]
