"""The dataset contract: every kind of file sesp writes loads back and is described."""

import math

import numpy as np
import pytest

from sesp import Grid, Pair, SeSP, analyze, describe, load, save, scan
from sesp.cli import main
from sesp.dataset import cell_area, grid_of, pair_of
from sesp.measures import lattice_excluded_area, monte_carlo, normalized_excluded_area
from sesp.regions import summarize
from sesp.report import area_text
from sesp.sweep import run

from cases import SMALL, ZED, point_files, write_sweep

GRID = Grid(20, nphi=8)


def _files(tmp_path):
    asp = SeSP(n=2, opening=math.pi / 2)
    files = {
        "scan": save(scan(asp, GRID, segments=16), tmp_path / "scan.nc"),
        "summary": save(summarize(asp, GRID, segments=16), tmp_path / "summary.nc"),
        "analysis": save(
            analyze(asp, GRID, segments=16, keep=["classes", "topology"], resolution=1e-2, rtol=1e-3),
            tmp_path / "analysis.nc",
        ),
        "mixture": save(analyze(asp, GRID, other=ZED, segments=16, rtol=1e-3), tmp_path / "mixture.nc"),
        "phases": save(
            analyze(asp, GRID, keep=["phases"], rtol=1e-3),
            tmp_path / "phases.nc",
        ),
        "monte_carlo": save(monte_carlo(asp, samples=200, segments=16, seed=1), tmp_path / "mc.nc"),
    }
    collected = run(write_sweep(tmp_path, SMALL.format(out=tmp_path / "sweep")), workers=1, progress=False)
    files["point"] = point_files(tmp_path / "sweep")[0]
    files["sweep"] = collected
    return files


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    return _files(tmp_path_factory.mktemp("kinds"))


KINDS = {
    "scan": "sesp.scan",
    "summary": "sesp.summary",
    "analysis": "sesp.summary",
    "mixture": "sesp.summary",
    "phases": "sesp.summary",
    "monte_carlo": "sesp.monte_carlo",
    "point": "sesp.point",
    "sweep": "sesp.sweep",
}


@pytest.mark.parametrize("kind", KINDS)
def test_every_kind_of_file_loads_back_and_is_described(files, kind, capsys):
    ds = load(files[kind])
    assert ds.attrs["sesp_format"] == KINDS[kind]
    text = describe(ds)
    assert KINDS[kind] in text and "variables:" in text
    assert main(["info", str(files[kind])]) == 0
    out = capsys.readouterr().out
    assert KINDS[kind] in out and "Traceback" not in out


@pytest.mark.parametrize("kind", ["scan", "summary", "analysis", "point"])
def test_pair_and_grid_are_rebuilt_from_any_single_pair_file(files, kind):
    ds = load(files[kind])
    pair = pair_of(ds)
    assert isinstance(pair, Pair) and pair.identical
    grid = grid_of(ds)
    assert (grid.nx, grid.ny) == (ds.sizes["x"], ds.sizes["y"])
    np.testing.assert_allclose(grid.x, ds.x.values, rtol=0, atol=1e-12)
    assert cell_area(ds) == pytest.approx(grid.dx * grid.dy)


def test_mixture_file_rebuilds_both_particles(files):
    pair = pair_of(load(files["mixture"]))
    assert not pair.identical
    np.testing.assert_array_equal(pair.curve2.vertices, ZED.vertices)


def test_info_gives_the_analysis_area_with_its_error_bar(files, capsys):
    ds = load(files["analysis"])
    main(["info", str(files["analysis"])])
    out = capsys.readouterr().out
    mean, error = float(ds.mean_excluded_area), float(ds.mean_excluded_area_error)
    assert f"A_ex     : {area_text(mean, error)} (of the smooth curves)" in out


def test_info_normalises_by_the_closed_shape_measured_alike(files, capsys):
    """`sesp info` on a scan gives the smooth curves' A_ex, normalised by the smooth closed circle's 4π; the
    field's own lattice count is normalised by the closed polygon of its N = 16 segments, 2A + P²/2π."""
    ds = load(files["scan"])
    main(["info", "--rtol", "1e-4", str(files["scan"])])
    out = capsys.readouterr().out
    assert f"closed {4 * math.pi:.6g} b^2" in out
    closed = Pair.of(SeSP(n=2), segments=16).curve1
    polygon = 2 * closed.area + closed.length**2 / (2 * math.pi)
    assert normalized_excluded_area(ds) == lattice_excluded_area(ds) / polygon
    assert polygon != pytest.approx(4 * math.pi, rel=1e-3)
    assert ds.attrs["sesp_format"] == "sesp.scan"


@pytest.mark.parametrize("kind", KINDS)
def test_every_variable_and_coordinate_is_labelled_and_the_file_is_cf(files, kind):
    ds = load(files[kind])
    for key in ("Conventions", "title", "history", "source", "date_created"):
        assert ds.attrs.get(key), f"{kind}: global attribute {key} missing"
    assert "sesp" in ds.attrs["history"] and ds.attrs["Conventions"].startswith("CF-")
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert var.attrs.get("long_name"), f"{kind}: {name} has no long_name"
        if "flag_values" not in var.attrs:  # CF flag variables carry flag meanings instead of units
            assert "units" in var.attrs, f"{kind}: {name} has no units"


@pytest.mark.parametrize("kind", KINDS)
def test_units_read_by_cf_tools_as_what_they_are(files, kind):
    """cf-xarray's UDUNITS registry (pint) reads every variable's units; lengths and areas, reduced by b, are
    pure numbers (units "1", with ``in_units_of``), never "b", which UDUNITS reads as the barn."""
    from cf_xarray.units import units as udunits

    ds = load(files[kind])
    checked = 0
    for name, var in {**ds.data_vars, **ds.coords}.items():
        if "units" not in var.attrs:
            continue
        unit = udunits.Unit(var.attrs["units"])  # raises where UDUNITS cannot read it
        if "in_units_of" in var.attrs:
            assert unit.dimensionless and var.attrs["in_units_of"] in ("b", "b^2", "b^-2"), (kind, name)
            checked += 1
        assert var.attrs["units"] not in ("b", "b^2", "b^-2"), f"{kind}: {name} in barns"
    assert checked > 0, f"{kind}: no length or area found"
