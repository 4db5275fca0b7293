"""Streaming reductions over the field of allowed states.

The field (phi, y, x) is produced chunk by chunk over φ
(:func:`sesp.field.iter_slices`); a reduction sees every chunk once, in
order, and keeps only what it needs. :func:`sesp.field.reduce` drives any
number of reductions from one pass, so a scan, a summary and an analysis
never compute the field twice, and a new reduction over the field is one
class:

.. code-block:: python

    class MyReduction(Reduction):
        fields = ("allowed",)            # what each chunk must carry
        def start(self, pair, grid): ... # allocate
        def add(self, part): ...         # fold in part.allowed[k] for k in part.k0..part.k1-1
        def finish(self): return {"name": (dims, array, attrs)}

Chunks may arrive out of order in φ (mirror images follow the computed
slices); every reduction here indexes by ``part.k0``, so its result does not
depend on the order or the chunk size, and it folds serially, so it does
not depend on the thread count either.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from .dataset import LONG_NAMES, coords_sha256, field_sha256
from .units import quantity

__all__ = ["Reduction", "StoredField", "ExcludedAreaByPhi", "EntangledAreaByPhi", "FIELDS"]

FIELDS = ("allowed", "crossings", "entangled")
_DTYPES = {"allowed": bool, "crossings": np.uint16, "entangled": bool}


class Reduction:
    """One pass over the orientation chunks of a field (see the module notes)."""

    fields: tuple = ("allowed",)

    def start(self, pair, grid) -> None:
        """Prepare for the pass over ``grid`` (box resolved) for ``pair``."""

    def add(self, part) -> None:
        """Fold in one chunk: ``part.allowed`` etc. shaped (k1 - k0, ny, nx)."""
        raise NotImplementedError

    def finish(self) -> dict:
        """Variables of the result: name -> (dims, array, attrs)."""
        raise NotImplementedError

    def attrs(self) -> dict:
        """Dataset attributes this reduction adds (default none)."""
        return {}


class StoredField(Reduction):
    """Keep the whole field: ``allowed`` and optionally ``crossings`` and ``entangled``."""

    def __init__(self, names=("allowed",)):
        unknown = [n for n in names if n not in FIELDS]
        if unknown or "allowed" not in names:
            raise ValueError(f"fields must include 'allowed' and be some of {FIELDS}, got {names}")
        self.fields = tuple(names)
        self.data = {}

    def start(self, pair, grid):
        self.grid = grid
        shape = (grid.nphi, grid.ny, grid.nx)
        self.data = {name: np.empty(shape, dtype=_DTYPES[name]) for name in self.fields}

    def add(self, part):
        for name, array in self.data.items():
            array[part.k0 : part.k1] = getattr(part, name)

    def finish(self):
        dims = ("phi", "y", "x")
        return {name: (dims, array, {"long_name": LONG_NAMES[name], "units": "1"}) for name, array in self.data.items()}

    def attrs(self):
        axes = {"x": xr.DataArray(self.grid.x), "y": xr.DataArray(self.grid.y), "phi": xr.DataArray(self.grid.phi)}
        return {"allowed_sha256": field_sha256(self.data["allowed"]), "coords_sha256": coords_sha256(axes)}


class ExcludedAreaByPhi(Reduction):
    """A_ex(φ) = (excluded nodes at φ) · dx · dy, in b²."""

    def start(self, pair, grid):
        self.cell = grid.dx * grid.dy
        self.excluded = np.zeros(grid.nphi, dtype=np.int64)

    def add(self, part):
        allowed = part.allowed
        self.excluded[part.k0 : part.k1] = allowed[0].size - np.count_nonzero(allowed, axis=(1, 2))

    def finish(self):
        attrs = quantity(2, "excluded area at fixed orientation A_ex(φ)")
        return {"excluded_area": (("phi",), self.excluded * self.cell, attrs)}


class EntangledAreaByPhi(Reduction):
    """A_ent(φ) = (entangled states at φ) · dx · dy, in b²: the area where particle 2 is allowed and entangled."""

    fields = ("allowed", "entangled")

    def start(self, pair, grid):
        self.cell = grid.dx * grid.dy
        self.count = np.zeros(grid.nphi, dtype=np.int64)

    def add(self, part):
        self.count[part.k0 : part.k1] = np.count_nonzero(part.entangled, axis=(1, 2))

    def finish(self):
        attrs = quantity(2, "entangled area at fixed orientation A_ent(φ)")
        return {"entangled_area": (("phi",), self.count * self.cell, attrs)}
