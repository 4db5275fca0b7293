"""`sesp.excluded_area` at its default rtol (1e-5) against exact orientation means: the ASP's smooth arcs at
Ψ = 90°, 180°, 270° (semi-analytic A_ex(φ), `sesp.exact.arc_excluded_area`, averaged by the periodic trapezoid
on 1024 and 2048 orientations and extrapolated), and closed superellipses (2A + P²/2π with the smooth curve's
area and perimeter). Prints the error, the bar, the settings the refinement reached and the time.

python benchmarks/excluded_area_rtol.py
"""

import math
import time

import numpy as np
from _common import machine, table

import sesp
from sesp.exact import arc_excluded_area, superellipse_area, superellipse_perimeter

RTOL = 1e-5


def arc_mean(opening: float) -> float:
    means = []
    for nphi in (1024, 2048):
        half = np.array([arc_excluded_area(2 * math.pi * k / nphi, opening, panels=100) for k in range(nphi // 2 + 1)])
        means.append(np.concatenate([half, half[1:-1][::-1]]).mean())
    return means[1] + (means[1] - means[0]) / 3  # the trapezoid's error falls as nphi⁻² (kinked A_ex(φ))


def closed_mean(particle) -> float:
    return 2 * superellipse_area(particle) + superellipse_perimeter(particle) ** 2 / (2 * math.pi)


def main():
    cases = [(f"ASP, opening {d} deg", sesp.SeSP(n=2, opening=math.radians(d)), None) for d in (90, 180, 270)]
    cases += [(f"closed n = {n}, aspect {a}", sesp.SeSP(n=n, aspect=a), None) for n, a in ((4, 1.0), (8, 1.5))]
    sesp.excluded_area(cases[0][1], rtol=None)  # compile outside the timings
    rows, met = [], True
    for name, particle, _ in cases:
        exact = arc_mean(particle.opening) if particle.n == 2 else closed_mean(particle)
        t0 = time.perf_counter()
        ds = sesp.excluded_area(particle, rtol=RTOL)
        seconds = time.perf_counter() - t0
        mean, bar = float(ds.mean_excluded_area), float(ds.mean_excluded_area_error)
        error = abs(mean / exact - 1)
        ok = error <= RTOL and abs(mean - exact) <= bar and ds.attrs["converged"]
        met &= bool(ok)
        settings = f"{ds.attrs['segments']}/{ds.attrs['nphi']}/{ds.attrs['rows']}"
        rows.append([name, f"{exact:.9f}", f"{mean:.9f}", f"{error:.1e}", f"{bar / mean:.1e}", settings,
                     f"{seconds:.2f}", "yes" if ok else "NO"])  # fmt: skip
    print(f"machine: {machine()}\n")
    table(rows, ["case", "exact b^2", "sesp b^2", "rel. error", "rel. bar", "segments/nphi/rows", "s", "ok"])
    print(f"\ntarget  every case within rtol {RTOL:g} and within its bar: {'met' if met else 'NOT met'}")


if __name__ == "__main__":
    main()
