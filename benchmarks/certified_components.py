"""Certified excluded components (sesp.certified) at the default resolution: counts, brackets, depths and times.

Each case is one call of :func:`sesp.certified.certified_components` at its defaults (ε = 1e-5 b, rim 1e-3 b, base
64). The ASP rows have exact answers: lens and body for 0 < Ψ < π, the lens's inscribed radius 1 − sin(Ψ/2), the lens
counted while that is at least ε + rim (until Ψ = 174.85°), none above π.
Run: ``python benchmarks/certified_components.py [n:degrees[:rim] ...]`` (rim in b; the cost of a lower one:
``2:90:1e-3 2:90:1e-4``).
"""

import math
import sys
import time

from _common import machine, table

from sesp import SeSP
from sesp.certified import certified_components

CASES = [(2, 90), (2, 179), (2, 181), (4, 170), (4, 176), (4, 178), (8, 0), (8, 120), (8, 170), (8, 175)]
CASES += [(10, 170), (10, 175)]


def main(cases):
    certified_components(SeSP(n=2, opening=math.radians(200)), resolution=1e-3)  # compile outside the timings
    rows = []
    for n, degrees, *rim in cases:
        start = time.perf_counter()
        found = certified_components(SeSP(n=n, opening=math.radians(degrees)), rim=rim[0] if rim else None)
        seconds = time.perf_counter() - start
        depths = " ".join(f"{c.depth:.2e}" for c in found.components)
        exact = f"{1 - math.sin(math.radians(degrees) / 2):.5f}" if n == 2 and degrees < 180 else ""
        rows.append(
            (n, degrees, f"{found.rim:.1e}", found.bracket, depths, exact, f"{found.evaluations}", f"{seconds:.1f}")
        )
        print(found, flush=True)
    print(machine())
    table(rows, ["n", "Ψ (deg)", "rim (b)", "count", "proved depths (b)", "exact lens", "cells", "s"])


if __name__ == "__main__":
    picked = [tuple(float(v) for v in a.split(":")) for a in sys.argv[1:]]
    main(picked or CASES)
