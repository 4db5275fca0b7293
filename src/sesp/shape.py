"""Particle geometry: superellipse sector particles and general thin polylines.

Lengths are in units of b, the superellipse semi-axis along y. Angles are in
radians.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np

from .checks import MAX_PARTICLE, MIN_SEGMENT_RATIO, check_opening, check_positive, check_range, check_segments

__all__ = ["SeSP", "Polyline", "as_polyline", "convex_hull", "DEFAULT_SEGMENTS"]

DEFAULT_SEGMENTS = 256

# Dense sampling for the arc-length table: chords are refined until none is
# longer than this fraction of the curve length.
_DENSE_CHORD = 2.0**-16


class Polyline:
    """A thin particle given by its vertices, in its own frame.

    The particle's centre (the point it rotates about) is the origin of the
    vertex coordinates; its orientation vector is +x.

    Parameters
    ----------
    vertices : (K, 2) array_like
        K >= 2 finite vertices in units of b. Consecutive vertices must differ.
        A closed curve repeats its first vertex at the end.
    thickness : float
        Thickness D >= 0 in units of b: the particle is every point within
        D/2 of the polyline (a bent wire). 0, the default, is the thin curve.

    Examples
    --------
    >>> from sesp import Polyline
    >>> needle = Polyline([[-1.0, 0.0], [1.0, 0.0]])
    >>> needle.length
    2.0
    """

    def __init__(self, vertices, thickness: float = 0.0):
        v = np.array(vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 2:
            raise ValueError(f"vertices must have shape (K, 2), got {v.shape}")
        if v.shape[0] < 2:
            raise ValueError(f"vertices must hold at least 2 points, got {v.shape[0]}")
        if not np.all(np.isfinite(v)):
            raise ValueError("vertices must be finite (no NaN or inf)")
        if np.abs(v).max() > MAX_PARTICLE:
            raise ValueError(f"vertices must lie within {MAX_PARTICLE:g} b of the centre, got {np.abs(v).max():g}")
        seg = np.hypot(*np.diff(v, axis=0).T)
        shortest = MIN_SEGMENT_RATIO * max(float(np.ptp(v, axis=0).max()), float(np.abs(v).max()))
        if np.any(seg <= shortest):
            k = int(np.flatnonzero(seg <= shortest)[0])
            raise ValueError(
                f"vertices {k} and {k + 1} coincide: segments must be longer than {MIN_SEGMENT_RATIO:g} of the"
                f" particle's size ({shortest:.3g} b), got {seg[k]:.3g} b"
            )
        self.thickness = check_range("thickness", thickness, 0.0, MAX_PARTICLE, " b")
        v.flags.writeable = False
        self._vertices = v

    @property
    def vertices(self) -> np.ndarray:
        """(K, 2) ndarray: vertex coordinates in units of b (read-only)."""
        return self._vertices

    @property
    def segments(self) -> int:
        """Number of segments, K - 1."""
        return self._vertices.shape[0] - 1

    @property
    def segment_lengths(self) -> np.ndarray:
        """(K - 1,) ndarray: length of each segment, in units of b."""
        return np.hypot(*np.diff(self._vertices, axis=0).T)

    @property
    def length(self) -> float:
        """Total length of the polyline, in units of b."""
        return float(self.segment_lengths.sum())

    @property
    def max_radius(self) -> float:
        """Largest distance of a point of the polyline from its centre (b).

        Distance is convex along a segment, so the maximum is at a vertex.
        """
        return float(np.hypot(*self._vertices.T).max())

    @property
    def is_closed(self) -> bool:
        """True when the last vertex equals the first."""
        return bool(np.array_equal(self._vertices[0], self._vertices[-1]))

    @property
    def area(self) -> float:
        """Enclosed area of a closed polyline (shoelace formula), in b²."""
        if not self.is_closed:
            raise ValueError("area is defined only for a closed polyline")
        x, y = self._vertices[:-1].T
        return float(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y)))

    def hull(self) -> np.ndarray:
        """Vertices of the convex hull, counter-clockwise, without repetition.

        Returns
        -------
        (H, 2) ndarray
            H >= 2 (a straight needle's hull is its two endpoints).
        """
        return convex_hull(self._vertices)

    def __eq__(self, other) -> bool:
        return (
            isinstance(other, Polyline)
            and np.array_equal(self._vertices, other._vertices)
            and self.thickness == other.thickness
        )

    def __hash__(self):
        return hash((self._vertices.tobytes(), self.thickness))

    def __repr__(self) -> str:
        thick = f", thickness={self.thickness:g}" if self.thickness else ""
        return f"Polyline(<{self._vertices.shape[0]} vertices>, length={self.length:.6g}{thick})"


def convex_hull(points) -> np.ndarray:
    """Convex hull of 2D points by Andrew's monotone chain, counter-clockwise.

    Collinear points on the hull boundary are dropped. For points that all lie
    on one line the two extreme points are returned.
    """
    pts = np.unique(np.asarray(points, dtype=np.float64), axis=0)  # sorted by x, then y
    if len(pts) <= 2:
        return pts

    def half(seq):
        chain = []
        for p in seq:
            while len(chain) >= 2:
                o, a = chain[-2], chain[-1]
                if (a[0] - o[0]) * (p[1] - o[1]) - (a[1] - o[1]) * (p[0] - o[0]) > 0:
                    break
                chain.pop()
            chain.append(p)
        return chain

    lower = half(pts)
    upper = half(pts[::-1])
    hull = np.array(lower[:-1] + upper[:-1])
    return hull if len(hull) >= 2 else pts[[0, -1]]


@dataclass(frozen=True)
class SeSP:
    """A superellipse sector particle.

    The part of the superellipse ``x = A sgn(cos θ)|cos θ|^(2/n)``,
    ``y = sgn(sin θ)|sin θ|^(2/m)`` with θ in [Ψ/2, 2π − Ψ/2]: a curve with an
    opening of aperture Ψ centred on the +x direction.

    Parameters
    ----------
    n : float
        Degree along x, > 0 (2: circle; large: square corners; < 1: astroid-like).
    m : float, optional
        Degree along y, > 0. Defaults to ``n``.
    aspect : float
        Aspect ratio A = a/b > 0; the semi-axes are A along x and 1 along y.
    opening : float
        Opening aperture Ψ in radians, 0 <= Ψ < 2π. Ψ = 0 is the closed curve.
    thickness : float
        Thickness D >= 0 in units of b: the particle is every point within D/2
        of the curve. Two particles overlap when their curves come closer than
        (D₁ + D₂)/2. 0, the default, is the infinitely thin curve.

    References
    ----------
    K. Kornick, T. Brzinski, S. V. Franklin, "The excluded area of superellipse
    sector particles". M. Pilu and R. B. Fisher, "Equal-distance sampling of
    superellipse models", BMVC 1995.

    Examples
    --------
    >>> import numpy as np
    >>> from sesp import SeSP
    >>> asp = SeSP(n=2, opening=np.pi / 2)
    >>> line = asp.polyline(64)
    >>> line.vertices.shape
    (65, 2)
    """

    n: float = 2.0
    m: float | None = None
    aspect: float = 1.0
    opening: float = 0.0
    thickness: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "n", check_positive("n", self.n))
        m = self.n if self.m is None else check_positive("m", self.m)
        object.__setattr__(self, "m", m)
        object.__setattr__(self, "aspect", check_range("aspect", self.aspect, 1 / MAX_PARTICLE, MAX_PARTICLE))
        object.__setattr__(self, "opening", check_opening(self.opening))
        object.__setattr__(self, "thickness", check_range("thickness", self.thickness, 0.0, MAX_PARTICLE, " b"))

    def closed(self) -> SeSP:
        """The same shape with no opening (Ψ = 0)."""
        return SeSP(n=self.n, m=self.m, aspect=self.aspect, opening=0.0, thickness=self.thickness)

    @property
    def is_convex_closed(self) -> bool:
        """True when the closed curve bounds a convex region (n >= 1 and m >= 1)."""
        return self.n >= 1 and self.m >= 1

    def point(self, theta) -> np.ndarray:
        """Points of the superellipse at parameter θ (radians), shape (..., 2)."""
        theta = np.asarray(theta, dtype=np.float64)
        c, s = np.cos(theta), np.sin(theta)
        # cos and sin of multiples of π/2 carry rounding noise of ~1e-16, which
        # |.|^(2/n) would magnify for large n; zeroing it keeps the point on the curve.
        c = np.where(np.abs(c) < 1e-15, 0.0, c)
        s = np.where(np.abs(s) < 1e-15, 0.0, s)
        x = self.aspect * np.sign(c) * np.abs(c) ** (2.0 / self.n)
        y = np.sign(s) * np.abs(s) ** (2.0 / self.m)
        return np.stack([x, y], axis=-1)

    def _upper_arc_table(self):
        """θ and cumulative arc length along the upper half, θ in [Ψ/2, π] (read-only arrays, computed once
        per shape: thickness does not enter)."""
        return _arc_table(replace(self, thickness=0.0))

    def _arc_table_uncached(self):
        """The table of :meth:`_upper_arc_table`.

        Intervals are halved until each chord is short or the curve is straight
        over it (midpoint within 1e-10 of the chord): for large n the curve
        moves like |θ − π/2|^(2/n) along its flat sides, where halving in θ
        would never end, but there it is straight.
        """
        theta = np.linspace(self.opening / 2, math.pi, 4097)
        pts = self.point(theta)
        scale = float(np.hypot(*np.diff(pts, axis=0).T).sum()) or 1.0
        for _ in range(200):
            chord = np.hypot(*np.diff(pts, axis=0).T)
            cand = np.flatnonzero(chord > _DENSE_CHORD * scale)
            mids = 0.5 * (theta[cand] + theta[cand + 1])
            mid_pts = self.point(mids)
            a, b = pts[cand], pts[cand + 1]
            ab, am = b - a, mid_pts - a
            dev = np.abs(ab[:, 0] * am[:, 1] - ab[:, 1] * am[:, 0]) / chord[cand]
            split = (dev > 1e-10 * scale) & (mids > theta[cand]) & (mids < theta[cand + 1])
            if not split.any():
                break
            order = np.argsort(np.concatenate([theta, mids[split]]), kind="stable")
            theta = np.concatenate([theta, mids[split]])[order]
            pts = np.concatenate([pts, mid_pts[split]])[order]
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
        theta.flags.writeable = False
        arc.flags.writeable = False
        return theta, arc

    def _points_at(self, targets, theta, arc):
        """Curve points at arc lengths ``targets`` along the upper half.

        Bisection in θ on the distance from the start of the table interval
        that holds each target. Where θ cannot resolve the curve (the flat
        sides of a large-n curve, where one ulp of θ moves the point a
        visible distance) the interval is straight, and the point is placed
        on its chord instead.
        """
        k = np.clip(np.searchsorted(arc, targets, side="right") - 1, 0, len(theta) - 2)
        lo, hi = theta[k].copy(), theta[k + 1].copy()
        start, stop = self.point(theta[k]), self.point(theta[k + 1])
        want = targets - arc[k]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            far = np.hypot(*(self.point(mid) - start).T) > want
            hi = np.where(far, mid, hi)
            lo = np.where(far, lo, mid)
        pts = self.point(0.5 * (lo + hi))
        missed = np.abs(np.hypot(*(pts - start).T) - want) > 1e-9 * max(arc[-1], 1e-300)
        if missed.any():
            step = stop[missed] - start[missed]
            unit = step / np.hypot(*step.T)[:, None]
            pts[missed] = start[missed] + want[missed, None] * unit
        return pts

    @property
    def length(self) -> float:
        """Arc length of the curve itself (not of a polyline), in units of b."""
        return 2.0 * float(self._upper_arc_table()[1][-1])

    @property
    def max_radius(self) -> float:
        """Largest distance of a point of the curve from its centre, in b."""
        theta, _ = self._upper_arc_table()
        return float(np.hypot(*self.point(theta).T).max())

    def departure(self, segments: int = DEFAULT_SEGMENTS) -> float:
        """Largest distance (b) from a point of the curve to its :meth:`polyline` of ``segments`` segments.

        Measured at the points of the dense arc-length table (chords within
        1e-10 of the curve), each against the polyline segment spanning its
        arc length and the two beside it; about (s/2)²·κ/2 at the largest
        curvature κ, s the longest segment.
        """
        theta, arc = self._upper_arc_table()
        v = self.polyline(segments).vertices
        pts = self.point(theta)
        n_seg = len(v) - 1
        starts = self.vertex_arcs(n_seg)
        k = np.clip(np.searchsorted(starts, arc, side="right") - 1, 0, n_seg - 1)
        best = np.full(len(pts), np.inf)
        for shift in (-1, 0, 1):
            j = np.clip(k + shift, 0, n_seg - 1)
            a, d = v[j], v[j + 1] - v[j]
            w = pts - a
            lam = np.clip((w * d).sum(-1) / np.maximum((d * d).sum(-1), 1e-300), 0.0, 1.0)
            best = np.minimum(best, np.hypot(*(w - lam[:, None] * d).T))
        return float(best.max())

    def flank_and_back(self, n_seg: int):
        """Segment counts (i, j) of one flank and of the back when the polyline can be its own mirror image
        in x, else None.

        For 0 < Ψ < π the curve θ in [Ψ/2, π − Ψ/2] (the upper flank) is its own mirror image in x, and
        the back θ in [π − Ψ/2, π + Ψ/2] its own in y; of the splits N = 2i + j (i segments of equal arc on each
        flank, j on the back) it takes the one whose longest segment is shortest, among even i where N allows;
        None too when its shortest segment would be under a quarter of its longest.
        """
        if not 0.0 < self.opening < math.pi or n_seg < 3:
            return None
        total = 2.0 * self._upper_arc_table()[1][-1]
        flank = self._flank_arc()
        back = total - 2.0 * flank
        # An even i puts a vertex at θ = π/2, on the axis (a corner or cusp of some curves).
        i = np.arange(2, (n_seg - 1) // 2 + 1, 2)
        if i.size == 0:
            i = np.arange(1, (n_seg - 1) // 2 + 1)
        longest = np.maximum(flank / i, back / (n_seg - 2 * i))
        best = int(i[np.argmin(longest)])
        shortest = min(flank / best, back / (n_seg - 2 * best))
        if shortest < longest.min() / 4:  # a flank or back far shorter than L/N (Ψ near 0 or π): equal arc
            return None
        return best, n_seg - 2 * best

    def _flank_arc(self) -> float:
        """Arc length (b) of the upper flank, θ in [Ψ/2, π − Ψ/2]: twice that to θ = π/2, measured from the
        last table point before π/2 along the chord (the table is straight within 1e-10 there; interpolating in
        θ would not be where the curve moves like |θ − π/2|^(2/n))."""
        theta, arc = self._upper_arc_table()
        k = int(np.searchsorted(theta, math.pi / 2, side="right")) - 1
        return 2.0 * float(arc[k] + np.hypot(*(self.point(math.pi / 2) - self.point(theta[k]))))

    def vertex_arcs(self, n_seg: int) -> np.ndarray:
        """Arc lengths (b, from θ = Ψ/2) of the polyline's vertices on the upper half, 1 + N//2 of them."""
        theta, arc = self._upper_arc_table()
        half = arc[-1]
        counts = self.flank_and_back(n_seg)
        if counts is None:
            return np.arange(n_seg // 2 + 1) * (2.0 * half / n_seg)
        i, j = counts
        flank = self._flank_arc()
        on_flank = np.arange(i + 1) * (flank / i)
        on_back = flank + np.arange(1, j // 2 + 1) * (2.0 * (half - flank) / j)
        return np.concatenate([on_flank, on_back])

    def polyline(self, segments: int = DEFAULT_SEGMENTS) -> Polyline:
        """The curve as N segments of (nearly) equal arc length, mirror-symmetric in both axes where the
        curve is.

        The curve's upper half mirrored in y is its lower half, and for 0 < Ψ < π its upper flank (θ in
        [Ψ/2, π − Ψ/2]) mirrored in x is itself, as is the lower. N = 2i + j segments,
        i of equal arc on each flank and j on the back, keep both symmetries; the split makes the longest
        segment as short as it can (see :meth:`flank_and_back`): for the ASP at N = 256 its arc is at
        most 3% longer than (2π − Ψ)/N; and a corner at θ = π/2 (n = 1) becomes a vertex, so the diamond's
        polygon is the diamond where the split is made (tests/test_shape.py). The symmetry
        in x matters for the excluded set: the pinch between two lobes lies on x = 0, where the mirrored
        polygons touch as the curves do, instead of leaving a neck as thick as the polygons' departure.
        With Ψ = 0, Ψ >= π, N < 3, or a flank or back too short for segments a quarter as long as the others
        (Ψ near 0 or π: at N = 256 the split is made from 1.5° to 179.5° for the ASP, from 10.25° to 174.75°
        for the diamond), the N segments are of exactly equal arc.

        Vertices lie on the curve: |x/A|^n + |y|^m = 1 to rounding, or to
        1e-7 on the flat sides of large n (seen from n ≈ 10), where θ cannot
        resolve the curve and they are placed on a straight stretch of it. The endpoints are exact.

        Parameters
        ----------
        segments : int
            N >= 1.

        Returns
        -------
        Polyline
            N + 1 vertices; for Ψ = 0 the last equals the first.
        """
        n_seg = check_segments(segments)
        theta, arc = self._upper_arc_table()
        upper = self._points_at(self.vertex_arcs(n_seg), theta, arc)
        upper[0] = self.point(theta[0])
        counts = self.flank_and_back(n_seg)
        if counts is not None:
            i = counts[0]
            if i % 2 == 0:
                upper[i // 2] = self.point(math.pi / 2)
            upper[i - np.arange((i + 1) // 2)] = upper[: (i + 1) // 2] * np.array([-1.0, 1.0])
        if n_seg % 2 == 0:
            upper[-1] = self.point(math.pi)
        lower = upper[: (n_seg + 1) // 2][::-1] * np.array([1.0, -1.0])
        return Polyline(np.concatenate([upper, lower]), thickness=self.thickness)


@functools.lru_cache(maxsize=64)
def _arc_table(shape: SeSP):
    """The arc-length table of a (thin) SeSP, kept for the shapes used last: a sweep point builds the
    polylines of one shape at several segment counts."""
    return shape._arc_table_uncached()


def as_polyline(particle, segments: int = DEFAULT_SEGMENTS) -> Polyline:
    """The polyline that represents ``particle`` (a SeSP or a Polyline)."""
    if isinstance(particle, Polyline):
        return particle
    if isinstance(particle, SeSP):
        return particle.polyline(segments)
    raise TypeError(f"particle must be a SeSP or a Polyline, got {type(particle).__name__}")
