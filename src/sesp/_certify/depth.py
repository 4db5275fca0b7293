"""The depth search: a certified lower bound on each candidate's depth, and an upper bound.

A point deeper than d lies in a leaf whose upper bound reaches d, so a
candidate's depth is proved at its tallest in-leaves (the largest upper
bounds) by bisection, each walk beginning where the last one failed; a
candidate not yet proved deep enough is searched from its deepest proved
leaf for a deeper point (a pattern search). The largest upper bound on any
of its leaves bounds its depth from above.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from .centres import cover
from .leaves import IN, Leaves, first_per_group, tallest_per_group
from .problem import Memo, Problem

DIRECTIONS = 16  # directions of the pattern search for a deeper point
HALVINGS = 10  # halvings of its step, from half the depth
MOVES = 8  # moves at one step at most


def tops(upper, candidate) -> np.ndarray:
    """Per candidate (indexed by its root leaf): an upper bound on its depth (b), the largest ``upper`` of its
    leaves."""
    top = np.zeros(len(upper))
    member = candidate >= 0
    np.maximum.at(top, candidate[member], upper[member])
    return top


def depths(problem: Problem, leaves: Leaves, status, upper, candidate, memo: Memo):
    """(depth, best): per candidate root, a certified lower bound on its depth (b), proved at its
    ``candidates`` tallest in-leaves (among equal bounds, those farthest from every other leaf), and the leaf
    where it was proved largest (root -> leaf index)."""
    depth = np.zeros(len(leaves))
    inn = np.nonzero(status == IN)[0]
    if not len(inn):
        return depth, {}
    most = problem.settings.candidates
    inn = inn[tallest_per_group(upper[inn], candidate[inn], most)]  # ties at the cut too: broken by ``far``
    rest = np.nonzero(status != IN)[0]
    if len(rest):
        tree = cKDTree(np.column_stack([leaves.x[rest], leaves.y[rest]]))
        far, _ = tree.query(np.column_stack([leaves.x[inn], leaves.y[inn]]), workers=-1)
    else:
        far = leaves.h[inn]
    order = inn[np.lexsort((far, upper[inn]))[::-1]]
    best = {}
    for k in order[first_per_group(candidate[order], most)]:
        got = depth_at(problem, leaves, k, upper[k], memo)
        if got > depth[candidate[k]]:
            depth[candidate[k]], best[candidate[k]] = got, k
    return depth, best


def depth_at(problem: Problem, leaves: Leaves, k, bound, memo: Memo) -> float:
    """b: the largest depth the certificate proves at leaf k's centre, within ``depth_ratio``; ``bound`` (b): an
    upper bound on the depth there. Proved once per leaf (``memo.depths``)."""
    key = (leaves.level[k], leaves.i[k], leaves.j[k])
    if key not in memo.depths:
        lo = problem.resolution + leaves.radius[k]
        memo.depths[key] = proved_depth(problem, leaves.x[k], leaves.y[k], lo, bound, leaves.middle[k])[0]
    return memo.depths[key]


def proved_depth(problem: Problem, x, y, lo, bound, start):
    """(depth, φ): the largest depth (b, ≥ ``lo``, known proved) the certificate proves at (x, y), within a
    factor ``depth_ratio``, by geometric bisection up to ``bound`` (b, an upper bound on the depth there), and
    the orientation (rad) at which the last walk that failed failed (else ``start``). Each walk begins where the
    last one failed: one that fails again fails there, at once."""
    ratio = problem.settings.depth_ratio
    hi = min(bound, 2.0 * problem.half) * ratio  # a little above the bound: a depth at the bound is found
    stop = np.zeros(1)
    while hi > lo * ratio:
        mid = math.sqrt(lo * hi)
        ok = cover(problem, np.array([x]), np.array([y]), np.array([mid]), np.array([problem.most_steps]), 0.0, start,
                   True, stop)[0]  # fmt: skip
        if ok == 1:
            lo = mid
        else:
            hi, start = mid, float(stop[0])
    return lo, start


def deepest(problem: Problem, leaves: Leaves, k, depth, top, memo: Memo) -> tuple:
    """(depth, x, y): the depth ``depth`` (b) proved at leaf k's centre, raised by a pattern search from it
    (DIRECTIONS directions, steps from half that depth, halved HALVINGS times, at most MOVES moves each, a move
    where a neighbour is proved ``search_ratio`` times as deep): the inscribed radius of the component, from
    below, and the point (b) where it is proved. ``top`` (b): an upper bound on the depth anywhere in the
    component (a point proved deeper than the step lies in the same component). Searched once per leaf
    (``memo.deepest``)."""
    key = (leaves.level[k], leaves.i[k], leaves.j[k])
    if key not in memo.deepest:
        memo.deepest[key] = _searched_deeper(problem, leaves.x[k], leaves.y[k], depth, top, leaves.middle[k])
    return memo.deepest[key]


def _searched_deeper(problem: Problem, x, y, depth, top, start) -> tuple:
    """:func:`deepest` from (x, y), proved ``depth`` deep; the walks begin where the last one failed."""
    settings = problem.settings
    step = depth / 2
    turns = np.linspace(0.0, 2.0 * math.pi, DIRECTIONS, endpoint=False)
    stops = np.zeros(DIRECTIONS)
    steps = np.full(DIRECTIONS, problem.most_steps)
    for _ in range(HALVINGS):
        for _ in range(MOVES):
            if depth * settings.depth_ratio >= top:
                return depth, float(x), float(y)
            xs, ys = x + step * np.cos(turns), y + step * np.sin(turns)
            r = np.full(DIRECTIONS, depth * settings.search_ratio)
            deeper = cover(problem, xs, ys, r, steps, 0.0, start, True, stops) == 1
            if not deeper.any():
                start = float(stops[0])
                break
            x, y = xs[np.argmax(deeper)], ys[np.argmax(deeper)]
            depth, start = proved_depth(problem, x, y, depth * settings.search_ratio, top, start)
        step /= 2
    return depth, float(x), float(y)
