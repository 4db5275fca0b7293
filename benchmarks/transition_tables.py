"""Where the certified count of excluded components changes over Ψ, per n and base grid, with the time per n.

Every change is bracketed by bisection (``sesp.transitions``); the table
says, per n, whether the brackets, and the counts decided on each side of
them, are identical on every base grid given: for the certain changes (the
counts on the two sides have no value in common) and for all of them (also
where a count becomes undecided, which depends on the cells). It also says
whether the grids contradict each other: at every opening counted on two
grids, their brackets must share a value (two decided counts must be equal:
the count does not depend on the cells, :mod:`sesp.certified`).

With several ``--workers`` each table is run once per number of worker processes, and the script says
whether the tables are identical and how the times compare (the counts do not depend on them).

    python benchmarks/transition_tables.py [--n 2 4 8 10] [--bases 64 63 48] [--resolution 1e-5]
                                           [--from 0] [--to 360] [--step 4.8] [--width 0.3] [--workers 2]
"""

import argparse
import math
import time

from _common import machine, table

from sesp import SeSP
from sesp.topology import transitions


def _said(t, n, base, start):
    """Print one change as soon as it is bracketed (a stopped run keeps what it found)."""
    print(f"n = {n:g}, base {base}: {math.degrees(t.low):.3f}-{math.degrees(t.high):.3f} deg, "
          f"{t.before.bracket} -> {t.after.bracket} ({time.perf_counter() - start:.0f} s in)", flush=True)  # fmt: skip


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=float, nargs="+", default=[2, 4, 8, 10])
    ap.add_argument("--bases", type=int, nargs="+", default=[64, 63, 48])
    ap.add_argument("--resolution", type=float, default=1e-5, help="ε, b")
    ap.add_argument("--from", dest="start", type=float, default=0.0, help="degrees")
    ap.add_argument("--to", type=float, default=360.0, help="degrees")
    ap.add_argument("--step", type=float, default=4.8, help="degrees (16 widths: four halvings end at the width)")
    ap.add_argument("--width", type=float, default=0.3, help="degrees")
    ap.add_argument("--segments", type=int, default=256)
    ap.add_argument("--workers", type=int, nargs="+", default=[2], help="worker processes (each number is run)")
    args = ap.parse_args()
    print(f"machine: {machine()}; resolution {args.resolution:g} b, {args.segments} segments, step {args.step:g}°, "
          f"brackets at most {args.width:g}° wide\n")  # fmt: skip
    for n in args.n:
        seen, counts = {}, {}
        for base in args.bases:  # each change is printed as it is bracketed, each run's table when it is done
            runs = {}
            for workers in args.workers:
                found, seconds = _run(n, base, workers, args)
                runs[workers] = ({o: (f.low, f.high) for o, f in found.counts.items()}, seconds)
            counts[base] = found.counts  # opening -> Certified (the same with any number of workers)
            # where each change lies and what is known on each side (a count, or None where undecided)
            got = {"certain changes": found.certain_changes(), "all changes": found.changes}
            seen[base] = {which: [(round(math.degrees(t.low), 4), round(math.degrees(t.high), 4), t.before.count,
                                   t.after.count) for t in ts] for which, ts in got.items()}  # fmt: skip
            if len(runs) > 1:
                same = len({tuple(sorted(counts.items())) for counts, _ in runs.values()}) == 1
                first = runs[args.workers[0]][1]
                times = ", ".join(f"{p} workers {t:.0f} s ({t / first:.2f})" for p, (_, t) in runs.items())
                print(f"n = {n:g}, base {base}: counts at every opening {'identical' if same else 'NOT identical'}; "
                      f"{times}\n", flush=True)  # fmt: skip
        for which in ("certain changes", "all changes") if len(seen) > 1 else ():  # one grid: nothing to compare
            same = len({tuple(v[which]) for v in seen.values()}) == 1
            print(f"n = {n:g}: {which} {'identical' if same else 'NOT identical'} on bases {args.bases}", flush=True)
        if len(counts) > 1:
            print(f"n = {n:g}: {_contradictions(counts)}", flush=True)
        print(flush=True)


def _contradictions(counts) -> str:
    """Whether two grids contradict each other at an opening both counted: brackets with no value in common."""
    bases, common, said = list(counts), 0, []
    for k, a in enumerate(bases):
        for b in bases[k + 1 :]:
            for opening in sorted(counts[a].keys() & counts[b].keys()):
                common += 1
                fa, fb = counts[a][opening], counts[b][opening]
                if fa.high < fb.low or fb.high < fa.low:
                    said.append(f"{math.degrees(opening):.2f}°: base {a} {fa.bracket}, base {b} {fb.bracket}")
    if not said:
        return f"no contradiction: at the {common} (opening, pair of grids) counted on both, the brackets share a value"
    return f"CONTRADICTED at {len(said)} of {common} (opening, pair of grids): " + "; ".join(said)


def _run(n, base, workers, args):
    """One table: its changes printed as they are bracketed, then the table; (Transitions, seconds)."""
    start = time.perf_counter()
    found = transitions(
        SeSP(n=n), (math.radians(args.start), math.radians(args.to)), step=math.radians(args.step),
        width=math.radians(args.width), resolution=args.resolution, base=base, segments=args.segments,
        progress=True, workers=workers,
        on_change=lambda t: _said(t, n, base, start),
    )  # fmt: skip
    seconds = time.perf_counter() - start
    rows = []
    for t in found.changes:
        where = f"{math.degrees(t.low):.3f}-{math.degrees(t.high):.3f}"
        change = f"{t.before.bracket} -> {t.after.bracket}"
        said = t.what().split("; ", 1)[-1][:70]
        rows.append([f"{n:g}", base, workers, where, change, "yes" if t.certain else "no", said])
    rows.append([f"{n:g}", base, workers, "-", f"{len(found.counts)} openings", "", f"{seconds:.0f} s"])
    table(rows, ["n", "base", "workers", "bracket (deg)", "count", "certain", "what"])
    said = ", ".join(f"{math.degrees(t.low):.3f}-{math.degrees(t.high):.3f}: {t.before.count} -> {t.after.count}"
                     for t in found.certain_changes())  # fmt: skip
    print(f"certain changes (between decided counts): {said or 'none'}", flush=True)
    costly = sorted(found.counts.items(), key=lambda item: -item[1].seconds)[:6]
    said = ", ".join(f"{math.degrees(o):.2f}° {f.seconds:.0f} s" for o, f in costly)
    print(f"costliest counts (seconds each): {said}\n", flush=True)
    return found, seconds


if __name__ == "__main__":
    main()
