"""Worker processes with all of numba's threads each, waiting without spinning, against an equal share each.

Sweeps and the search over Ψ run their jobs in worker processes (``sesp.workers.start_pool``). With an equal
share of the threads each, the last job left running (the last sweep point, the end of a bisection chain) uses
one core of two. With all the threads each, it uses both; but OpenMP's threads spin between parallel loops by
default, so while two workers run they take the cores from each other. ``start_pool`` gives each worker all the
threads and the passive wait (unless ``OMP_WAIT_POLICY`` is set). Each job is run the three ways in one run; the
table gives the times, the ratios to the equal shares, and whether the results are identical (they must be:
each item is written by one thread).

    python benchmarks/worker_threads.py [--chain]

The sweep: n ∈ {4, 10} × Ψ ∈ {60°, 120°, 160°}, keeping topology, at the sweep defaults, 2 workers. ``--chain``
adds the bisection of n = 10's change at Ψ → 0 (0°-4.8° to 0.3° at the default ε, 256 segments; minutes).
"""

import argparse
import math
import os
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
import xarray as xr
from _common import machine, table

import sesp.sweep
import sesp.topology
from sesp import SeSP
from sesp.workers import start_pool

MODES = {"equal shares, spinning": (False, False), "all threads, spinning": (True, False),
         "all threads, passive": (True, True)}  # fmt: skip
SWEEP = """[sweep]
name = "topo"
angles = "degrees"
[particle]
n = [4, 10]
opening = [60, 120, 160]
[output]
keep = ["topology"]
"""


def _pools(every, passive):
    """``start_pool`` with every thread or an equal share per worker, waiting passively or as OpenMP does."""

    def pool(workers, initializer=None, initargs=(), on_orphan=None):
        threads = None if every else max(1, numba.get_num_threads() // workers)
        return start_pool(workers, initializer, initargs, threads=threads, passive=passive, on_orphan=on_orphan)

    return pool


def _sweep(folder):
    path = Path(folder) / "topo.toml"
    path.write_text(SWEEP)
    out = sesp.sweep.run(path, output=Path(folder) / "out", workers=2, progress=False)
    with xr.open_dataset(out) as ds:
        return {k: ds[k].values.copy() for k in ds.data_vars}


def _chain():
    found = sesp.topology.transitions(SeSP(n=10), (0.0, math.radians(4.8)), step=math.radians(4.8),
                                      width=math.radians(0.3), workers=2)  # fmt: skip
    return {round(o, 9): (f.low, f.high) for o, f in found.counts.items()}


def _same(a, b):
    """Whether two jobs' results are identical: every stored array of the sweep (NaN where no component is
    equal to NaN), or the counts at every opening."""
    if all(isinstance(v, np.ndarray) for v in a.values()):
        return a.keys() == b.keys() and all(np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f") for k in a)
    return a == b


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--chain", action="store_true", help="also the bisection chain of n = 10 near 0° (minutes)")
    args = ap.parse_args()
    if os.environ.get("OMP_WAIT_POLICY"):
        raise SystemExit("unset OMP_WAIT_POLICY: the 'spinning' modes are OpenMP's default")
    jobs = {"sweep, 6 points": None, "chain, n = 10 at 0°-4.8°": _chain} if args.chain else {"sweep, 6 points": None}
    rows = []
    for name, job in jobs.items():
        times, results = {}, {}
        for mode, (every, passive) in MODES.items():
            sesp.sweep.start_pool = sesp.topology.start_pool = _pools(every, passive)
            with tempfile.TemporaryDirectory() as folder:
                start = time.perf_counter()
                results[mode] = _sweep(folder) if job is None else job()
                times[mode] = time.perf_counter() - start
        first = next(iter(MODES))
        for mode in MODES:
            same = _same(results[first], results[mode])
            rows.append([name, mode, f"{times[mode]:.1f}", f"{times[mode] / times[first]:.2f}",
                         "yes" if same else "NO"])  # fmt: skip
    print(machine())
    table(rows, ["job", "workers' threads", "seconds", "ratio", "identical"])


if __name__ == "__main__":
    main()
