"""The quadtree of leaves: square cells of the reach box, what is known at each centre, and how they split.

Leaf (level, i, j) is cell (i, j) of the grid ``base``·2^level cells to a
side over [−half, half]². Its centre is a whole number times half a cell
side, so the centres of a leaf and of its mirror images about both axes are
exact images of each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

OUT, IN, UNDECIDED = 0, 1, 2  # a leaf's status: no point of it in E_ε, all of it in E_ε, not known


@dataclass(frozen=True, eq=False)
class Leaves:
    """Per leaf: where it is, and what is known at its centre.

    ``x``, ``y`` (b): its centre; ``h`` (b): its half-diagonal; ``allowed``: some φ
    keeps the curves apart at the centre; ``clearance`` (b): a translation this
    short keeps that orientation allowed; ``middle`` (rad): that orientation,
    or one allowed nearby where the centre is not allowed; ``deep``: every
    point of the leaf is certified at least ε deep; ``radius`` (b): the disk
    of this radius about the centre is certified in E_ε (0 if not deep);
    ``steps``: intervals of φ its depth walk may take; ``ran_out``: the walk
    used them all without an answer; ``bound`` (b): an upper bound on the depth
    anywhere in it, from its parent's centre."""

    level: np.ndarray
    i: np.ndarray
    j: np.ndarray
    x: np.ndarray
    y: np.ndarray
    h: np.ndarray
    allowed: np.ndarray
    clearance: np.ndarray
    middle: np.ndarray
    deep: np.ndarray
    steps: np.ndarray
    ran_out: np.ndarray
    radius: np.ndarray
    bound: np.ndarray

    def __len__(self) -> int:
        return len(self.x)

    def take(self, which) -> Leaves:
        """The leaves selected by ``which`` (a mask or indices)."""
        return Leaves(**{f.name: getattr(self, f.name)[which] for f in fields(self)})

    def with_values(self, which, **values) -> Leaves:
        """A copy with ``values`` (per field: one value per selected leaf) written at ``which``."""
        changed = {}
        for name, value in values.items():
            column = getattr(self, name).copy()
            column[which] = value
            changed[name] = column
        return replace(self, **changed)

    def keys(self, which) -> list:
        """(level, i, j) of the leaves ``which`` (indices), to remember them by."""
        return list(zip(self.level[which], self.i[which], self.j[which]))


def joined(parts: list) -> Leaves:
    """The leaves of ``parts``, in order."""
    return Leaves(**{f.name: np.concatenate([getattr(p, f.name) for p in parts]) for f in fields(Leaves)})


def centres(base: int, half: float, level, i, j):
    """(x, y, h): the centres (b) of leaves (level, i, j) and their half-diagonals (b), exact mirror images of
    each other about both axes (a whole number times half a cell side)."""
    cells = base * np.exp2(level)
    step = half / cells  # half a cell side
    return (2 * i + 1 - cells) * step, (2 * j + 1 - cells) * step, step * math.sqrt(2.0)


def first_cells(base: int):
    """(level, i, j, bound) of the base grid's cells, before anything is known (bound: inf)."""
    i, j = np.meshgrid(np.arange(base, dtype=np.int64), np.arange(base, dtype=np.int64), indexing="ij")
    return np.zeros(base * base, np.int64), i.ravel(), j.ravel(), np.full(base * base, np.inf)


def children(parent: Leaves):
    """(level, i, j, bound, steps) of the four children of each ``parent`` leaf, in the parents' order. The
    parent's centre is a corner of each child: where it is allowed, its clearance bounds the child's depth
    (the depth is 1-Lipschitz)."""
    m = len(parent)
    level = np.repeat(parent.level + 1, 4)
    i = np.repeat(parent.i * 2, 4) + np.tile(np.array([0, 1, 0, 1]), m)
    j = np.repeat(parent.j * 2, 4) + np.tile(np.array([0, 0, 1, 1]), m)
    child_h = np.repeat(parent.h / 2, 4)
    was_allowed = np.repeat(parent.allowed, 4)
    bound = np.where(was_allowed, np.maximum(0.0, 2 * child_h - np.repeat(parent.clearance, 4)), np.inf)
    return level, i, j, bound, np.repeat(parent.steps, 4)


def mirror_row(base: int, level, j):
    """The row of each leaf's mirror image about the x axis."""
    return base * (1 << level) - 1 - j


def images(base: int, leaves: Leaves) -> np.ndarray:
    """Per leaf: the index of its mirror image about the x axis (itself where that is no leaf)."""

    def key(j):
        return (leaves.level << 50) | (leaves.i << 25) | j

    keys = key(leaves.j)
    order = np.argsort(keys)
    flipped = key(mirror_row(base, leaves.level, leaves.j))
    at = np.minimum(np.searchsorted(keys, flipped, sorter=order), len(keys) - 1)
    image = order[at]
    return np.where(keys[image] == flipped, image, np.arange(len(keys)))


def first_per_group(groups, most):
    """Indices (ascending) of the first ``most`` entries of each value in ``groups``."""
    by = np.argsort(groups, kind="stable")
    g = groups[by]
    start = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])  # where each group begins, in ``by``
    rank = np.arange(len(g)) - np.repeat(start, np.diff(np.r_[start, len(g)]))
    return np.sort(by[rank < most])


def tallest_per_group(values, groups, most):
    """Indices (ascending) of the ``most`` largest entries of ``values`` in each value of ``groups``, and of every
    entry equal to the smallest of those (a tie at the cut is kept, for the caller to break)."""
    by = np.lexsort((-values, groups))  # by group, largest first
    g, v = groups[by], values[by]
    start = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])
    size = np.diff(np.r_[start, len(g)])
    cut = np.repeat(v[start + np.minimum(size, most) - 1], size)
    return np.sort(by[v >= cut])
