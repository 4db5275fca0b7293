"""What to refine: the leaves whose splitting could change the count's bracket, and the splitting itself.

Candidates are the components of in ∪ undecided leaves; parts are the
components of in-leaves (joined where they touch or their certified disks
meet). Only an undecided leaf that could change the bracket is split:

* between two parts of one candidate that may each be a counted component;
* in a candidate without a part;
* in a candidate neither counted nor shallow, where its bound reaches ε + rim
  and a child's may fall below it;
* on a candidate's rim, where some point of the leaf lies farther than rim
  from every certified disk and farther than ε + rim from every allowed one
  (:func:`searched`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..kernels import cells as cell_kernels
from .bounds import Classified, allowed_points, seek_allowed
from .centres import certified_disks, evaluate, nearest_middle
from .depth import deepest, depths, tops
from .leaves import IN, OUT, UNDECIDED, Leaves, children, images, joined
from .problem import Memo, Problem


@dataclass(frozen=True, eq=False)
class Refinement:
    """Per leaf: ``split`` (split it), ``retry`` (certify it again with four times as many intervals),
    ``between`` (undecided, between two parts that may each be counted), ``seed`` (the part, as a leaf index,
    of an in-leaf whose part may be a counted component of its own; −1 otherwise) and ``candidate`` (the root
    leaf of its candidate; −1 for an out-leaf)."""

    split: np.ndarray
    retry: np.ndarray
    between: np.ndarray
    seed: np.ndarray
    candidate: np.ndarray


def plan(problem: Problem, leaves: Leaves, found: Classified, points, memo: Memo):
    """(Refinement, sought): what to refine after classification ``found``, and the allowed points sought near
    the tall leaves of candidates neither counted nor shallow (:func:`~.bounds.seek_allowed`), for the next
    round's bounds (``points``: the allowed points known before, not leaf centres)."""
    status, upper, (ea, eb) = found.status, found.upper, found.edges
    und, inn = status == UNDECIDED, status == IN
    candidate = cell_kernels.components(status != OUT, ea, eb)
    seed, between = _seeds(problem, leaves, found, candidate)
    root = np.maximum(candidate, 0)
    depth, top = _candidate_depths(problem, leaves, found, candidate, memo)
    shallow = (candidate >= 0) & (top[root] < problem.bar)  # in a candidate proved shallower than ε + rim
    has_part = np.zeros(len(leaves), bool)
    has_part[candidate[inn]] = True
    empty = und & ~has_part[root]
    # a leaf that may be that deep, split where its children's bounds may fall below ε + rim: the bound at a
    # child's centre is at least the parent's less h (the depth is 1-Lipschitz)
    tall = (candidate >= 0) & ~shallow & (depth[root] < problem.bar) & (upper >= problem.bar)
    unsure = tall & (upper - 2 * leaves.h < problem.bar)
    sought = seek_allowed(problem, leaves, upper, candidate, tall, memo)
    on_rim = und & ~shallow & (upper >= problem.bar)
    shown = np.zeros(len(leaves), bool)
    rim = np.full(int(on_rim.sum()), problem.rim)
    shown[on_rim] = searched(problem, leaves, inn, on_rim, rim, np.concatenate([points, sought]))
    if problem.mirror:  # a leaf shown searched shows its mirror image searched too (nearest disks may tie)
        shown |= shown[images(problem.base, leaves)]
    on_rim &= ~shown
    above_floor = leaves.h * math.sqrt(2.0) > problem.floor
    split = ((between | empty) & ~shallow | on_rim | unsure) & above_floor
    retry = und & leaves.ran_out & (leaves.steps < problem.most_steps)
    return Refinement(split & ~retry, retry, between, seed, candidate), sought


def _candidate_depths(problem: Problem, leaves: Leaves, found: Classified, candidate, memo: Memo):
    """(depth, top) per candidate root (b): the depth proved, raised by a search for a deeper point where it
    is not yet ε + rim in a candidate not shown shallow, and the upper bound."""
    depth, best = depths(problem, leaves, found.status, found.upper, candidate, memo)
    top = tops(found.upper, candidate)
    undecided = (candidate >= 0) & (top[np.maximum(candidate, 0)] >= problem.bar)
    for r in np.unique(candidate[undecided & (depth[np.maximum(candidate, 0)] < problem.bar)]):
        if r in best:  # not proved that deep at the leaves tried: search for a deeper point from the best
            depth[r] = deepest(problem, leaves, best[r], depth[r], top[r], memo)[0]
    return depth, top


def _seeds(problem: Problem, leaves: Leaves, found: Classified, candidate):
    """(seed, between): per in-leaf, its part (a leaf index) where that part may be a counted component of its
    own, else −1; per leaf, whether it is undecided and on a near-shortest path between two such parts."""
    status, (ea, eb) = found.status, found.edges
    und, inn = status == UNDECIDED, status == IN
    near = cell_kernels.adjacency(len(leaves), ea, eb)
    parts = cell_kernels.disk_components(inn, leaves.x, leaves.y, leaves.radius, leaves.h, near)
    seed = np.where(inn, parts, -1)
    seed = np.where(_capable(problem, seed, und, found)[np.maximum(seed, 0)], seed, -1)
    between = und & cell_kernels.corridors(seed, und | inn, near, 2)
    return seed, between


def _capable(problem: Problem, seed, und, found: Classified):
    """Per seed (a leaf index): whether its part may be a counted component of its own. Such a component holds a
    point at least ε + rim deep, so a leaf whose bound reaches that (tall), joined to the part within E_ε and
    without passing another part (that part would be in the same component): the tall leaf is the part's own,
    or lies in a run of undecided leaves that touches the part."""
    ea, eb = found.edges
    tall = found.upper >= problem.bar
    run = cell_kernels.components(und, ea, eb)  # per undecided leaf: its run of undecided leaves
    tall_run = np.zeros(len(tall), bool)
    tall_run[run[und & tall]] = True
    capable = np.zeros(len(tall), bool)
    capable[seed[(seed >= 0) & tall]] = True
    touch = (seed[ea] >= 0) & und[eb]
    capable[seed[ea[touch]][tall_run[run[eb[touch]]]]] = True
    return capable


def searched(problem: Problem, leaves: Leaves, inn, which, rim, points):
    """Per ``which`` leaf: whether no component deeper than ε + ``rim`` (b; per leaf) can hide in it apart from
    the certified parts. That holds where each of its points q lies within ``rim`` of a certified disk (an
    in-leaf's) or within ε + ``rim`` of an allowed disk (an allowed point's clearance; ``points``: those that
    are no leaf's centre):

    * a point q with p(q) ≥ ε + d, d its distance to a certified disk, joins that disk's part: the disk of
      radius p(q) − ε about q lies in E_ε (the depth is 1-Lipschitz) and reaches the certified disk;
    * within ε + rim of an allowed disk, p(q) < ε + rim.

    Shown on ``subcells`` squares a side per leaf, each inside one disk of the ``nearest`` of each kind."""
    settings = problem.settings
    k = settings.subcells
    offsets = ((np.arange(k) + 0.5) / k * 2.0 - 1.0) / math.sqrt(2.0)  # square centres, in half-diagonals
    x, y, h = leaves.x[which], leaves.y[which], leaves.h[which]
    known = allowed_points(leaves, points)
    disks = []  # per leaf: the centres and radii (b) of its nearest disks of each kind
    for cx, cy, cr, extra in (
        (leaves.x[inn], leaves.y[inn], leaves.radius[inn], rim),
        (*known.T, problem.resolution + rim),
    ):
        near = min(settings.nearest, len(cx))
        if near:
            _, idx = cKDTree(np.column_stack([cx, cy])).query(np.column_stack([x, y]), k=near, workers=-1)
            idx = idx.reshape(len(x), near)
            disks.append((cx[idx], cy[idx], cr[idx] + extra[:, None]))
    if not disks:
        return np.zeros(len(x), bool)
    cx, cy, reach = (np.ascontiguousarray(np.concatenate(d, axis=1)) for d in zip(*disks))
    return cell_kernels.squares_in_disks((x, y, h), offsets, (cx, cy, reach))


def retried(problem: Problem, leaves: Leaves, retry) -> Leaves:
    """The leaves, with those ``retry`` certified again with four times as many intervals of φ."""
    idx = np.nonzero(retry)[0]
    if not len(idx):
        return leaves
    steps = leaves.steps[idx] * 4
    got = certified_disks(problem, leaves.x[idx], leaves.y[idx], leaves.h[idx], steps, leaves.middle[idx])
    return leaves.with_values(idx, steps=steps, deep=got[0], radius=got[1], ran_out=got[2])


def split(problem: Problem, leaves: Leaves, which):
    """(leaves, allowed, evaluated): the leaves with those ``which`` replaced by their four children (the rest
    first, then the children level by level), the parents' allowed centres (k, 3: x, y, clearance; they stay
    known allowed points) and how many children were evaluated. Each child tries first the parent's allowed
    orientation, or that of the nearest leaf whose centre is allowed."""
    parent, rest = leaves.take(which), leaves.take(~which)
    a = parent.allowed
    kept = np.column_stack([parent.x[a], parent.y[a], parent.clearance[a]])
    level, i, j, bound, steps = children(parent)
    hint = np.where(parent.allowed, parent.middle, np.nan)
    lost = np.nonzero(~parent.allowed)[0]
    hint[lost] = nearest_middle(leaves, parent.x[lost], parent.y[lost])
    hint = np.repeat(hint, 4)
    made = [rest]
    for lv in np.unique(level):
        sel = level == lv
        made.append(evaluate(problem, level[sel], i[sel], j[sel], bound[sel], steps[sel], hint[sel]))
    return joined(made), kept, len(level)
