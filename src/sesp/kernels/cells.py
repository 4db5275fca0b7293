"""Cell kernels: the adjacency of a quadtree's leaves and the components of sets of leaves.

Leaves are squares of a quadtree over a base grid of ``base`` × ``base``
cells: leaf (level, i, j) covers cells i and j of the grid 2^level times finer
than the base. Two leaves are adjacent when their closed squares meet (along
an edge or at a corner). Components are found with one union-find.
"""

import math

import numpy as np
from numba import njit

from .common import JIT, find_root

_DIRECTIONS = np.array([(di, dj) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj], dtype=np.int64)


@njit(**JIT)
def _key(level, i, j):
    return (level << 56) | (i << 28) | j


@njit(**JIT)
def leaf_edges(level, ii, jj, base):
    """(a, b): every ordered pair of adjacent leaves (both orders), at least once.

    A leaf looks for the leaf holding each of its 8 same-size neighbours: that
    neighbour itself or the larger leaf it lies in (its ancestors are tried
    in turn). A neighbour subdivided into smaller leaves is not found this
    way, but each of those finds this leaf, so every adjacent pair is found; each is listed both ways.
    """
    n = level.shape[0]
    keys = np.empty(n, np.int64)
    for a in range(n):
        keys[a] = _key(level[a], ii[a], jj[a])
    order = np.argsort(keys)
    sorted_keys = keys[order]
    ea = np.empty(8 * n, np.int64)
    eb = np.empty(8 * n, np.int64)
    m = 0
    for a in range(n):
        for d in range(8):
            k = level[a]
            i = ii[a] + _DIRECTIONS[d, 0]
            j = jj[a] + _DIRECTIONS[d, 1]
            size = base << k
            if i < 0 or j < 0 or i >= size or j >= size:
                continue
            while k >= 0:
                key = _key(k, i, j)
                at = np.searchsorted(sorted_keys, key)
                if at < n and sorted_keys[at] == key:
                    ea[m] = a
                    eb[m] = order[at]
                    m += 1
                    break
                k -= 1
                i >>= 1
                j >>= 1
    return np.concatenate((ea[:m], eb[:m])), np.concatenate((eb[:m], ea[:m]))


@njit(**JIT)
def _union(parent, a, b):
    ra, rb = find_root(parent, a), find_root(parent, b)
    if ra != rb:
        parent[max(ra, rb)] = min(ra, rb)


@njit(**JIT)
def _labels(parent, member):
    out = np.full(member.shape[0], -1, np.int64)
    for a in range(member.shape[0]):
        if member[a]:
            out[a] = find_root(parent, a)
    return out


@njit(**JIT)
def components(member, ea, eb):
    """Per leaf: the smallest leaf index of its component among the ``member`` leaves (−1 for others)."""
    parent = np.arange(member.shape[0])
    for e in range(ea.shape[0]):
        if member[ea[e]] and member[eb[e]]:
            _union(parent, ea[e], eb[e])
    return _labels(parent, member)


@njit(**JIT)
def adjacency(n, ea, eb):
    """(start, neighbour): the leaves adjacent to leaf a are ``neighbour[start[a]:start[a + 1]]`` (edges (a, b)
    grouped by a, in their order: a counting sort)."""
    start = np.zeros(n + 1, np.int64)
    for e in range(ea.shape[0]):
        start[ea[e] + 1] += 1
    for a in range(n):
        start[a + 1] += start[a]
    at = start[:-1].copy()
    neighbour = np.empty(ea.shape[0], np.int64)
    for e in range(ea.shape[0]):
        neighbour[at[ea[e]]] = eb[e]
        at[ea[e]] += 1
    return start, neighbour


@njit(**JIT)
def disk_components(member, x, y, radius, half_diagonal, start, neighbour):
    """Components of the ``member`` leaves, joined where they are adjacent or where the disks of ``radius`` about
    their centres meet, among leaves two steps apart (the union of two meeting disks is connected); a leaf whose
    disk is no wider than itself reaches no farther than its neighbours. ``start``, ``neighbour``: :func:`adjacency`."""
    n = member.shape[0]
    parent = np.arange(n)
    for a in range(n):
        if not member[a]:
            continue
        for e in range(start[a], start[a + 1]):
            b = neighbour[e]
            if member[b]:
                _union(parent, a, b)
            if radius[a] <= half_diagonal[a]:
                continue
            for f in range(start[b], start[b + 1]):
                c = neighbour[f]
                if c != a and member[c] and math.hypot(x[a] - x[c], y[a] - y[c]) <= radius[a] + radius[c]:
                    _union(parent, a, c)
    return _labels(parent, member)


@njit(**JIT)
def _steps_from(source, passable, start, neighbour):
    """Steps from the ``source`` leaves to every leaf through ``passable`` leaves (−1: not reached)."""
    n = source.shape[0]
    steps = np.full(n, -1, np.int64)
    queue = np.empty(n, np.int64)
    tail = 0
    for a in range(n):
        if source[a]:
            steps[a] = 0
            queue[tail] = a
            tail += 1
    head = 0
    while head < tail:
        a = queue[head]
        head += 1
        for e in range(start[a], start[a + 1]):
            b = neighbour[e]
            if passable[b] and steps[b] < 0:
                steps[b] = steps[a] + 1
                queue[tail] = b
                tail += 1
    return steps


@njit(**JIT)
def corridors(seed, passable, start, neighbour, slack):
    """Leaves on the shortest paths (in steps, within ``slack`` more) through ``passable`` leaves from each seed
    (leaves sharing a label ≥ 0) to the seed nearest to it: where two seeds could be joined. ``start``,
    ``neighbour``: :func:`adjacency`."""
    n = seed.shape[0]
    labels = np.unique(seed[seed >= 0])
    k = labels.shape[0]
    out = np.zeros(n, np.bool_)
    if k < 2:
        return out
    steps = np.empty((k, n), np.int64)
    for s in range(k):
        steps[s] = _steps_from(seed == labels[s], passable, start, neighbour)
    for s in range(k):
        nearest, length = -1, np.iinfo(np.int64).max
        for t in range(k):
            if t == s:
                continue
            for a in range(n):
                if seed[a] == labels[t] and 0 <= steps[s, a] < length:
                    nearest, length = t, steps[s, a]
        if nearest < 0:
            continue
        for a in range(n):
            if steps[s, a] >= 0 and steps[nearest, a] >= 0 and steps[s, a] + steps[nearest, a] <= length + slack:
                out[a] = True
    return out


@njit(**JIT)
def graded(split, undecided, level, ea, eb):
    """``split`` grown until no undecided leaf next to a split one is two or more levels larger than its
    children will be (a 2:1 graded tree, so that what is certified on fine leaves meets what was certified on
    coarse ones)."""
    changed = True
    while changed:
        changed = False
        for e in range(ea.shape[0]):
            a, b = ea[e], eb[e]
            if split[a] and not split[b] and undecided[b] and level[b] < level[a]:
                split[b] = True
                changed = True
    return split
