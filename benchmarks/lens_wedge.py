"""The allowed wedge that parts the lens from the body for small Ψ, from brute-force exact-in-φ rows.

For a closed, centrally symmetric curve, a copy turned by π and moved by
(0, y) meets the curve in two points at height y/2, one on each side. With
the openings cut out, both fall in an opening while |y| / 2 is less than the
opening's half-height sin(Ψ/2)^(2/m): the position (0, y) is then allowed.
Around x = 0 this makes an allowed wedge that runs up from the particle's
centre (excluded) between the lens, right of it, and the body, left of it.
It is the only thing that parts the two for small Ψ (n = 8: 1e-3 b wide
0.1 b up at Ψ = 5°), so for the curve the lens is a component of its own for
every Ψ > 0, however thin the wedge.

The particles sesp computes are 256-segment polygons. Sampled at equal arc
along the whole curve, a polygon turned by π is not the same polygon
mirrored (its nodes fall elsewhere on the curve): near y = 0 the two cross
more than twice and the wedge stops short of the axis, leaving an excluded
neck about as thick as the polygon's departure from the curve (n = 8: 3e-6 b
at Ψ = 167.5°, 1e-6 b at 175°), which joins the lens to the body. sesp's
polygons are their own mirror images in x on the flanks
(:meth:`sesp.shape.SeSP.polyline`), so the wedge's foot reaches the axis at
x = 0 as for the curve. ``--neck`` measures it: the least height of the
wedge's foot over x from -0.3 to 0.3 b (bisected in y), i.e. the
half-thickness of the excluded strip along the axis that joins the lens to
the body (1e-10 b or so is the bisection's own resolution: a pinch).

For each opening and height y this samples the widest window W (exact in φ)
along the row at y on cells of ``--cell`` from x = -0.005 to 0.02 b and
prints the allowed run that holds x = 0 (its ends, b), whether W = 0 on
either side of it within the row (the wedge is closed there by the body and
the lens), and W and its middle at x = 0 (the middle is φ = π).

    python benchmarks/lens_wedge.py [--n 8] [--openings 1 2 5] [--cell 1e-5]
    python benchmarks/lens_wedge.py --neck --openings 30 90 150 167.5 175 179

No certified cell is involved: it is a check the certified count is held to
(``tests/test_certified.py``: lens and body parted at small Ψ).
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table

from sesp import SeSP
from sesp.orientations import widest_window

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


def foot_height(particle, x, top=0.02, steps=45):
    """Per x (b): the height (b) below which the column at x is excluded, bisected from [0, top].

    Bisection assumes one change from W = 0 to W > 0 up the column: an allowed
    pocket below the change it finds would be missed. ``steps`` halvings of ``top``.
    """
    low, high = np.zeros(len(x)), np.full(len(x), top)
    for _ in range(steps):
        mid = 0.5 * (low + high)
        width, _ = widest_window(particle, x, mid)
        low, high = np.where(width == 0, mid, low), np.where(width == 0, high, mid)
    return low


def neck(particle):
    """(least foot height (b), its x (b), W = 0 on the axis row throughout): the axis strip's thinnest point."""
    x = np.linspace(-0.3, 0.3, 601)
    i = int(np.argmin(foot_height(particle, x)))
    fine = np.linspace(x[max(i - 2, 0)], x[min(i + 2, len(x) - 1)], 401)
    heights = foot_height(particle, fine)
    j = int(np.argmin(heights))
    axis, _ = widest_window(particle, fine, np.zeros(len(fine)))
    return heights[j], fine[j], bool(np.all(axis == 0))


def neck_table(args):
    rows = []
    for degrees in args.openings:
        start = time.perf_counter()
        height, x, closed = neck(SeSP(n=args.n, opening=math.radians(degrees)))
        rows.append([f"{degrees:g}", f"{height:.2e}", f"{x:.5f}", "yes" if closed else "no",
                     f"{time.perf_counter() - start:.1f} s"])  # fmt: skip
    table(rows, ["opening (deg)", "half-thickness (b)", "at x (b)", "axis excluded", "time"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=float, default=8)
    parser.add_argument("--openings", type=float, nargs="+", default=[1, 2, 5])
    parser.add_argument("--cell", type=float, default=1e-5)
    parser.add_argument("--neck", action="store_true", help="the axis strip's thinnest point per opening")
    args = parser.parse_args()
    print(machine())
    if args.neck:
        print(f"n = m = {args.n:g}, N = 256: the excluded strip along the axis at its thinnest, x in [-0.3, 0.3] b")
        neck_table(args)
        return
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
