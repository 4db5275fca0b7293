"""Start-up: `sesp scan` on 64 x 64 x 32 with numba's cache empty and warm (and the first-run message), and
the README's main job, `sesp sweep sweeps/quick.toml`, the same two ways.

python benchmarks/startup.py
"""

import os
import subprocess
import sys
import tempfile
import time

from _common import machine, table

COMMAND = [sys.executable, "-m", "sesp", "-q", "scan", "--nx", "64", "--nphi", "32"]
QUICK = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sweeps", "quick.toml")


def timed(out, env=None, command=None):
    t0 = time.perf_counter()
    command = COMMAND + ["-o", out] if command is None else command
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    return time.perf_counter() - t0, result


def quick_sweep(tmp, env=None) -> float:
    """Wall seconds of `sesp sweep sweeps/quick.toml` into a fresh folder."""
    out = tempfile.mkdtemp(dir=tmp)
    seconds, result = timed(None, env, [sys.executable, "-m", "sesp", "-q", "sweep", QUICK, "--output", out])
    if result.returncode:
        raise SystemExit(result.stderr)
    return seconds


def main():
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "s.nc")
        cold_env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(tmp, "empty-cache"))
        t_cold, cold = timed(out, cold_env)
        timed(out)  # make sure the default cache is warm
        runs = [timed(out)[0] for _ in range(3)]
        quick_cold = quick_sweep(tmp, dict(os.environ, NUMBA_CACHE_DIR=os.path.join(tmp, "empty-cache-2")))
        quick_warm = quick_sweep(tmp)
    warm = min(runs)
    said = "compiling" in cold.stderr
    print(f"machine: {machine()}\n")
    table(
        [
            ["cold (empty numba cache)", f"{t_cold:.2f}", "yes" if said else "no"],
            ["warm (best of 3)", f"{warm:.2f}", ""],
            ["sesp sweep sweeps/quick.toml, cold", f"{quick_cold:.1f}", ""],
            ["sesp sweep sweeps/quick.toml, warm", f"{quick_warm:.1f}", ""],
        ],
        ["run", "wall s", "says it is compiling"],
    )
    print(f"\ntarget 6  warm start < 2 s: {warm:.2f} s  {'met' if warm < 2 else 'NOT met'}")
    print(f"target 6  first run says it is compiling: {'met' if said else 'NOT met'}")


if __name__ == "__main__":
    main()
