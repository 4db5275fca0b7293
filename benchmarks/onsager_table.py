"""Second virial coefficient, orientational spectrum and the leading Onsager instability of SeSPs.

For n = 2, 4, 8, 10 at Ψ = 0°, 90°, 180°, 270°: A_ex(φ) from shifted lattices (256² × 256, N = 256),
then B₂ = ⟨A_ex⟩/2, a₁, a₂, a₄ with error bars, the order that goes unstable first and its
ρ*⟨A_ex⟩ (sesp.onsager). The thin-needle check ρ*₂⟨A_ex⟩ = 3 heads the table.

    python benchmarks/onsager_table.py [--nx 256] [--nphi 256]
"""

import argparse
import math
import time

from _common import machine, table

from sesp import Grid, Polyline, SeSP
from sesp.measures import shifted_excluded_area
from sesp.onsager import ORDER_NAMES, instabilities, orientational_spectrum, second_virial


def row(label, area):
    spectrum = orientational_spectrum(area, 6)
    found = instabilities(area)
    k = int(found.leading_order)

    def coeff(j):
        return f"{float(spectrum.a.sel(k=j)):+.4f} ± {float(spectrum.a_error.sel(k=j)):.1e}"

    if k:
        lead = f"{ORDER_NAMES.get(k, k)} (k={k})"
        reduced = f"{float(found.reduced_density.sel(k=k)):.3f} ± {float(found.reduced_density_error.sel(k=k)):.1e}"
    else:
        lead, reduced = "none", "-"
    return [label, f"{float(second_virial(area)):.4f}", coeff(1), coeff(2), coeff(4), lead, reduced]


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--nx", type=int, default=256)
    ap.add_argument("--nphi", type=int, default=256)
    args = ap.parse_args()
    grid = Grid(args.nx, nphi=args.nphi)
    t0 = time.perf_counter()
    rows = [row("needle L = 2 (exact: B2 = 4/pi = 1.2732, a2 = -1.6977, 3.000)",
                shifted_excluded_area(Polyline([[-1.0, 0.0], [1.0, 0.0]]), Grid(512, nphi=args.nphi)))]  # fmt: skip
    for n in (2, 4, 8, 10):
        for degrees in (0, 90, 180, 270):
            area = shifted_excluded_area(SeSP(n=n, opening=math.radians(degrees)), grid)
            rows.append(row(f"n = {n:g}, Psi = {degrees} deg", area))
    print(f"machine: {machine()}")
    print(f"A_ex(phi): shifted lattices {args.nx}^2 x {args.nphi}, N = 256; {time.perf_counter() - t0:.1f} s in all\n")
    table(rows, ["particle", "B2 (b^2)", "a1 (b^2)", "a2 (b^2)", "a4 (b^2)", "first unstable", "rho* <A_ex>"])


if __name__ == "__main__":
    main()
