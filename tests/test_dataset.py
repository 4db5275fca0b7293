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
    """pint-xarray, with cf-xarray's UDUNITS registry, quantifies every variable of every kind of file: lengths,
    areas and densities reduced by b are pure numbers (units "1", the power of b in their long_name, the unit b
    named once in the global attribute length_unit), angles radians; no other attribute holds a unit, and each
    error bar is named by its value's ancillary_variables."""
    import cf_xarray.units  # noqa: F401  (pint reads CF units)
    import pint_xarray  # noqa: F401
    import xarray as xr

    ds = xr.open_dataset(files[kind])
    quantified = ds.pint.quantify()  # raises where a unit cannot be read
    assert ds.attrs["length_unit"].startswith("b, the semi-axis")
    reduced = 0
    for name, var in {**ds.data_vars, **ds.coords}.items():
        assert not {"in_units_of", "resolution_units"} & set(var.attrs), f"{kind}: {name}"
        if var.attrs.get("long_name", "").endswith((", b", ", b²", ", b⁻²", ", b⁴")):
            assert quantified[name].pint.units.dimensionless, f"{kind}: {name}"
            reduced += 1
        if f"{name}_error" in ds.data_vars:
            assert var.attrs["ancillary_variables"] == f"{name}_error", f"{kind}: {name}"
    assert reduced > 0, f"{kind}: no length, area or density found"
    if "phi" in ds.coords:
        assert str(quantified.phi.pint.units) == "radian"


def test_b3_and_b2_carry_their_powers_of_b_when_quantified():
    import cf_xarray.units  # noqa: F401
    import pint_xarray  # noqa: F401

    from sesp.virial import third_virial

    found = third_virial(SeSP(n=2, opening=math.pi / 2), rtol=None, nodes=33, nphi=4, shifts=1)
    quantified = found.pint.quantify()
    assert quantified.third_virial_coefficient.pint.units.dimensionless
    assert found.third_virial_coefficient.attrs["long_name"].endswith(", b⁴")
    assert found.second_virial_coefficient.attrs["long_name"].endswith(", b²")
    assert found.third_virial_coefficient.attrs["ancillary_variables"] == "third_virial_coefficient_error"
