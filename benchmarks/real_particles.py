"""Certified counts of particles a granular physicist uses, at the defaults (ε = 1e-5 b, rim 1e-3 b, base 64).

Each case runs in its own process, stopped after ``--limit`` seconds (a count that is not done by then is
printed as such), with the kernels compiled beforehand by one small count of the same kind. Cases: the thin ASP
at 90° (for comparison), the same arc 0.05 b thick, a staple (three unit segments), a bent polyline (no mirror
symmetry) and the mixture of an n = 4 SeSP with it.

Run: ``python benchmarks/real_particles.py [--limit SECONDS] [name ...]``
"""

import argparse
import json
import subprocess
import sys
import time

from _common import machine, table

BENT = "Polyline([[-0.6, -0.3], [0.1, 0.2], [0.5, -0.4]])"
CASES = {
    "asp 90": "SeSP(n=2, opening=math.radians(90)), None",
    "asp 90, 0.05 b thick": "SeSP(n=2, opening=math.radians(90), thickness=0.05), None",
    "staple": "Polyline([[0.5, -0.5], [-0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]]), None",
    "bent": f"{BENT}, None",
    "n = 4 at 100° with bent": f"SeSP(n=4, opening=math.radians(100)), {BENT}",
}

ONE = """
import json, math, sys, time
from sesp import Polyline, SeSP, certified_components
particle, other = {case}
certified_components(particle, other, resolution=1e-2, progress=False)  # compiled outside the timing
start = time.perf_counter()
found = certified_components(particle, other, progress=False)
said = found.to_dict()
print(json.dumps({{"seconds": time.perf_counter() - start, "cells": said["cells"],
                  "bracket": str(found.low) if found.low == found.high else f"{{found.low}}-{{found.high}}",
                  "components": [(c["depth"], c["status"]) for c in said["components"]]}}))
"""


def run(case: str, limit: float) -> tuple:
    start = time.perf_counter()
    try:
        done = subprocess.run(
            [sys.executable, "-c", ONE.format(case=case)], capture_output=True, text=True, timeout=limit, check=True
        )
    except subprocess.TimeoutExpired:
        return f"no count after {limit:.0f} s", "", "", f"> {limit:.0f}"
    got = json.loads(done.stdout.strip().splitlines()[-1])
    depths = "; ".join(f"{d:.3g} b ({status})" for d, status in got["components"])
    return got["bracket"], depths, got["cells"], f"{got['seconds']:.1f} ({time.perf_counter() - start:.0f} wall)"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=float, default=300.0, help="seconds per case (default 300)")
    parser.add_argument("names", nargs="*", help=f"cases (default all): {', '.join(CASES)}")
    args = parser.parse_args()
    rows = []
    for name, case in CASES.items():
        if args.names and name not in args.names:
            continue
        rows.append((name, *run(case, args.limit)))
        print(rows[-1], flush=True)
    print(machine())
    table(rows, ["particle", "count", "components: depth (status)", "cells", "s"])


if __name__ == "__main__":
    main()
