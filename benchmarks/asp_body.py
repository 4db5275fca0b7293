"""How deep the ASP's body is near Ψ = π, by exact windows along rays, against what the depth certificate proves.

Near π the body of the ASP (n = 2) is a thin wedge along −x, where the two
arcs nearly coincide: at each position t = (x, 0) on the axis this prints

* ``rays``: the distance from t to the nearest allowed position found along
  ``--rays`` directions (exact windows in φ, bisected to 1e-7 b): an upper
  bound on the depth p(t), and close to it;
* ``pair``: the depth one pair of runs proves (no two end points);
* ``proved``: the depth the certificate proves with two end points
  (:func:`sesp.kernels.depth.two_tips`), as the certified count uses it;

each a bisection, and, per opening, the largest of each over the positions
tried. The count (``sesp topology``) counts the body while it is at least
ε + rim = 1.01e-3 b deep. ``--intervals`` also prints, at that position, how
many intervals of φ a walk needs at 0.5, 0.9 and 0.99 of the proved depth, and
at 1.01 of it how many a walk from φ = 0 takes to fail and how many one begun
where that one failed.

    python benchmarks/asp_body.py [--openings 176 177 177.9 178.2] [--positions 24] [--intervals]
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table

from sesp import SeSP
from sesp.kernels import depth as depth_kernels
from sesp.orientations import widest_window
from sesp.pair import as_pair

SEGMENTS = 256


def nearest_allowed(part, x, y, rays, reach):
    """b: the distance from (x, y) to the nearest allowed position found along ``rays`` directions (exact in φ),
    each ray scanned in 200 steps up to ``reach`` (b) and bisected to 1e-7 b."""
    turns = np.linspace(0.0, 2.0 * math.pi, rays, endpoint=False)
    far = np.full(rays, np.inf)
    for s in np.linspace(reach, reach / 200, 200):  # the nearest allowed step along each ray
        width, _ = widest_window(part, x + s * np.cos(turns), y + s * np.sin(turns), segments=SEGMENTS)
        far = np.where(width > 0, s, far)
    lo, hi = np.where(np.isfinite(far), far - reach / 200, 0.0), far
    for _ in range(24):
        live = np.isfinite(hi)
        mid = np.where(live, 0.5 * (lo + hi), 0.0)
        width, _ = widest_window(part, x + mid * np.cos(turns), y + mid * np.sin(turns), segments=SEGMENTS)
        hi = np.where(live & (width > 0), mid, hi)
        lo = np.where(live & (width <= 0), mid, lo)
    return float(hi.min())


def proved(curves, x, y, tips):
    """b: the largest depth the certificate proves at (x, y), by geometric bisection to a factor 1.001."""
    lo, hi = 1e-9, 0.1
    while hi > lo * 1.001:
        mid = math.sqrt(lo * hi)
        ok = depth_kernels.certified_deep(
            curves, np.array([x]), np.array([y]), mid, 4096, options=depth_kernels.OPTIONS._replace(tips=tips)
        )[0]
        lo, hi = (mid, hi) if ok == 1 else (lo, mid)
    return lo


def intervals(curves, x, r, start=0.0):
    """The fewest intervals of φ with which the walk at depth r (b) from ``start`` ends (proved or failed)."""
    lo, hi = 1, 4096
    while lo < hi:
        mid = (lo + hi) // 2
        got = depth_kernels.certified_deep(curves, np.array([x]), np.array([0.0]), r, mid, start=start)[0]
        lo, hi = (lo, mid) if got != -1 else (mid + 1, hi)
    return lo


def walks(curves, x, depth):
    """Intervals needed at 0.5, 0.9 and 0.99 of ``depth``, and to fail at 1.01 of it from φ = 0 and from where
    that walk failed."""
    stops = np.zeros(1)
    depth_kernels.certified_deep(curves, np.array([x]), np.array([0.0]), 1.01 * depth, 4096, stops=stops)
    return [intervals(curves, x, f * depth) for f in (0.5, 0.9, 0.99, 1.01)] + [
        intervals(curves, x, 1.01 * depth, float(stops[0]))
    ]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--openings", type=float, nargs="+", default=[176.0, 177.0, 177.9, 178.2], help="degrees")
    ap.add_argument("--positions", type=int, default=24, help="positions along −x, up to the body's end")
    ap.add_argument("--rays", type=int, default=64)
    ap.add_argument("--intervals", action="store_true", help="intervals of φ the walks need at the best position")
    args = ap.parse_args()
    print(f"machine: {machine()}; {SEGMENTS} segments\n")
    rows = []
    for degrees in args.openings:
        start = time.perf_counter()
        part = SeSP(n=2, opening=math.radians(degrees))
        pair = as_pair(part, segments=SEGMENTS)
        curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
        end = 2 * math.sin(math.radians(180 - degrees) / 2) * 1.5  # b: past the body's end on the axis
        best = (0.0, 0.0, 0.0, 0.0)
        for x in -np.linspace(end / args.positions, end, args.positions):
            if widest_window(part, np.array([x]), np.array([0.0]), segments=SEGMENTS)[0][0] > 0:
                continue  # allowed: not in the body
            got = (proved(curves, x, 0.0, True), proved(curves, x, 0.0, False))
            if got[0] > best[1]:
                best = (x, *got, nearest_allowed(part, x, 0.0, args.rays, 4 * got[0]))
        x, with_tips, pair_only, rays = best
        if args.intervals:
            at = walks(curves, x, with_tips)
            print(f"{degrees:g} deg, x {x:+.4f} b: intervals at 0.5, 0.9, 0.99 of the proved depth: {at[:3]}; "
                  f"to fail at 1.01: {at[3]} from 0, {at[4]} from where that walk failed", flush=True)  # fmt: skip
        rows.append((f"{degrees:g}", f"{x:+.4f}", f"{rays:.3e}", f"{pair_only:.3e}", f"{with_tips:.3e}",
                     f"{with_tips / rays:.3f}", f"{time.perf_counter() - start:.1f}"))  # fmt: skip
    table(rows, ["opening (deg)", "x (b)", "rays (b)", "pair (b)", "proved (b)", "proved/rays", "s"])


if __name__ == "__main__":
    main()
