"""One certified count's fixed inputs (:class:`Problem`), and what its rounds have tried (:class:`Memo`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..kernels import depth as depth_kernels
from ..kernels.common import chunk_boxes, chunk_count
from ..kernels.orientations import radial_spans
from ..pair import Pair
from .settings import Settings


@dataclass(frozen=True, eq=False)
class Problem:
    """What every step of the count reads and none changes.

    ``resolution`` ε (b); ``rim`` (b): a component is counted from ``bar`` =
    ε + rim deep; ``base``: cells along each side of the reach box
    [−``half``, ``half``]² before refinement; ``levels``: halvings down to
    cells no wider than ``floor`` = ε/4; ``steps``, ``most_steps``: the
    intervals of φ a depth walk may take at first and at most. The curves,
    prepared once for the kernels: ``curves`` (depth), ``spans2`` and
    ``boxes1`` (exact windows and clearances)."""

    pair: Pair
    resolution: float
    rim: float
    base: int
    settings: Settings
    half: float
    levels: int
    steps: int
    most_steps: int
    curves: tuple
    spans2: np.ndarray
    boxes1: np.ndarray

    @property
    def floor(self) -> float:
        """b: the smallest cell side refinement goes to."""
        return self.resolution / 4

    @property
    def bar(self) -> float:
        """b: a component is counted where it is at least this deep."""
        return self.resolution + self.rim

    @property
    def mirror(self) -> bool:
        """Whether each leaf below the x axis is decided as its mirror image (a mirror-symmetric pair)."""
        return self.pair.mirror_symmetric


def prepare(pair: Pair, resolution: float, rim: float, base: int, settings: Settings) -> Problem:
    """The :class:`Problem` of counting ``pair``'s components at ``resolution`` with ``rim`` (b).

    The rim used is at most half a base cell's half-diagonal (and at least ε): a part is a seed of its own where
    its certified disk reaches the rim, and every part holding a base cell must be one."""
    half = pair.reach
    floor = resolution / 4
    v1, v2 = pair.vertices1, pair.vertices2
    # a walk around φ needs an interval each time a vertex passes a crossing: a closed N-gon at a shallow overlap
    # takes N to 3N (fewer at first would only be retried)
    steps = settings.steps_per_vertex * max(len(v1), len(v2))
    return Problem(
        pair=pair,
        resolution=resolution,
        rim=max(resolution, min(rim, half * math.sqrt(2.0) / base / 2)),
        base=base,
        settings=settings,
        half=half,
        levels=max(1, math.ceil(math.log2(2 * half / base / floor))),
        steps=steps,
        most_steps=max(settings.most_steps, steps),
        curves=depth_kernels.prepared(v1, v2),
        spans2=radial_spans(v2),
        boxes1=chunk_boxes(v1, np.empty((chunk_count(v1), 4))),
    )


@dataclass
class Memo:
    """What earlier rounds of one count tried, so that no round tries it again: depths proved at leaves and
    found by searches from them (b, by leaf (level, i, j)), corners tried (as whole multiples of the finest cell
    side) and leaves from which allowed points were sought."""

    depths: dict = field(default_factory=dict)
    deepest: dict = field(default_factory=dict)
    corners: set = field(default_factory=set)
    sought: set = field(default_factory=set)
