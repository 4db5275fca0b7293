"""Which maps of a transition search follow channels: the openings whose base window has allowed slivers.

A map follows allowed channels only from the slivers of its base window
(:func:`sesp.maps.base_slivers`); a map whose base window has none is made
exactly as before channels were followed. So this tells which maps of a
search saved before that change must be made again, and which stand.

    python benchmarks/channel_seeds.py [--n 4 8 10] [--bases 128 97] [--floor 1e-4] [--steps 0 175 180]
    python benchmarks/channel_seeds.py --n 4 --bases 128 --folder DIR/maps_n4_base128

The openings looked at are every 5° and, in each 5° step from ``--steps``,
the 15 points a bisection to ±0.005 rad can visit (Ψ + 5°·k/16): a superset
of the maps :func:`sesp.map_transitions` makes there. ``--folder``: the
openings of the maps saved there (``map_<opening>.nc``) instead.
"""

import argparse
import math
from pathlib import Path

from _common import machine, table

from sesp import SeSP
from sesp.maps import base_slivers


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=float, nargs="+", default=[4, 8, 10])
    parser.add_argument("--bases", type=int, nargs="+", default=[128, 97])
    parser.add_argument("--floor", type=float, default=1e-4)
    parser.add_argument("--steps", type=float, nargs="*", default=[0.0, 175.0, 180.0])
    parser.add_argument("--folder", type=Path, default=None)
    args = parser.parse_args()
    print(machine())
    if args.folder is not None:
        openings = sorted(math.degrees(float(p.stem[4:])) for p in args.folder.glob("map_*.nc"))
    else:
        openings = sorted({5.0 * k for k in range(72)} | {a + 5.0 * j / 16 for a in args.steps for j in range(1, 16)})
    rows = []
    for n in args.n:
        for base in args.bases:
            seeded = []
            for degrees in openings:
                seeds = base_slivers(SeSP(n=n, opening=math.radians(degrees)), base=base, floor=args.floor)
                if len(seeds):
                    seeded.append(f"{degrees:.4f} ({len(seeds)})")
            rows.append((f"{n:g}", base, len(openings), ", ".join(seeded) or "none"))
            print(*rows[-1], flush=True)
    table(rows, ["n", "base", "openings", "with slivers (deg, sliver nodes)"])


if __name__ == "__main__":
    main()
