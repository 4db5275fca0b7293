import math

import numpy as np
import pytest
from scipy.integrate import quad

from sesp import Polyline, SeSP
from sesp.shape import convex_hull


@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"n": -1}, "n"),
        ({"n": 0}, "n"),
        ({"n": float("nan")}, "n"),
        ({"m": -2}, "m"),
        ({"aspect": 0}, "aspect"),
        ({"opening": -0.1}, "opening"),
        ({"opening": 2 * math.pi}, "opening"),
        ({"opening": 7.0}, "opening"),
    ],
)
def test_invalid_parameters_are_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        SeSP(**kwargs)


@pytest.mark.parametrize("segments", [0, -3, 2.5, True])
def test_invalid_segments(segments):
    with pytest.raises(ValueError, match="segments"):
        SeSP().polyline(segments)


def test_m_defaults_to_n_and_closed_keeps_shape():
    p = SeSP(n=4, aspect=1.5, opening=1.0)
    assert p.m == 4
    c = p.closed()
    assert (c.n, c.m, c.aspect, c.opening) == (4, 4, 1.5, 0.0)


@pytest.mark.parametrize("n, opening, segments", [(2, 0.0, 64), (2, math.pi / 2, 33), (8, 1.0, 40), (0.7, 2.0, 25)])
def test_polyline_endpoints_exact_and_mirror_symmetric(n, opening, segments):
    p = SeSP(n=n, opening=opening)
    v = p.polyline(segments).vertices
    assert v.shape == (segments + 1, 2)
    np.testing.assert_allclose(v[0], p.point(opening / 2), rtol=0, atol=1e-15)
    np.testing.assert_array_equal(v[-1], v[0] * [1, -1])
    np.testing.assert_array_equal(v[::-1], v * [1, -1])


def test_closed_polyline_is_closed():
    line = SeSP(n=8).polyline(64)
    assert line.is_closed


def _polar_radius(p: SeSP, alpha):
    # |x/A|^n + |y|^n = 1 in polar form (n = m): smooth in α for n > 1.
    return (abs(math.cos(alpha) / p.aspect) ** p.n + abs(math.sin(alpha)) ** p.n) ** (-1 / p.n)


def _polar_speed(p: SeSP, alpha, h=1e-6):
    r = _polar_radius(p, alpha)
    dr = (_polar_radius(p, alpha + h) - _polar_radius(p, alpha - h)) / (2 * h)
    return math.hypot(r, dr)


@pytest.mark.parametrize("n, opening", [(2, 0.5), (4, math.pi / 2), (8, 1.0), (2, 0.0), (4, 4.0)])
def test_vertices_are_equally_spaced_in_arc_length_within_the_flanks_and_the_back(n, opening):
    """Arc length along the true curve (quadrature in polar angle) between vertices is the same on each flank
    (θ in [Ψ/2, π − Ψ/2] and its mirror) and on the back; for Ψ = 0 or Ψ >= π it is L/N throughout. The
    flanks and the back are split so that the longest segment is no longer than L/(N − 4)."""
    p = SeSP(n=n, aspect=1.3, opening=opening)
    segments = 24
    v = p.polyline(segments).vertices
    alpha = np.unwrap(np.arctan2(v[:, 1], v[:, 0]) % (2 * np.pi))
    arcs = np.array([quad(lambda a: _polar_speed(p, a), lo, hi, limit=200)[0] for lo, hi in zip(alpha[:-1], alpha[1:])])
    assert arcs.sum() == pytest.approx(p.length, rel=1e-6)
    i, j = p.flank_and_back(segments) or (0, segments)
    for section in (arcs[:i], arcs[i : i + j], arcs[i + j :]):
        if section.size:
            np.testing.assert_allclose(section, section.mean(), rtol=1e-5)
    assert arcs.max() < p.length / (segments - 4)


@pytest.mark.parametrize("n, opening, segments", [(2, 0.5, 24), (8, 2.9, 256), (0.5, 1.5, 33), (10, 3.1, 7)])
def test_the_polylines_flank_is_its_own_mirror_image_in_x_and_its_back_in_y(n, opening, segments):
    """The curve's flank θ in [Ψ/2, π − Ψ/2] is its own mirror image in x, its back θ in [π − Ψ/2, π + Ψ/2]
    its own in y; so are the polyline's, exactly, with a vertex at θ = π/2 when the flank has an even count."""
    p = SeSP(n=n, opening=opening)
    v = p.polyline(segments).vertices
    i, j = p.flank_and_back(segments)
    assert 2 * i + j == segments
    np.testing.assert_array_equal(v[: i + 1][::-1], v[: i + 1] * [-1, 1])
    np.testing.assert_array_equal(v[i : i + j + 1][::-1], v[i : i + j + 1] * [1, -1])
    if i % 2 == 0:
        np.testing.assert_array_equal(v[i // 2], [0.0, 1.0])


@pytest.mark.parametrize("degrees", [5, 30, 90, 150, 170, 179])
def test_the_longest_chord_is_near_equal_arc_and_corners_at_the_axis_are_vertices(degrees):
    """The ASP's longest chord spans at most 3% more than (2π − Ψ)/N at N = 256 (its departure is the
    sagitta of that chord); the diamond (n = 1) has its corners at θ = π/2 and π as vertices wherever the
    flanks and back are split (30° to 170° here), so its polygon is exact. At 5° and 179° the back or the
    flanks are too short for the split and the N segments are of equal arc: the corner at π/2 is cut."""
    psi = math.radians(degrees)
    v = SeSP(n=2, opening=psi).polyline(256).vertices
    chord = np.hypot(*np.diff(v, axis=0).T).max()
    assert 2 * math.asin(chord / 2) <= 1.03 * (2 * math.pi - psi) / 256
    split = SeSP(n=1, opening=psi).flank_and_back(256) is not None
    assert split == (10.25 <= degrees <= 174.75)  # the range shape.SeSP.polyline states
    assert (SeSP(n=1, opening=psi).departure(256) < 1e-12) == split


def test_circle_polyline_lies_on_the_circle_and_length_converges():
    p = SeSP(n=2, opening=math.pi / 2)
    line = p.polyline(1024)
    np.testing.assert_allclose(np.hypot(*line.vertices.T), 1.0, atol=1e-12)
    assert line.length == pytest.approx(1.5 * math.pi, rel=1e-6)
    assert p.length == pytest.approx(1.5 * math.pi, rel=1e-8)
    assert p.max_radius == pytest.approx(1.0, abs=1e-12)


def test_max_radius_of_square_like_curve_is_corner_distance():
    p = SeSP(n=50)  # |x|^50 + |y|^50 = 1: the corner (t, t) has t = 2^(-1/50)
    assert p.max_radius == pytest.approx(math.sqrt(2) * 2 ** (-1 / 50), rel=1e-4)


def test_polyline_validation():
    with pytest.raises(ValueError, match="at least 2"):
        Polyline([[0, 0]])
    with pytest.raises(ValueError, match="finite"):
        Polyline([[0, 0], [np.nan, 1]])
    with pytest.raises(ValueError, match="coincide"):
        Polyline([[0, 0], [1, 0], [1, 0]])
    with pytest.raises(ValueError, match="shape"):
        Polyline([0, 1, 2])


def test_polyline_measures():
    square = Polyline([[1, 1], [-1, 1], [-1, -1], [1, -1], [1, 1]])
    assert square.length == 8
    assert square.area == 4
    assert square.max_radius == pytest.approx(math.sqrt(2))
    np.testing.assert_array_equal(square.hull(), [[-1, -1], [1, -1], [1, 1], [-1, 1]])
    with pytest.raises(ValueError, match="closed"):
        _ = Polyline([[0, 0], [1, 0]]).area


def test_convex_hull_of_random_points_contains_them():
    rng = np.random.default_rng(3)
    pts = rng.normal(size=(200, 2))
    hull = convex_hull(pts)
    edges = np.roll(hull, -1, axis=0) - hull
    rel = pts[:, None, :] - hull[None, :, :]
    cross = edges[None, :, 0] * rel[..., 1] - edges[None, :, 1] * rel[..., 0]
    assert np.all(cross >= -1e-12)
    assert set(map(tuple, hull)) <= set(map(tuple, pts))


def test_needle_hull_is_its_endpoints():
    np.testing.assert_array_equal(Polyline([[-1, 0], [0, 0], [1, 0]]).hull(), [[-1, 0], [1, 0]])


@pytest.mark.parametrize("n", [0.3, 2, 10, 50, 200])
def test_vertices_satisfy_the_superellipse_equation(n):
    p = SeSP(n=n, aspect=1.4, opening=1.0)
    v = p.polyline(256).vertices
    residual = np.abs(np.abs(v[:, 0] / 1.4) ** n + np.abs(v[:, 1]) ** n - 1)
    assert residual.max() < (1e-7 if n >= 8 else 1e-12)


@pytest.mark.parametrize(
    "make, word",
    [
        (lambda: Polyline([[0.0, 0.0], [1e300, 0.0]]), "must lie within"),
        (lambda: Polyline([[0.0, 0.0], [1e-170, 0.0], [1.0, 0.0]]), "coincide"),
        (lambda: Polyline([[0.0, 0.0], [1.0, 0.0]], thickness=1e9), "thickness"),
        (lambda: SeSP(aspect=1e200), "aspect must be in"),
        (lambda: SeSP(aspect=1e-200), "aspect must be in"),
        (lambda: SeSP(n=True), "n must be"),
        (lambda: SeSP(thickness=float("inf")), "thickness"),
    ],
)
def test_extreme_magnitudes_are_refused_on_input(make, word):
    """Outside the stated valid range (lengths up to 1e6 b, segments longer than 1e-9 of the size) sesp refuses."""
    with pytest.raises(ValueError, match=word):
        make()


@pytest.mark.parametrize("n", [2, 4, 8, 10])
def test_the_mirror_symmetric_split_departs_from_the_curve_within_5_percent_of_equal_arc(n, monkeypatch):
    """At N = 256 the flank-symmetric polyline departs from the curve no more than 1.05 times as far as the
    polyline of exactly equal arc does (docs/design.md §1), over openings from 5° to 179°."""
    openings = [math.radians(d) for d in (5, 30, 90, 150, 170, 179)]
    symmetric = [SeSP(n=n, opening=psi).departure(256) for psi in openings]
    monkeypatch.setattr(SeSP, "flank_and_back", lambda self, segments: None)
    equal_arc = [SeSP(n=n, opening=psi).departure(256) for psi in openings]
    assert max(s / e for s, e in zip(symmetric, equal_arc)) <= 1.05
