"""The allowed wedge that parts the lens from the body for small Ψ, from brute-force exact-in-φ rows.

For a closed, centrally symmetric curve, a copy turned by π and moved by
(0, y) meets the curve in two points at height y/2, one on each side. With
the openings cut out, both fall in an opening while |y| / 2 is less than the
opening's half-height sin(Ψ/2)^(2/m): the position (0, y) is then allowed.
Around x = 0 this makes an allowed wedge that runs up from the particle's
centre (excluded) between the lens, right of it, and the body, left of it.
It is the only thing that parts the two for small Ψ (n = 8: 1e-3 b wide
0.1 b up at Ψ = 5°), so the lens is a component of its own for every Ψ > 0,
however thin the wedge.

For each opening and height y this samples the widest window W (exact in φ)
along the row at y on cells of ``--cell`` from x = -0.005 to 0.02 b and
prints the allowed run that holds x = 0 (its ends, b), whether W = 0 on
either side of it within the row (the wedge is closed there by the body and
the lens), and W and its middle at x = 0 (the middle is φ = π).

    python benchmarks/lens_wedge.py [--n 8] [--openings 1 2 5] [--cell 1e-5]

No adaptive map is involved: it is the check the maps are held to
(``tests/test_maps.py``: the maps on 97 and 128 base cells at Ψ = 5°).
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table

from sesp import SeSP, widest_window

HEIGHTS = (0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3)  # b
XMIN, XMAX = -0.005, 0.02  # b


def wedge(particle, y, cell):
    """(x_low, x_high, closed on both sides, W at x = 0, its middle) along the row at height y."""
    x = np.concatenate([np.arange(XMIN, 0.0, cell), np.arange(0.0, XMAX + cell / 2, cell)])
    width, middle = widest_window(particle, x, np.full(len(x), y))
    zero = int(np.flatnonzero(x == 0.0)[0])
    if width[zero] == 0:
        return None, None, False, 0.0, math.nan
    excluded = np.flatnonzero(width == 0)
    left, right = excluded[excluded < zero], excluded[excluded > zero]
    low = x[left[-1] + 1] if len(left) else x[0]
    high = x[right[0] - 1] if len(right) else x[-1]
    return low, high, bool(len(left) and len(right)), width[zero], middle[zero]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=float, default=8)
    parser.add_argument("--openings", type=float, nargs="+", default=[1, 2, 5])
    parser.add_argument("--cell", type=float, default=1e-5)
    args = parser.parse_args()
    print(machine())
    print(f"n = m = {args.n:g}, rows from x = {XMIN} to {XMAX} b, cells {args.cell:g} b")
    rows = []
    for degrees in args.openings:
        particle = SeSP(n=args.n, opening=math.radians(degrees))
        half_height = math.sin(math.radians(degrees) / 2) ** (2 / args.n)
        for y in HEIGHTS:
            start = time.perf_counter()
            low, high, closed, w, mid = wedge(particle, y, args.cell)
            span = "-" if low is None else f"{low:.6f}..{high:.6f}"
            middle = "-" if math.isnan(mid) else f"{math.degrees(mid):.2f}"
            rows.append([
                f"{degrees:g}", f"{y:g}", f"{y / 2 < half_height}", span, "yes" if closed else "no",
                f"{w:.2e}", middle, f"{time.perf_counter() - start:.1f} s",
            ])  # fmt: skip
    table(rows, ["opening (deg)", "y (b)", "y/2 in opening", "allowed run at x = 0 (b)", "closed both sides",
                 "W at x = 0 (rad)", "middle (deg)", "time"])  # fmt: skip


if __name__ == "__main__":
    main()
