"""The same commands timed on two installs of sesp, alternately in one run: the ratio after / before.

Each install is a Python interpreter with sesp installed (for example the virtual environments of two
checkouts). Every case runs ``--repeat`` times on each, alternating, after one untimed run that compiles the
kernels (a table's are compiled by the cases before it); the table gives the best wall time of each and the
speed ratio, time before / time after (above 1: faster after; the machines are noisy: compare, don't quote lone
seconds).

    python benchmarks/versions.py --before /path/to/old/venv/bin/python --after /path/to/new/venv/bin/python
"""

import argparse
import subprocess
import sys
import time

from _common import machine, table

CASES = {
    "sesp topology --n 4 --opening 176": ["-m", "sesp.cli", "-q", "topology", "--n", "4", "--opening", "176"],
    "sesp area --n 8 --opening 90": ["-m", "sesp.cli", "-q", "area", "--n", "8", "--opening", "90"],
    "third_virial(ASP 90°) at its defaults": [
        "-c",
        "import math; from sesp import SeSP; from sesp.virial import third_virial; "
        "third_virial(SeSP(n=2, opening=math.radians(90)))",
    ],
    "one table: n = 4, 0°-360°, 2 workers": [
        "-c",
        "from sesp import SeSP; from sesp.topology import transitions; transitions(SeSP(n=4), workers=2)",
    ],
}


def _wall(python, args) -> float:
    start = time.perf_counter()
    subprocess.run([python, *args], check=True, capture_output=True)
    return time.perf_counter() - start


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--before", required=True, help="the Python interpreter of the install before")
    ap.add_argument("--after", default=sys.executable, help="the Python interpreter of the install after")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cases", nargs="*", default=list(CASES), help="names of CASES to run")
    args = ap.parse_args()
    rows = []
    for name in args.cases:
        command = CASES[name]
        if not name.startswith("one table"):  # compile outside the timings (a table's compile is in the others)
            for python in (args.before, args.after):
                _wall(python, command)
        times = {"before": [], "after": []}
        for _ in range(args.repeat):
            for which in ("before", "after"):
                times[which].append(_wall(getattr(args, which), command))
        best = {k: min(v) for k, v in times.items()}
        speed = best["before"] / best["after"]
        rows.append((name, f"{best['before']:.2f}", f"{best['after']:.2f}", f"{speed:.3f}"))
        print(f"{name}: before {times['before']}, after {times['after']}", flush=True)
    print(machine())
    table(rows, ["case", "before s (best)", "after s (best)", "speed after / before (time before / after)"])


if __name__ == "__main__":
    main()
