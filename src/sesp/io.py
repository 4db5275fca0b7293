"""netCDF files: save atomically, load with validation.

Loading never executes anything from a file: netCDF holds arrays and plain
attributes only, and every variable sesp relies on is checked before use.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import netCDF4
import numpy as np
import xarray as xr

from .dataset import SespFileError, validate
from .fileprobe import check_expansion, probe

__all__ = ["save", "load", "SespFileError", "validate"]


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
    tmp = ""
    try:  # an interrupt just after mkstemp must not leave the temporary either
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        os.close(fd)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # mkstemp creates 0600; a result file is for sharing
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=_encoding(ds))
        os.replace(tmp, path)
    except (OSError, RuntimeError) as err:  # netCDF reports a failed write as RuntimeError
        if tmp:
            Path(tmp).unlink(missing_ok=True)
        raise OSError(f"{path}: could not write the file ({err}); is the disk full or the folder read-only?") from err
    except BaseException:
        if tmp:
            Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _open(path: Path) -> xr.Dataset:
    try:
        with netCDF4.Dataset(path) as nc:  # the header alone: refuse what would not fit before reading data
            check_expansion(nc, path.stat().st_size)
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except Exception as err:  # a damaged file can make the library raise almost anything
        raise SespFileError(f"{path}: not a readable netCDF file ({type(err).__name__}: {err})") from None


def load(path, *, isolate: bool = True) -> xr.Dataset:
    """Read a dataset written by :func:`save`, checking that it is a sesp file.

    Parameters
    ----------
    path : path-like
        The netCDF file.
    isolate : bool
        First read the file in a separate process (:mod:`sesp.fileprobe`, about 0.2 s), so that a damaged
        file that crashes the netCDF/HDF5 library ends that process, not this one. Turn it off only for
        files just written or already probed.

    Raises
    ------
    FileNotFoundError
        No such file.
    SespFileError
        Not netCDF, damaged, not written by sesp, variables larger than the file can hold, missing or
        malformed variables, or a field that does not match its recorded SHA-256.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such file")
    if isolate and (why := probe([path])[path]) is not None:
        raise SespFileError(f"{path}: not a readable netCDF file ({why})")
    ds = _open(path)
    for name in ("allowed", "overlap"):
        if name in ds and ds[name].dtype != bool and ds[name].dtype.kind in "iu":
            if np.isin(ds[name].values, (0, 1)).all():
                ds[name] = ds[name].astype(bool)
    try:
        return validate(ds, path)
    except SespFileError:
        raise
    except Exception as err:  # attributes of the wrong type or shape in a damaged file
        raise SespFileError(f"{path}: malformed sesp file ({type(err).__name__}: {err})") from None
