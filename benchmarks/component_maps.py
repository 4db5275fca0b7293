"""Adaptive maps of the excluded set (exact in φ), drawn with each component in its own colour.

For each opening: the components (area, inscribed radius, bounding box,
floor flag), the positions classified and the time, and a PNG of the map in
``benchmarks/figures/component_map_n{n}_{degrees}.png`` (the whole set, and
beside it the neighbourhood of the particle's centre).

    python benchmarks/component_maps.py [--n 4] [--openings 170 176 178] [--floor 1e-7] [--base 128]
"""

import argparse
import math
import time
from pathlib import Path

from _common import machine, table

from sesp import SeSP, excluded_map
from sesp.plot import component_map, save_figure

FIGURES = Path(__file__).resolve().parent / "figures"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=float, default=4.0)
    parser.add_argument("--openings", type=float, nargs="+", default=[170, 176, 178])
    parser.add_argument("--floor", type=float, default=1e-7)
    parser.add_argument("--base", type=int, default=128)
    args = parser.parse_args()
    import matplotlib.pyplot as plt

    print(machine())
    rows = []
    for degrees in args.openings:
        particle = SeSP(n=args.n, opening=math.radians(degrees))
        t0 = time.perf_counter()
        found = excluded_map(particle, base=args.base, floor=args.floor, progress=True)
        seconds = time.perf_counter() - t0
        for k, c in enumerate(found.components, start=1):
            box = ", ".join(f"{v:.4f}" for v in c.bbox)
            rows.append((f"{degrees:g}", k, f"{c.area:.4g}", f"{c.inscribed_radius:.3g}", box, c.touches_floor))
        rows.append((f"{degrees:g}", f"{found.count} in all", found.positions, f"{seconds:.0f} s", "", ""))
        fig, (whole, centre) = plt.subplots(1, 2, figsize=(11, 5))
        component_map(found, ax=whole, particle=particle)
        component_map(found, ax=centre, window=(-0.15, 0.15, -0.15, 0.15))
        centre.set_title("near the particle's centre")
        fig.suptitle(f"n = {args.n:g}, opening {degrees:g} deg: excluded set on an adaptive map, exact in phi")
        fig.tight_layout()
        save_figure(fig, FIGURES / f"component_map_n{args.n:g}_{degrees:g}.png")
        plt.close(fig)
    table(rows, ["opening deg", "component", "area b^2", "inscribed b", "bbox (b)", "at floor"])


if __name__ == "__main__":
    main()
