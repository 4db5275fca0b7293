"""analyze(): one pass, the same numbers as the separate functions, whatever is kept."""

import math

import numpy as np
import pytest
import xarray as xr

from sesp import Grid, SeSP, analyze, certified_components, describe, excluded_area, scan
from sesp.measures import closed_excluded_area, lattice_excluded_area, scanline_excluded_area, smooth_excluded_area
from sesp.regions import summarize

from cases import NEEDLE

ASP = SeSP(n=2, opening=math.pi / 2)
GRID = Grid(24, nphi=16)


def test_analysis_equals_scan_summary_and_components():
    ds = analyze(ASP, GRID, segments=24, keep=["allowed", "classes", "topology"], resolution=1e-2, rtol=1e-3)
    field = scan(ASP, GRID, segments=24)
    summary = summarize(ASP, GRID, segments=24)
    np.testing.assert_array_equal(ds.allowed.values, field.allowed.values)
    for name in ("classes", "allowed_fraction"):
        xr.testing.assert_identical(ds[name].drop_attrs(), summary[name].drop_attrs())
    xr.testing.assert_identical(
        ds.lattice_excluded_area.drop_attrs(), summary.excluded_area.drop_attrs().rename("lattice_excluded_area")
    )
    assert float(ds.lattice_excluded_area.mean()) == pytest.approx(lattice_excluded_area(field), rel=1e-12)
    assert float(ds.closed_excluded_area) == pytest.approx(4 * math.pi, rel=1e-12)  # the smooth closed circle
    assert closed_excluded_area(summary) < 4 * math.pi  # the field's: the closed polygon of 24 segments
    found = certified_components(ASP, resolution=1e-2, segments=24)
    assert (int(ds.excluded_components), int(ds.excluded_components_high)) == (found.low, found.high) == (2, 2)
    assert ds.component_depth.values[:2].tolist() == [c.depth for c in found.components]
    assert ds.excluded_components.attrs["resolution"] == 1e-2 and float(ds.component_rim) == found.rim == 1e-2
    assert "2 excluded components at resolution 0.01 b, at least resolution + 0.01 b deep" in describe(ds)
    assert ds.attrs["allowed_sha256"] == field.attrs["allowed_sha256"]


def test_excluded_area_alone_runs_no_lattice_pass_and_is_sesp_excluded_area():
    """A_ex is :func:`sesp.excluded_area` of the particles at the same rtol (the mean and its bar as it gives
    them, A_ex(φ) at the grid's orientations), whatever the lattice's segments; nothing is counted on the
    lattice."""
    best = excluded_area(ASP, rtol=1e-3)
    for segments in (24, 30):
        ds = analyze(ASP, GRID, segments=segments, rtol=1e-3)
        assert "classes" not in ds and "allowed" not in ds and "lattice_excluded_area" not in ds
        assert ds.attrs["sesp_format"] == "sesp.summary" and ds.attrs["excluded_area_of"] == "smooth curves"
        for name in ("mean_excluded_area", "mean_excluded_area_error"):
            assert float(ds[name]) == float(best[name])
        step = best.sizes["phi"] // GRID.nphi
        np.testing.assert_array_equal(ds.excluded_area.values, best.excluded_area.values[::step])
        assert float(ds.second_virial_coefficient) == float(best.mean_excluded_area) / 2
        assert float(ds.second_virial_coefficient_error) == float(best.mean_excluded_area_error) / 2


def test_orientations_not_among_the_refined_ones_are_evaluated_at_its_settings():
    """A grid of 12 orientations (not dividing 128): A_ex(φ) there at the settings the refinement reached."""
    ds = analyze(ASP, Grid(24, nphi=12), rtol=1e-3)
    settings = {k: ds.attrs[f"excluded_area_{k}"] for k in ("segments", "rows")}
    there = smooth_excluded_area(ASP, nphi=12, **settings)
    np.testing.assert_array_equal(ds.excluded_area.values, there.excluded_area.values)
    assert float(ds.mean_excluded_area) == float(excluded_area(ASP, rtol=1e-3).mean_excluded_area)


def test_a_polyline_is_measured_as_given():
    ds = analyze(NEEDLE, GRID, rtol=1e-3)
    assert ds.attrs["excluded_area_of"] == "polylines as given"
    best = excluded_area(NEEDLE, rtol=1e-3)
    assert float(ds.mean_excluded_area) == float(best.mean_excluded_area)
    lines = scanline_excluded_area(NEEDLE, nphi=GRID.nphi, rows=best.attrs["rows"])
    np.testing.assert_array_equal(ds.excluded_area.values, lines.excluded_area.values)


def test_scanline_and_lattice_areas_agree_within_the_lattice_resolution():
    """The stored A_ex(φ) (scanlines) and the lattice's count of the same pair: within a few boundary cells."""
    grid = Grid(128, nphi=16)
    ds = analyze(ASP, grid, segments=64, keep=["excluded_area", "classes"], rtol=1e-3)
    np.testing.assert_allclose(ds.excluded_area.values, ds.lattice_excluded_area.values, rtol=2e-2)


def test_polylines_have_no_closed_shape():
    ds = analyze(NEEDLE, Grid(64, nphi=8), rtol=1e-4)
    assert np.isnan(float(ds.closed_excluded_area))
    exact = 4 * np.abs(np.sin(ds.phi.values))  # needles of length 2: ℓ² |sin φ|, mean 8/π
    np.testing.assert_allclose(ds.excluded_area.values, exact, atol=1e-3)
    assert abs(float(ds.mean_excluded_area) - 8 / math.pi) <= 3 * float(ds.mean_excluded_area_error) + 1e-12


@pytest.mark.parametrize("keep, word", [(["bogus"], "keep"), ([], "keep"), (["crossings"], "beside 'allowed'")])
def test_keep_is_checked(keep, word):
    with pytest.raises(ValueError, match=word):
        analyze(ASP, GRID, keep=keep)


def test_a_bad_resolution_is_refused_before_any_work():
    with pytest.raises(ValueError, match=r"resolution must be in \[1e-09, 1\] b"):
        analyze(ASP, Grid(4096, nphi=4096), keep=["classes", "topology"], resolution=-1.0)
