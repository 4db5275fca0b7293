"""netCDF files: save atomically, load with validation.

Loading never executes anything from a file: netCDF holds arrays and plain
attributes only, and every variable sesp relies on is checked before use.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

from .scan import field_sha256

__all__ = ["save", "load", "SespFileError"]

# Variables each kind of sesp file must hold: name -> (dims, dtype kind).
REQUIRED = {
    "sesp.scan": {"allowed": (("phi", "y", "x"), "b")},
    "sesp.monte_carlo": {"overlap": (("sample",), "b"), "excluded_area": ((), "f")},
    "sesp.point": {"excluded_area": (("phi",), "f")},
    "sesp.sweep": {},
}
OPTIONAL = {"crossings": (("phi", "y", "x"), "u"), "entangled": (("phi", "y", "x"), "b")}


class SespFileError(ValueError):
    """A file that is not a readable sesp dataset, or whose contents do not check out."""


def _encoding(ds: xr.Dataset) -> dict:
    enc = {}
    for name, var in ds.data_vars.items():
        enc[name] = {"zlib": True, "complevel": 4}
        if var.dims[:1] == ("phi",) and var.ndim == 3:
            enc[name]["chunksizes"] = (1, *var.shape[1:])
    return enc


def save(ds: xr.Dataset, path) -> Path:
    """Write ``ds`` to netCDF4 (zlib-compressed), atomically.

    The file is written under a temporary name in the same folder and renamed
    into place, so ``path`` is either absent or complete, never partial.
    Booleans round-trip exactly.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; a result file is for sharing
    try:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(ds))
        os.replace(tmp, path)
    except (OSError, RuntimeError) as err:  # netCDF reports a failed write as RuntimeError
        Path(tmp).unlink(missing_ok=True)
        raise OSError(f"{path}: could not write the file ({err}); is the disk full or the folder read-only?") from err
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _open(path: Path) -> xr.Dataset:
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except (OSError, ValueError, RuntimeError, KeyError) as err:
        raise SespFileError(f"{path}: not a readable netCDF file ({err})") from None


def _check_variable(path, ds, name, dims, kind):
    var = ds[name]
    if var.dims != dims:
        raise SespFileError(f"{path}: variable {name!r} has dims {var.dims}, expected {dims}")
    if var.dtype.kind != kind:
        raise SespFileError(f"{path}: variable {name!r} has dtype {var.dtype}, expected kind {kind!r}")


def _check_scan(path: Path, ds: xr.Dataset):
    for dim, key in (("x", "nx"), ("y", "ny"), ("phi", "nphi")):
        if key not in ds.attrs or ds.sizes.get(dim) != int(ds.attrs[key]):
            raise SespFileError(f"{path}: size of {dim} does not match attribute {key}")
    expected = ds.attrs.get("allowed_sha256")
    if expected is not None and field_sha256(ds.allowed.values) != expected:
        raise SespFileError(f"{path}: allowed field does not match its recorded SHA-256 (file corrupted?)")


def validate(ds: xr.Dataset, path="<dataset>") -> xr.Dataset:
    """Check that ``ds`` is a well-formed sesp dataset; raise SespFileError if not."""
    kind = ds.attrs.get("sesp_format")
    if kind not in REQUIRED:
        raise SespFileError(f"{path}: not a sesp dataset (attribute sesp_format is {kind!r})")
    for name, (dims, dtype_kind) in REQUIRED[kind].items():
        if name not in ds:
            raise SespFileError(f"{path}: missing variable {name!r} required in a {kind} file")
        _check_variable(path, ds, name, dims, dtype_kind)
    for name, (dims, dtype_kind) in OPTIONAL.items():
        if name in ds:
            _check_variable(path, ds, name, dims, dtype_kind)
    if kind == "sesp.scan":
        _check_scan(path, ds)
    return ds


def load(path) -> xr.Dataset:
    """Read a dataset written by :func:`save`, checking that it is a sesp file.

    Raises
    ------
    FileNotFoundError
        No such file.
    SespFileError
        Not netCDF, not written by sesp, missing or malformed variables, or an
        ``allowed`` field that does not match its recorded SHA-256.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    ds = _open(path)
    for name in ("allowed", "overlap"):
        if name in ds and ds[name].dtype != bool and ds[name].dtype.kind in "iu":
            if np.isin(ds[name].values, (0, 1)).all():
                ds[name] = ds[name].astype(bool)
    return validate(ds, path)
