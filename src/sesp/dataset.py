"""The dataset contract: what every kind of sesp file holds, in one place.

Every module that writes or reads a sesp Dataset (scan, measures, regions,
analysis, io, sweep, plot, cli) goes through these names and functions
instead of reading ``ds.attrs`` its own way.

Kinds of dataset (attribute ``sesp_format``):

=====================  ======================================================
``sesp.scan``          the field ``allowed(phi, y, x)`` (optionally
                       ``crossings``, ``entangled``) and any reductions of it
``sesp.summary``       ``excluded_area(phi)`` and, as kept, per-position
                       reductions over φ (``allowed_fraction``, ``classes``, ...)
``sesp.point``         one parameter point of a sweep (a summary or scan
                       plus the point's record)
``sesp.sweep``         collected sweep: swept parameters as dimensions
``sesp.monte_carlo``   random placements and their A_ex estimate
=====================  ======================================================

Scans, summaries and points carry the attributes of the pair
(:func:`pair_attrs`) and of the grid (:func:`grid_attrs`), so
:func:`pair_of` and :func:`grid_of` rebuild both.
"""

from __future__ import annotations

import hashlib
import shlex
import sys
from datetime import UTC, datetime

import numpy as np
import xarray as xr

from . import version
from .grid import Grid
from .pair import Pair
from .shape import Polyline, SeSP
from .units import LENGTH_UNIT, quantity

__all__ = [
    "FORMATS",
    "FORMAT_VERSION",
    "SespFileError",
    "format_of",
    "base_attrs",
    "particle_attrs",
    "particle_of",
    "pair_variables",
    "pair_attrs",
    "pair_of",
    "grid_attrs",
    "grid_of",
    "cell_area",
    "coords",
    "LONG_NAMES",
    "field_sha256",
    "coords_sha256",
    "validate",
    "parameter_attrs",
    "PROVENANCE",
]

FORMAT_VERSION = 1
SHAPE_KEYS = ("n", "m", "aspect", "opening")
FIELD_DIMS = ("phi", "y", "x")
PLANE_DIMS = ("y", "x")

# Variables each kind of sesp dataset must hold: name -> (dims, dtype kind).
REQUIRED = {
    "sesp.scan": {"allowed": (FIELD_DIMS, "b")},
    "sesp.summary": {"excluded_area": (("phi",), "f")},
    "sesp.monte_carlo": {"overlap": (("sample",), "b"), "excluded_area": ((), "f")},
    "sesp.point": {"excluded_area": (("phi",), "f")},
    "sesp.sweep": {},
}
FORMATS = tuple(REQUIRED)
OPTIONAL = {
    "crossings": (FIELD_DIMS, "u"),
    "entangled": (FIELD_DIMS, "b"),
    "allowed_fraction": (PLANE_DIMS, "f"),
    "classes": (PLANE_DIMS, "i"),
}

LONG_NAMES = {
    "allowed": "state allowed (curves do not meet)",
    "crossings": "segment pairs that meet (n)",
    "entangled": "allowed and mutually entangled (each curve meets the other's convex hull)",
}


class SespFileError(ValueError):
    """A file that is not a readable sesp dataset, or whose contents do not check out."""


def format_of(ds) -> str | None:
    """The ``sesp_format`` of a dataset, or None."""
    return ds.attrs.get("sesp_format")


TITLES = {
    "sesp.scan": "allowed states of a particle pair on an (x, y, phi) grid (particles: see particle_kind, other_kind)",
    "sesp.summary": "excluded area and position classes of a particle pair (particles: see particle_kind, other_kind)",
    "sesp.point": "one parameter point of a sesp sweep",
    "sesp.sweep": "collected sesp sweep over particle parameters",
    "sesp.monte_carlo": "Monte-Carlo estimate of the excluded area of a particle pair",
}
# Attributes that record when and how a file was made; they differ between otherwise identical results.
PROVENANCE = ("history", "date_created")


def base_attrs(kind: str) -> dict:
    """The first attributes of every sesp dataset: format and version, and the CF global attributes.

    ``history`` records the time, the sesp version and the command line of
    the process that made the dataset; ``date_created`` the time (UTC, ISO 8601).
    """
    if kind not in FORMATS:
        raise ValueError(f"kind must be one of {FORMATS}, got {kind!r}")
    now = datetime.now(UTC).replace(microsecond=0).isoformat()
    return {
        "sesp_format": kind,
        "sesp_format_version": FORMAT_VERSION,
        "length_unit": LENGTH_UNIT,
        "sesp_version": version.__version__,
        "Conventions": "CF-1.10",
        "title": TITLES[kind],
        "source": f"sesp {version.__version__}",
        "history": f"{now} sesp {version.__version__}: {shlex.join(sys.argv) or 'python'}",
        "date_created": now,
    }


# Labels of the sweep parameters as coordinates: name -> (long_name, units).
PARAMETER_ATTRS = {
    "n": ("degree of the superellipse along x", "1"),
    "m": ("degree of the superellipse along y", "1"),
    "aspect": ("aspect ratio a/b", "1"),
    "opening": ("opening Psi", "rad"),
    "opening_degrees": ("opening Psi", "degree"),
    "thickness": ("thickness D", "b"),
    "segments": ("polyline segments N", "1"),
}


def parameter_attrs(name: str) -> dict:
    """``long_name`` and ``units`` of a sweep parameter coordinate (``other_`` names: particle 2's)."""
    base = name.removeprefix("other_")
    long_name, units = PARAMETER_ATTRS.get(base, (base, "1"))
    long_name = long_name if base == name else f"{long_name} of particle 2"
    if units == "b":
        return quantity(1, long_name)
    return {"long_name": long_name, "units": units}


# --- particles and pairs ---------------------------------------------------------------


def particle_attrs(particle, curve: Polyline, prefix: str) -> dict:
    """Attributes that describe ``particle`` and its polyline, keys prefixed."""
    attrs = {f"{prefix}_kind": type(particle).__name__}
    if isinstance(particle, SeSP):
        attrs.update({f"{prefix}_{k}": getattr(particle, k) for k in SHAPE_KEYS})
    attrs[f"{prefix}_thickness"] = curve.thickness
    attrs[f"{prefix}_segments"] = curve.segments
    attrs[f"{prefix}_length"] = curve.length
    attrs[f"{prefix}_max_radius"] = curve.max_radius
    return attrs


def pair_variables(pair: Pair) -> dict:
    """The two polylines' vertices as variables ``particle_vertices`` and ``other_vertices`` (b)."""
    return {
        f"{prefix}_vertices": (
            (f"{prefix}_vertex", "xy"),
            curve.vertices.copy(),
            quantity(1, f"vertices of {'particle 1' if prefix == 'particle' else 'particle 2'}'s polyline"),
        )  # fmt: skip
        for prefix, curve in (("particle", pair.curve1), ("other", pair.curve2))
    }


VERTEX_VARIABLES = ("particle_vertices", "other_vertices")


def particle_of(ds, prefix: str = "particle"):
    """The SeSP or Polyline a dataset describes (:func:`particle_attrs`, :func:`pair_variables`)."""
    attrs = ds.attrs
    kind = attrs.get(f"{prefix}_kind")
    thickness = float(attrs.get(f"{prefix}_thickness", 0.0))
    if kind == "SeSP":
        return SeSP(**{k: float(attrs[f"{prefix}_{k}"]) for k in SHAPE_KEYS}, thickness=thickness)
    if kind == "Polyline":
        name = f"{prefix}_vertices"
        vertices = ds[name].values if name in ds else attrs[name]  # files of sesp < 0.2 kept them as attributes
        return Polyline(np.asarray(vertices, dtype=float).reshape(-1, 2), thickness=thickness)
    raise SespFileError(f"attribute {prefix}_kind must be 'SeSP' or 'Polyline', got {kind!r}")


def pair_attrs(pair: Pair) -> dict:
    """Attributes that reproduce ``pair``: both particles, their polylines, the tolerance."""
    attrs = {}
    attrs.update(particle_attrs(pair.particle, pair.curve1, "particle"))
    attrs.update(particle_attrs(pair.other, pair.curve2, "other"))
    attrs["identical_particles"] = int(pair.identical)
    attrs["contact_distance"] = pair.contact
    attrs["touch_tolerance"] = pair.tolerance
    return attrs


def pair_of(ds) -> Pair:
    """The pair a scan, summary or point was computed for, rebuilt from its attributes."""
    attrs = ds.attrs
    if "particle_kind" not in attrs:
        raise SespFileError(f"a {format_of(ds)} dataset does not describe one pair of particles")
    segments = int(attrs["particle_segments"])
    first, second = particle_of(ds, "particle"), particle_of(ds, "other")
    return Pair.of(first, None if attrs.get("identical_particles") and first == second else second, segments=segments)


# --- grids -----------------------------------------------------------------------------


def grid_attrs(grid: Grid) -> dict:
    """Grid description for dataset attributes (the box must be set)."""
    return {"nx": grid.nx, "ny": grid.ny, "nphi": grid.nphi, "half_width": grid.half_width}


def grid_of(ds) -> Grid:
    """The grid of a scan or summary: from its attributes, else from its coordinates."""
    attrs = ds.attrs
    if all(k in attrs for k in ("nx", "ny", "nphi", "half_width")):
        return Grid(int(attrs["nx"]), int(attrs["ny"]), int(attrs["nphi"]), half_width=float(attrs["half_width"]))
    x, y = ds["x"].values, ds["y"].values
    return Grid(len(x), len(y), ds.sizes.get("phi", 1), half_width=float(len(x) * (x[1] - x[0]) / 2))


def cell_area(ds) -> float:
    """Area (b²) of one (x, y) cell of a dataset's lattice."""
    return float(ds.x[1] - ds.x[0]) * float(ds.y[1] - ds.y[0])


def coords(grid: Grid, dims=FIELD_DIMS) -> dict:
    """Labelled coordinates of ``grid`` along ``dims``."""
    every = {
        "phi": ("phi", grid.phi, {"units": "rad", "long_name": "orientation of particle 2 (φ)"}),
        "y": ("y", grid.y, quantity(1, "y of particle 2's centre")),
        "x": ("x", grid.x, quantity(1, "x of particle 2's centre")),
    }
    return {d: every[d] for d in dims}


def coords_sha256(ds) -> str:
    """SHA-256 of the x, y and phi coordinates a field lives on (float64 bytes, in that order)."""
    digest = hashlib.sha256()
    for name in ("x", "y", "phi"):
        digest.update(np.ascontiguousarray(np.asarray(ds[name].values, dtype=np.float64)).tobytes())
    return digest.hexdigest()


def field_sha256(allowed) -> str:
    """SHA-256 of a boolean field's C-ordered bytes (one byte per state)."""
    data = np.ascontiguousarray(np.asarray(allowed, dtype=bool))
    return hashlib.sha256(data.view(np.uint8)).hexdigest()


# --- validation of what is read ----------------------------------------------------------


def _check_variable(where, ds, name, dims, kind):
    var = ds[name]
    if format_of(ds) == "sesp.sweep":  # swept parameters come first
        dims = var.dims[: var.ndim - len(dims)] + dims
    if var.dims != dims:
        raise SespFileError(f"{where}: variable {name!r} has dims {var.dims}, expected {dims}")
    if var.dtype.kind != kind:
        raise SespFileError(f"{where}: variable {name!r} has dtype {var.dtype}, expected kind {kind!r}")


def _check_field(where, ds: xr.Dataset):
    for dim, key in (("x", "nx"), ("y", "ny"), ("phi", "nphi")):
        if key not in ds.attrs or ds.sizes.get(dim) != int(ds.attrs[key]):
            raise SespFileError(f"{where}: size of {dim} does not match attribute {key}")
    for key, actual in (("allowed_sha256", field_sha256(ds.allowed.values)), ("coords_sha256", coords_sha256(ds))):
        expected = ds.attrs.get(key)
        if expected is None:
            raise SespFileError(f"{where}: attribute {key} is missing: the field cannot be checked (file altered?)")
        if actual != expected:
            raise SespFileError(
                f"{where}: the field or its coordinates do not match their recorded SHA-256, {key} (file altered?)"
            )


def validate(ds: xr.Dataset, where="<dataset>") -> xr.Dataset:
    """Check that ``ds`` is a well-formed sesp dataset; raise SespFileError if not."""
    kind = format_of(ds)
    if kind not in REQUIRED:
        raise SespFileError(f"{where}: not a sesp dataset (attribute sesp_format is {kind!r})")
    version = ds.attrs.get("sesp_format_version")
    if isinstance(version, bool) or not isinstance(version, (int, np.integer)) or version != FORMAT_VERSION:
        raise SespFileError(
            f"{where}: sesp_format_version {version if version is None else str(version)} is not the version"
            f" this sesp reads ({FORMAT_VERSION})"
        )
    for name, (dims, dtype_kind) in REQUIRED[kind].items():
        if name not in ds:
            raise SespFileError(f"{where}: missing variable {name!r} required in a {kind} file")
        _check_variable(where, ds, name, dims, dtype_kind)
    for name, (dims, dtype_kind) in OPTIONAL.items():
        if name in ds:
            _check_variable(where, ds, name, dims, dtype_kind)
    if "allowed" in ds and ds.allowed.dims == FIELD_DIMS and kind in ("sesp.scan", "sesp.point"):
        _check_field(where, ds)
    return ds
