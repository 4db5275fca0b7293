"""The first ordering transition of the isotropic state over the opening Ψ, for n = 2, 4 and 8 (second-virial
Onsager theory: `sesp.onsager.first_transition` on `sesp.excluded_area` at rtol 1e-4), as a table, a netCDF
file and the figure `benchmarks/figures/phase_diagram.png`. With a thickness D (b) the particles are thick and
the Parsons–Lee densities are given too (`first_transition(..., particle_area=a)`), in
`benchmarks/figures/phase_diagram_thick.png`.

python benchmarks/phase_diagram.py [STEP_DEGREES [THICKNESS]]
"""

import math
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np
import xarray as xr
from _common import machine, table

import sesp
from sesp.onsager import ORDER_NAMES, first_transition
from sesp.units import quantity

HERE = Path(__file__).parent
STEP = float(sys.argv[1]) if len(sys.argv) > 1 else 15.0
THICKNESS = float(sys.argv[2]) if len(sys.argv) > 2 else 0.0
NS = (2, 4, 8)
NAME = "phase_diagram_thick" if THICKNESS else "phase_diagram"


def _plain(found) -> dict:
    """The first transition's numbers: order, density, ordered density, continuous."""
    return {
        "order": int(found.transition_order), "density": float(found.transition_density),
        "ordered_density": float(found.ordered_density), "continuous": bool(found.continuous),
    }  # fmt: skip


def main():
    openings = np.radians(np.arange(0.0, 360.0, STEP))
    shape = (len(NS), len(openings))
    names = ("transition_density", "ordered_density", "parsons_lee_transition_density", "parsons_lee_ordered_density")
    out = {name: np.full(shape, np.nan) for name in (*names, "seconds")}
    order, continuous = np.zeros(shape, dtype=int), np.zeros(shape, dtype=int)
    rows = []
    for i, n in enumerate(NS):
        for j, opening in enumerate(openings):
            t0 = time.perf_counter()
            particle = sesp.SeSP(n=n, opening=opening, thickness=THICKNESS)
            area = sesp.excluded_area(particle, rtol=1e-4)
            found = _plain(first_transition(area))
            parsons_lee = (
                _plain(first_transition(area, particle_area=sesp.onsager.particle_area(particle)))
                if THICKNESS
                else found
            )
            out["seconds"][i, j] = time.perf_counter() - t0
            out["transition_density"][i, j], out["ordered_density"][i, j] = found["density"], found["ordered_density"]
            out["parsons_lee_transition_density"][i, j] = parsons_lee["density"]
            out["parsons_lee_ordered_density"][i, j] = parsons_lee["ordered_density"]
            order[i, j], continuous[i, j] = found["order"], found["continuous"]
            kind = "-" if not found["order"] else ("continuous" if found["continuous"] else "first order")
            gap = found["ordered_density"] - found["density"]
            name = ORDER_NAMES.get(found["order"], "none")
            gap_text = f"{gap:.2g}" if gap > 0 else "-"
            row = [f"{n}", f"{math.degrees(opening):.0f}", name, kind, f"{found['density']:.4g}", gap_text]
            if THICKNESS:
                pl_gap = parsons_lee["ordered_density"] - parsons_lee["density"]
                row += [f"{parsons_lee['density']:.4g}", f"{pl_gap:.2g}" if pl_gap > 0 else "-"]
            rows.append([*row, f"{out['seconds'][i, j]:.1f}"])
    ds = xr.Dataset(
        {
            **{name: (("n", "opening"), out[name], quantity(-2, name.replace("_", " "))) for name in names},
            "transition_order": (("n", "opening"), order, {"long_name": "k of the first order (0: none)"}),
            "continuous": (("n", "opening"), continuous),
        },
        coords={"n": list(NS), "opening": ("opening", openings, {"units": "rad"})},
        attrs={"thickness": THICKNESS},
    )
    ds.to_netcdf(HERE / "figures" / f"{NAME}.nc")
    fig = sesp.plot.phase_diagram(ds)
    sesp.plot.save_figure(fig, HERE / "figures" / f"{NAME}.png")
    print(f"machine: {machine()}\n")
    if THICKNESS:
        print(f"thickness D = {THICKNESS:g} b; Parsons-Lee densities beside the second-virial ones\n")
    header = ["n", "opening deg", "first order", "transition", "density b^-2", "gap b^-2"]
    header += ["Parsons-Lee b^-2", "its gap b^-2"] if THICKNESS else []
    table(rows, [*header, "s"])
    print(f"\n{len(rows)} points in {out['seconds'].sum():.0f} s; figure: benchmarks/figures/{NAME}.png")


if __name__ == "__main__":
    main()
