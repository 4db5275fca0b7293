"""Where n = 4's tail parts from the body, exact in φ on the symmetry axis.

Below about 168° the excluded set of n = m = 4 (A = 1, N = 256) holds the
stretch of the axis left of the centre, from the tail's tip to the body,
whole. The tail parts from the body where an allowed gap opens in it. This
script samples that stretch (``--left`` to ``--right``, b) at ``--spacing``
and counts its excluded runs with :func:`sesp.orientations.allowed_orientations` (exact in
φ) over Ψ from ``--from`` to ``--top`` every ``--step`` degrees, then bisects
the first change to ``--tolerance`` degrees. The bracket is where a gap wider
than the spacing first opens on the axis: the break of the set in the plane
cannot come before it (the axis joins tail and body until then), and the
maps' components say whether it comes there, not later around a hole.

    python benchmarks/tail_break.py [--from 167] [--top 169] [--step 0.25] [--tolerance 0.001]
        [--left -0.6] [--right -0.02] [--spacing 1e-5]
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table

from sesp import SeSP
from sesp.orientations import allowed_orientations


def excluded_runs(degrees, xs):
    """(number of excluded runs, widest allowed gap between two of them, b) on the axis nodes ``xs``."""
    excluded = allowed_orientations(SeSP(n=4, opening=math.radians(degrees)), xs, 0.0) == 0
    edges = np.flatnonzero(np.diff(np.concatenate([[0], excluded.astype(np.int8), [0]]))).reshape(-1, 2)
    between = [xs[a] - xs[b - 1] for (_, b), (a, _) in zip(edges[:-1], edges[1:])]  # excluded node to node
    return len(edges), max(between, default=0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--from", dest="low", type=float, default=167.0)
    ap.add_argument("--top", type=float, default=169.0)
    ap.add_argument("--step", type=float, default=0.25)
    ap.add_argument("--tolerance", type=float, default=0.001)
    ap.add_argument("--left", type=float, default=-0.6)
    ap.add_argument("--right", type=float, default=-0.02)
    ap.add_argument("--spacing", type=float, default=1e-5)
    args = ap.parse_args()
    print(machine())
    xs = np.arange(args.left, args.right, args.spacing)
    print(f"n = m = 4, A = 1, N = 256; {len(xs)} axis nodes from {args.left:g} to {args.right:g} b, "
          f"{args.spacing:g} b apart")  # fmt: skip
    t0 = time.perf_counter()
    rows, found = [], None
    for degrees in np.arange(args.low, args.top + 1e-9, args.step):
        runs, gap = excluded_runs(degrees, xs)
        rows.append((f"{degrees:.3f}", runs, f"{gap:.2e}"))
        if found is None and rows[0][1] != runs:
            found = (degrees - args.step, degrees)
    table(rows, ["Psi (deg)", "excluded runs", "widest gap (b)"])
    if found is None:
        print("no change over the range")
        return
    low, high = found
    before = excluded_runs(low, xs)[0]
    while high - low > args.tolerance:
        mid = 0.5 * (low + high)
        low, high = (mid, high) if excluded_runs(mid, xs)[0] == before else (low, mid)
    runs, gap = excluded_runs(high, xs)
    print(f"first gap on the axis: Psi in [{low:.4f}, {high:.4f}] deg ({before} -> {runs} excluded runs; "
          f"widest gap {gap:.2e} b at {high:.4f} deg); {time.perf_counter() - t0:.0f} s")  # fmt: skip


if __name__ == "__main__":
    main()
