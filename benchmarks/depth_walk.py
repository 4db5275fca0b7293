"""Depth walks with and without lengthened pairs where the widest pair is r apart: intervals, time, answers.

The positions are those a certified count proves at ε + h: the centres of its in-cells (h their half-diagonal).
Each walk (:func:`sesp.kernels.depth.certified_deep`, two end points tried, fallback 1e-9 b, four intervals per
vertex) runs twice in one process, with ``lengthen`` off and on, and the table gives the wall time of each
(best of 3), their ratio, the median number of intervals a walk takes (on a sample, the least budget at which it
no longer runs out) and the fraction of positions whose answer is the same. Lengthening only changes which
pair certifies an interval, so every answer it gives is proved; a different answer is a walk one way could not
finish. Run: ``python benchmarks/depth_walk.py [n:degrees:segments ...]``.
"""

import math
import sys

import numpy as np
from _common import best_of, machine, table

from sesp import SeSP
from sesp.certified import IN, certified_components
from sesp.kernels import depth as depth_kernels
from sesp.pair import as_pair

CASES = [(2, 45, 128), (2, 90, 128), (8, 45, 128), (4, 176, 256), (10, 160, 256)]
BUDGETS = (1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512, 1024)
SAMPLE = 2000


def _options(lengthen):
    """The walk's options, lengthening pairs that are r apart or not."""
    return depth_kernels.OPTIONS._replace(lengthen=lengthen)


def intervals(curves, x, y, r, lengthen):
    """Per position: the least budget of BUDGETS at which its walk no longer runs out (the intervals it takes)."""
    need = np.full(len(x), BUDGETS[-1])
    for budget in reversed(BUDGETS):
        got = depth_kernels.certified_deep(curves, x, y, r, budget, options=_options(lengthen))
        need[got != -1] = budget
    return need


def walks(curves, x, y, r, steps, lengthen):
    """(seconds, answers): the walks at (x, y) to depth r (b), best of 3."""
    return best_of(lambda: depth_kernels.certified_deep(curves, x, y, r, steps, 1e-9, options=_options(lengthen)))


def main(cases):
    rows = []
    for n, degrees, segments in cases:
        particle = SeSP(n=n, opening=math.radians(degrees))
        found = certified_components(particle, segments=segments)
        cells = found.cells
        inn = cells["status"] == IN
        x, y = cells["x"][inn], cells["y"][inn]
        r = found.resolution + cells["side"][inn] / math.sqrt(2.0)
        pair = as_pair(particle, segments=segments)
        curves = depth_kernels.prepared(pair.vertices1, pair.vertices2)
        steps = 4 * max(len(pair.vertices1), len(pair.vertices2))
        off, on = (walks(curves, x, y, r, steps, lengthen) for lengthen in (False, True))
        pick = np.random.default_rng(0).choice(len(x), min(SAMPLE, len(x)), replace=False)
        medians = [int(np.median(intervals(curves, x[pick], y[pick], r[pick], k))) for k in (False, True)]
        rows.append((
            n, degrees, segments, len(x), f"{off[0]:.2f}", f"{on[0]:.2f}", f"{on[0] / off[0]:.2f}", *medians,
            f"{np.mean(off[1] == on[1]):.4f}",
        ))  # fmt: skip
    print(machine())
    table(rows, ["n", "Ψ°", "segments", "positions", "off s", "on s", "on/off", "intervals off", "on", "same"])


if __name__ == "__main__":
    args = [tuple(float(v) if k == 1 else int(v) for k, v in enumerate(a.split(":"))) for a in sys.argv[1:]]
    main(args or CASES)
