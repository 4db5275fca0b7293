"""Exact and semi-analytic excluded areas, independent of sesp's engines: references to check them against.

* :func:`arc_excluded_area`: A_ex(φ) of two smooth circular arcs (the ASP, n = 2, aspect 1), from the
  intersection points of two unit circles: one quadrature in the centres' distance of a measure that is
  exact (arcs of directions).
* :func:`minkowski_excluded_area`: A_ex(φ) of a closed convex polygon with itself, the area of K ⊕ −R_φK.
* :func:`superellipse_area` and :func:`superellipse_perimeter` of the smooth closed curve
  |x/A|^n + |y|^m = 1, for 2A + P²/2π (the orientation mean for closed convex curves).
"""

from __future__ import annotations

import math

import numpy as np

from .shape import SeSP, convex_hull

__all__ = ["arc_excluded_area", "minkowski_excluded_area", "superellipse_area", "superellipse_perimeter"]

TAU = 2 * math.pi


def _arc(start: float, length: float) -> list[tuple[float, float]]:
    """The directions [start, start + length) modulo 2π, as intervals within [0, 2π)."""
    s = start % TAU
    return [(s, min(s + length, TAU))] + ([(0.0, s + length - TAU)] if s + length > TAU else [])


def _union_measure(intervals) -> float:
    total, lo, hi = 0.0, math.inf, -math.inf
    for s, e in sorted(intervals):
        if s > hi:
            total += max(0.0, hi - lo)
            lo, hi = s, e
        else:
            hi = max(hi, e)
    return total + max(0.0, hi - lo)


def _meeting_directions(beta: float, phi: float, opening: float) -> float:
    """Measure of the directions α of t, |t| = 2 cos β, at which the two unit arcs meet.

    The circles (centres 0 and t) cross at directions α ± β from the first centre, which are directions
    α + π ∓ β from the second; the arcs meet when, for one sign, the point lies on both arcs (arc 1:
    directions [Ψ/2, 2π − Ψ/2); arc 2 the same, turned by φ).
    """
    length = TAU - opening
    pieces = []
    for sign in (1.0, -1.0):
        on_first = _arc(opening / 2 - sign * beta, length)
        on_second = _arc(opening / 2 - math.pi + sign * beta + phi, length)
        pieces += [(max(a, c), min(b, d)) for a, b in on_first for c, d in on_second if min(b, d) > max(a, c)]
    return _union_measure(pieces)


def arc_excluded_area(phi: float, opening: float, panels: int = 1000) -> float:
    """A_ex(φ) (b²) of two smooth unit circular arcs of opening Ψ (the ASP with itself).

    A_ex(φ) = ∫₀² d dd · m(d), m the measure of meeting directions at distance d = 2 cos β; in β,
    ∫₀^{π/2} m(β) 4 cos β sin β dβ, by 6-point Gauss-Legendre on ``panels`` panels (m is piecewise linear
    in β: the error is below 1e-12 b² at the default).
    """
    nodes, weights = np.polynomial.legendre.leggauss(6)
    edges = np.linspace(0.0, math.pi / 2, panels + 1)
    total = 0.0
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        betas = (a + b) / 2 + (b - a) / 2 * nodes
        measure = np.array([_meeting_directions(beta, phi, opening) for beta in betas])
        total += (b - a) / 2 * float(np.sum(weights * measure * 4 * np.cos(betas) * np.sin(betas)))
    return total


def minkowski_excluded_area(vertices, phi: float) -> float:
    """A_ex(φ) (b²) of the closed convex polygon ``vertices`` (k, 2) with itself: the area of K ⊕ −R_φK,
    the hull of every difference of a vertex and a turned vertex."""
    v = np.asarray(vertices, dtype=float)
    c, s = math.cos(phi), math.sin(phi)
    turned = v @ np.array([[c, s], [-s, c]])
    hull = convex_hull((v[:, None, :] - turned[None, :, :]).reshape(-1, 2))
    x, y = hull[:, 0], hull[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def superellipse_area(particle: SeSP) -> float:
    """Area (b²) enclosed by the smooth closed superellipse of ``particle`` (opening ignored):
    4A Γ(1 + 1/n) Γ(1 + 1/m) / Γ(1 + 1/n + 1/m)."""
    n, m = particle.n, particle.m
    return 4 * particle.aspect * math.gamma(1 + 1 / n) * math.gamma(1 + 1 / m) / math.gamma(1 + 1 / n + 1 / m)


def superellipse_perimeter(particle: SeSP, points: int = 1 << 18) -> float:
    """Perimeter (b) of the smooth closed superellipse of ``particle``: a polygon of ``points`` vertices
    placed by the parameter θ, refined by one Richardson step (the polygon's error falls as its
    spacing squared)."""

    def polygon(k):
        theta = np.linspace(0.0, TAU, k + 1)
        c, s = np.cos(theta), np.sin(theta)
        # cos(π/2) is 6e-17, not 0, and |.|^(2/n) makes that 9e-5 for n = 8: a point off the curve
        c[np.abs(c) < 1e-15] = 0.0
        s[np.abs(s) < 1e-15] = 0.0
        x = particle.aspect * np.sign(c) * np.abs(c) ** (2 / particle.n)
        y = np.sign(s) * np.abs(s) ** (2 / particle.m)
        return float(np.hypot(np.diff(x), np.diff(y)).sum())

    return (4 * polygon(points) - polygon(points // 2)) / 3
