"""Where the excluded island vanishes: its area against Ψ, and a power-law fit.

For n = 4 and 8 the island (the excluded component on the +x axis, apart
from the main body) is measured on a 512 x 512 x 1024 grid, and its area fitted
to c · (Ψ_c − Ψ)^p. On a finite grid the island is lost once it is thinner
than a few cells, before it truly vanishes; the fit shows where it vanishes.
For the ASP (n = 2) the exact island is the lens (π − Ψ) − sin Ψ, Ψ_c = π.

    python benchmarks/island.py [--nx 512]
"""

import argparse
import math

import numpy as np
from _common import machine, table
from scipy.optimize import curve_fit

from sesp import Grid, SeSP
from sesp.regions import summarize
from sesp.topology import excluded_components

OPENINGS = {4: (110, 125, 135, 140, 145), 8: (90, 110, 120, 125, 130, 140)}


def island_area(n, degrees, nx):
    s = summarize(SeSP(n=n, opening=math.radians(degrees)), Grid(nx, nphi=2 * nx), entangled=False)
    comps = excluded_components(s)
    row = int(np.argmin(np.abs(s.y.values)))
    x = s.x.values
    right = set(comps.labels[row, (x > 0.2) & (x < 1.3)].tolist()) - {0}
    left = set(comps.labels[row, x < -0.2].tolist()) - {0}
    island = sorted(right - left)
    return float(comps.areas[island[0] - 1]) if island else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--nx", type=int, default=512)
    args = ap.parse_args()
    rows = []
    for n, openings in OPENINGS.items():
        areas = np.array([island_area(n, d, args.nx) for d in openings])
        psi = np.radians(openings)

        def law(x, c, psi_c, p):
            return c * np.clip(psi_c - x, 1e-9, None) ** p

        (c, psi_c, p), cov = curve_fit(law, psi, areas, p0=(0.05, math.pi, 3), maxfev=20000)
        rows.append(
            [
                f"n={n}",
                " ".join(f"{d}:{a:.4f}" for d, a in zip(openings, areas)),
                f"{c:.3f}",
                f"{p:.2f}",
                f"{math.degrees(psi_c):.1f} +- {math.degrees(math.sqrt(cov[1, 1])):.1f}",
            ]
        )
    print(f"machine: {machine()}; grid {args.nx}^2 x {2 * args.nx}\n")
    table(rows, ["shape", "island area (b^2) at Psi (deg)", "c", "p", "Psi_c (deg)"])


if __name__ == "__main__":
    main()
