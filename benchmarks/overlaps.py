"""sesp.overlaps, the overlap test state by state: states per second against a shapely loop, measured in one
run, and its agreement with shapely and with sesp.scan.

    python benchmarks/overlaps.py                # 10^6 states for sesp, 20 000 for shapely

The particle is the ASP at Ψ = 90° (256 segments); states (x, y, φ) are uniform over the square of half-width
its reach and over φ. Shapely decides each state with ``LineString.intersects`` on the same polylines.
"""

import argparse
import math
import time

import numpy as np
from _common import machine, table
from shapely import affinity
from shapely.geometry import LineString

from sesp import Grid, Pair, SeSP, overlaps, scan


def _shapely_loop(pair, x, y, phi) -> np.ndarray:
    fixed, moving = LineString(pair.vertices1), LineString(pair.vertices2)
    out = np.empty(len(x), dtype=bool)
    for s in range(len(x)):
        placed = affinity.translate(affinity.rotate(moving, phi[s], origin=(0, 0), use_radians=True), x[s], y[s])
        out[s] = fixed.intersects(placed)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--states", type=int, default=1_000_000)
    ap.add_argument("--shapely-states", type=int, default=20_000)
    args = ap.parse_args()
    pair = Pair.of(SeSP(n=2, opening=math.radians(90)))
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-pair.reach, pair.reach, size=(2, args.states))
    phi = rng.uniform(0, 2 * math.pi, size=args.states)
    overlaps(pair, None, x[:10], y[:10], phi[:10])  # compile outside the timing
    t0 = time.perf_counter()
    found = overlaps(pair, None, x, y, phi)
    sesp_seconds = time.perf_counter() - t0
    k = args.shapely_states
    t0 = time.perf_counter()
    reference = _shapely_loop(pair, x[:k], y[:k], phi[:k])
    shapely_seconds = time.perf_counter() - t0
    sesp_rate, shapely_rate = args.states / sesp_seconds, k / shapely_seconds
    grid = Grid(96, nphi=16)
    field = scan(pair, grid)
    gx, gy = np.meshgrid(field.x.values, field.y.values)
    on_grid = np.stack([overlaps(pair, None, gx, gy, p) for p in field.phi.values])
    print(f"sesp.overlaps against a shapely loop, the ASP at 90 deg (256 segments); {machine()}")
    table(
        [
            ["sesp.overlaps", f"{args.states:,}", f"{sesp_seconds:.2f}", f"{sesp_rate:,.0f}", "1"],
            [
                "shapely loop",
                f"{k:,}",
                f"{shapely_seconds:.2f}",
                f"{shapely_rate:,.0f}",
                f"{shapely_rate / sesp_rate:.4f}",
            ],
        ],  # fmt: skip
        ["test", "states", "s", "states/s", "rate / sesp's"],
    )
    print(f"\nsesp.overlaps is {sesp_rate / shapely_rate:.0f} times the shapely loop's rate; overlapping "
          f"{found.mean():.4f} of the states")  # fmt: skip
    print(f"states where sesp and shapely differ: {int((found[:k] != reference).sum())} of {k:,}")
    differ = int((on_grid == field.allowed.values).sum())
    print(f"states of a {grid.nx} x {grid.ny} x {grid.nphi} scan where overlaps differs from not allowed: "
          f"{differ} of {on_grid.size:,}")  # fmt: skip


if __name__ == "__main__":
    main()
