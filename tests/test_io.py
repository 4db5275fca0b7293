import numpy as np
import pytest
import xarray as xr

from sesp import Grid, SeSP, SespFileError, load, save, scan
from sesp.measures import monte_carlo


@pytest.fixture(scope="module")
def ds():
    return scan(SeSP(n=4, opening=1.0), Grid(20, 21, nphi=6), segments=16, crossings=True)


def test_round_trip_is_bit_exact(ds, tmp_path):
    path = save(ds, tmp_path / "a.nc")
    back = load(path)
    assert back.allowed.dtype == bool
    np.testing.assert_array_equal(back.allowed.values, ds.allowed.values)
    np.testing.assert_array_equal(back.crossings.values, ds.crossings.values)
    xr.testing.assert_identical(back.drop_attrs(), ds.drop_attrs())
    for key, value in ds.attrs.items():
        np.testing.assert_array_equal(back.attrs[key], value)


def test_file_is_compressed(ds, tmp_path):
    big = scan(SeSP(n=2), Grid(128, nphi=16), segments=64)
    path = save(big, tmp_path / "big.nc")
    assert path.stat().st_size < big.allowed.size / 4


def test_monte_carlo_round_trip(tmp_path):
    mc = monte_carlo(SeSP(), samples=100, segments=16, seed=1)
    back = load(save(mc, tmp_path / "mc.nc"))
    np.testing.assert_array_equal(back.overlap.values, mc.overlap.values)
    assert float(back.excluded_area) == float(mc.excluded_area)


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        load(tmp_path / "nope.nc")


def test_not_netcdf(tmp_path):
    path = tmp_path / "junk.nc"
    path.write_bytes(b"this is not netCDF")
    with pytest.raises(SespFileError, match="not a readable netCDF"):
        load(path)


def test_truncated_file(ds, tmp_path):
    path = save(ds, tmp_path / "t.nc")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(SespFileError, match="t.nc"):
        load(path)


def test_foreign_netcdf(tmp_path):
    path = tmp_path / "foreign.nc"
    xr.Dataset({"temperature": ("t", np.arange(3.0))}).to_netcdf(path)
    with pytest.raises(SespFileError, match="not a sesp dataset"):
        load(path)


def test_missing_variable_and_wrong_dims(ds, tmp_path):
    path = save(ds.drop_vars("allowed"), tmp_path / "m.nc")
    with pytest.raises(SespFileError, match="missing variable 'allowed'"):
        load(path)
    path = save(ds.transpose("x", "y", "phi", ...), tmp_path / "d.nc")
    with pytest.raises(SespFileError, match="dims"):
        load(path)


def test_tampered_field_fails_checksum(ds, tmp_path):
    bad = ds.copy(deep=True)
    bad.allowed.values[0, 0, 0] = ~bad.allowed.values[0, 0, 0]
    with pytest.raises(SespFileError, match="SHA-256"):
        load(save(bad, tmp_path / "x.nc"))


def test_attributes_that_do_not_match_data(ds, tmp_path):
    bad = ds.copy()
    bad.attrs["nx"] = 99
    with pytest.raises(SespFileError, match="nx"):
        load(save(bad, tmp_path / "x.nc"))


def test_save_leaves_no_temporary_files(ds, tmp_path):
    save(ds, tmp_path / "a.nc")
    assert [p.name for p in tmp_path.iterdir()] == ["a.nc"]


def _without(key):
    def alter(d):
        d.attrs.pop(key)
        return d

    return alter


def _with_version(d):
    d.attrs["sesp_format_version"] = 99
    return d


@pytest.mark.parametrize(
    "alter, word",
    [
        (_without("allowed_sha256"), "allowed_sha256 is missing"),
        (_without("coords_sha256"), "coords_sha256 is missing"),
        (lambda d: d.assign_coords(x=d.x * 10), "coords_sha256"),
        (_with_version, "sesp_format_version 99"),
        (_without("sesp_format_version"), "sesp_format_version None"),
    ],
)
def test_integrity_gaps_are_refused(ds, tmp_path, alter, word):
    bad = alter(ds.copy(deep=True))
    with pytest.raises(SespFileError, match=word):
        load(save(bad, tmp_path / "bad.nc"))
