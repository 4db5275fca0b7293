"""The first ordering transition of the isotropic state over the opening Ψ, for n = 2, 4 and 8 (second-virial
Onsager theory: `sesp.onsager.first_transition` on `sesp.excluded_area` at rtol 1e-4), as a table, a netCDF
file and the figure `benchmarks/figures/phase_diagram.png`.

python benchmarks/phase_diagram.py [STEP_DEGREES]
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

HERE = Path(__file__).parent
STEP = float(sys.argv[1]) if len(sys.argv) > 1 else 15.0
NS = (2, 4, 8)


def main():
    openings = np.radians(np.arange(0.0, 360.0, STEP))
    shape = (len(NS), len(openings))
    out = {name: np.full(shape, np.nan) for name in ("transition_density", "ordered_density", "seconds")}
    order, continuous = np.zeros(shape, dtype=int), np.zeros(shape, dtype=int)
    rows = []
    for i, n in enumerate(NS):
        for j, opening in enumerate(openings):
            t0 = time.perf_counter()
            found = first_transition(sesp.excluded_area(sesp.SeSP(n=n, opening=opening), rtol=1e-4))
            out["seconds"][i, j] = time.perf_counter() - t0
            out["transition_density"][i, j], out["ordered_density"][i, j] = found["density"], found["ordered_density"]
            order[i, j], continuous[i, j] = found["order"], found["continuous"]
            kind = "-" if not found["order"] else ("continuous" if found["continuous"] else "first order")
            gap = found["ordered_density"] - found["density"]
            name = ORDER_NAMES.get(found["order"], "none")
            gap_text = f"{gap:.2g}" if gap > 0 else "-"
            rows.append([f"{n}", f"{math.degrees(opening):.0f}", name, kind, f"{found['density']:.4g}", gap_text,
                         f"{out['seconds'][i, j]:.1f}"])  # fmt: skip
    ds = xr.Dataset(
        {
            "transition_density": (("n", "opening"), out["transition_density"], {"units": "1", "in_units_of": "b^-2"}),
            "ordered_density": (("n", "opening"), out["ordered_density"], {"units": "1", "in_units_of": "b^-2"}),
            "transition_order": (("n", "opening"), order, {"long_name": "k of the first order (0: none)"}),
            "continuous": (("n", "opening"), continuous),
        },
        coords={"n": list(NS), "opening": ("opening", openings, {"units": "rad"})},
    )
    ds.to_netcdf(HERE / "figures" / "phase_diagram.nc")
    fig = sesp.plot.phase_diagram(ds)
    sesp.plot.save_figure(fig, HERE / "figures" / "phase_diagram.png")
    print(f"machine: {machine()}\n")
    table(rows, ["n", "opening deg", "first order", "transition", "density b^-2", "gap b^-2", "s"])
    print(f"\n{len(rows)} points in {out['seconds'].sum():.0f} s; figure: benchmarks/figures/phase_diagram.png")


if __name__ == "__main__":
    main()
