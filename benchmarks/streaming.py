"""Target 4: streaming reductions of a grid larger than memory.

Reduces a 2048 x 2048 x 1024 grid (4.3e9 states; the full field would take
4.3 GB as booleans, 8.6 GB as counts) to A_ex(φ), allowed fraction, class
maps (with the entangled test) and excluded components, chunk by chunk, and
reports wall time and peak memory (target: peak < 2 GB).

    python benchmarks/streaming.py [--nx 2048] [--nphi 1024]
"""

import argparse
import math
import time

from _common import machine, peak_rss_mib, table

from sesp import Grid, SeSP
from sesp.regions import summarize
from sesp.topology import lattice_components


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--nx", type=int, default=2048)
    ap.add_argument("--nphi", type=int, default=1024)
    args = ap.parse_args()
    particle = SeSP(n=2, opening=math.pi / 2)
    summarize(particle, Grid(16, nphi=2))  # compile
    grid = Grid(args.nx, nphi=args.nphi)
    t0 = time.perf_counter()
    s = summarize(particle, grid)
    t_scan = time.perf_counter() - t0
    comps = lattice_components(s)
    wall = time.perf_counter() - t0
    peak = peak_rss_mib()
    print(f"machine: {machine()}\n")
    table(
        [
            [
                f"{args.nx}x{args.nx}x{args.nphi}",
                f"{grid.states:.3g}",
                f"{grid.states / 2**30:.1f}",
                f"{t_scan:.1f}",
                f"{wall:.1f}",
                f"{peak:.0f}",
                comps.count,
            ]
        ],
        ["grid", "states", "field GiB (bool)", "scan+reduce s", "with components s", "peak MiB", "components"],
    )
    print(f"\nA_ex = {float(s.excluded_area.mean()):.6f} b^2")
    print(f"target 4  peak memory < 2 GB: {peak:.0f} MiB  {'met' if peak < 2000 else 'NOT met'}")


if __name__ == "__main__":
    main()
