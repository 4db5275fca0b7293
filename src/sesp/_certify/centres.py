"""Deciding points: whether a position is allowed (and how far that lasts) or certified deep.

A leaf's centre is decided cheapest first: the orientation allowed nearby
(the hint) is tried, and where it keeps the curves apart the centre is
allowed, with its clearance; elsewhere the depth certificate
(:mod:`sesp.kernels.depth`) tries to prove the centre ε + h deep (then the
whole leaf lies in E_ε), and otherwise at least ``proof_depth`` deep
(excluded); only what neither decides goes to the exact windows in φ
(:mod:`sesp.kernels.orientations`), which give the same answer.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..kernels import depth as depth_kernels
from ..kernels import orientations as orientation_kernels
from ..kernels.common import small_chunks
from ..orientations import ANGLE_GAP, SCREEN_SLACK
from .leaves import Leaves, centres, mirror_row
from .problem import Problem


def evaluate(problem: Problem, level, i, j, bound, steps=None, hint=None) -> Leaves:
    """Leaves (level, i, j) with what is known at each centre (``bound``, b: an upper bound on each leaf's depth).

    ``steps``: intervals of φ each depth walk may take (default ``problem.steps``); ``hint`` (rad, NaN for
    none): an orientation to try first at each centre. For a mirror-symmetric pair, (t, φ) overlaps where
    (Mt, −φ) does (M: y → −y), so a leaf's mirror image is decided as it is, its orientations turned to −φ:
    each pair of images is decided once, above the axis (the centres and the polylines are exact images)."""
    n = len(i)
    steps = np.full(n, problem.steps) if steps is None else steps
    hint = np.full(n, np.nan) if hint is None else hint
    if not problem.mirror:
        return _decided(problem, level, i, j, bound, steps, hint)
    flip = mirror_row(problem.base, level, j)
    below = j < flip
    key = np.column_stack([level, i, np.where(below, flip, j)])
    _, first, back = np.unique(key, axis=0, return_index=True, return_inverse=True)
    back = back.ravel()
    once = _decided(
        problem, level[first], i[first], key[first, 2], bound[first], steps[first], np.where(below, -hint, hint)[first]
    )
    leaves = once.take(back)
    return Leaves(**{
        **leaves.__dict__, "j": j, "bound": bound, "y": np.where(below, -leaves.y, leaves.y),
        "middle": np.where(below, -leaves.middle, leaves.middle),
    })  # fmt: skip


def _decided(problem, level, i, j, bound, steps, hint) -> Leaves:
    """:func:`evaluate` of every leaf."""
    x, y, h = centres(problem.base, problem.half, level, i, j)
    n = len(x)
    clearance = np.zeros(n)
    middle = np.where(np.isnan(hint), 0.0, hint)
    tried = np.nonzero(~np.isnan(hint))[0]
    if len(tried):
        clearance[tried], middle[tried] = widest(problem, x[tried], y[tried], hint[tried], h[tried])
    allowed = clearance > 0
    deep, ran_out, radius, excluded = np.zeros(n, bool), np.zeros(n, bool), np.zeros(n), np.zeros(n, bool)
    met = np.nonzero(~allowed)[0]  # where the hint failed (or there was none): certify depth first, from the hint
    deep[met], radius[met], ran_out[met], excluded[met] = certified_disks(
        problem, x[met], y[met], h[met], steps[met], middle[met]
    )
    rest = np.nonzero(~allowed & ~excluded)[0]  # neither allowed nor proved excluded: the exact windows decide
    if len(rest) and problem.pair.contact > 0.0:  # thick: first the cheap orientations (:func:`sampled`)
        found, phi = sampled(problem, x[rest], y[rest], h[rest])
        sel = rest[found]
        allowed[sel] = True
        clearance[sel], middle[sel] = widest(problem, x[sel], y[sel], phi[found], h[sel])
        rest = rest[~found]
    if len(rest):
        ok, mid = windows(problem, x[rest], y[rest])
        sel = rest[ok]
        allowed[sel], middle[sel] = True, mid[ok]
        clearance[sel] = np.maximum(clearance_of(problem, x[sel], y[sel], mid[ok], h[sel]), 0.0)
    clearance = np.where(allowed, clearance, 0.0)
    return Leaves(level, i, j, x, y, h, allowed, clearance, middle, deep, steps, ran_out, radius, bound)


def clearance_of(problem: Problem, x, y, phi, h):
    """b: how far each position may move with curve 2 turned by ``phi`` before the pair meets (≤ 0: it meets);
    measured up to 2h."""
    got = np.empty(len(x))
    p = problem.pair
    with small_chunks():
        orientation_kernels.clearance_at(p.vertices1, problem.boxes1, p.vertices2, x, y, phi, 2 * h + p.contact, got)
    return got - p.contact


def widest(problem: Problem, x, y, phi, h):
    """The clearance (b) at each position, raised by a pattern search over φ from ``phi`` where it is positive
    (the settings' ``turns``, each tried on both sides, kept where the clearance grows), and the orientation
    reached (rad). A larger clearance bounds the depth near the position more tightly: fewer cells are split."""
    clearance, phi = clearance_of(problem, x, y, phi, h), phi.copy()
    for turn in problem.settings.turns:
        for side in (turn, -turn):
            k = np.nonzero((clearance > 0) & (clearance < 2 * h))[0]  # 2h: as far as a clearance is measured
            if not len(k):
                return clearance, phi
            got = clearance_of(problem, x[k], y[k], phi[k] + side, h[k])
            better = got > clearance[k]
            clearance[k[better]], phi[k[better]] = got[better], phi[k[better]] + side
    return clearance, phi


def sampled(problem: Problem, x, y, h):
    """(found, φ): the positions at which one of ``samples`` evenly spaced orientations keeps the curves apart,
    and the orientation (rad) of the largest clearance (measured up to 2h, b) among them. Thick pairs try these
    before the exact windows: for them the windows solve six times as many sinusoids per pair of segments, over
    the more pairs that a wider annulus lets through, and cost many times what a thin pair's do
    (``benchmarks/README.md``)."""
    k, n = problem.settings.samples, len(x)
    turns = np.arange(k) * (2.0 * np.pi / k)
    got = clearance_of(problem, np.repeat(x, k), np.repeat(y, k), np.tile(turns, n), np.repeat(h, k)).reshape(n, k)
    best = got.argmax(axis=1)
    return got[np.arange(n), best] > 0.0, turns[best]


def windows(problem: Problem, x, y):
    """Whether each position is allowed, exactly in φ, and the middle of its widest window (rad)."""
    p, n = problem.pair, len(x)
    width, mid, clear = np.empty(n), np.empty(n), np.empty(n)
    with small_chunks():
        orientation_kernels.windows_at(
            p.vertices1, p.vertices2, problem.spans2, problem.boxes1, x, y, SCREEN_SLACK, ANGLE_GAP, p.contact,
            np.zeros(n), width, mid, clear,
        )  # fmt: skip
    return width > 0, mid


def cover(problem: Problem, x, y, r, steps, fallback=0.0, start=0.0, tips=0, stops=None):
    """:func:`sesp.kernels.depth.certified_deep` of positions (x, y) at depth ``r`` (b) of the particles, thick
    or thin, else ``fallback``, with two end points tried where ``tips`` (:meth:`~.settings.Settings.walk_options`)."""
    options = problem.settings.walk_options(tips)
    contact = problem.pair.contact
    return depth_kernels.certified_deep(problem.curves, x, y, r, steps, fallback, start, options, stops, contact)


def certified_disks(problem: Problem, x, y, h, steps, start):
    """(deep, radius, ran_out, excluded) of leaves centred at (x, y) with half-diagonals h (b): certified at
    least ε deep throughout (ε + h at the centre), the radius (b) about the centre so certified (wider than
    the leaf where it is under the rim), where the walk ran out of intervals, and the centres proved excluded
    (at least ``proof_depth`` deep). The walks begin at ``start`` (rad): an orientation allowed nearby, where a
    walk that fails fails first. Two end points are tried at ε + h, not for the wider disks, which only save
    cells (their walks near the depth take ever shorter turns): where no pair of runs holds, and at every step
    where a walk of the leaf's (or of a parent's) ran out of intervals (``steps`` above the first): a pair's
    intervals may shrink towards an orientation that only two end points hold (two staples with their arms
    along each other), and the walk would run out again."""
    if not len(x):
        return np.zeros(0, bool), np.zeros(0), np.zeros(0, bool), np.zeros(0, bool)
    eps, rim = problem.resolution, problem.rim
    got = np.zeros(len(x), np.int8)
    for tips, which in ((1, steps <= problem.steps), (2, steps > problem.steps)):
        k = np.nonzero(which)[0]
        if len(k):
            got[k] = cover(problem, x[k], y[k], eps + h[k], steps[k], problem.settings.proof_depth, start[k], tips)
    deep, ran_out = got == 1, got == -1
    radius = np.where(deep, h, 0.0)
    thin = np.nonzero(deep & (h < rim))[0]
    if len(thin):
        wider = np.maximum(3 * h[thin], rim)
        ok = cover(problem, x[thin], y[thin], eps + wider, steps[thin], start=start[thin]) == 1
        radius[thin[ok]] = wider[ok]
        # a disk of the rim's radius makes a part a seed of its own: try it where the wider disk failed
        short = thin[~ok & (wider > rim)]
        if len(short):
            ok = cover(problem, x[short], y[short], np.full(len(short), eps + rim), steps[short], start=start[short])
            radius[short[ok == 1]] = rim
    return deep, radius, ran_out, got > 0


def allowed(problem: Problem, x, y, hint):
    """Whether each position is allowed, decided as a centre is: allowed where the curves keep apart at ``hint``
    (rad; NaN for none), excluded where the depth certificate proves it (at ``proof_depth``, within
    ``fallback_steps`` intervals from the hint), the exact windows deciding the rest; and an allowed orientation
    (rad) at each allowed position, NaN elsewhere. Every position the windows allow is allowed; a hint also
    finds the apex of a pinch's allowed wedge, where the curves keep apart by about 1e-11 b in windows narrower
    than ANGLE_GAP (1e-9 rad), which the windows close."""
    ok, rest, phi = np.zeros(len(x), bool), np.ones(len(x), bool), hint.copy()
    tried = np.nonzero(~np.isnan(hint))[0]
    if len(tried):
        ok[tried] = clearance_of(problem, x[tried], y[tried], hint[tried], np.full(len(tried), problem.floor)) > 0
        rest[tried[ok[tried]]] = False
    k = np.nonzero(rest)[0]
    if len(k):
        start = np.where(np.isnan(hint[k]), 0.0, hint[k])
        settings = problem.settings
        proved = cover(problem, x[k], y[k], settings.proof_depth, settings.fallback_steps, start=start) == 1
        k = k[~proved]
    if len(k):
        ok[k], phi[k] = windows(problem, x[k], y[k])
    return ok, np.where(ok, phi, np.nan)


def nearest_middle(leaves: Leaves, x, y):
    """The allowed orientation (rad) of the leaf nearest each point (x, y) whose centre is allowed; NaN where no
    leaf's is (windows move continuously with the position)."""
    donors = np.nonzero(leaves.allowed)[0]
    if not len(x) or not len(donors):
        return np.full(len(x), np.nan)
    tree = cKDTree(np.column_stack([leaves.x[donors], leaves.y[donors]]))
    _, nearest = tree.query(np.column_stack([x, y]), workers=-1)
    return leaves.middle[donors[nearest]]
