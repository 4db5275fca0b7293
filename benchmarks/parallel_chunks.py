"""Certified counts with the kernels' positions handed out in small chunks against equal shares per thread.

The kernels over positions (depth certificates, exact windows, clearances) cost a hundred times more near
the curves than far from them, and the positions come in runs, so one equal share per thread leaves a thread
idle. Each case is counted both ways in one run, alternately; the table gives the times, their ratio, and
whether the cells and counts are identical (they must be: each position is written by one thread).

    python benchmarks/parallel_chunks.py [n:degrees ...]
"""

import math
import sys
import time

import numpy as np
from _common import machine, table

from sesp import SeSP
from sesp.certified import certified_components
from sesp.kernels import common

CASES = [(2, 90), (4, 90), (4, 170), (4, 176), (8, 45), (10, 160), (4, 2.4)]


def _counted(n, degrees, chunk):
    common.POSITIONS_PER_CHUNK = chunk
    start = time.perf_counter()
    found = certified_components(SeSP(n=n, opening=math.radians(degrees)))
    return found, time.perf_counter() - start


def main(cases):
    certified_components(SeSP(n=2, opening=math.radians(200)), resolution=1e-3)  # compile outside the timings
    chunk = common.POSITIONS_PER_CHUNK
    rows, total = [], np.zeros(2)
    for n, degrees in cases:
        equal, t_equal = _counted(n, degrees, 0)
        small, t_small = _counted(n, degrees, chunk)
        same = all(np.array_equal(equal.cells[k], small.cells[k]) for k in equal.cells)
        same &= (equal.low, equal.high) == (small.low, small.high)
        total += (t_equal, t_small)
        rows.append((f"{n:g}", f"{degrees:g}", small.bracket, small.evaluations, f"{t_equal:.1f}", f"{t_small:.1f}",
                     f"{t_small / t_equal:.2f}", "yes" if same else "NO"))  # fmt: skip
    common.POSITIONS_PER_CHUNK = chunk
    rows.append(("all", "", "", "", f"{total[0]:.1f}", f"{total[1]:.1f}", f"{total[1] / total[0]:.2f}", ""))
    print(machine())
    table(rows, ["n", "Ψ (deg)", "count", "cells", "equal shares (s)", f"chunks of {chunk} (s)", "ratio", "identical"])


if __name__ == "__main__":
    picked = [tuple(float(v) for v in a.split(":")) for a in sys.argv[1:]]
    main(picked or CASES)
