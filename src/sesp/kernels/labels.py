"""Component-labelling kernel: persistence of the distance-to-complement field (robust components)."""

import numpy as np
from numba import njit

from .common import JIT, find_root


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

    The components judged are those the node touches, not the largest of
    each connected part: where a part already holds bodies kept apart (two
    wings and the tip they meet at), a body that reaches it at the tip is
    judged against the tip. Where the node touches several of a part's
    bodies, the widest verdict wins (absorbed, then undecided, then apart),
    so the result does not depend on the order the neighbours are visited.

    Undecided necks: where the lower peak is at least ``resolved`` and
    ratio · p − NEAR <= s < neck · p, the neck is narrower than the smaller
    body but wide enough to join them at this resolution, or it parts them
    by less than a node (the distance field is exact to about a node); the
    two are kept apart and the meeting is written to ``necks`` (rows: node,
    the two components' numbers, s), as many as it holds, for a finer look
    (``neck`` = 0: none).
    Returns (count, number of necks found).
    """
    n = dist.shape[0]
    parent = np.arange(n)  # union-find over connected parts (their roots: the parts' highest peaks)
    peak = np.zeros(n)
    merged_into = np.full(n, -1)  # body absorbed into another body (not compressed)
    kept = np.zeros(n, dtype=np.bool_)  # body that survived a meeting as its own component
    owner = np.full(n, -1)  # body a node joined when it was added
    added = np.zeros(n, dtype=np.bool_)
    neck_node = np.empty(necks.shape[0], dtype=np.int64)
    neck_a = np.empty(necks.shape[0], dtype=np.int64)
    neck_b = np.empty(necks.shape[0], dtype=np.int64)
    touched = np.empty(27, dtype=np.int64)  # neighbours already added
    found = 0
    for node in order:
        added[node] = True
        m = 0
        steepest = -1  # the added neighbour of largest distance: the node takes its component (steepest ascent)
        for k in range(27):
            nb = _neighbour(node, k, shape[0], shape[1], shape[2], periodic)
            if nb < 0 or not added[nb]:
                continue
            if steepest < 0 or dist[nb] > dist[steepest]:
                steepest = nb
            touched[m] = nb
            m += 1
        if m == 0:
            peak[node] = dist[node]
            owner[node] = node
            continue
        for i in range(1, m):
            best = find_root(parent, touched[0])
            r = find_root(parent, touched[i])
            if r == best:
                continue
            verdict, hi, lo = _meeting(touched, m, parent, best, r, owner, kept, merged_into, peak, dist[node],
                                       ratio, min_peak, neck, resolved)  # fmt: skip
            if verdict == 2:
                merged_into[lo] = hi
                kept[lo] = False
            else:
                kept[lo] = True
                if verdict == 1:
                    if found < neck_node.shape[0]:
                        neck_node[found], neck_a[found], neck_b[found] = node, hi, lo
                    found += 1
            top, low = (best, r) if peak[best] >= peak[r] else (r, best)
            if merged_into[low] < 0:
                kept[low] = True  # the lower part's own body stays what it was: apart from those it met
            parent[low] = top
        parent[node] = find_root(parent, touched[0])
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
def _body(root, kept, merged_into):
    """The body a birth node's nodes belong to now: itself, or the body it was absorbed into."""
    while not kept[root] and merged_into[root] >= 0:
        root = merged_into[root]
    return root


# Node spacings: a neck decided apart within this of the rule's threshold (ratio · p − NEAR <= s < ratio · p) is
# listed as undecided when necks are asked for: the distance field is exact to about a node, so the verdict
# could go the other way on a finer window.
NEAR = 1.0


@njit(**JIT)
def _meeting(touched, m, parent, best, r, owner, kept, merged_into, peak, s, ratio, min_peak, neck, resolved):
    """(verdict, higher body, lower body) where a node of value s joins the parts rooted at ``best`` and
    ``r``: over each pair of bodies it touches, one in each part, 2 (absorb the lower), 1 (undecided neck)
    or 0 (apart), the widest verdict and its pair."""
    verdict, hi, lo = -1, -1, -1
    for i in range(m):
        if find_root(parent, touched[i]) != best:
            continue
        a = _body(owner[touched[i]], kept, merged_into)
        for j in range(m):
            if find_root(parent, touched[j]) != r:
                continue
            b = _body(owner[touched[j]], kept, merged_into)
            up, down = (a, b) if peak[a] >= peak[b] else (b, a)
            p = peak[down]
            apart = s < ratio * p and p >= min_peak
            near = neck > 0 and p >= resolved and s >= ratio * p - NEAR
            if apart and not near:
                v = 0
            elif s < neck * p and p >= resolved:
                v = 1
            else:
                v = 2
            if v > verdict:
                verdict, hi, lo = v, up, down
    return verdict, hi, lo


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
