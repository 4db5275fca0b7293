"""Units of the quantities in sesp's datasets, in a form CF tools read correctly.

Lengths are reduced by b, the superellipse's semi-axis along y (DESIGN.md): x = 1.5 means 1.5 b. A reduced
quantity is a pure number, so its CF ``units`` is "1" (cf-xarray and pint read it as dimensionless, which it
is; UDUNITS would read "b" as the barn), and the power of b it was reduced by is said in its ``long_name``
(", b²"), which xarray's plot labels show, and once for the file in the global attribute ``length_unit``. No
attribute holds a unit string other than ``units``.
"""

__all__ = ["quantity", "dimensionless", "LENGTH_UNIT", "link_errors"]

# the global attribute of every dataset: what the unit of length is
LENGTH_UNIT = "b, the semi-axis of the superellipse along y: lengths, areas, densities are pure numbers in powers of b"
_POWER = {1: "b", 2: "b²", -2: "b⁻²", 4: "b⁴", -1: "b⁻¹"}


def quantity(power: int, long_name: str) -> dict:
    """The attributes of a quantity reduced by b**power: ``units`` "1", and the power of b in ``long_name``."""
    return {"units": "1", "long_name": f"{long_name}, {_POWER[power]}"}


def dimensionless(long_name: str) -> dict:
    """The attributes of a pure number (a ratio, a reduced density, an order parameter)."""
    return {"units": "1", "long_name": long_name}


def link_errors(ds):
    """``ds`` with each variable X that has an error variable (``X_error``) naming it in ``ancillary_variables``
    (CF), and each error variable's long_name saying whose error it is. Returns ``ds`` (changed in place)."""
    for name in list(ds.data_vars):
        error = f"{name}_error"
        if error in ds.data_vars:
            ds[name].attrs["ancillary_variables"] = error
            said = ds[error].attrs.get("long_name", "")
            if not said.startswith("error bar of") and not said.startswith("standard error of"):
                ds[error].attrs["long_name"] = f"error bar of {name}" + (f" ({said})" if said else "")
            ds[error].attrs.setdefault("units", ds[name].attrs.get("units", "1"))
    return ds
