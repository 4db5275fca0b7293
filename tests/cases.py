"""Shared test cases: particles, small sweep files and helpers that several test modules use."""

import math
import os
from pathlib import Path

import numpy as np

from sesp import Polyline, SeSP
from sesp.orientations import blocked_orientations

ROOT = Path(__file__).resolve().parents[1]

# SESP_FULL_TESTS=1: every test at full strength (the variants marked `full`, the fault tests' full counts).
FULL = bool(os.environ.get("SESP_FULL_TESTS"))

STAPLE = Polyline([[0.5, 1.0], [-0.5, 1.0], [-0.5, -1.0], [0.5, -1.0]])
ZED = Polyline([[-0.6, 0.8], [0.4, 0.8], [-0.4, -0.8], [0.6, -0.8]])
NEEDLE = Polyline([[-1.0, 0.0], [1.0, 0.0]])

# Polylines of several kinds (SeSPs convex and not, closed, staples) for kernel comparisons.
SHAPES = [
    SeSP(n=2, opening=math.pi / 2).polyline(24),
    SeSP(n=8, opening=1.0).polyline(31),
    SeSP(n=0.6, aspect=1.7, opening=2.5).polyline(20),
    SeSP(n=4).polyline(16),
    STAPLE,
    ZED,
]

# A sweep small enough for unit tests: 8 points of 24² × 16 states, A_ex to 1e-3; {out} is the output folder.
SMALL = """
[sweep]
name = "small"
output = "{out}"
angles = "degrees"

[particle]
n = [2, 8]
opening = {{ start = 30, stop = 120, step = 30 }}
segments = 24

[grid]
nx = 24
nphi = 16

[output]
keep = ["excluded_area", "classes"]
rtol = 1e-3
"""


def write_sweep(folder: Path, text: str, name: str = "s.toml") -> Path:
    """Write a sweep file into ``folder`` and return its path."""
    path = folder / name
    path.write_text(text)
    return path


def point_files(folder: Path) -> list:
    """The point files of a sweep output folder (16-hex-digit names)."""
    return sorted(p for p in folder.glob("*.nc") if len(p.stem) == 16)


def interval_disagreements(particle, other, ds, segments) -> int:
    """States of the direct scan ``ds`` whose allowed flag disagrees with the exact blocked φ intervals."""
    disagree = 0
    phi = ds.phi.values[:, None]
    for iy, y in enumerate(ds.y.values):
        for ix, x in enumerate(ds.x.values):
            spans = blocked_orientations(particle, x, y, other=other, segments=segments)
            blocked = ((spans[:, 0] <= phi + 1e-12) & (phi <= spans[:, 1] + 1e-12)).any(axis=1)
            disagree += int(np.count_nonzero(blocked == ds.allowed.values[:, iy, ix]))
    return disagree


def content_digest(path) -> str:
    """SHA-256 of a netCDF file's contents: every variable's name, dims, dtype, bytes and attributes, and the
    global attributes, leaving out those that record when and how the file was made (``history``, ...)."""
    import hashlib

    import xarray as xr

    from sesp.dataset import PROVENANCE

    digest = hashlib.sha256()
    with xr.open_dataset(path) as ds:
        for name in sorted(ds.variables):
            var = ds.variables[name]
            digest.update(f"{name}{var.dims}{var.dtype}{sorted(var.attrs.items())!r}".encode())
            digest.update(np.ascontiguousarray(var.values).tobytes())
        attrs = {k: v for k, v in ds.attrs.items() if k not in PROVENANCE}
        digest.update(repr(sorted((k, repr(v)) for k, v in attrs.items())).encode())
    return digest.hexdigest()
