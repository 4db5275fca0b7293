"""analyze(): one pass, the same numbers as the separate functions, whatever is kept."""

import math

import numpy as np
import pytest
import xarray as xr

from sesp import Grid, SeSP, analyze, closed_excluded_area, excluded_area, excluded_components, scan, summarize

from cases import NEEDLE

ASP = SeSP(n=2, opening=math.pi / 2)
GRID = Grid(24, nphi=16)


def test_analysis_equals_scan_summary_and_components():
    ds = analyze(ASP, GRID, segments=24, keep=["allowed", "classes", "topology"])
    field = scan(ASP, GRID, segments=24)
    summary = summarize(ASP, GRID, segments=24)
    np.testing.assert_array_equal(ds.allowed.values, field.allowed.values)
    for name in ("classes", "allowed_fraction", "excluded_area"):
        xr.testing.assert_identical(ds[name].drop_attrs(), summary[name].drop_attrs())
    assert float(ds.mean_excluded_area) == pytest.approx(excluded_area(field), rel=1e-12)
    assert float(ds.closed_excluded_area) == closed_excluded_area(summary)
    assert int(ds.excluded_components) == excluded_components(summary).count
    assert ds.attrs["allowed_sha256"] == field.attrs["allowed_sha256"]


def test_excluded_area_alone_runs_no_per_position_reduction():
    ds = analyze(ASP, GRID, segments=24)
    assert "classes" not in ds and "allowed" not in ds and ds.attrs["sesp_format"] == "sesp.summary"
    np.testing.assert_array_equal(ds.excluded_area.values, summarize(ASP, GRID, segments=24).excluded_area.values)


def test_polylines_have_no_closed_shape():
    ds = analyze(NEEDLE, Grid(64, nphi=8))
    assert np.isnan(float(ds.closed_excluded_area))
    exact = 4 * np.abs(np.sin(ds.phi.values))  # needles of length 2: ℓ² |sin φ|
    assert float(ds.mean_excluded_area) == pytest.approx(exact.mean(), rel=0.05)


@pytest.mark.parametrize("keep, word", [(["bogus"], "keep"), ([], "keep"), (["crossings"], "beside 'allowed'")])
def test_keep_is_checked(keep, word):
    with pytest.raises(ValueError, match=word):
        analyze(ASP, GRID, keep=keep)
