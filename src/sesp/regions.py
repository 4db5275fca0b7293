"""Position classes: free, spooning, entangled, excluded (DESIGN.md §3).

Per position (x, y) of particle 2's centre, over all orientations φ:

* ``excluded``: no orientation allowed;
* ``free``: every orientation allowed;
* ``entangled``: some allowed orientation is mutually entangled (each curve
  meets the other's filled convex hull while the curves do not meet);
* ``spooning``: some but not all orientations allowed, none entangled.

``free`` takes precedence over ``entangled``: a position where every
orientation is allowed is free even if some of them entangle.

Everything here is a per-position reduction over φ, so it can be computed
chunk by chunk (:func:`summarize`) without holding the (phi, y, x) field.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .grid import Grid
from .shape import DEFAULT_SEGMENTS

__all__ = ["CLASSES", "classify", "position_summary", "summarize", "allowed_orientations", "blocked_orientations"]

# Gaps between blocked-orientation intervals narrower than this (radians)
# are rounding at shared end points, not allowed orientations.
ANGLE_GAP = 1e-9
# Width (b) by which the pair screen of the exact orientation kernel is widened.
SCREEN_SLACK = 1e-9

CLASSES = ("free", "spooning", "entangled", "excluded")
FREE, SPOONING, ENTANGLED, EXCLUDED = range(4)


class _Accumulator:
    """Running per-position sums over orientation chunks."""

    def __init__(self, phi, ny, nx, with_entangled):
        self.phi = np.asarray(phi)
        self.count = np.zeros((ny, nx), dtype=np.int64)
        self.cos = np.zeros((ny, nx))
        self.sin = np.zeros((ny, nx))
        self.tangled = np.zeros((ny, nx), dtype=bool) if with_entangled else None
        self.excluded_per_phi = np.zeros(len(self.phi), dtype=np.int64)

    def add(self, k0, allowed, entangled=None):
        """Fold in orientations k0 .. k0 + len(allowed) - 1 (serially: deterministic)."""
        phi = self.phi[k0 : k0 + allowed.shape[0]]
        self.count += np.count_nonzero(allowed, axis=0)
        # one orientation at a time, in order: no BLAS, so sums do not depend on threads
        for k, angle in enumerate(phi):
            self.cos[allowed[k]] += math.cos(angle)
            self.sin[allowed[k]] += math.sin(angle)
        self.excluded_per_phi[k0 : k0 + allowed.shape[0]] = allowed[0].size - np.count_nonzero(allowed, axis=(1, 2))
        if self.tangled is not None and entangled is not None:
            self.tangled |= entangled.any(axis=0)

    def classes(self):
        nphi = len(self.phi)
        out = np.full(self.count.shape, SPOONING, dtype=np.int8)
        if self.tangled is not None:
            out[self.tangled] = ENTANGLED
        out[self.count == nphi] = FREE
        out[self.count == 0] = EXCLUDED
        return out

    def dataset(self, x, y, attrs) -> xr.Dataset:
        nphi = len(self.phi)
        strength = np.where(self.count > 0, np.hypot(self.sin, self.cos) / np.maximum(self.count, 1), np.nan)
        # A vanishing resultant (e.g. every φ allowed) has no direction.
        defined = strength > 1e-9
        mean = np.where(defined, np.mod(np.arctan2(self.sin, self.cos), 2 * math.pi), np.nan)
        dims = ("y", "x")
        cell = float(x[1] - x[0]) * float(y[1] - y[0])
        data = {
            "allowed_fraction": (
                dims,
                self.count / nphi,
                {"units": "1", "long_name": "fraction of orientations allowed"},
            ),
            "mean_orientation": (
                dims,
                mean,
                {"units": "rad", "long_name": "circular mean of allowed φ (NaN: none or no direction)"},
            ),
            "orientation_order": (dims, strength, {"units": "1", "long_name": "mean resultant length of allowed φ"}),
            "excluded_area": (("phi",), self.excluded_per_phi * cell, {"units": "b^2", "long_name": "A_ex(φ)"}),
        }
        flags = _flag_attrs() if self.tangled is not None else {**_flag_attrs(), "comment": "entangled not computed"}
        data["classes"] = (dims, self.classes(), flags)
        coords = {
            "y": ("y", y, {"units": "b"}),
            "x": ("x", x, {"units": "b"}),
            "phi": ("phi", self.phi, {"units": "rad"}),
        }
        summary_attrs = {k: v for k, v in attrs.items() if k != "allowed_sha256"}
        summary_attrs["sesp_format"] = "sesp.summary"
        return xr.Dataset(data, coords=coords, attrs=summary_attrs)


def _flag_attrs() -> dict:
    return {
        "flag_values": np.arange(len(CLASSES), dtype=np.int8),
        "flag_meanings": " ".join(CLASSES),
        "long_name": "position class",
    }


def position_summary(ds: xr.Dataset) -> xr.Dataset:
    """Per-position reductions of a scan held in memory.

    Returns
    -------
    xarray.Dataset
        Over (y, x): ``allowed_fraction``, ``mean_orientation`` (circular mean
        of allowed φ, rad; NaN where none), ``orientation_order`` (mean
        resultant length, 0..1), ``classes`` (int8 with CF ``flag_values`` /
        ``flag_meanings``); over phi: ``excluded_area`` A_ex(φ), b².
        Positions can be ``entangled`` only if the scan has the ``entangled``
        field; otherwise they are ``spooning``.
    """
    acc = _Accumulator(ds.phi.values, ds.sizes["y"], ds.sizes["x"], "entangled" in ds)
    acc.add(0, ds.allowed.values, ds.entangled.values if "entangled" in ds else None)
    return acc.dataset(ds.x.values, ds.y.values, ds.attrs)


def classify(ds: xr.Dataset) -> xr.DataArray:
    """Position classes (y, x): 0 free, 1 spooning, 2 entangled, 3 excluded.

    ``ds`` is a scan (with the ``entangled`` field for the entangled class)
    or a summary from :func:`summarize`.

    Examples
    --------
    >>> from sesp import SeSP, Grid, scan
    >>> ds = scan(SeSP(n=2, opening=1.0), Grid(32, nphi=16), segments=32, entangled=True)
    >>> classify(ds).attrs["flag_meanings"]
    'free spooning entangled excluded'
    """
    if "classes" in ds:
        return ds.classes
    return position_summary(ds).classes


def summarize(
    particle,
    grid: Grid | None = None,
    *,
    other=None,
    segments: int = DEFAULT_SEGMENTS,
    entangled: bool = True,
    chunk: int | None = None,
    progress: bool = False,
) -> xr.Dataset:
    """Scan and reduce over φ chunk by chunk, never holding the (phi, y, x) field.

    Same result as ``position_summary(scan(...))`` with memory
    O(nx · ny · chunk) instead of O(nx · ny · nphi), so grids larger than
    memory can be reduced.

    Parameters
    ----------
    particle, grid, other, segments
        As in :func:`sesp.scan`.
    entangled : bool
        Compute the entanglement test (needed for the ``entangled`` class).
    chunk : int, optional
        Orientations per chunk; by default about 128 MiB of working memory.
    """
    from .scan import iter_slices, prepare

    setup = prepare(particle, grid, other=other, segments=segments)
    g = setup.grid
    acc = _Accumulator(g.phi, g.ny, g.nx, entangled)
    for part in iter_slices(setup, entangled=entangled, chunk=chunk, progress=progress):
        acc.add(part.k0, part.allowed, part.entangled)
    return acc.dataset(g.x, g.y, setup.attrs())


def _vertices(particle, other, segments):
    """The pair's polyline vertices, as the exact orientation kernels take them."""
    from .scan import _curves

    return tuple(np.ascontiguousarray(curve.vertices) for curve in _curves(particle, other, segments))


def blocked_orientations(particle, x: float, y: float, *, other=None, segments: int = DEFAULT_SEGMENTS):
    """The orientations φ at which particle 2, centred at (x, y), meets particle 1: exact in φ.

    No orientation grid: for every pair of segments the set of φ where they
    meet is bounded by roots of sinusoids in φ, found in closed form, so the
    result is exact for the two polylines up to rounding.

    Returns
    -------
    (k, 2) ndarray
        Sorted, possibly overlapping intervals [start, end] of φ in [0, 2π], radians.
    """
    from . import _kernels

    v1, v2 = _vertices(particle, other, segments)
    starts, ends = _kernels.blocked_angles(v1, v2, float(x), float(y), SCREEN_SLACK)
    return np.column_stack([starts, ends])


def allowed_orientations(particle, x, y, *, other=None, segments: int = DEFAULT_SEGMENTS) -> np.ndarray:
    """Measure of the allowed orientations at each position, exact in φ (radians, 0 to 2π).

    A position is excluded exactly when the result is 0. Unlike a scan this
    samples no orientations, so no narrow allowed interval of φ is missed;
    gaps narrower than ``ANGLE_GAP`` (1e-9 rad) between blocked intervals
    count as closed. Cost: a few thousand segment pairs per position.

    Parameters
    ----------
    particle, other, segments
        As in :func:`sesp.scan`.
    x, y : array_like
        Positions of particle 2's centre, in b; broadcast together.
    """
    from . import _kernels

    v1, v2 = _vertices(particle, other, segments)
    xs, ys = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    out = np.empty(xs.size)
    _kernels.allowed_angle_at(
        v1,
        v2,
        xs.ravel().copy(),
        ys.ravel().copy(),  # owned, writeable copies
        SCREEN_SLACK,
        ANGLE_GAP,
        out,
    )
    return out.reshape(xs.shape)
