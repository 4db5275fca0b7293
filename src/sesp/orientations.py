"""Orientations at a fixed position, exact in φ: no orientation grid.

For every pair of segments the set of φ where they meet is bounded by roots
of sinusoids in φ, found in closed form, so the blocked orientations at a
position are a finite union of intervals, exact for the two polylines up to
rounding. A position is excluded exactly when no orientation is left.
"""

from __future__ import annotations

import numpy as np

from .kernels import orientations
from .pair import as_pair
from .shape import DEFAULT_SEGMENTS

__all__ = ["blocked_orientations", "allowed_orientations", "widest_window", "ANGLE_GAP", "SCREEN_SLACK"]

# Gaps between blocked-orientation intervals narrower than this (radians)
# are rounding at shared end points, not allowed orientations.
ANGLE_GAP = 1e-9
# Width (b) by which the pair screen of the exact orientation kernel is widened.
SCREEN_SLACK = 1e-9


def blocked_orientations(particle, x: float, y: float, *, other=None, segments: int = DEFAULT_SEGMENTS):
    """The orientations φ at which particle 2, centred at (x, y), meets particle 1: exact in φ.

    For thick particles, "meets" is "comes within the contact distance".

    Parameters
    ----------
    particle, other, segments
        As in :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    x, y : float
        Position of particle 2's centre, in b.

    Returns
    -------
    (k, 2) ndarray
        Sorted, possibly overlapping intervals [start, end] of φ in [0, 2π], radians.
    """
    pair = as_pair(particle, other, segments)
    starts, ends = orientations.blocked_intervals(pair.vertices1, pair.vertices2, x, y, SCREEN_SLACK, pair.contact)
    return np.column_stack([starts, ends])


def allowed_orientations(particle, x, y, *, other=None, segments: int = DEFAULT_SEGMENTS) -> np.ndarray:
    """Measure of the allowed orientations at each position, exact in φ (radians, 0 to 2π).

    A position is excluded exactly when the result is 0. Unlike a scan this
    samples no orientations, so no narrow allowed interval of φ is missed;
    gaps narrower than ``ANGLE_GAP`` (1e-9 rad) between blocked intervals
    count as closed. Cost: a few thousand segment pairs per position.

    Parameters
    ----------
    particle, other, segments
        As in :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    x, y : array_like
        Positions of particle 2's centre, in b; broadcast together.

    Returns
    -------
    ndarray
        Radians, shaped like the broadcast positions.
    """
    pair = as_pair(particle, other, segments)
    xs, ys = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    out = orientations.allowed_measures(
        pair.vertices1, pair.vertices2, xs.ravel().copy(), ys.ravel().copy(), SCREEN_SLACK, ANGLE_GAP, pair.contact
    )  # owned, writeable copies
    return out.reshape(xs.shape)


def widest_window(particle, x, y, *, other=None, segments: int = DEFAULT_SEGMENTS) -> tuple:
    """(width, middle): the widest window of allowed orientations at each position, exact in φ (radians).

    ``width`` is 0 exactly where the position is excluded (gaps narrower than
    ``ANGLE_GAP`` count as closed); ``middle`` is the orientation at its centre.
    ``particle``, ``other``, ``segments`` as in :func:`sesp.scan`; ``x``, ``y``
    (b) are broadcast together.
    """
    pair = as_pair(particle, other, segments)
    xs, ys = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    width, middle, _ = orientations.widest_windows(
        pair.vertices1, pair.vertices2, xs.ravel(), ys.ravel(), SCREEN_SLACK, ANGLE_GAP, pair.contact
    )
    return width.reshape(xs.shape), middle.reshape(xs.shape)
