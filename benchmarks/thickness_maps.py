"""The ASP at Ψ = 90°, thin and thick side by side: allowed-configuration maps and class areas.

Writes benchmarks/figures/asp90_thin_vs_thick.png (256² × 256 summaries, N = 256) and prints the area of
each position class for D/b = 0 and 0.1: thickness shrinks the entangled and spooning regions and grows
the excluded one.

    python benchmarks/thickness_maps.py [--thickness 0.1]
"""

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from _common import machine, table

from sesp import Grid, SeSP, plot
from sesp.dataset import cell_area
from sesp.regions import CLASSES, summarize

OUT = Path(__file__).resolve().parent / "figures" / "asp90_thin_vs_thick.png"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--thickness", type=float, default=0.1)
    args = ap.parse_args()
    thicknesses = (0.0, args.thickness)
    particles = [SeSP(n=2, opening=math.pi / 2, thickness=d) for d in thicknesses]
    box = Grid(256, nphi=256).resolve(2 + args.thickness + 1e-9)  # one box for both maps
    summaries = [summarize(p, box) for p in particles]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), layout="constrained")
    for ax, particle, summary in zip(axes, particles, summaries):
        plot.allowed_map(summary, ax=ax, particle=particle, colorbar=ax is axes[-1])
        ax.set_title(f"ASP, $\\Psi = 90°$, $D = {particle.thickness:g}\\,b$", fontsize=10)
    OUT.parent.mkdir(exist_ok=True)
    fig.savefig(OUT, dpi=130)
    rows = []
    for particle, summary in zip(particles, summaries):
        counts = np.bincount(summary.classes.values.ravel(), minlength=len(CLASSES)) * cell_area(summary)
        rows.append(
            [f"{particle.thickness:g}", *[f"{a:.4f}" for a in counts], f"{float(summary.excluded_area.mean()):.4f}"]
        )
    print(f"machine: {machine()}\nwrote {OUT}\n")
    table(rows, ["D (b)", *[f"{c} (b^2)" for c in CLASSES], "A_ex (b^2)"])


if __name__ == "__main__":
    main()
