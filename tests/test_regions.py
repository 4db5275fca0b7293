import math

import numpy as np
import pytest
import shapely
import xarray as xr

from sesp import Grid, Polyline, SeSP, scan
from sesp.orientations import allowed_orientations
from sesp.regions import CLASSES, classify, position_summary, summarize

import naive
from cases import ZED, interval_disagreements


def _brute_force_classes(curve1, curve2, ds):
    """Per-state classification with shapely and the naive orientation test."""
    line1, hull1 = shapely.LineString(curve1.vertices), shapely.Polygon(curve1.hull())
    out = np.empty((ds.sizes["y"], ds.sizes["x"]), dtype=int)
    for iy, y in enumerate(ds.y.values):
        for ix, x in enumerate(ds.x.values):
            allowed = tangled = 0
            for phi in ds.phi.values:
                v2 = naive.transform(curve2.vertices, x, y, phi)
                if naive.crossings(curve1.vertices, curve2.vertices, x, y, phi):
                    continue
                allowed += 1
                hull2 = shapely.Polygon(naive.transform(curve2.hull(), x, y, phi))
                tangled += shapely.LineString(v2).intersects(hull1) and line1.intersects(hull2)
            nphi = ds.sizes["phi"]
            out[iy, ix] = 3 if allowed == 0 else 0 if allowed == nphi else 2 if tangled else 1
    return out


@pytest.mark.parametrize("first, second", [(SeSP(n=2, opening=math.pi / 2), None), (SeSP(n=8, opening=2.0), ZED)])
def test_classes_match_brute_force(first, second):
    ds = scan(first, Grid(14, 16, nphi=10), other=second, segments=16, entangled=True)
    curve1 = first.polyline(16)
    curve2 = curve1 if second is None else second
    expected = _brute_force_classes(curve1, curve2, ds)
    got = classify(ds).values
    np.testing.assert_array_equal(got, expected)
    assert len(np.unique(got)) == 4  # every class exercised


def test_entangled_field_matches_shapely_on_random_states():
    p = SeSP(n=4, opening=1.2)
    ds = scan(p, Grid(40, nphi=16), segments=24, entangled=True)
    curve = p.polyline(24)
    line1, hull1 = shapely.LineString(curve.vertices), shapely.Polygon(curve.hull())
    rng = np.random.default_rng(11)
    hits = 0
    for k, iy, ix in zip(*(rng.integers(0, s, 600) for s in ds.allowed.shape)):
        state = (ds.x.values[ix], ds.y.values[iy], ds.phi.values[k])
        v2 = shapely.LineString(naive.transform(curve.vertices, *state))
        h2 = shapely.Polygon(naive.transform(curve.hull(), *state))
        ref = (not line1.intersects(v2)) and v2.intersects(hull1) and line1.intersects(h2)
        hits += ref
        assert ds.entangled.values[k, iy, ix] == ref
    assert hits > 10


def test_flags_follow_cf_conventions():
    ds = scan(SeSP(n=2, opening=1.0), Grid(24, nphi=8), segments=24, entangled=True)
    classes = classify(ds)
    assert classes.attrs["flag_meanings"].split() == list(CLASSES)
    np.testing.assert_array_equal(classes.attrs["flag_values"], [0, 1, 2, 3])


def test_streaming_summary_equals_in_memory_summary():
    p = SeSP(n=8, opening=1.5)
    grid = Grid(36, 34, nphi=24)
    whole = position_summary(scan(p, grid, segments=32, entangled=True))
    streamed = summarize(p, grid, segments=32, chunk=5)
    xr.testing.assert_equal(whole.classes, streamed.classes)
    xr.testing.assert_equal(whole.allowed_fraction, streamed.allowed_fraction)
    xr.testing.assert_allclose(whole.mean_orientation, streamed.mean_orientation)
    xr.testing.assert_equal(whole.excluded_area, streamed.excluded_area)


def test_mean_orientation_of_a_single_allowed_direction():
    ds = scan(SeSP(n=2, opening=1.0), Grid(20, nphi=8), segments=16)
    allowed = np.zeros_like(ds.allowed.values)
    allowed[3] = True  # only φ_3 allowed everywhere
    summary = position_summary(ds.assign(allowed=(ds.allowed.dims, allowed)))
    np.testing.assert_allclose(summary.mean_orientation.values, ds.phi.values[3])
    np.testing.assert_allclose(summary.orientation_order.values, 1.0)
    np.testing.assert_allclose(summary.allowed_fraction.values, 1 / 8)


def _asp_excluded_exact(x, y, opening):
    """Exact excluded positions of two ASPs (unit arcs), from circle geometry.

    Particle 2's arc lies on the unit circle about its centre t, which meets
    particle 1's circle in two points seen from t an angle 2 acos(|t|/2)
    apart; no orientation fits iff that angle is >= Ψ (|t| <= 2 cos Ψ/2) and
    neither point lies in particle 1's opening, i.e. t is in both or neither
    of the unit disks about the endpoints.
    """
    X, Y = np.meshgrid(x, y)
    ex, ey = math.cos(opening / 2), math.sin(opening / 2)
    in_plus = (X - ex) ** 2 + (Y - ey) ** 2 < 1
    in_minus = (X - ex) ** 2 + (Y + ey) ** 2 < 1
    radius = 2 * math.cos(opening / 2) if opening < math.pi else 0.0
    boundary = np.minimum.reduce(
        [
            np.abs(np.hypot(X, Y) - radius),
            np.abs(np.hypot(X - ex, Y - ey) - 1),
            np.abs(np.hypot(X - ex, Y + ey) - 1),
        ]
    )
    return (np.hypot(X, Y) < radius) & ~(in_plus ^ in_minus), boundary


@pytest.mark.parametrize("degrees", [40, 90, 150, 200])
def test_asp_excluded_positions_match_exact_geometry(degrees):
    opening = math.radians(degrees)
    s = summarize(SeSP(n=2, opening=opening), Grid(128, nphi=512), segments=256, entangled=False)
    exact, boundary = _asp_excluded_exact(s.x.values, s.y.values, opening)
    got = s.allowed_fraction.values == 0
    h = float(s.x[1] - s.x[0])
    assert np.all(boundary[got != exact] < 2 * h)  # disagreement only at the exact boundary
    far = boundary >= 2 * h
    if degrees < 180:
        assert np.count_nonzero(exact & far) > 20  # the comparison is not vacuous
    if degrees > 180:
        assert not got.any()  # no excluded position at all for Ψ > π


# --- orientations exact in φ ------------------------------------------------------------


@pytest.mark.parametrize("other", [None, SeSP(n=4, m=2, aspect=0.7, opening=2.0)])
def test_blocked_orientations_contain_exactly_the_overlapping_sampled_states(other):
    """Every state of a direct scan is blocked exactly when its φ lies in a blocked interval."""
    particle = SeSP(n=4, opening=math.radians(100))
    ds = scan(particle, Grid(12, nphi=24), other=other, segments=24, engine="direct")
    assert interval_disagreements(particle, other, ds, 24) == 0


@pytest.mark.parametrize("offset", [0.05, 0.2, 0.37, 0.49])
def test_allowed_orientations_of_crossed_needles_are_exact(offset):
    """Needle 2 centred at (0, y) on needle 1's bisector meets it iff |sin φ| >= 2y/ℓ: allowed 4·asin(2y/ℓ)."""
    needle = Polyline([[-0.5, 0.0], [0.5, 0.0]])
    allowed = allowed_orientations(needle, 0.0, offset)
    assert allowed == pytest.approx(4 * math.asin(2 * offset), abs=1e-12)


def test_exact_allowed_measure_is_near_the_sampled_fraction_and_misses_no_allowed_state():
    """Exact measures sit within one orientation step of a scan's allowed fraction; positions allowed at a
    sampled φ are never excluded exactly."""
    particle = SeSP(n=2, opening=math.radians(120))
    ds = scan(particle, Grid(16, nphi=64), segments=32)
    x, y = np.meshgrid(ds.x.values, ds.y.values)
    exact = allowed_orientations(particle, x, y, segments=32)
    sampled = ds.allowed.values.mean(axis=0) * 2 * math.pi
    assert np.abs(exact - sampled).max() <= 2 * math.pi / 64 + 1e-9
    assert not np.any((exact == 0) & (sampled > 0))
