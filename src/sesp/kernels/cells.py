"""Cell kernels: the adjacency of a quadtree's leaves and the components of sets of leaves.

Leaves are squares of a quadtree over a base grid of ``base`` × ``base``
cells: leaf (level, i, j) covers cells i and j of the grid 2^level times finer
than the base. Two leaves are adjacent when their closed squares meet (along
an edge or at a corner). Components are found with one union-find.
"""

import math

import numpy as np
from numba import njit, prange

from .common import JIT, find_root

_DIRECTIONS = np.array([(di, dj) for di in (-1, 0, 1) for dj in (-1, 0, 1) if di or dj], dtype=np.int64)


@njit(**JIT)
def _key(level, i, j):
    return (level << 56) | (i << 28) | j


@njit(**JIT, parallel=True)
def leaf_edges(level, ii, jj, base):
    """(a, b): every ordered pair of adjacent leaves (both orders), at least once.

    A leaf looks for the leaf holding each of its 8 same-size neighbours: that
    neighbour itself or the larger leaf it lies in (its ancestors are tried
    in turn). A neighbour subdivided into smaller leaves is not found this
    way, but each of those finds this leaf, so every adjacent pair is found; each is listed both ways.
    Each leaf writes its own 8 slots (one thread each): the pairs come in the same order on any thread count.
    """
    n = level.shape[0]
    keys = np.empty(n, np.int64)
    for a in range(n):
        keys[a] = _key(level[a], ii[a], jj[a])
    order = np.argsort(keys)
    sorted_keys = keys[order]
    found = np.full(8 * n, -1, np.int64)  # slot 8a + d: the leaf holding leaf a's neighbour d, or -1
    for a in prange(n):
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
                    found[8 * a + d] = order[at]
                    break
                k -= 1
                i >>= 1
                j >>= 1
    slots = np.flatnonzero(found >= 0)
    ea, eb = slots // 8, found[slots]
    return np.concatenate((ea, eb)), np.concatenate((eb, ea))


@njit(**JIT)
def squares_in_disks(leaves, offsets, disks):
    """Per leaf a (``leaves``: centres x, y and half-diagonals h, b): whether each of its k × k squares, centred
    at (x + h·offsets[p], y + h·offsets[q]) with half-diagonal h/k, lies inside one of its disks (``disks``:
    cx, cy, reach, each (leaves, d): the disk about (cx[a, d], cy[a, d]) of radius reach[a, d]) strictly: its
    centre is nearer than the radius less h/k."""
    x, y, h = leaves
    cx, cy, reach = disks
    k = offsets.shape[0]
    out = np.zeros(x.shape[0], np.bool_)
    for a in range(x.shape[0]):
        sh = h[a] / k
        every = True
        for p in range(k):
            for q in range(k):
                sx, sy = x[a] + h[a] * offsets[p], y[a] + h[a] * offsets[q]
                inside = False
                for d in range(cx.shape[1]):
                    if math.hypot(sx - cx[a, d], sy - cy[a, d]) + sh < reach[a, d]:
                        inside = True
                        break
                every = every and inside
                if not every:
                    break
            if not every:
                break
        out[a] = every
    return out


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
def disk_components(member, x, y, radius, half_diagonal, near):
    """Components of the ``member`` leaves, joined where they are adjacent or where the disks of ``radius`` about
    their centres meet, among leaves two steps apart (the union of two meeting disks is connected); a leaf whose
    disk is no wider than itself reaches no farther than its neighbours. ``near``: :func:`adjacency`."""
    start, neighbour = near
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
def _breadth_first(queue, passable, near, limit, steps, label, within=None):
    """A breadth-first search through ``passable`` leaves from the leaves listed first in the ``queue``
    (touched, tail): their ``steps`` 0, ``label`` set; ``steps`` −1 where not reached. Each leaf reached gets its
    steps, up to ``limit``, and the label of the leaf it was reached from. Returns how many leaves were reached,
    listed first in ``touched`` (so that ``steps`` can be reset). ``near``: :func:`adjacency`; ``within``: steps
    of another search; where given, only leaves that search reached (≥ 0) are passed through."""
    touched, tail = queue
    start, neighbour = near
    head = 0
    while head < tail:
        a = touched[head]
        head += 1
        if steps[a] >= limit:
            continue
        for e in range(start[a], start[a + 1]):
            b = neighbour[e]
            if passable[b] and steps[b] < 0 and (within is None or within[b] >= 0):
                steps[b], label[b] = steps[a] + 1, label[a]
                touched[tail] = b
                tail += 1
    return tail


@njit(**JIT)
def _nearest_seeds(rank, passable, near, k):
    """Per seed (``rank`` 0..k−1 per leaf, −1 for others): the steps through ``passable`` leaves to the nearest
    other seed, and that seed (the lowest-ranked of the nearest; −1 where none is reached). One breadth-first
    search from all seeds at once labels every leaf with a nearest seed; the shortest path from seed s to
    another crosses an edge (a, b) whose labels differ first, and there d(a) + 1 + d(b) is its length."""
    start, neighbour = near
    n = rank.shape[0]
    d = np.full(n, -1, np.int64)
    label = np.full(n, -1, np.int64)
    queue = np.empty(n, np.int64)
    tail = 0
    for a in range(n):
        if rank[a] >= 0:
            d[a], label[a] = 0, rank[a]
            queue[tail] = a
            tail += 1
    _breadth_first((queue, tail), passable, near, np.iinfo(np.int64).max, d, label)
    length = np.full(k, np.iinfo(np.int64).max, np.int64)
    nearest = np.full(k, -1, np.int64)
    for a in range(n):
        if d[a] < 0:
            continue
        for e in range(start[a], start[a + 1]):
            b = neighbour[e]
            if d[b] < 0 or label[b] == label[a]:
                continue
            s, t, steps = label[a], label[b], d[a] + 1 + d[b]
            if steps < length[s] or (steps == length[s] and t < nearest[s]):
                length[s], nearest[s] = steps, t
    return length, nearest


@njit(**JIT)
def _steps_within(members, passable, near, limit, steps, touched, label):
    """Steps from the leaves ``members`` through ``passable`` leaves (``near``: :func:`adjacency`), up to
    ``limit``, written into ``steps`` (−1 where not reached, on entry and for leaves farther; ``label``:
    scratch); returns how many leaves were reached, listed first in ``touched``."""
    tail = 0
    for a in members:
        steps[a] = 0
        touched[tail] = a
        tail += 1
    return _breadth_first((touched, tail), passable, near, limit, steps, label)


@njit(**JIT)
def corridors(seed, passable, near, slack):
    """Leaves on the shortest paths (in steps, within ``slack`` more) through ``passable`` leaves from each seed
    (leaves sharing a label ≥ 0) to the seed nearest to it: where two seeds could be joined. ``near``:
    :func:`adjacency`; every seed's leaves passable. Memory in proportion to the leaves, not to
    leaves times seeds: each path is searched only as far as it is long, and from the nearest seed only within
    what the search from the seed reached."""
    n = seed.shape[0]
    out = np.zeros(n, np.bool_)
    labels = np.unique(seed[seed >= 0])
    k = labels.shape[0]
    if k < 2:
        return out
    rank = np.full(n, -1, np.int64)
    for a in range(n):
        if seed[a] >= 0:
            rank[a] = np.searchsorted(labels, seed[a])
    order = np.argsort(rank, kind="mergesort")
    first = np.searchsorted(rank[order], np.arange(-1, k + 1))[1:]  # seed s's leaves: order[first[s]:first[s + 1]]
    length, nearest = _nearest_seeds(rank, passable, near, k)
    from_s, from_t = np.full(n, -1, np.int64), np.full(n, -1, np.int64)
    touched_s, touched_t, scratch = np.empty(n, np.int64), np.empty(n, np.int64), np.zeros(n, np.int64)
    for s in range(k):
        t = nearest[s]
        if t < 0:
            continue
        limit = length[s] + slack
        m_s = _steps_within(order[first[s] : first[s + 1]], passable, near, limit, from_s, touched_s, scratch)
        # from t only within the leaves reached from s: a shortest path from t to a leaf a with
        # d_s(a) + d_t(a) <= limit passes only leaves b with d_s(b) <= d_s(a) + d_t(a) - d_t(b) <= limit, so its
        # steps are found there exactly, and elsewhere the sum stays above limit. A search from all of a large
        # seed's leaves for each seed near it would cost seeds times leaves.
        m_t = 0
        for i in range(m_s):
            a = touched_s[i]
            if rank[a] == t:
                from_t[a] = 0
                touched_t[m_t] = a
                m_t += 1
        m_t = _breadth_first((touched_t, m_t), passable, near, limit, from_t, scratch, from_s)
        for i in range(m_s):
            a = touched_s[i]
            if from_t[a] >= 0 and from_s[a] + from_t[a] <= limit:
                out[a] = True
        for i in range(m_s):
            from_s[touched_s[i]] = -1
        for i in range(m_t):
            from_t[touched_t[i]] = -1
    return out
