"""Why odd grids see the n = 8 body as two mirror lobes just below Ψ = π.

At Ψ = 178.75° (n = m = 8, A = 1, N = 256) the grid count (nphi = 1024) is 1
on 256² and 2 on 257²: only odd grids have a row of nodes on the symmetry
axis. This script maps the excluded set exactly in φ
(:func:`sesp.regions.allowed_orientations`) in a window around the lobes,
measures the allowed slit along the axis (its x extent, the φ measure it
admits, its half-thickness in y) and counts the window's 8-connected
excluded pieces: 1 means the two "lobes" are joined inside the window.

    python benchmarks/axis_slit.py [--degrees 178.75] [--n 8]
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table
from scipy import ndimage

from sesp import Grid, SeSP, allowed_orientations, summarize
from sesp.topology import excluded_components


def slit_half_thickness(particle, x, top=0.01, steps=30):
    """Largest y (b) with allowed φ at (x, y), by bisection below ``top`` (excluded there)."""
    low, high = 0.0, top
    for _ in range(steps):
        mid = 0.5 * (low + high)
        low, high = (mid, high) if allowed_orientations(particle, x, mid)[()] > 0 else (low, mid)
    return low


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--degrees", type=float, default=178.75, help="opening Ψ, degrees")
    ap.add_argument("--n", type=float, default=8.0, help="degree n = m")
    args = ap.parse_args()
    particle = SeSP(n=args.n, m=args.n, opening=math.radians(args.degrees))
    print(f"machine: {machine()}")
    print(f"n = m = {args.n:g}, opening {args.degrees:g} deg, N = 256\n")

    rows = []
    for nx in (256, 257):
        summary = summarize(particle, Grid(nx, nphi=1024), segments=256, entangled=False)
        found = excluded_components(summary)
        spacing = float(summary.x[1] - summary.x[0])
        rows.append((f"grid count {nx}^2", found.count, f"peaks {found.peaks.tolist()} nodes"))

    t0 = time.perf_counter()
    xs, ys = np.linspace(-0.8, -0.4, 101), np.linspace(-0.04, 0.04, 81)
    excluded = allowed_orientations(particle, *np.meshgrid(xs, ys)) == 0
    _, pieces = ndimage.label(excluded, structure=np.ones((3, 3)))
    rows.append(("exact map, window x -0.8..-0.4, y -0.04..0.04 (101 x 81)", pieces, "8-connected excluded pieces"))

    axis = allowed_orientations(particle, xs, 0.0)
    slit = xs[axis > 0]
    if len(slit):
        rows.append(
            (
                "allowed slit on the axis, x (b)",
                f"{slit.min():.3f} .. {slit.max():.3f}",
                f"phi measure {axis[axis > 0].min():.1e} .. {axis[axis > 0].max():.1e} rad",
            )
        )
        middle = float(np.median(slit))
        rows.append(
            (
                f"slit half-thickness at x = {middle:.3f} (b)",
                f"{slit_half_thickness(particle, middle):.1e}",
                f"grid node spacing {spacing:.1e}",
            )
        )
    rows.append(("exact map time (s)", f"{time.perf_counter() - t0:.0f}", ""))
    table(rows, ("quantity", "value", "note"))
    print("\nthe window, y >= 0 (# excluded):")
    for j in range(len(ys) // 2, len(ys), 4):
        print(f"{ys[j]:+.3f} " + "".join("#" if e else "." for e in excluded[j]))


if __name__ == "__main__":
    main()
