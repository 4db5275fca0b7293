"""Targets 1-2: raster throughput, entangled cost, raster vs direct; the operation floor.

N = 256 segments, SeSP n = 2, Ψ = π/2. ``scan()`` with the raster engine fills
256 × 256 × 128 and 512 × 512 × 128 grids (allowed only, and with the entangled
field); for SeSPs it computes φ in [0, π] and mirrors the rest, which the tests
show to be identical to computing every slice. The kernel row times every slice
computed, for the floor. The direct engine is timed on a few φ slices of the 256
grid (all of them would take minutes) and checked state for state against scan().

Floor: per φ slice the raster engine sets up N² parallelograms and tests the
grid nodes in each one's bounding box; the table gives both counts and the
measured time per operation.

    python benchmarks/engines.py [--n 2] [--phi-direct 2]
"""

import argparse
import math

import numpy as np
from _common import best_of, machine, table

from sesp import Grid, Pair, SeSP, scan
from sesp.field import resolve_grid
from sesp.kernels.overlap import crossing_field


def prepare(particle, grid, segments):
    """(pair, grid with its box set), as scan() prepares them."""
    pair = Pair.of(particle, segments=segments)
    return pair, resolve_grid(pair, grid)


def fill(setup, k1, engine="raster"):
    """The engine's overlap field for orientations 0..k1-1, as scan() computes it."""
    pair, grid = setup
    c, s = grid.rotations()
    v1, v2 = pair.vertices1, pair.vertices2
    return crossing_field(v1, v2, c[:k1], s[:k1], grid.x, grid.y, pair.tolerance, engine=engine, reach=pair.reach)


def candidate_nodes(setup, k):
    """Parallelogram set-ups and bounding-box nodes the raster engine visits at φ_k (numpy replica)."""
    pair, grid = setup
    c, s = grid.rotations()
    v1 = pair.curve1.vertices
    b2 = pair.curve2.vertices @ np.array([[c[k], s[k]], [-s[k], c[k]]])
    a, d = v1[:-1, None, :], np.diff(v1, axis=0)[:, None, :]
    b, f = b2[None, :-1, :], -np.diff(b2, axis=0)[None, :, :]
    cc = a - b
    lo = cc + np.minimum(d, 0) + np.minimum(f, 0)
    hi = cc + np.maximum(d, 0) + np.maximum(f, 0)
    origin = np.array([grid.x[0], grid.y[0]])
    step = np.array([grid.dx, grid.dy])
    i0 = np.maximum(np.ceil((lo - origin) / step), 0)
    i1 = np.minimum(np.floor((hi - origin) / step), [grid.nx - 1, grid.ny - 1])
    counts = np.prod(np.clip(i1 - i0 + 1, 0, None), axis=-1)
    return counts.size, int(counts.sum())


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--n", type=float, default=2.0)
    ap.add_argument("--segments", type=int, default=256)
    ap.add_argument("--nphi", type=int, default=128)
    ap.add_argument("--phi-direct", type=int, default=2, help="φ slices timed for the direct engine")
    ap.add_argument("--thickness", type=float, default=0.05, help="thickness D (b) of the thick row")
    args = ap.parse_args()
    particle = SeSP(n=args.n, opening=math.pi / 2)

    warm = prepare(particle, Grid(16, nphi=2), segments=args.segments)
    fill(warm, 2), fill(warm, 2, "direct")
    scan(particle, Grid(128, nphi=64), segments=args.segments, entangled=True)  # compile outside the timing

    rows, rates = [], {}
    for nx in (256, 512):
        grid = Grid(nx, nphi=args.nphi)
        setup = prepare(particle, grid, segments=args.segments)
        t_allowed, ds = best_of(lambda grid=grid: scan(particle, grid, segments=args.segments))
        t_both, _ = best_of(lambda grid=grid: scan(particle, grid, segments=args.segments, entangled=True))
        t_kernel, _ = best_of(lambda setup=setup: fill(setup, setup[1].nphi))
        setups, nodes = candidate_nodes(setup, 0)
        per_op = t_kernel * 2 / grid.nphi / (setups + nodes) * 1e9  # 2 threads
        rates[nx] = grid.states / t_allowed
        rows.append(
            [
                f"scan raster {nx}x{nx}x{grid.nphi}",
                grid.states,
                f"{t_allowed:.3f}",
                f"{rates[nx] / 1e6:.1f}",
                f"{t_both / t_allowed:.2f}",
                "",
                "",
                "",
            ]
        )
        rows.append(
            [
                "  kernel, every slice",
                grid.states,
                f"{t_kernel:.3f}",
                f"{grid.states / t_kernel / 1e6:.1f}",
                "",
                f"{setups}",
                f"{nodes}",
                f"{per_op:.1f}",
            ]
        )
        if nx == 256:
            k = args.phi_direct
            t_direct, direct = best_of(lambda setup=setup, k=k: fill(setup, k, "direct"), repeat=1)
            assert np.array_equal(direct == 0, ds.allowed.values[:k]), "engines disagree"
            rate_direct = k * nx * nx / t_direct
            rows.append(
                [f"direct {nx}x{nx}x{k}", k * nx * nx, f"{t_direct:.3f}", f"{rate_direct / 1e6:.4f}", "", "", "", ""]
            )
    print(f"machine: {machine()}")
    print(f"particle: SeSP n={args.n:g}, opening=90 deg, N={args.segments}\n")
    thick = SeSP(n=args.n, opening=math.pi / 2, thickness=args.thickness)
    scan(thick, Grid(64, nphi=8), segments=args.segments)  # compile outside the timing
    thick_grid = Grid(256, nphi=args.nphi)
    t_thick, _ = best_of(lambda: scan(thick, thick_grid, segments=args.segments))
    t_thin, _ = best_of(lambda: scan(particle, thick_grid, segments=args.segments))
    rows.append([f"  thin, same run ({256}x{256})", thick_grid.states, f"{t_thin:.3f}",
                 f"{thick_grid.states / t_thin / 1e6:.1f}", "", "", "", ""])  # fmt: skip
    rows.append([f"thick D={args.thickness:g} b ({256}x{256})", thick_grid.states, f"{t_thick:.3f}",
                 f"{thick_grid.states / t_thick / 1e6:.1f}", "", "", "", ""])  # fmt: skip
    table(
        rows,
        [
            "engine / grid",
            "states",
            "seconds",
            "Mstates/s",
            "with entangled / allowed",
            "setups/phi",
            "nodes/phi",
            "ns/op (1 core)",
        ],
    )
    ratio = rates[256] / rate_direct
    hull_ratio = float(rows[0][4])
    print()
    met = "met" if rates[256] >= 50e6 else "NOT met"
    print(f"target 1  raster >= 50 Mstates/s at 256^2x128: {rates[256] / 1e6:.1f}  {met}")
    print(
        f"target 1  finer grid faster per state (512 vs 256): {rates[512] / rates[256]:.2f}x  "
        f"{'met' if rates[512] > rates[256] else 'NOT met'}"
    )
    print(f"target 1  entangled costs <= 3x allowed: {hull_ratio:.2f}x  {'met' if hull_ratio <= 3 else 'NOT met'}")
    print(f"target 2  raster / direct >= 1000x: {ratio:.0f}x  {'met' if ratio >= 1000 else 'NOT met'}")
    print("direct slices identical to raster slices: yes")
    thick_ratio = t_thick / t_thin
    met = "met" if thick_ratio <= 2 else "NOT met"
    print(f"target 6  thick (D = {args.thickness:g} b) costs <= 2x thin: {thick_ratio:.2f}x  {met}")


if __name__ == "__main__":
    main()
