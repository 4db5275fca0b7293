"""The exact oracles of docs/design.md §4 with the figures they give (the same checks as tests/test_measures.py).

python benchmarks/oracles.py
"""

import math

import numpy as np

from sesp import Grid, Polyline, SeSP, scan
from sesp.measures import convex_excluded_area, kinematic_integral, lattice_excluded_area, monte_carlo

needle = Polyline([[-1.0, 0.0], [1.0, 0.0]])
for nx in (512, 511):
    ds = scan(needle, Grid(nx, nphi=16))
    a = lattice_excluded_area(ds, by="phi").values
    ex = 4 * np.abs(np.sin(ds.phi.values))
    g = np.abs(np.sin(ds.phi.values)) > 0.3
    err = np.max(np.abs(a[g] / ex[g] - 1))
    print(f"needles nx={nx}: max rel err {err:.2e} (|sin phi| > 0.3); A_ex(0) = {a[0]:.4f} b^2")
ds = scan(SeSP(n=2), Grid(256, nphi=8), segments=256)
ref = convex_excluded_area(SeSP(n=2).polyline(256))
err = np.max(np.abs(lattice_excluded_area(ds, by="phi").values / ref - 1))
print(
    f"closed circle: max |A_ex(phi)/(2A+P^2/2pi) - 1| = {err:.2e}; (2A+P^2/2pi)/4pi - 1 = {ref / (4 * math.pi) - 1:.2e}"
)
for n in (4, 8):
    ds = scan(SeSP(n=n), Grid(512, nphi=64), segments=256)
    err = lattice_excluded_area(ds) / convex_excluded_area(SeSP(n=n).polyline(256)) - 1
    print(f"closed n={n} nx=512: rel err vs 2A+P^2/2pi = {err:+.2e}")
for n in (2, 8):
    m, e = kinematic_integral(scan(SeSP(n=n, opening=math.pi / 2), Grid(512, nphi=128), segments=256, crossings=True))
    print(f"Poincare n={n}: measured {m:.4f}, 4 L1 L2 = {e:.4f}, rel err {m / e - 1:+.2e}")
p = SeSP(n=2, opening=math.pi / 2)
g = lattice_excluded_area(scan(p, Grid(512, nphi=128), segments=64))
mc = monte_carlo(p, samples=100_000, segments=64, seed=2024)
mc_area, mc_error = float(mc.excluded_area), float(mc.excluded_area_error)
print(f"Monte Carlo: {mc_area:.4f} +- {mc_error:.4f} vs grid {g:.4f}: z = {(mc_area - g) / mc_error:+.2f}")
