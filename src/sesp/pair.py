"""The pair of particles a computation is about, prepared once for every engine.

A :class:`Pair` holds the two particles as given, their polylines, and how
the curves meet: the contact distance of thick particles, the contact
tolerance (touching counts as overlap), the reach r₁ + r₂ + contact beyond
which they cannot meet, and whether the pair is mirror symmetric about the
x axis. Every engine (raster, direct, Monte Carlo, the
entanglement hull test and the exact-in-φ orientation intervals) takes a
prepared pair, so a property of how particles meet is set here, once.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from .shape import DEFAULT_SEGMENTS, Polyline, SeSP, as_polyline

__all__ = ["Pair", "as_pair", "TOUCH_TOLERANCE"]

# Touching counts as overlap: states within this distance (relative to r₁ + r₂)
# of touching are overlaps, identically in every engine.
TOUCH_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Pair:
    """Two thin particles and how they meet.

    Particle 1 (``particle``) is fixed at the origin with orientation +x;
    particle 2 (``other``) is rotated by φ about its centre, then moved by
    (x, y). Build one with :meth:`of`.

    Attributes
    ----------
    particle, other : SeSP or Polyline
        The particles as given (``other`` is ``particle`` for a pair of
        identical particles).
    curve1, curve2 : Polyline
        Their polylines (a Polyline is used as given; a SeSP is sampled with
        ``segments`` segments of nearly equal arc length, see
        :meth:`sesp.shape.SeSP.polyline`).
    segments : int
        Polyline segments N of each SeSP.
    """

    particle: SeSP | Polyline
    other: SeSP | Polyline
    curve1: Polyline
    curve2: Polyline
    segments: int
    _hulls: dict = field(default_factory=dict, compare=False, repr=False)

    @classmethod
    def of(cls, particle, other=None, *, segments: int = DEFAULT_SEGMENTS) -> Pair:
        """The pair of ``particle`` with ``other`` (default: a copy of ``particle``)."""
        curve1 = as_polyline(particle, segments)
        curve2 = curve1 if other is None else as_polyline(other, segments)
        return cls(particle, particle if other is None else other, curve1, curve2, int(segments))

    @property
    def contact(self) -> float:
        """Contact distance (D₁ + D₂)/2 (b): the curves overlap when they come this close (0: thin)."""
        return 0.5 * (self.curve1.thickness + self.curve2.thickness)

    @property
    def reach(self) -> float:
        """r₁ + r₂ + contact (b): centres further apart than this cannot meet."""
        return self.curve1.max_radius + self.curve2.max_radius + self.contact

    @property
    def departure(self) -> float:
        """How far (b) the polylines depart from the curves, summed over the two SeSPs (0 for Polylines, which
        are their own curves): a set of positions thinner than this may be the polylines' and not the curves'."""
        return sum(p.departure(self.segments) if isinstance(p, SeSP) else 0.0 for p in (self.particle, self.other))

    @property
    def tolerance(self) -> float:
        """Contact tolerance (b): curves closer than this count as touching."""
        return TOUCH_TOLERANCE * self.reach

    @property
    def identical(self) -> bool:
        """Whether both particles have the same polyline."""
        return self.curve1 == self.curve2

    @property
    def mirror_symmetric(self) -> bool:
        """Whether the state (x, y, −φ) is the state (x, −y, φ) mirrored.

        SeSPs are mirror-symmetric about the x axis, and so are their
        polylines, exactly; a Polyline in general is not.
        """
        return isinstance(self.particle, SeSP) and isinstance(self.other, SeSP)

    @property
    def vertices1(self) -> np.ndarray:
        """(N₁ + 1, 2) ndarray: particle 1's vertices, C-contiguous, for the kernels."""
        return np.ascontiguousarray(self.curve1.vertices)

    @property
    def vertices2(self) -> np.ndarray:
        """(N₂ + 1, 2) ndarray: particle 2's vertices in its own frame."""
        return np.ascontiguousarray(self.curve2.vertices)

    def hulls(self) -> tuple[np.ndarray, np.ndarray]:
        """Convex hulls of the two curves, counter-clockwise (computed once)."""
        if not self._hulls:
            self._hulls["both"] = (self.curve1.hull(), self.curve2.hull())
        return self._hulls["both"]

    def thickened(self, extra: float) -> Pair:
        """The same pair with both particles ``extra`` (b) thicker: the contact distance grows by ``extra``."""
        particle, other = (_thicker(p, c, extra) for p, c in ((self.particle, self.curve1), (self.other, self.curve2)))
        return Pair.of(particle, None if self.other is self.particle else other, segments=self.segments)

    def closed(self) -> Pair:
        """The same pair with both SeSPs closed (Ψ = 0)."""
        if not self.mirror_symmetric:
            raise ValueError("the closed shape is defined for SeSPs only: pass reference= for a Polyline")
        other = None if self.other is self.particle else self.other.closed()
        return Pair.of(self.particle.closed(), other, segments=self.segments)


def _thicker(particle, curve: Polyline, extra: float):
    if isinstance(particle, SeSP):
        return replace(particle, thickness=particle.thickness + extra)
    return Polyline(curve.vertices, thickness=curve.thickness + extra)


def as_pair(particle, other=None, segments: int = DEFAULT_SEGMENTS) -> Pair:
    """``particle`` if it is already a :class:`Pair` (then ``other`` must be None), else ``Pair.of(...)``."""
    if isinstance(particle, Pair):
        if other is not None:
            raise ValueError("other must be None when the first argument is already a Pair")
        return particle
    return Pair.of(particle, other, segments=segments)
