"""Target 5: the whole-paper sweep (n in {2, 4, 8, 10} x Ψ in 5° steps x all φ, 256 x 256 x 128).

Runs sweeps/exponent_opening_orientation.toml into a temporary folder and
reports the wall time (target < 2 minutes on 2 cores).

    python benchmarks/paper_sweep.py [--workers 1]
"""

import argparse
import tempfile
import time
from pathlib import Path

import xarray as xr
from _common import machine, peak_rss_mib, table

from sesp.sweep import run, warm_up

SWEEP = Path(__file__).resolve().parents[1] / "sweeps" / "exponent_opening_orientation.toml"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--workers", type=int, default=1)
    args = ap.parse_args()
    warm_up()
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        target = run(SWEEP, output=Path(tmp) / "out", workers=args.workers, progress=False)
        wall = time.perf_counter() - t0
        ds = xr.open_dataset(target)
        dims = dict(ds.excluded_area.sizes)
        ds.close()
    print(f"machine: {machine()}\n")
    table(
        [[SWEEP.name, str(dims), args.workers, f"{wall:.1f}", f"{peak_rss_mib():.0f}"]],
        ["sweep", "excluded_area dims", "workers", "wall s", "peak MiB (parent)"],
    )
    print(f"\ntarget 5  whole-paper sweep < 120 s: {wall:.1f} s  {'met' if wall < 120 else 'NOT met'}")


if __name__ == "__main__":
    main()
