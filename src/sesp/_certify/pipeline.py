"""The certified count as one pipeline: evaluate the base cells, then classify, plan and refine until the plan
is empty, and read the candidates off the last round."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..pair import Pair
from ..progress import progress_bar
from .bounds import classify, probe_corners
from .centres import evaluate
from .depth import deepest, depths, tops
from .leaves import IN, first_cells
from .problem import Memo, prepare
from .refine import plan, retried, split
from .settings import Settings


@dataclass(frozen=True, eq=False)
class Outcome:
    """A finished count, as arrays. Per candidate listed, deepest first: ``parts`` (certified parts that may
    each be counted), ``depth`` and ``top`` (b: certified lower and upper bounds on its depth), ``area`` and
    ``area_bound`` (b²: its in-leaves, all its leaves), ``box`` ((k, 4): xmin, xmax, ymin, ymax, b) and
    ``point`` ((k, 2), b: where its depth is proved, or its leaf of largest upper bound where none is). Per
    leaf, ``cells``: x, y, side (b), status and component (its candidate's rank, −1 for none). ``rim`` (b):
    the rim used; ``floor`` (b): the smallest cell side reached; ``evaluations``: leaves evaluated."""

    parts: np.ndarray
    depth: np.ndarray
    top: np.ndarray
    area: np.ndarray
    area_bound: np.ndarray
    box: np.ndarray
    point: np.ndarray
    cells: dict
    rim: float
    floor: float
    evaluations: int


def count(pair: Pair, resolution: float, rim: float, base: int, settings: Settings, progress=False) -> Outcome:
    """The certified count of ``pair``'s excluded components at ``resolution`` (b) with ``rim`` (b), on ``base``
    cells a side at first (:func:`sesp.certified_components` defines it)."""
    problem = prepare(pair, resolution, rim, base, settings)
    memo = Memo()
    leaves = evaluate(problem, *first_cells(base))
    points, evaluations = np.empty((0, 3)), len(leaves)  # points: allowed points that are no leaf's centre
    with progress_bar(problem.levels, progress, "certified components", unit="level") as bar:
        reached = 0
        while True:
            found = classify(problem, leaves, points)
            refinement, sought = plan(problem, leaves, found, points, memo)
            small = refinement.between & (2 * leaves.h < problem.resolution)
            corners, any_allowed = probe_corners(problem, leaves, small, memo)
            points = np.concatenate([points, sought, corners])
            if any_allowed:
                continue  # classified again, with the allowed corners found, before any leaf is split
            if not refinement.split.any() and not refinement.retry.any():
                break
            leaves = retried(problem, leaves, refinement.retry)
            leaves, kept, evaluated = split(problem, leaves, refinement.split)
            points, evaluations = np.concatenate([points, kept]), evaluations + evaluated
            if (now := int(leaves.level.max())) > reached:
                bar.update(now - reached)
                reached = now
    return _outcome(problem, leaves, found, refinement, memo, evaluations)


def _outcome(problem, leaves, found, refinement, memo, evaluations) -> Outcome:
    """The candidates of the last round that are listed (not shallow, or holding a cell certified in E_ε), deepest
    first, with their parts, depths and areas."""
    status, candidate, seed = found.status, refinement.candidate, refinement.seed
    area = (leaves.h * math.sqrt(2.0)) ** 2
    depth, best = depths(problem, leaves, status, found.upper, candidate, memo)
    top = tops(found.upper, candidate)
    where = {}
    for root, k in best.items():
        depth[root], *where[root] = deepest(problem, leaves, k, depth[root], top[root], memo)
    member = np.nonzero(candidate >= 0)[0]
    member = member[np.argsort(candidate[member], kind="stable")]  # the leaves of each candidate, one run per root
    roots, first = np.unique(candidate[member], return_index=True)
    rows, kept = [], []
    for r, m in zip(roots, np.split(member, first[1:])):
        inn = m[status[m] == IN]
        if top[r] < problem.bar and not len(inn):
            continue  # shallow, and no cell of it certified in E_ε: nothing to list
        kept.append(r)
        box = (leaves.x[m].min(), leaves.x[m].max(), leaves.y[m].min(), leaves.y[m].max())
        parts = len(np.unique(seed[m][seed[m] >= 0]))
        tallest = m[np.argmax(found.upper[m])]
        point = where.get(r, (leaves.x[tallest], leaves.y[tallest]))
        rows.append((parts, depth[r], top[r], area[inn].sum(), area[m].sum(), *box, *point))
    table = np.array(rows, dtype=float).reshape(-1, 11)
    order = np.argsort(-table[:, 1], kind="stable")
    table = table[order]
    rank = np.full(len(leaves), -1)
    rank[np.array(kept, dtype=np.int64)[order]] = np.arange(len(kept))
    cells = {
        "x": leaves.x, "y": leaves.y, "side": leaves.h * math.sqrt(2.0), "status": status,
        "component": np.where(candidate >= 0, rank[np.maximum(candidate, 0)], -1),
    }  # fmt: skip
    floor = 2.0 * problem.half / (problem.base * 2.0 ** int(leaves.level.max()))
    return Outcome(
        table[:, 0].astype(int), table[:, 1], table[:, 2], table[:, 3], table[:, 4], table[:, 5:9], table[:, 9:],
        cells,
        problem.rim, floor, evaluations,
    )  # fmt: skip
