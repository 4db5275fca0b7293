"""Exact-in-φ maps: the pair screen by sorted annuli against the screen of every pair, in one run.

Times ``allowed_orientations`` on a square map of positions over the pair's
reach (N = 256, Ψ = 90°) with the kernel of commit 32e530d (every segment
pair screened by its annuli; one allocation per pair) and today's (curve 2's
segments sorted by their inner radius, so each segment of curve 1 finds its
candidates by two binary searches; one scratch buffer per position), checks
that both give the same measures, and times today's widest window with the
clearance certificate (:func:`sesp.maps.widest_window`, the adaptive maps'
classification). Then one adaptive map of the ASP per opening and base
grid, with the positions it classified.

    python benchmarks/window_map.py [--nodes 512] [--n 2 4 8] [--maps 30 90 150 179 181] [--bases 128 97]
"""

import argparse
import importlib.util
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import machine, table

from sesp import SeSP
from sesp.kernels.orientations import widest_windows
from sesp.maps import excluded_map
from sesp.orientations import ANGLE_GAP, SCREEN_SLACK
from sesp.pair import as_pair

OLD = "32e530d"
ROOT = Path(__file__).resolve().parents[1]


def old_kernels(folder):
    """The orientation kernels of commit ``OLD``, as a package in ``folder`` (numba compiles them anew)."""
    package = Path(folder) / "old_kernels"
    package.mkdir()
    for name in ("common", "orientations"):
        text = subprocess.run(
            ["git", "show", f"{OLD}:src/sesp/kernels/{name}.py"], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout
        (package / f"{name}.py").write_text(text.replace("cache=True", "cache=False"))
    (package / "__init__.py").write_text("")
    spec = importlib.util.spec_from_file_location("old_kernels", package / "__init__.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["old_kernels"] = module
    spec.loader.exec_module(module)
    from old_kernels import orientations

    return orientations


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nodes", type=int, default=512)
    parser.add_argument("--n", type=float, nargs="+", default=[2, 4, 8])
    parser.add_argument("--maps", type=float, nargs="+", default=[30, 90, 150, 179, 181])
    parser.add_argument("--bases", type=int, nargs="+", default=[128, 97])
    args = parser.parse_args()
    print(machine())
    with tempfile.TemporaryDirectory() as folder:
        old = old_kernels(folder)
        rows = []
        for n in args.n:
            pair = as_pair(SeSP(n=n, opening=math.radians(90)))
            side = (np.arange(args.nodes) - (args.nodes - 1) / 2) * (2 * pair.reach / args.nodes)
            x, y = (a.ravel().copy() for a in np.meshgrid(side, side))
            v1, v2 = pair.vertices1, pair.vertices2
            for k in (old, None):  # compile on a few positions first
                if k is old:
                    k.allowed_measures(v1, v2, x[:4], y[:4], SCREEN_SLACK, ANGLE_GAP)
                else:
                    widest_windows(v1, v2, x[:4], y[:4], SCREEN_SLACK, ANGLE_GAP, 0.0, np.ones(4))
            from sesp.kernels.orientations import allowed_measures

            allowed_measures(v1, v2, x[:4], y[:4], SCREEN_SLACK, ANGLE_GAP)
            t0 = time.perf_counter()
            before = old.allowed_measures(v1, v2, x, y, SCREEN_SLACK, ANGLE_GAP)
            t_old = time.perf_counter() - t0
            t0 = time.perf_counter()
            now = allowed_measures(v1, v2, x, y, SCREEN_SLACK, ANGLE_GAP)
            t_new = time.perf_counter() - t0
            t0 = time.perf_counter()
            width, _, _ = widest_windows(v1, v2, x, y, SCREEN_SLACK, ANGLE_GAP, 0.0, np.full(len(x), 0.01))
            t_window = time.perf_counter() - t0
            rows.append(
                (
                    f"{n:g}",
                    f"{args.nodes}^2",
                    f"{t_old:.1f}",
                    f"{t_new:.1f}",
                    f"{t_old / t_new:.2f}x",
                    f"{np.abs(now - before).max():.1e}",
                    int(np.count_nonzero(before == 0) == np.count_nonzero(width == 0)),
                    f"{t_window:.1f}",
                )
            )
        print("\nallowed orientations on a map of positions (N = 256, opening 90 deg)")
        table(
            rows,
            ["n", "positions", "old s", "new s", "speed-up", "max |diff| rad", "same excluded", "window+clearance s"],
        )
    rows = []
    for degrees, base in ((d, b) for d in args.maps for b in args.bases):
        t0 = time.perf_counter()
        found = excluded_map(SeSP(n=2, opening=math.radians(degrees)), base=base)
        rows.append(
            (
                f"{degrees:g}",
                base,
                found.count,
                found.positions,
                f"{found.finest:.1e}",
                ", ".join(f"{c.area:.4f}" for c in found.components) or "-",
                f"{time.perf_counter() - t0:.1f}",
            )
        )
    print("\nadaptive maps of the ASP's excluded set (floor 1e-7 b); exact lens area (pi - opening) - sin(opening)")
    table(rows, ["opening deg", "base", "components", "positions", "finest cell b", "areas b^2", "s"])


if __name__ == "__main__":
    main()
