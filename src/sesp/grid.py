"""The regular (x, y, φ) grid of pair states.

Nodes are cell centres of a square box [-L, L]² with ``nx × ny`` cells, and
``nphi`` equally spaced orientations φ_k = 2πk / nphi. Lengths in units of b.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace

import numpy as np

from .checks import MAX_LENGTH, check_count, check_range

__all__ = ["Grid", "available_memory"]

MAX_CELLS_PER_AXIS = 1 << 16

# Bytes per state of each stored field.
FIELD_BYTES = {"allowed": 1, "crossings": 2, "entangled": 1}


def available_memory() -> int:
    """Bytes of physical memory currently available (a conservative reading)."""
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return 8 << 30


@dataclass(frozen=True)
class Grid:
    """Resolution and extent of a scan.

    Parameters
    ----------
    nx : int
        Cells along x, >= 3.
    ny : int, optional
        Cells along y, >= 3; defaults to ``nx``.
    nphi : int
        Orientations, >= 1; φ_k = 2πk / nphi.
    half_width : float, optional
        Half-width L of the square box, in units of b. By default it is set
        from the particles: r₁ + r₂ plus one cell, where r is the largest
        distance of a particle point from its centre. Two particles further
        apart than r₁ + r₂ cannot meet, so the default box truncates nothing.

    Examples
    --------
    >>> from sesp import Grid
    >>> Grid(64, nphi=32).resolve(2.0).x[:2]
    array([-2.03225806, -1.96774194])
    """

    nx: int = 256
    ny: int | None = None
    nphi: int = 128
    half_width: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "nx", check_count("nx", self.nx, 3, MAX_CELLS_PER_AXIS))
        ny = self.nx if self.ny is None else check_count("ny", self.ny, 3, MAX_CELLS_PER_AXIS)
        object.__setattr__(self, "ny", ny)
        object.__setattr__(self, "nphi", check_count("nphi", self.nphi, 1, MAX_CELLS_PER_AXIS))
        if self.half_width is not None:
            object.__setattr__(self, "half_width", check_range("half_width", self.half_width, 1e-9, MAX_LENGTH, " b"))

    @property
    def states(self) -> int:
        """Number of (x, y, φ) states."""
        return self.nx * self.ny * self.nphi

    def nbytes(self, fields=("allowed",)) -> int:
        """Memory, in bytes, of the stored fields over the whole grid."""
        return self.states * sum(FIELD_BYTES[f] for f in fields)

    def check_memory(self, fields=("allowed",), limit: int | None = None, working: int = 0) -> None:
        """Raise ``MemoryError`` before allocation if the fields and ``working`` bytes would not fit.

        ``limit`` defaults to half the memory available now; ``working`` is
        what a pass holds besides the stored fields (:func:`sesp.field.working_bytes`).
        """
        limit = available_memory() // 2 if limit is None else int(limit)
        stored = self.nbytes(fields)
        if stored + working > limit:
            what = f"{stored / 2**30:.2f} GiB for {', '.join(fields)} and " if fields else ""
            raise MemoryError(
                f"grid nx={self.nx}, ny={self.ny}, nphi={self.nphi} needs {what}{working / 2**30:.2f} GiB of "
                f"working buffers, over the memory limit of {limit / 2**30:.2f} GiB: "
                "use fewer cells or orientations, or a streaming reduction"
            )

    def resolve(self, reach: float) -> Grid:
        """This grid with its box set: ``half_width`` = reach + one cell, if unset.

        ``reach`` is r₁ + r₂ in units of b.
        """
        if self.half_width is not None:
            return self
        cells = min(self.nx, self.ny)
        # L = reach + 2L / cells  =>  L = reach * cells / (cells - 2)
        return replace(self, half_width=float(reach) * cells / (cells - 2))

    def _require_box(self):
        if self.half_width is None:
            raise ValueError("the grid's half_width is not set: call resolve(reach) first")

    @property
    def dx(self) -> float:
        """Cell width along x, in units of b."""
        self._require_box()
        return 2.0 * self.half_width / self.nx

    @property
    def dy(self) -> float:
        """Cell height along y, in units of b."""
        self._require_box()
        return 2.0 * self.half_width / self.ny

    @property
    def x(self) -> np.ndarray:
        """(nx,) ndarray: cell-centre x coordinates; exactly symmetric about 0."""
        return (np.arange(self.nx) - (self.nx - 1) / 2) * self.dx

    @property
    def y(self) -> np.ndarray:
        """(ny,) ndarray: cell-centre y coordinates; exactly symmetric about 0."""
        return (np.arange(self.ny) - (self.ny - 1) / 2) * self.dy

    @property
    def phi(self) -> np.ndarray:
        """(nphi,) ndarray: orientations 2πk / nphi, radians."""
        return 2.0 * np.pi * np.arange(self.nphi) / self.nphi

    def rotations(self) -> tuple[np.ndarray, np.ndarray]:
        """cos φ_k and sin φ_k, exact (0, ±1) at multiples of π/2."""
        return exact_cos_sin(np.arange(self.nphi), self.nphi)


def exact_cos_sin(k: np.ndarray, nphi: int) -> tuple[np.ndarray, np.ndarray]:
    """cos and sin of 2πk/nphi, with exact values at multiples of π/2.

    Exact rotations by π/2 keep parallel segments exactly parallel, so the
    degenerate pairs (docs/design.md, engines) are seen as such by both engines; and
    cos(−φ) = cos φ, sin(−φ) = −sin φ hold exactly, so mirror-symmetric
    particles give exactly mirror-symmetric fields.
    """
    k = np.asarray(k)
    # angles past π are mirrored from below π, so R(−φ) is exactly R(φ) mirrored
    upper = 2 * k > nphi
    folded = np.where(upper, nphi - k, k)
    angle = 2.0 * np.pi * folded / nphi
    c, s = np.cos(angle), np.where(upper, -1.0, 1.0) * np.sin(angle)
    quarter = (4 * k) % nphi == 0
    q = (4 * k[quarter]) // nphi % 4
    c[quarter] = np.array([1.0, 0.0, -1.0, 0.0])[q]
    s[quarter] = np.array([0.0, 1.0, 0.0, -1.0])[q]
    return c, s
