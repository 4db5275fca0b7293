"""Slow, obvious references for the fast kernels (no numba, no shared code)."""

import numpy as np


def transform(vertices, x, y, phi):
    """Vertices rotated by phi about the origin, then moved by (x, y)."""
    c, s = np.cos(phi), np.sin(phi)
    v = np.asarray(vertices, dtype=float)
    return np.stack([c * v[:, 0] - s * v[:, 1] + x, s * v[:, 0] + c * v[:, 1] + y], axis=1)


def _orient(a, b, c):
    return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])


def segment_pairs_meet(v1, v2):
    """(N1, N2) bool: which segments of polyline v1 meet which of v2.

    Textbook orientation test; collinear touching handled by projections.
    """
    p, p2 = v1[:-1, None, :], v1[1:, None, :]
    q, q2 = v2[None, :-1, :], v2[None, 1:, :]
    o1, o2 = _orient(p, p2, q), _orient(p, p2, q2)
    o3, o4 = _orient(q, q2, p), _orient(q, q2, p2)
    proper = (o1 * o2 <= 0) & (o3 * o4 <= 0)
    collinear = (o1 == 0) & (o2 == 0) & (o3 == 0) & (o4 == 0)
    if collinear.any():
        lo1, hi1 = np.minimum(p, p2), np.maximum(p, p2)
        lo2, hi2 = np.minimum(q, q2), np.maximum(q, q2)
        boxes = np.all((lo1 <= hi2) & (lo2 <= hi1), axis=-1)
        proper = np.where(collinear, boxes, proper)
    return proper


def crossings(curve1, curve2, x, y, phi):
    """Number of segment pairs that meet at state (x, y, phi)."""
    return int(segment_pairs_meet(np.asarray(curve1), transform(curve2, x, y, phi)).sum())


def point_in_convex(poly, pts):
    """Points inside or on a counter-clockwise convex polygon."""
    a = poly
    b = np.roll(poly, -1, axis=0)
    o = _orient(a[None, :, :], b[None, :, :], np.asarray(pts)[:, None, :])
    return np.all(o >= -1e-12, axis=1)


def _steps_from(sources, passable, adjacent):
    """Breadth-first steps from the ``sources`` leaves through ``passable`` ones (−1: not reached)."""
    steps = np.full(len(passable), -1)
    frontier = list(np.flatnonzero(sources))
    steps[frontier] = 0
    while frontier:
        nxt = []
        for a in frontier:
            for b in adjacent[a]:
                if passable[b] and steps[b] < 0:
                    steps[b] = steps[a] + 1
                    nxt.append(b)
        frontier = nxt
    return steps


def corridors(seed, passable, edges, slack):
    """Leaves on the shortest paths (within ``slack`` steps more) from each seed to its nearest other seed (the
    lowest label among the nearest), by one search from every seed: the definition, at seeds × leaves."""
    adjacent = [[] for _ in seed]
    for a, b in edges:
        adjacent[a].append(b)
    labels = np.unique(seed[seed >= 0])
    steps = np.array([_steps_from(seed == lab, passable, adjacent) for lab in labels])
    out = np.zeros(len(seed), bool)
    for s in range(len(labels)):
        found = [(min(v for v in steps[s][seed == labels[t]] if v >= 0), t) for t in range(len(labels))
                 if t != s and (steps[s][seed == labels[t]] >= 0).any()]  # fmt: skip
        if not found:
            continue
        length, t = min(found)
        both = (steps[s] >= 0) & (steps[t] >= 0)
        out |= both & (steps[s] + steps[t] <= length + slack)
    return out


def crossing_parity(cross, runs):
    """Parity of the crossings (i, j) with i0 <= i < i1 and j0 <= j < j1, counted one by one."""
    i0, i1, j0, j1 = runs
    return int(sum(i0 <= i < i1 and j0 <= j < j1 for i, j in cross) % 2)
