"""B₃ from the overlap indicators (`sesp.virial.third_virial`): exact anchors, and the ASP at Ψ = 90° against
Monte Carlo on sesp's state-by-state overlap test, with the time each needs for the same error bar.

python benchmarks/third_virial.py
"""

import math
import sys

from _common import machine, table

from sesp import Polyline, SeSP
from sesp.virial import third_virial, third_virial_monte_carlo

DISKS = 4 / 3 - math.sqrt(3) / math.pi
SQUARE = Polyline([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]])
SAMPLES = int(sys.argv[1]) if len(sys.argv) > 1 else 200_000


def main():
    third_virial(SeSP(n=2), rtol=None, nodes=41, nphi=4)  # compile outside the timings
    rows, met = [], True
    for name, call, exact in [
        ("thin rings, 301 nodes", lambda: third_virial(SeSP(n=2), rtol=None, nodes=301, nphi=4, segments=512), DISKS),
        ("thin rings, 401 nodes", lambda: third_virial(SeSP(n=2), rtol=None, nodes=401, nphi=4, segments=512), DISKS),
        ("parallel squares, 201 nodes", lambda: third_virial(SQUARE, orientations="fixed", rtol=None, nodes=201), 0.75),
        ("parallel squares, 401 nodes", lambda: third_virial(SQUARE, orientations="fixed", rtol=None, nodes=401), 0.75),
    ]:
        b = call()
        ratio, bar = float(b.reduced_third_virial), float(b.reduced_third_virial_error)
        ok = abs(ratio - exact) < 1e-3 and abs(ratio - exact) <= bar
        met &= ok
        rows.append([name, f"{exact:.7f}", f"{ratio:.7f}", f"{ratio - exact:+.1e}", f"{bar:.1e}",
                     f"{b.attrs['seconds']:.1f}", "yes" if ok else "NO"])  # fmt: skip
    print(f"machine: {machine()}\n")
    table(rows, ["B3/B2^2", "exact", "sesp", "error", "bar", "s", "ok"])
    print(f"\ntarget  anchors within 1e-3 and their bars: {'met' if met else 'NOT met'}\n")

    asp = SeSP(n=2, opening=math.pi / 2)
    lattice = third_virial(asp, rtol=None, nodes=201, nphi=32)
    sampled = third_virial_monte_carlo(asp, samples=SAMPLES, seed=1)
    b3, bar = float(lattice.third_virial_coefficient), float(lattice.third_virial_coefficient_error)
    mc, se = float(sampled.third_virial_coefficient), float(sampled.third_virial_coefficient_error)
    t_lattice, t_mc = lattice.attrs["seconds"], sampled.attrs["seconds"]
    t_mc_same = t_mc * (se / bar) ** 2  # Monte Carlo's error falls as 1/sqrt(samples)
    agree = abs(b3 - mc) <= 3 * se + bar
    table(
        [
            ["lattice, 201 nodes, nphi 32", f"{b3:.4f}", f"{bar:.3f} (bar)", f"{t_lattice:.1f}"],
            [f"Monte Carlo, {SAMPLES} samples", f"{mc:.4f}", f"{se:.3f} (s.e.)", f"{t_mc:.1f}"],
        ],
        ["ASP, 90 deg: B3 (b^4)", "value", "error", "s"],
    )
    print(f"\nagreement within 3 standard errors plus the lattice's bar: {'yes' if agree else 'NO'}"
          f" (difference {abs(b3 - mc):.3f})")  # fmt: skip
    print(f"Monte Carlo to the lattice's error bar: {t_mc_same:.0f} s, {t_mc_same / t_lattice:.1f}x the lattice's time")


if __name__ == "__main__":
    main()
