"""Transition tables on adaptive maps (exact in φ), on two base grids of different parity and size.

For each n: :func:`sesp.map_transitions` over Ψ (every ``--step`` degrees,
each change bisected to ±0.005 rad), once on each base grid; prints the
brackets side by side, whether they are identical, and the time of each
search; saves each search as ``map_transitions_n{n}_base{b}.nc`` in
``--out``. A bracket is marked * where it is unresolved
(``transition_unresolved``: a component that changes in it, parting,
joining, appearing, vanishing or leaving the axis, is seen only at the
floor, encloses allowed slivers that may part it, is thinner than the
polylines depart from the curves, or was joined so that the partition is
its own mirror image about the x-axis, as the set's is: ``mirror_joined``),
and the brackets not marked on either
grid are compared too.

    python benchmarks/map_transitions.py [--n 2 4 8 10] [--bases 128 97] [--from 0] [--top 360] [--step 5]
        [--floor 1e-7] [--finer LOW HIGH ...] [--out DIR] [--reuse] [--figures DIR]

After the table it names the steps of Ψ whose brackets (or marks) differ
between the grids. ``--finer LOW HIGH`` (degrees, may be given again)
searches the steps in that range at a floor ten times finer on both grids
(``map_transitions(finer=...)``; the maps in ``maps_n{n}_base{b}/floor_<f>``),
and so each step beside one where the floors disagree at the opening they
share: give it the steps named, and run again. A bracket found at the finer
floor is printed with it, as ``[1e-05 b]``.

``--figures DIR``: the counts and the components' areas over Ψ on both grids
(:func:`sesp.plot.map_transitions_plot`), ``map_transitions_n{n}.png`` per n.

Each map is saved as it is made, in ``--out/maps_n{n}_base{b}/``: a search
stopped part way resumes from them when run again (its time is then that of
the last run). ``--reuse`` takes a search already saved in ``--out`` (same n
and base) from those maps, with the time it took then, instead of making
them again; so the two base grids can be searched by two processes at once
(``--bases 128 128`` and ``--bases 97 97``) and the table printed
afterwards, and the brackets' marks are those of the code that prints them.
A saved search whose maps folder is gone is an error with ``--reuse``: its
maps would be made again, and the time printed would not be theirs.
"""

import argparse
import math
import time
from pathlib import Path

import numpy as np
import xarray as xr
from _common import machine, table

from sesp import SeSP, map_transitions
from sesp.report import map_change


def brackets(result, floor):
    """[(change, low_deg, high_deg)] of a transition dataset ("3 -> 3 (off axis 0 -> 2)" where only
    the number of components off the axis changed; "[1e-05 b]" after it where found at a floor other
    than ``floor``)."""
    found = []
    for t, (lo, hi) in enumerate(zip(result.low_degrees.values, result.high_degrees.values)):
        at = float(result.transition_floor[t]) if "transition_floor" in result else floor
        found.append((map_change(result, t) + (f" [{at:g} b]" if at != floor else ""), float(lo), float(hi)))
    return found


def differing_steps(first, second, low, step):
    """The steps of Ψ ("165-170", degrees) whose brackets, with their marks, differ between two
    searches: ``first`` and ``second`` give ((change, low_deg, high_deg), marked) per transition."""
    by_step = [{}, {}]
    for side, found in zip(by_step, (first, second)):
        for bracket, marked in found:
            k = int(math.floor((bracket[1] - low) / step + 1e-9))
            side.setdefault(k, []).append((bracket, marked))
    keys = sorted(set(by_step[0]) | set(by_step[1]))
    return [f"{low + k * step:g}-{low + (k + 1) * step:g}" for k in keys if by_step[0].get(k) != by_step[1].get(k)]


def unresolved(result):
    """Per transition: whether a component that changes in it is unresolved (``transition_unresolved``)."""
    return [bool(v) for v in result.transition_unresolved.values]


def draw(n, results, folder):
    """Save the counts and areas over Ψ of the searches ``results`` ({label: dataset}) for this n."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from sesp.plot import map_transitions_plot, save_figure

    lens = (r"exact ASP lens $(\pi - \Psi) - \sin\Psi$", lambda psi: (math.pi - psi) - np.sin(psi))
    fig = map_transitions_plot(results, reference=lens if n == 2 else None)
    fig.suptitle(f"n = {n:g}: excluded components on adaptive maps, exact in φ")
    folder.mkdir(parents=True, exist_ok=True)
    save_figure(fig, folder / f"map_transitions_n{n:g}.png")
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=float, nargs="+", default=[2, 4, 8, 10])
    parser.add_argument("--bases", type=int, nargs=2, default=[128, 97])
    parser.add_argument("--from", dest="low", type=float, default=0.0)
    parser.add_argument("--top", type=float, default=360.0)
    parser.add_argument("--step", type=float, default=5.0)
    parser.add_argument("--floor", type=float, default=1e-7)
    parser.add_argument("--finer", type=float, nargs=2, action="append", default=[], metavar=("LOW", "HIGH"),
                        help="search the steps in LOW..HIGH degrees at a tenth of --floor")  # fmt: skip
    parser.add_argument("--out", type=Path, default=Path("."))
    parser.add_argument("--reuse", action="store_true", help="read searches already saved in --out")
    parser.add_argument("--figures", type=Path, default=None, help="save map_transitions_n{n}.png here")
    args = parser.parse_args()
    print(machine())
    print(
        f"openings {args.low:g}..{args.top:g} deg every {args.step:g} deg, bisected to +-0.005 rad; "
        f"N = 256; floor {args.floor:g} b; base grids {args.bases[0]} and {args.bases[1]}"
    )
    finer = [(math.radians(a), math.radians(b)) for a, b in args.finer]
    if finer:
        ranges = ", ".join(f"{a:g}-{b:g}" for a, b in args.finer)
        print(f"steps in {ranges} deg (and beside them where the floors disagree) at a floor of {args.floor / 10:g} b")
    same_everywhere = same_resolved = True
    for n in args.n:
        found, seconds, flagged, searched = {}, {}, {}, {}
        for base in dict.fromkeys(args.bases):  # a base given twice is searched once
            path = args.out / f"map_transitions_n{n:g}_base{base}.nc"
            maps = args.out / f"maps_n{n:g}_base{base}"
            saved = xr.load_dataset(path) if args.reuse and path.exists() else None
            if saved is not None and not maps.is_dir():
                raise SystemExit(f"--reuse: {path} has no maps folder {maps} to rebuild it from (remove --reuse)")
            t0 = time.perf_counter()
            result = map_transitions(
                SeSP(n=n),
                (math.radians(args.low), math.radians(args.top)),
                step=math.radians(args.step),
                base=base,
                floor=args.floor,
                progress=saved is None,
                folder=maps,
                finer=finer,
            )
            result.attrs["seconds"] = saved.attrs["seconds"] if saved is not None else time.perf_counter() - t0
            result.to_netcdf(path)
            searched[base] = result
            seconds[base] = result.attrs["seconds"]
            found[base] = brackets(result, args.floor)
            flagged[base] = unresolved(result)
        if args.figures is not None:
            draw(n, {f"{base} cells": searched[base] for base in args.bases}, args.figures)
        a, b = (found[base] for base in args.bases)
        rows = []
        for k in range(max(len(a), len(b))):
            cells = []
            for side, flags in zip((a, b), (flagged[base] for base in args.bases)):
                t = side[k] if k < len(side) else None
                mark = " *" if t and flags[k] else ""
                cells += [f"{t[0]}{mark}", f"{t[1]:.2f}-{t[2]:.2f}", f"{t[2] - t[1]:.2f}"] if t else ["-"] * 3
            rows.append((f"{n:g}", *cells))
        same = a == b
        same_everywhere &= same
        resolved = [[t for t, f in zip(found[base], flagged[base]) if not f] for base in args.bases]
        same_resolved &= resolved[0] == resolved[1]
        verdict = "identical" if same else "DIFFERENT"
        rows.append((f"{n:g}", verdict, f"{len(resolved[0])} not *", f"{seconds[args.bases[0]]:.0f} s", "",
                     f"{len(resolved[1])} not *", f"{seconds[args.bases[1]]:.0f} s"))  # fmt: skip
        b1, b2 = args.bases
        table(
            rows, ["n", f"change {b1}", f"bracket {b1} (deg)", "width", f"change {b2}", f"bracket {b2} (deg)", "width"]
        )
        differ = differing_steps(*(zip(found[base], flagged[base]) for base in args.bases), args.low, args.step)
        print(f"n = {n:g}: steps whose brackets differ: {', '.join(differ) or 'none'}")
    verdict = "yes" if same_everywhere else "no"
    print("\n* unresolved: a component that changes in the bracket (sesp.maps.changed_components) is seen only at")
    print("  the floor, encloses allowed slivers that may part it, is thinner than the polylines depart from the")
    print("  curves, or was joined so that the partition is its own mirror image about the x-axis, as the set's is")
    print("  (ExcludedMap.limit, sesp.maps.mirror_joined)")
    print(f"all brackets identical on base grids {args.bases[0]} and {args.bases[1]}: {verdict}")
    print(f"brackets not marked * identical on both: {'yes' if same_resolved else 'no'}")


if __name__ == "__main__":
    main()
