"""Position classes: free, spooning, entangled, excluded.

Per position (x, y) of particle 2's centre, over all orientations φ:

* ``excluded``: no orientation allowed;
* ``free``: every orientation allowed;
* ``entangled``: some allowed orientation is mutually entangled (each curve
  meets the other's filled convex hull while the curves do not meet);
* ``spooning``: some but not all orientations allowed, none entangled.

``free`` takes precedence over ``entangled``: a position where every
orientation is allowed is free even if some of them entangle.

Everything here is a per-position reduction over φ (:class:`PositionSummary`),
so it can be computed chunk by chunk (:func:`summarize`) without holding the
(phi, y, x) field.
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from .dataset import VERTEX_VARIABLES, coords, grid_of
from .field import Slices, reduce, resolve_grid
from .grid import Grid
from .pair import as_pair
from .reductions import ExcludedAreaByPhi, Reduction
from .shape import DEFAULT_SEGMENTS

__all__ = ["CLASSES", "PositionSummary", "classify", "position_summary", "summarize", "class_attrs"]

CLASSES = ("free", "spooning", "entangled", "excluded")
FREE, SPOONING, ENTANGLED, EXCLUDED = range(4)


def class_attrs() -> dict:
    """CF attributes of a ``classes`` variable."""
    return {
        "flag_values": np.arange(len(CLASSES), dtype=np.int8),
        "flag_meanings": " ".join(CLASSES),
        "long_name": "position class",
    }


class PositionSummary(Reduction):
    """Running per-position sums over orientation chunks: fractions, mean orientation, classes, A_ex(φ).

    With ``entangled`` False the entanglement test is not run and no position
    is ``entangled`` (they are ``spooning``).
    """

    def __init__(self, entangled: bool = True):
        self.entangled = bool(entangled)
        self.fields = ("allowed", "entangled") if entangled else ("allowed",)
        self.by_phi = ExcludedAreaByPhi()

    def start(self, pair, grid):
        self.phi = grid.phi
        self.count = np.zeros((grid.ny, grid.nx), dtype=np.int64)
        self.cos = np.zeros((grid.ny, grid.nx))
        self.sin = np.zeros((grid.ny, grid.nx))
        self.tangled = np.zeros((grid.ny, grid.nx), dtype=bool) if self.entangled else None
        self.by_phi.start(pair, grid)

    def add(self, part):
        """Fold in orientations part.k0 .. part.k1 - 1 (serially: deterministic)."""
        allowed = part.allowed
        self.count += np.count_nonzero(allowed, axis=0)
        # one orientation at a time, in order: no BLAS, so sums do not depend on threads
        for k, angle in enumerate(self.phi[part.k0 : part.k1]):
            self.cos[allowed[k]] += math.cos(angle)
            self.sin[allowed[k]] += math.sin(angle)
        self.by_phi.add(part)
        if self.tangled is not None and part.entangled is not None:
            self.tangled |= part.entangled.any(axis=0)

    def classes(self) -> np.ndarray:
        nphi = len(self.phi)
        out = np.full(self.count.shape, SPOONING, dtype=np.int8)
        if self.tangled is not None:
            out[self.tangled] = ENTANGLED
        out[self.count == nphi] = FREE
        out[self.count == 0] = EXCLUDED
        return out

    def finish(self):
        nphi = len(self.phi)
        strength = np.where(self.count > 0, np.hypot(self.sin, self.cos) / np.maximum(self.count, 1), np.nan)
        # A vanishing resultant (e.g. every φ allowed) has no direction.
        defined = strength > 1e-9
        mean = np.where(defined, np.mod(np.arctan2(self.sin, self.cos), 2 * math.pi), np.nan)
        dims = ("y", "x")
        flags = class_attrs() if self.entangled else {**class_attrs(), "comment": "entangled not computed"}
        return {
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
            **self.by_phi.finish(),
            "classes": (dims, self.classes(), flags),
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
    grid = grid_of(ds)
    summary = PositionSummary("entangled" in ds)
    summary.start(None, grid)
    tangled = ds.entangled.values if "entangled" in ds else None
    summary.add(Slices(0, grid.nphi, ds.allowed.values, None, tangled))
    attrs = {k: v for k, v in ds.attrs.items() if k not in ("allowed_sha256", "coords_sha256")}
    attrs["sesp_format"] = "sesp.summary"
    variables = summary.finish()
    variables.update({name: ds[name] for name in VERTEX_VARIABLES if name in ds})
    return xr.Dataset(variables, coords=coords(grid), attrs=attrs)


def classify(ds: xr.Dataset) -> xr.DataArray:
    """Position classes (y, x): 0 free, 1 spooning, 2 entangled, 3 excluded.

    ``ds`` is a scan (with the ``entangled`` field for the entangled class)
    or a summary from :func:`summarize`.

    Examples
    --------
    >>> from sesp import Grid, SeSP, classify, scan
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
        As in :func:`sesp.scan` (``particle`` may be a :class:`~sesp.Pair`).
    entangled : bool
        Compute the entanglement test (needed for the ``entangled`` class).
    chunk : int, optional
        Orientations per chunk; by default about 128 MiB of working memory.
    """
    pair = as_pair(particle, other, segments)
    grid = resolve_grid(pair, grid)
    return reduce(pair, grid, [PositionSummary(entangled)], kind="sesp.summary", chunk=chunk, progress=progress)
