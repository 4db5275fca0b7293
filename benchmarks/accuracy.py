"""Per-orientation accuracy of A_ex(φ): scanlines against the shifted lattice; the smooth ASP; error bars.

For n = 2, 4, 8, 10 at Ψ = 90° and 180° (N = 256 segments, 128 orientations), the maximum over φ of the
relative error of A_ex(φ) against a converged reference, and the time, for

* ``scanline_excluded_area`` at its default (512 line spacings, extrapolated), and
* ``shifted_excluded_area`` on its default 256² lattice.

The reference is the scanline quadrature at 8192 spacings; the first table checks it, and the default,
against the exact A_ex(φ) of closed convex superellipses (the area of K ⊕ −R_φK, the convex hull of all
vertex differences). The smooth ASP (``smooth_excluded_area``: 256, 128 and 64 segments, 2048 line
spacings) is compared with two smooth circular arcs (``sesp.exact.arc_excluded_area``) at Ψ = 90°, 180°,
270°. The coverage table counts how often the reported error bar of A_ex(φ) is at least the actual error,
against the exact results (closed shapes, two aspects) and against the reference (open shapes).

    python benchmarks/accuracy.py [--nphi 128]
"""

import argparse
import math

import numpy as np
from _common import best_of, machine, table

from sesp import Grid, Pair, SeSP
from sesp.exact import arc_excluded_area, minkowski_excluded_area
from sesp.measures import (
    SCANLINE_ROWS,
    SMOOTH_ROWS,
    scanline_excluded_area,
    shifted_excluded_area,
    smooth_excluded_area,
)

SEGMENTS = 256
REFERENCE_ROWS = 8192


def max_relative(values, reference) -> float:
    return float(np.max(np.abs(values / reference - 1)))


def closed_check(nphi):
    rows, cover = [], []
    for n in (2, 4, 8, 10):
        for aspect in (1.0, 1.7):
            particle = SeSP(n=n, aspect=aspect)
            ds = scanline_excluded_area(particle, nphi=nphi, segments=SEGMENTS)
            vertices = Pair.of(particle, segments=SEGMENTS).vertices1[:-1]
            exact = np.array([minkowski_excluded_area(vertices, phi) for phi in ds.phi.values])
            ref = scanline_excluded_area(particle, nphi=nphi, segments=SEGMENTS, rows=REFERENCE_ROWS)
            cover.append(ds.excluded_area_error.values >= np.abs(ds.excluded_area.values - exact))
            cover.append(ref.excluded_area_error.values >= np.abs(ref.excluded_area.values - exact))
            rows.append(
                [
                    f"closed n={n} aspect={aspect:g}",
                    f"{max_relative(ds.excluded_area.values, exact):.1e}",
                    f"{max_relative(ref.excluded_area.values, exact):.1e}",
                ]
            )
    return rows, np.concatenate(cover)


def open_comparison(nphi):
    rows, cover, ratios = [], [], []
    grid = Grid(256, nphi=nphi)
    for n in (2, 4, 8, 10):
        for degrees in (90, 180):
            particle = SeSP(n=n, opening=math.radians(degrees))
            ref = scanline_excluded_area(particle, nphi=nphi, segments=SEGMENTS, rows=REFERENCE_ROWS)
            exact = ref.excluded_area.values
            t_line, line = best_of(lambda p=particle: scanline_excluded_area(p, nphi=nphi, segments=SEGMENTS))
            t_lattice, lattice = best_of(lambda p=particle: shifted_excluded_area(p, grid, segments=SEGMENTS))
            cover.append(line.excluded_area_error.values >= np.abs(line.excluded_area.values - exact))
            ratios.append(t_line / t_lattice)
            rows.append(
                [
                    f"n={n} Ψ={degrees}°",
                    f"{max_relative(line.excluded_area.values, exact):.1e}",
                    f"{float(np.max(line.excluded_area_error.values / exact)):.1e}",
                    f"{t_line:.3f}",
                    f"{max_relative(lattice.values, exact):.1e}",
                    f"{t_lattice:.3f}",
                    f"{t_line / t_lattice:.2f}",
                ]
            )
    return rows, np.concatenate(cover), ratios


def coverage_by_spacing(nphi, spacings=(128, 512, 2048), openings=(45, 90, 180, 270)):
    """Per spacing: the fraction of per-φ errors (n = 2, 4, 8, 10 at the given openings, against the
    reference) that the error bar covers, the largest and median error in units of its bar (bars above
    rounding), and the bars at rounding level (all four trapezoid levels agreeing: a length piecewise linear
    between the coarsest lines) under a nonzero error."""
    rows = []
    for spacing in spacings:
        cover, ratio = [], []
        for n in (2, 4, 8, 10):
            for degrees in openings:
                particle = SeSP(n=n, opening=math.radians(degrees))
                ref = scanline_excluded_area(particle, nphi=nphi, segments=SEGMENTS, rows=REFERENCE_ROWS)
                ds = scanline_excluded_area(particle, nphi=nphi, segments=SEGMENTS, rows=spacing)
                error = np.abs(ds.excluded_area.values - ref.excluded_area.values)
                bar = ds.excluded_area_error.values
                cover.append(bar >= error)
                some = bar > 1e-12 * ref.excluded_area.values  # a bar above rounding
                ratio.append(np.where(some, error / np.where(some, bar, 1.0), np.where(error > 0, np.inf, 0.0)))
        cover, ratio = np.concatenate(cover), np.concatenate(ratio)
        finite = ratio[np.isfinite(ratio)]
        rows.append([spacing, cover.size, f"{cover.mean():.3f}", f"{finite.max():.2f}", f"{np.median(finite):.3f}",
                     int(np.isinf(ratio).sum())])  # fmt: skip
    return rows


def smooth_asp(nphi, rows=SMOOTH_ROWS):
    """The smooth ASP's orientation mean (extrapolated in N) against two smooth arcs, at the same φ; and
    whether each per-φ error bar covers the semi-analytic A_ex(φ)."""
    out, cover = [], []
    for degrees in (90, 180, 270):
        opening = math.radians(degrees)
        seconds, ds = best_of(
            lambda o=opening: smooth_excluded_area(SeSP(n=2, opening=o), nphi=nphi, rows=rows, segments=SEGMENTS),
            repeat=1,
        )
        exact = np.array([arc_excluded_area(phi, opening, panels=300) for phi in ds.phi.values])
        cover.append(ds.excluded_area_error.values >= np.abs(ds.excluded_area.values - exact))
        mean, bar = float(ds.mean_excluded_area), float(ds.mean_excluded_area_error)
        out.append(
            [f"Ψ={degrees}°", f"{exact.mean():.7f}", f"{mean:.7f}", f"{mean / exact.mean() - 1:+.1e}",
             f"{bar / exact.mean():.1e}", f"{seconds:.2f}"]
        )  # fmt: skip
    return out, np.concatenate(cover)


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--nphi", type=int, default=128)
    args = ap.parse_args()
    scanline_excluded_area(SeSP(), nphi=4, rows=16, segments=16)  # compile outside the timing
    shifted_excluded_area(SeSP(), Grid(16, nphi=4), segments=16)
    print(f"machine: {machine()}")
    print(f"N = {SEGMENTS} segments, {args.nphi} orientations; reference: scanlines at {REFERENCE_ROWS} spacings\n")

    closed_rows, closed_cover = closed_check(args.nphi)
    table(
        closed_rows, ["exact A_ex(φ) (K ⊕ −R_φK)", f"scanline {SCANLINE_ROWS}: max rel err", "reference: max rel err"]
    )
    print()
    open_rows, open_cover, ratios = open_comparison(args.nphi)
    table(
        open_rows,
        ["shape", f"scanline {SCANLINE_ROWS}: max rel err", "its max error bar (rel)", "s",
         "shifted 256²: max rel err", "s", "time scanline / shifted"],
    )  # fmt: skip
    print()
    smooth_rows, smooth_cover = smooth_asp(args.nphi)
    table(
        smooth_rows,
        ["smooth ASP, mean over φ", "semi-analytic (b²)", "smooth_excluded_area", "rel err", "error bar (rel)", "s"],
    )
    print()
    table(
        [
            ["closed convex, against exact (default and reference)", closed_cover.size, f"{closed_cover.mean():.3f}"],
            ["open Ψ = 90°, 180°, against the reference", open_cover.size, f"{open_cover.mean():.3f}"],
            ["smooth ASP Ψ = 90°, 180°, 270°, against the semi-analytic arcs", smooth_cover.size,
             f"{smooth_cover.mean():.3f}"],
        ],
        ["error-bar coverage of A_ex(φ)", "cases", "fraction covered"],
    )  # fmt: skip
    print()
    table(
        coverage_by_spacing(64),
        ["line spacings (n = 2, 4, 8, 10; Ψ = 45°, 90°, 180°, 270°; 64 φ)", "cases", "fraction covered",
         "largest error / bar", "median error / bar", "bar ~ 0, error > 0"],
    )  # fmt: skip
    worst_smooth = max(abs(float(r[3])) for r in smooth_rows)
    worst = max(float(r[1]) for r in open_rows)
    print(f"\ntarget  per-φ relative error <= 1e-3 at every φ (open shapes): worst {worst:.1e}  "
          f"{'met' if worst <= 1e-3 else 'NOT met'}")  # fmt: skip
    print(f"target  time <= shifted 256² run: scanline / shifted {min(ratios):.2f}-{max(ratios):.2f}x  "
          f"{'met' if max(ratios) <= 1.0 else 'NOT met'}")  # fmt: skip
    print(f"target  smooth ASP mean within 1e-5 of the semi-analytic value: worst {worst_smooth:.1e}  "
          f"{'met' if worst_smooth <= 1e-5 else 'NOT met'}")  # fmt: skip


if __name__ == "__main__":
    main()
