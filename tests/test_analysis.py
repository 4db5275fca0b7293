"""analyze(): one pass, the same numbers as the separate functions, whatever is kept."""

import math

import numpy as np
import pytest
import xarray as xr

from sesp import (
    Grid,
    SeSP,
    analyze,
    certified_components,
    closed_excluded_area,
    lattice_excluded_area,
    scan,
    scanline_excluded_area,
    smooth_excluded_area,
    summarize,
)
from sesp.measures import SCANLINE_ROWS

from cases import NEEDLE

ASP = SeSP(n=2, opening=math.pi / 2)
GRID = Grid(24, nphi=16)


def test_analysis_equals_scan_summary_and_components():
    ds = analyze(ASP, GRID, segments=24, keep=["allowed", "classes", "topology"], resolution=1e-2)
    field = scan(ASP, GRID, segments=24)
    summary = summarize(ASP, GRID, segments=24)
    np.testing.assert_array_equal(ds.allowed.values, field.allowed.values)
    for name in ("classes", "allowed_fraction"):
        xr.testing.assert_identical(ds[name].drop_attrs(), summary[name].drop_attrs())
    xr.testing.assert_identical(
        ds.lattice_excluded_area.drop_attrs(), summary.excluded_area.drop_attrs().rename("lattice_excluded_area")
    )
    assert float(ds.lattice_excluded_area.mean()) == pytest.approx(lattice_excluded_area(field), rel=1e-12)
    assert float(ds.closed_excluded_area) == closed_excluded_area(summary)
    found = certified_components(ASP, resolution=1e-2, segments=24)
    assert (int(ds.excluded_components), int(ds.excluded_components_high)) == (found.low, found.high) == (2, 2)
    assert ds.component_depth.values[:2].tolist() == [c.depth for c in found.components]
    assert ds.excluded_components.attrs["resolution"] == 1e-2
    assert ds.attrs["allowed_sha256"] == field.attrs["allowed_sha256"]


def test_excluded_area_alone_runs_no_lattice_pass():
    """A_ex(φ) is the smooth curves' (scanlines, extrapolated in N) with their error bars, and nothing is
    counted on the lattice."""
    ds = analyze(ASP, GRID, segments=24)
    assert "classes" not in ds and "allowed" not in ds and "lattice_excluded_area" not in ds
    assert ds.attrs["sesp_format"] == "sesp.summary" and ds.attrs["excluded_area_of"] == "smooth curves"
    lines = smooth_excluded_area(ASP, segments=24, nphi=GRID.nphi, rows=SCANLINE_ROWS)
    for name in ("excluded_area", "excluded_area_error", "mean_excluded_area", "mean_excluded_area_error"):
        np.testing.assert_array_equal(ds[name].values, lines[name].values)
    assert float(ds.second_virial_coefficient_error) == float(lines.mean_excluded_area_error) / 2


@pytest.mark.parametrize(
    "particle, segments, measured", [(NEEDLE, 24, "polylines as given"), (ASP, 30, "polygons of 30 segments")]
)
def test_polygons_stand_for_themselves_where_there_is_no_smooth_curve(particle, segments, measured):
    """A polyline, or segments not a multiple of 4: the polygon's A_ex(φ)."""
    ds = analyze(particle, GRID, segments=segments)
    assert ds.attrs["excluded_area_of"] == measured
    lines = scanline_excluded_area(particle, segments=segments, nphi=GRID.nphi)
    np.testing.assert_array_equal(ds.excluded_area.values, lines.excluded_area.values)


def test_scanline_and_lattice_areas_agree_within_the_lattice_resolution():
    """The stored A_ex(φ) (scanlines) and the lattice's count of the same pair: within a few boundary cells."""
    grid = Grid(128, nphi=16)
    ds = analyze(ASP, grid, segments=64, keep=["excluded_area", "classes"])
    np.testing.assert_allclose(ds.excluded_area.values, ds.lattice_excluded_area.values, rtol=2e-2)


def test_polylines_have_no_closed_shape():
    ds = analyze(NEEDLE, Grid(64, nphi=8))
    assert np.isnan(float(ds.closed_excluded_area))
    exact = 4 * np.abs(np.sin(ds.phi.values))  # needles of length 2: ℓ² |sin φ|
    assert float(ds.mean_excluded_area) == pytest.approx(exact.mean(), rel=0.05)


@pytest.mark.parametrize("keep, word", [(["bogus"], "keep"), ([], "keep"), (["crossings"], "beside 'allowed'")])
def test_keep_is_checked(keep, word):
    with pytest.raises(ValueError, match=word):
        analyze(ASP, GRID, keep=keep)


def test_a_bad_resolution_is_refused_before_any_work():
    with pytest.raises(ValueError, match="resolution must be a length > 0"):
        analyze(ASP, Grid(4096, nphi=4096), keep=["classes", "topology"], resolution=-1.0)
