"""Where the excluded island vanishes: its area against Ψ, and a power-law fit.

For n = 4 and 8 the island (the certified excluded component right of the
centre, apart from the body) is measured at resolution ε (the middle of its
certified area bracket), and its area fitted to c · (Ψ_c − Ψ)^p; the fit
shows where it vanishes. For the ASP (n = 2) the exact island is the lens
(π − Ψ) − sin Ψ, Ψ_c = π.

    python benchmarks/island.py [--resolution 1e-4]
"""

import argparse
import math

import numpy as np
from _common import machine, table
from scipy.optimize import curve_fit

from sesp import SeSP
from sesp.certified import certified_components

OPENINGS = {4: (110, 125, 135, 140, 145), 8: (90, 110, 120, 125, 130, 140)}


def island_area(n, degrees, resolution):
    """b²: the certified area of the component right of the centre (the island), NaN if none."""
    found = certified_components(SeSP(n=n, opening=math.radians(degrees)), resolution=resolution)
    right = [c for c in found.components if c.box[0] > 0]
    return float(0.5 * (right[0].area + right[0].area_bound)) if right else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--resolution", type=float, default=1e-4, help="ε, b")
    args = ap.parse_args()
    rows = []
    for n, openings in OPENINGS.items():
        areas = np.array([island_area(n, d, args.resolution) for d in openings])
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
    print(f"machine: {machine()}; certified at resolution {args.resolution:g} b\n")
    table(rows, ["shape", "island area (b^2) at Psi (deg)", "c", "p", "Psi_c (deg)"])


if __name__ == "__main__":
    main()
