"""Issue 3's transition table from the symmetry axis, exact in φ, on even and odd axis samplings.

For n = 2, 4, 8 (A = 1, N = 256) the excluded set's half-thickness along the
symmetry axis is measured at every ``--step`` degrees of Ψ with
:func:`sesp.topology.axis_profile` (no orientation grid; thickness searched
down to 1e-9 b), on 512 and 513 axis nodes; each change of the count of axis
components is bisected to ±0.02 rad. The table puts the two samplings side by
side: "same" when the brackets are identical. "shortest" is the shortest
counted component at the bracket's ends in axis nodes (below 4: near the
sampling's reach).

    python benchmarks/axis_transitions.py [--step 10] [--from 0] [--top 200] [--n 2 4 8]

A change and its reversal inside one step are not seen; ``--from 150 --step 1``
looks for them where the components close up.
"""

import argparse
import math
import time

from _common import machine, table

from sesp import SeSP
from sesp.topology import axis_transitions


def degrees(t):
    return f"{math.degrees(t.low):.2f}-{math.degrees(t.high):.2f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--step", type=float, default=10.0, help="degrees")
    ap.add_argument("--from", dest="bottom", type=float, default=0.0, help="smallest opening, degrees")
    ap.add_argument("--top", type=float, default=200.0, help="largest opening, degrees")
    ap.add_argument("--n", type=float, nargs="+", default=[2, 4, 8], help="degrees n = m of the families")
    args = ap.parse_args()
    samplings = (512, 513)
    print(f"machine: {machine()}")
    print(f"openings {args.bottom:g}..{args.top:g} deg every {args.step:g} deg, bisected to +-0.02 rad; N = 256\n")
    same_all = True
    for n in args.n:
        rows = []
        t0 = time.perf_counter()
        found = {
            k: axis_transitions(
                SeSP(n=n, m=n),
                (math.radians(args.bottom), math.radians(args.top)),
                nodes=k,
                step=math.radians(args.step),
            )
            for k in samplings
        }
        seconds = time.perf_counter() - t0
        lists = [next(iter(found[k].transitions.values())) for k in samplings]
        counts_equal = bool((found[512].counts == found[513].counts).all())
        for i in range(max(len(v) for v in lists)):
            a, b = (v[i] if i < len(v) else None for v in lists)
            same = (
                a is not None
                and b is not None
                and (a.low, a.high, a.count_low, a.count_high) == (b.low, b.high, b.count_low, b.count_high)
            )
            same_all &= same

            def cell(t):
                return "-" if t is None else f"{t.count_low} -> {t.count_high} at {degrees(t)}"

            def short(t):
                return "-" if t is None else f"{t.thinnest:.0f}"

            rows.append((n, cell(a), short(a), cell(b), short(b), "same" if same else "DIFFER"))
        rows.append(
            (
                n,
                f"counts on the {args.step:g} deg scan equal: {'yes' if counts_equal else 'NO'}",
                "",
                "",
                "",
                f"{seconds:.0f} s",
            )
        )
        table(rows, ("n", "512 axis nodes (deg)", "shortest", "513 axis nodes (deg)", "shortest", ""))
    print(f"\nall brackets identical on 512 and 513 axis nodes: {'yes' if same_all else 'no'}")


if __name__ == "__main__":
    main()
