"""Raster vs direct engine: states per second, same particle and grid, one run.

N = 256 segments, ASP-like SeSP (n = 2, Ψ = π/2), 256 × 256 × 128 grid. The
raster engine fills the whole grid; the direct engine is timed on a few φ
slices of the same grid (it would take minutes for all of them) and checked
state for state against the raster engine's slices.

    python benchmarks/engines.py [--n 2] [--phi-direct 2]
"""

import argparse
import math

import numpy as np

from _common import best_of, machine, table
from sesp import Grid, SeSP, scan
from sesp.scan import TOUCH_TOLERANCE, _fill_counts, as_polyline


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=float, default=2.0)
    ap.add_argument("--segments", type=int, default=256)
    ap.add_argument("--nx", type=int, default=256)
    ap.add_argument("--nphi", type=int, default=128)
    ap.add_argument("--phi-direct", type=int, default=2, help="φ slices timed for the direct engine")
    args = ap.parse_args()

    particle = SeSP(n=args.n, opening=math.pi / 2)
    grid = Grid(args.nx, nphi=args.nphi)
    scan(particle, Grid(16, nphi=2), segments=args.segments)  # compile outside the timing
    scan(particle, Grid(16, nphi=2), segments=args.segments, engine="direct")

    t_raster, ds = best_of(lambda: scan(particle, grid, segments=args.segments))
    curve = as_polyline(particle, args.segments)
    resolved = grid.resolve(2 * curve.max_radius)
    delta = TOUCH_TOLERANCE * 2 * curve.max_radius
    k = args.phi_direct
    t_direct, counts = best_of(lambda: _fill_counts(curve, curve, resolved, 0, k, "direct", False, delta), repeat=1)
    assert np.array_equal(counts == 0, ds.allowed.values[:k]), "engines disagree"

    rate_raster = grid.states / t_raster
    rate_direct = k * grid.nx * grid.ny / t_direct
    print(f"machine: {machine()}")
    print(f"particle: SeSP n={args.n:g}, opening=90 deg, N={args.segments}; grid {args.nx}x{args.nx}x{args.nphi}\n")
    table(
        [
            ["raster", f"{grid.states}", f"{t_raster:.3f}", f"{rate_raster / 1e6:.2f}"],
            ["direct", f"{k * grid.nx * grid.ny} ({k} phi)", f"{t_direct:.3f}", f"{rate_direct / 1e6:.4f}"],
        ],
        ["engine", "states", "seconds", "Mstates/s"],
    )
    print(f"\nraster / direct states per second: {rate_raster / rate_direct:.0f}x (target >= 1000x)")
    print(f"raster full grid: {t_raster:.3f} s (target < 1 s): {'met' if t_raster < 1 else 'NOT met'}")
    print(f"raster throughput: {rate_raster / 1e6:.1f} Mstates/s (issue 6 target >= 50): "
          f"{'met' if rate_raster >= 50e6 else 'NOT met'}")
    print("direct slices identical to raster slices: yes")


if __name__ == "__main__":
    main()
