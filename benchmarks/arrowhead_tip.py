"""Where the n = 4 arrowhead parts, from a brute-force exact-in-φ raster around its tip.

Near Ψ = 174.7° the excluded body of n = 4 is an arrowhead: two crescents
off the axis whose thin horns meet a small tip on the axis at x ≈ -0.43 b.
For each opening this samples the widest window W (exact in φ) on square
cells of side ``--cell`` over the box x in [-0.437, -0.428] b, y in
[-0.004, 0] b (the lower half: the set is mirror-symmetric about y = 0) and
prints:

* ``axis``: the excluded run along the axis (y = 0) in the box, if any:
  the tip;
* ``joined``: whether the tip is four-connected, through W = 0 cells, to
  the box's left or bottom edge, where the lower crescent enters the box;
* ``neck``: the narrowest part of the way between them, as the largest r
  such that the cells at least r (b) inside the set still join the tip to
  that edge (a half-width, to about one cell);
* ``area``: of the W = 0 cells in the box (b²).

    python benchmarks/arrowhead_tip.py [--openings 174.6875 174.7 ...] [--cell 1e-5]

No adaptive map is involved: it is the check the maps are held to.
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table
from scipy import ndimage

from sesp import SeSP
from sesp.orientations import widest_window

BOX = (-0.437, -0.428, -0.004, 0.0)  # b: xmin, xmax, ymin, ymax


def raster(degrees, cell):
    """(x, y, excluded) on the box: W = 0 at each cell centre."""
    xmin, xmax, ymin, ymax = BOX
    x = np.arange(xmin, xmax + cell / 2, cell)
    y = np.arange(ymax, ymin - cell / 2, -cell)[::-1]  # the last row is the axis, y = 0
    width, _ = widest_window(SeSP(n=4, opening=math.radians(degrees)), *np.meshgrid(x, y))
    return x, y, width == 0


def joins(deep, tip, edge):
    """Whether a four-connected part of ``deep`` holds a node of ``tip`` and one of ``edge``."""
    labels, _ = ndimage.label(deep)
    return bool(set(labels[tip & deep].tolist()) & set(labels[edge & deep].tolist()) - {0})


def neck(excluded, cell):
    """(joined, half-width of the narrowest part of the way from the tip to the left or bottom edge, b)."""
    tip = np.zeros_like(excluded)
    tip[-1] = excluded[-1]
    edge = np.zeros_like(excluded)
    edge[0], edge[:, 0] = excluded[0], excluded[:, 0]
    if not tip.any() or not joins(excluded, tip, edge):
        return False, 0.0
    depth = ndimage.distance_transform_edt(excluded) * cell
    low, high = 0.0, float(depth.max())
    for _ in range(40):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if joins(depth >= middle, tip, edge) else (low, middle)
    return True, low


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--openings", type=float, nargs="+",
                        default=[174.625, 174.6875, 174.7, 174.71, 174.72, 174.73, 174.75])  # fmt: skip
    parser.add_argument("--cell", type=float, default=1e-5)
    args = parser.parse_args()
    print(machine())
    print(f"box x {BOX[0]}..{BOX[1]} b, y {BOX[2]}..{BOX[3]} b, cells {args.cell:g} b")
    rows = []
    for degrees in args.openings:
        t0 = time.perf_counter()
        x, _, excluded = raster(degrees, args.cell)
        on_axis = x[excluded[-1]]
        joined, half_width = neck(excluded, args.cell)
        axis = f"{on_axis.min():.5f}..{on_axis.max():.5f}" if len(on_axis) else "-"
        rows.append((degrees, axis, "yes" if joined else "no", f"{half_width:.2g}" if joined else "-",
                     f"{excluded.sum() * args.cell**2:.3g}", f"{time.perf_counter() - t0:.0f} s"))  # fmt: skip
    table(rows, ["opening (deg)", "axis (b)", "joined", "neck (b)", "area (b^2)", "time"])


if __name__ == "__main__":
    main()
