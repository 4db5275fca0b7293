"""Upper bounds on the depth, from the allowed points known, and the leaves' statuses they decide.

The depth is 1-Lipschitz and 0 at an allowed point, so an allowed point at
distance d with clearance c bounds the depth of every point within the leaf
by d − c + h. A leaf is IN where its centre is certified ε + h deep, OUT
where its bound is below ε, UNDECIDED otherwise. Allowed points other than
leaf centres are found where bounds stay far above the depth: along rays
from a candidate's tallest leaves (:func:`seek_allowed`), and at the
corners of cells too small to hold a pinch's allowed wedge between their
centres (:func:`probe_corners`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..kernels import cells as cell_kernels
from .centres import allowed, nearest_middle
from .leaves import IN, OUT, UNDECIDED, Leaves, first_per_group, images
from .problem import Memo, Problem


@dataclass(frozen=True, eq=False)
class Classified:
    """Per leaf: ``status`` (OUT, IN or UNDECIDED) and ``upper`` (b), an upper bound on the depth anywhere in
    it; ``edges``: (a, b), the ordered pairs of adjacent leaves (:func:`sesp.kernels.cells.leaf_edges`)."""

    status: np.ndarray
    upper: np.ndarray
    edges: tuple


def allowed_points(leaves: Leaves, points) -> np.ndarray:
    """(k, 3): x, y (b) and clearance (b) of every allowed point known: leaf centres, then ``points``."""
    a = leaves.allowed
    return np.concatenate([np.column_stack([leaves.x[a], leaves.y[a], leaves.clearance[a]]), points])


def classify(problem: Problem, leaves: Leaves, points) -> Classified:
    """Each leaf's status and upper bound on its depth, from its own centre, its neighbours' allowed centres and
    the ``nearest`` allowed points known (``points``: those that are no leaf's centre)."""
    ea, eb = cell_kernels.leaf_edges(leaves.level, leaves.i, leaves.j, problem.base)
    x, y, h, clearance = leaves.x, leaves.y, leaves.h, leaves.clearance
    upper = np.where(leaves.allowed, np.maximum(0.0, h - clearance), leaves.bound)
    via = leaves.allowed[eb]
    a, b = ea[via], eb[via]
    reach = np.hypot(x[a] - x[b], y[a] - y[b]) + h[a] - clearance[b]
    np.minimum.at(upper, a, np.maximum(0.0, reach))
    far = ~leaves.allowed & (upper >= problem.resolution)  # in-leaves too: a candidate's largest bound decides it
    known = allowed_points(leaves, points)
    if far.any() and len(known):  # the nearest allowed point anywhere bounds the depth too
        near = min(problem.settings.nearest, len(known))
        gap, k = cKDTree(known[:, :2]).query(np.column_stack([x[far], y[far]]), k=near, workers=-1)
        reach = gap.reshape(-1, near) - known[k.reshape(-1, near), 2]
        upper[far] = np.minimum(upper[far], np.maximum(0.0, reach.min(axis=1) + h[far]))
    if problem.mirror:  # the depth is symmetric: each bound holds at the mirror image too (and ties stay alike)
        upper = np.minimum(upper, upper[images(problem.base, leaves)])
    status = np.full(len(x), UNDECIDED)
    status[leaves.deep] = IN
    status[(status == UNDECIDED) & (upper < problem.resolution)] = OUT
    return Classified(status, upper, (ea, eb))


def seek_allowed(problem: Problem, leaves: Leaves, upper, candidate, tall, memo: Memo) -> np.ndarray:
    """(k, 3): allowed points (clearance 0) near the ``tall`` leaves, for the bounds of the next round. From the
    ``tallest`` such leaves of each candidate not tried before (``memo.sought``), along ``rays`` directions, the
    allowed point nearest the leaf's centre that ``probes`` halvings meet, on rays as long as twice the bound
    at the centre that end in an allowed point. A split leaf's children are excluded centres, so splitting alone
    does not bring the allowed points nearer, and a bound may stay far above the depth."""
    settings = problem.settings
    if problem.mirror:  # the images below the axis come as mirror images of the points found above it
        tall = tall & (leaves.y >= 0)
    k = np.nonzero(tall & ~leaves.allowed)[0]
    k = k[[key not in memo.sought for key in leaves.keys(k)]] if len(k) else k
    if not len(k):
        return np.empty((0, 3))
    k = k[np.lexsort((-upper[k], candidate[k]))]  # by candidate, tallest first
    k = k[first_per_group(candidate[k], settings.tallest)]
    memo.sought.update(leaves.keys(k))
    rays = settings.rays
    turns = np.linspace(0.0, 2.0 * math.pi, rays, endpoint=False)
    x0, y0 = np.repeat(leaves.x[k], rays), np.repeat(leaves.y[k], rays)
    reach = np.repeat(2.0 * np.maximum(upper[k] - leaves.h[k], leaves.h[k]), rays)
    dx, dy = reach * np.tile(np.cos(turns), len(k)), reach * np.tile(np.sin(turns), len(k))
    ends, hint = allowed(problem, x0 + dx, y0 + dy, nearest_middle(leaves, x0 + dx, y0 + dy))
    x0, y0, dx, dy, hint = x0[ends], y0[ends], dx[ends], dy[ends], hint[ends]
    lo, up = np.zeros(len(x0)), np.ones(len(x0))  # not allowed at lo (the leaf's centre), allowed at up
    for _ in range(settings.probes):  # each probe tries first the orientation allowed at the ray's last allowed point
        t = (lo + up) / 2
        ok, phi = allowed(problem, x0 + t * dx, y0 + t * dy, hint)
        lo, up, hint = np.where(ok, lo, t), np.where(ok, t, up), np.where(ok, phi, hint)
    found = np.column_stack([x0 + up * dx, y0 + up * dy])
    if problem.mirror:
        found = np.concatenate([found, found * np.array([1.0, -1.0])])
    return np.column_stack([found, np.zeros(len(found))])


def probe_corners(problem: Problem, leaves: Leaves, left, memo: Memo):
    """(points, any): allowed corners (k, 3; clearance 0) of the ``left`` leaves, and whether any was found;
    each corner is tried once (``memo.corners``). A narrow allowed wedge (the pinch of lens and body at small
    Ψ lies on x = 0, a line of cell edges) passes between cell centres; the corners of a cell are its points
    too, and an allowed one bounds the depth of every point of the cell below ε (and of every cell near it)."""
    none = np.empty((0, 3)), False
    if not left.any():
        return none
    finest = problem.levels
    scale = np.exp2(finest - leaves.level[left])  # corners in units of the finest cell side
    i0, j0 = leaves.i[left] * scale, leaves.j[left] * scale
    cells = problem.base * 2**finest
    keys = {(a + da * s, b + db * s) for a, b, s in zip(i0, j0, scale) for da in (0, 1) for db in (0, 1)}
    if problem.mirror:  # a corner below the axis is decided as its mirror image
        keys = {(a, max(b, cells - b)) for a, b in keys}
    keys = sorted(k for k in keys if k not in memo.corners)
    if not keys:
        return none
    memo.corners.update(keys)
    corners = (2 * np.array(keys, dtype=float) - cells) * (problem.half / cells)  # exact mirror images, as centres
    x, y = corners[:, 0].copy(), corners[:, 1].copy()
    ok, _ = allowed(problem, x, y, nearest_middle(leaves, x, y))
    found = corners[ok]
    if problem.mirror:
        images_ = found[found[:, 1] > 0] * np.array([1.0, -1.0])
        memo.corners.update((a, cells - b) for a, b in keys)
        found = np.concatenate([found, images_])
    return np.column_stack([found, np.zeros(len(found))]), bool(ok.any())
