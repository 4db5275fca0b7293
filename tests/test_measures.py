"""Excluded area against exact results (docs/design.md §4), never against earlier output."""

import math

import numpy as np
import pytest

from sesp import (
    Grid,
    Polyline,
    SeSP,
    convex_excluded_area,
    excluded_area,
    excluded_area_error,
    kinematic_integral,
    monte_carlo,
    normalized_excluded_area,
    scan,
    shifted_excluded_area,
)
from sesp.measures import lattice_shifts

from cases import ZED


def test_needles_exclude_l_squared_sin_phi():
    length = 2.0
    needle = Polyline([[-1.0, 0.0], [1.0, 0.0]])
    for nx in (512, 511):
        ds = scan(needle, Grid(nx, nphi=16))
        area = excluded_area(ds, by="phi").values
        exact = length**2 * np.abs(np.sin(ds.phi.values))
        generic = np.abs(np.sin(ds.phi.values)) > 0.3
        np.testing.assert_allclose(area[generic], exact[generic], rtol=1e-2)
        # Parallel needles touch only on a segment (measure zero); on an odd grid
        # its nodes count, at most one row of 2ℓ / h nodes.
        h = float(ds.x[1] - ds.x[0])
        assert np.all(area[~generic & (exact < 1e-9)] <= 2 * length * h + 1e-12)


def test_two_circles_exclude_four_pi_at_every_orientation():
    segments = 256
    ds = scan(SeSP(n=2), Grid(256, nphi=8), segments=segments)
    polygon_value = convex_excluded_area(SeSP(n=2).polyline(segments))  # 4π up to the inscribed radius
    assert polygon_value == pytest.approx(4 * math.pi, rel=1e-3)
    np.testing.assert_allclose(excluded_area(ds, by="phi").values, polygon_value, rtol=2e-3)


@pytest.mark.parametrize("n", [4, 8])
def test_closed_convex_superellipse_matches_2_area_plus_p2_over_2pi(n):
    particle = SeSP(n=n)
    ds = scan(particle, Grid(512, nphi=64), segments=256)
    exact = convex_excluded_area(particle.polyline(256))
    assert excluded_area(ds) == pytest.approx(exact, rel=1e-3)


@pytest.mark.parametrize("particle", [SeSP(n=2, opening=math.pi / 2), SeSP(n=8, opening=math.pi / 2)])
def test_poincare_kinematic_formula(particle):
    ds = scan(particle, Grid(512, nphi=128), segments=256, crossings=True)
    measured, exact = kinematic_integral(ds)
    assert exact == pytest.approx(4 * particle.polyline(256).length ** 2)
    assert measured == pytest.approx(exact, rel=1e-3)


def test_poincare_for_a_mixture_of_a_sesp_and_a_zed():
    ds = scan(SeSP(n=0.7, opening=2.0), Grid(256, nphi=64), other=ZED, segments=48, crossings=True)
    measured, exact = kinematic_integral(ds)
    assert measured == pytest.approx(exact, rel=3e-3)


def test_normalized_excluded_area_of_closed_asp_is_one():
    ds = scan(SeSP(n=2), Grid(256, nphi=8), segments=256)
    assert normalized_excluded_area(ds) == pytest.approx(1.0, rel=2e-3)
    per_phi = normalized_excluded_area(ds, by="phi")
    assert per_phi.dims == ("phi",) and per_phi.attrs["units"] == "1"


def test_normalized_excluded_area_non_convex_uses_scanned_reference():
    ds = scan(SeSP(n=0.7, opening=0.0), Grid(96, nphi=8), segments=64)
    assert normalized_excluded_area(ds) == pytest.approx(1.0, abs=1e-12)


def test_error_estimate_is_of_the_size_of_the_true_error():
    """On exact cases the estimate exceeds the true error or trails it by < 10x."""
    ratios = []
    for n, nx, nphi in [(2, 128, 16), (4, 256, 64), (8, 256, 64), (4, 512, 64)]:
        particle = SeSP(n=n)
        ds = scan(particle, Grid(nx, nphi=nphi), segments=256)
        true = abs(excluded_area(ds) - convex_excluded_area(particle.polyline(256)))
        ratios.append(true / excluded_area_error(ds))
    assert max(ratios) < 10
    assert np.median(ratios) < 1


def test_monte_carlo_agrees_with_grid_within_three_standard_errors():
    particle = SeSP(n=2, opening=math.pi / 2)
    grid_value = excluded_area(scan(particle, Grid(512, nphi=128), segments=64))
    mc = monte_carlo(particle, samples=100_000, segments=64, seed=2024)
    assert abs(float(mc.excluded_area) - grid_value) < 3 * float(mc.excluded_area_error)


def test_excluded_area_rejects_unknown_by():
    ds = scan(SeSP(), Grid(8, nphi=2), segments=8)
    with pytest.raises(ValueError, match="by"):
        excluded_area(ds, by="x")


@pytest.mark.parametrize("n", [2, 4, 8])
def test_shifted_lattices_meet_the_closed_convex_formula(n):
    particle = SeSP(n=n)
    exact = convex_excluded_area(particle.polyline(128))
    shifted = shifted_excluded_area(particle, Grid(128, nphi=64), segments=128)
    assert float(shifted.mean()) == pytest.approx(exact, rel=5e-4)
    assert shifted.attrs["units"] == "b^2" and shifted.attrs["error_estimate"] > 0


def test_shifted_lattices_remove_the_bias_of_the_fixed_lattice():
    """Two circles exclude the disk |t| <= 2 at every φ: one lattice miscounts it the same way each time."""
    particle, grid = SeSP(n=2), Grid(128, nphi=64)
    exact = convex_excluded_area(particle.polyline(128))
    fixed = abs(excluded_area(scan(particle, grid, segments=128)) / exact - 1)
    moved = abs(float(shifted_excluded_area(particle, grid, segments=128).mean()) / exact - 1)
    assert moved < fixed / 10


def test_shifted_lattices_give_needles_l_squared_sin_phi():
    needle = Polyline([[-1.0, 0.0], [1.0, 0.0]])
    for nx in (256, 255):
        area = shifted_excluded_area(needle, Grid(nx, nphi=16))
        exact = 4.0 * np.abs(np.sin(area.phi.values))
        generic = np.abs(np.sin(area.phi.values)) > 0.3
        np.testing.assert_allclose(area.values[generic], exact[generic], rtol=2e-2)
        h = float(area.attrs["half_width"]) * 2 / nx
        assert np.all(area.values[~generic & (exact < 1e-9)] <= 2 * 2.0 * h + 1e-12)


def test_shifted_mirror_slices_equal_computed_slices():
    """SeSPs compute φ in [0, π] and mirror the rest; a Polyline computes every slice."""
    particle = SeSP(n=4, opening=1.3)
    for nphi in (16, 15):
        mirrored = shifted_excluded_area(particle, Grid(48, nphi=nphi), segments=40)
        computed = shifted_excluded_area(particle.polyline(40), Grid(48, nphi=nphi))
        np.testing.assert_array_equal(mirrored.values, computed.values)


def test_lattice_shifts_are_within_a_cell_and_mirror_pairwise():
    shifts = lattice_shifts(10)
    assert np.all(np.abs(shifts) <= 0.5) and np.all(shifts[0] == 0)
    for k in range(1, 5):  # φ_(10 - k) = −φ_k takes the y-mirror of φ_k's shift
        np.testing.assert_array_equal(shifts[10 - k], shifts[k] * [1, -1])
    assert len(np.unique(shifts[:6], axis=0)) == 6


def test_shifted_excluded_area_refuses_a_box_too_small():
    with pytest.raises(ValueError, match="half a cell"):
        shifted_excluded_area(SeSP(), Grid(32, nphi=4, half_width=2.0), segments=16)
