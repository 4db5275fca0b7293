"""Adaptive maps of the excluded set (exact in φ), drawn with each component in its own colour.

For each opening: the components (area, inscribed radius, bounding box,
what it may be an artefact of: ``ExcludedMap.limit``), the positions classified and the time, and a PNG of the map in
``benchmarks/figures/component_map_n{n}_{degrees}.png`` (the whole set, and
beside it the components along the axis, with y stretched). As an independent
look, the runs of x along the axis (y = 0) and 1e-4 b off it where the widest
window is 0, sampled every 1e-3 b over |x| <= 0.4 b.

    python benchmarks/component_maps.py [--n 4] [--openings 170 176 178] [--floor 1e-7] [--base 128]
        [--segments 256] [--maps-folder DIR]

``--maps-folder``: each map is saved there and read back on the next run
(``sesp.maps.stored_map``: the folder ``sesp topology --maps-folder`` and
``map_transitions.py`` use), so the figures can be redrawn without mapping
again; the time printed is then that of reading the map.
"""

import argparse
import math
import time
from pathlib import Path

import numpy as np
from _common import machine, table

from sesp import SeSP, widest_window
from sesp.maps import stored_map
from sesp.pair import as_pair
from sesp.plot import component_map, save_figure

FIGURES = Path(__file__).resolve().parent / "figures"


def axis_runs(particle, y, segments, step=1e-3, reach=0.4):
    """Runs [x0, x1] (b) along the line at height y where the widest window is 0."""
    x = np.arange(-reach, reach + step / 2, step)
    width, _ = widest_window(particle, x, np.full_like(x, y), segments=segments)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], (width == 0).astype(int), [0]])))
    return [(float(x[a]), float(x[b - 1])) for a, b in zip(edges[::2], edges[1::2])]


def axis_window(found, thin=0.02):
    """(xmin, xmax, ymin, ymax), b: the components along the axis (less than ``thin`` off it), y stretched to
    show their thickness, at least 10 finest cells; |x| <= 0.3 b when there are none."""
    strips = [c.bbox for c in found.components if max(abs(c.bbox[2]), abs(c.bbox[3])) < thin]
    reach = 1.05 * max([abs(v) for b in strips for v in b[:2]], default=0.3 / 1.05)
    half = max([10 * found.finest] + [max(abs(b[2]), abs(b[3])) for b in strips])
    return (-reach, reach, -1.5 * half, 1.5 * half)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--n", type=float, default=4.0)
    parser.add_argument("--openings", type=float, nargs="+", default=[170, 176, 178])
    parser.add_argument("--floor", type=float, default=1e-7)
    parser.add_argument("--base", type=int, default=128)
    parser.add_argument("--segments", type=int, default=256, help="polyline segments N of each particle")
    parser.add_argument("--maps-folder", type=Path, default=None)
    args = parser.parse_args()
    import matplotlib.pyplot as plt

    print(machine())
    rows = []
    for degrees in args.openings:
        particle = SeSP(n=args.n, opening=math.radians(degrees))
        t0 = time.perf_counter()
        pair = as_pair(particle, segments=args.segments)
        found = stored_map(args.maps_folder, particle.opening, pair, base=args.base, floor=args.floor, progress=True)
        seconds = time.perf_counter() - t0
        for k, c in enumerate(found.components, start=1):
            box = ", ".join(f"{v:.4f}" for v in c.bbox)
            rows.append((f"{degrees:g}", k, f"{c.area:.4g}", f"{c.inscribed_radius:.3g}", box, found.limit(c) or "-"))
        rows.append((f"{degrees:g}", f"{found.count} in all", found.positions, f"{seconds:.0f} s", "", ""))
        for y in (0.0, 1e-4):
            runs = ", ".join(f"[{a:.3f}, {b:.3f}]" for a, b in axis_runs(particle, y, args.segments))
            rows.append((f"{degrees:g}", f"W = 0 at y = {y:g}", "", "", runs, ""))
        if any(len(c.x) == 0 for c in found.components):  # a map file written before the nodes were kept
            print(f"{degrees:g} deg: the stored map holds no nodes, figure not drawn; remove it to map again")
            continue
        fig, (whole, centre) = plt.subplots(1, 2, figsize=(11, 5))
        component_map(found, ax=whole, particle=particle)
        near = axis_window(found)
        component_map(found, ax=centre, window=near, aspect="auto")
        stretch = (near[1] - near[0]) / (near[3] - near[2]) * 0.8  # the panel is about 0.8 as tall as wide
        centre.set_title(f"along the axis, y stretched {stretch:.0f} times")
        fig.suptitle(f"n = {args.n:g}, opening {degrees:g} deg, N = {args.segments}: excluded set on an adaptive map, "
                     "exact in phi")  # fmt: skip
        fig.tight_layout()
        tag = "" if args.segments == 256 else f"_N{args.segments}"
        save_figure(fig, FIGURES / f"component_map_n{args.n:g}_{degrees:g}{tag}.png")
        plt.close(fig)
    table(rows, ["opening deg", "component", "area b^2", "inscribed b", "bbox (b)", "unresolved"])


if __name__ == "__main__":
    main()
