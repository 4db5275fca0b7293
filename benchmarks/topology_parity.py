"""Issue 3's parity check: excluded-component counts and transitions on even vs odd grids.

For n = 2, 4, 8 (ASP family, A = 1, N = 256) the excluded positions are counted
every ``--step`` degrees of Ψ on nx = 256 and nx = 257 (nphi = 1024), and the
count changes are bisected to ±0.02 rad on each grid. The table lists every
opening where the counts differ with the thinnest counted component (inscribed
radius in node spacings), then the transitions of both grids side by side with
their ``resolved`` flag (thinnest component >= RESOLVED_PEAK nodes).

    python benchmarks/topology_parity.py [--step 5] [--nphi 1024]
"""

import argparse
import math
import time

from _common import machine, table

from sesp import Grid, SeSP
from sesp.topology import RESOLVED_PEAK, find_transitions


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--step", type=float, default=5.0, help="degrees")
    ap.add_argument("--nphi", type=int, default=1024)
    ap.add_argument("--top", type=float, default=190.0, help="largest opening, degrees")
    args = ap.parse_args()
    grids = (256, 257)
    print(f"machine: {machine()}")
    print(
        f"openings 0..{args.top:g} deg every {args.step:g} deg; nphi = {args.nphi}; N = 256; "
        f"resolved: thinnest component >= {RESOLVED_PEAK:g} nodes\n"
    )
    summary = []
    for n in (2, 4, 8):
        t0 = time.perf_counter()
        results = {
            nx: find_transitions(
                SeSP(n=n),
                "excluded",
                (0.0, math.radians(args.top)),
                grid=Grid(nx, nphi=args.nphi),
                step=math.radians(args.step),
                refine_factor=1,
            )
            for nx in grids
        }
        seconds = time.perf_counter() - t0
        a, b = (results[nx] for nx in grids)
        rows = []
        for k, opening in enumerate(a.openings):
            if a.counts[k] != b.counts[k]:
                rows.append(
                    [
                        f"{math.degrees(opening):.1f}",
                        a.counts[k],
                        b.counts[k],
                        f"{a.thinnest[k]:.1f}",
                        f"{b.thinnest[k]:.1f}",
                    ]
                )
        same = int((a.counts == b.counts).sum())
        print(f"n = {n}: counts equal at {same} of {len(a.openings)} openings ({seconds:.0f} s)")
        if rows:
            table(rows, ["Psi (deg)", "count 256", "count 257", "thinnest 256", "thinnest 257"])
        rows = []
        for nx in grids:
            for t in results[nx].transitions[(nx, nx, args.nphi)]:
                rows.append(
                    [
                        nx,
                        f"{t.count_low} -> {t.count_high}",
                        f"{math.degrees(t.low):.2f}",
                        f"{math.degrees(t.high):.2f}",
                        f"{t.thinnest:.1f}",
                        "yes" if t.resolved else "no",
                    ]
                )
        table(rows, ["nx", "change", "from (deg)", "to (deg)", "thinnest", "resolved"])
        resolved = {
            nx: [
                (t.count_low, t.count_high, round(t.low, 6), round(t.high, 6))
                for t in results[nx].transitions[(nx, nx, args.nphi)]
                if t.resolved
            ]
            for nx in grids
        }
        summary.append([n, len(resolved[256]), len(resolved[257]), "yes" if resolved[256] == resolved[257] else "no"])
        print()
    table(summary, ["n", "resolved transitions 256", "resolved 257", "identical brackets"])


if __name__ == "__main__":
    main()
