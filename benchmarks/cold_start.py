"""The README's first command with nothing compiled: which numba kernels `sesp sweep sweeps/quick.toml` compiles,
how long each takes, and the wall time cold and warm, measured in one run.

    python benchmarks/cold_start.py              # the sweep in this process, one worker, numba's cache empty

Compile times are numba's own "numba:compile" events, each kernel's own (a kernel compiled on the way for another
counts for itself), so that they add up to the time spent compiling.
"""

import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
QUICK = ROOT / "sweeps" / "quick.toml"


def _run(cache: str, out: str) -> tuple[float, list]:
    """Wall seconds of the quick sweep in a fresh interpreter with numba's cache at ``cache``, and the kernels
    it compiled with their seconds."""
    import json
    import subprocess

    code = f"""
import json, time
from numba.core import event
records, stack = [], []
class Listener(event.Listener):  # each kernel's own time: what the kernels it compiles on the way took is theirs
    def on_start(self, ev): stack.append([time.perf_counter(), 0.0])
    def on_end(self, ev):
        start, inner = stack.pop()
        took = time.perf_counter() - start
        if stack: stack[-1][1] += took
        f = ev.data["dispatcher"].py_func
        records.append((f.__module__ + "." + f.__name__, took - inner))
event.register("numba:compile", Listener())
t0 = time.perf_counter()
from sesp.cli import main
code = main(["-q", "sweep", {str(QUICK)!r}, "--workers", "1", "--output", {out!r}])
print(json.dumps([time.perf_counter() - t0, records]))
"""
    env = dict(os.environ, NUMBA_CACHE_DIR=cache)
    t0 = time.perf_counter()
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if result.returncode:
        raise SystemExit(result.stderr)
    _, records = json.loads(result.stdout.strip().splitlines()[-1])
    return wall, records


def main():
    with tempfile.TemporaryDirectory() as tmp:
        cache = os.path.join(tmp, "numba-cache")
        cold, compiled = _run(cache, os.path.join(tmp, "cold"))
        warm, again = _run(cache, os.path.join(tmp, "warm"))
    total = {}
    for name, seconds in compiled:
        total[name] = total.get(name, 0.0) + seconds
    print(f"sesp sweep sweeps/quick.toml (one worker), numba's cache empty, then warm: {os.cpu_count()} cores\n")
    for name, seconds in sorted(total.items(), key=lambda item: -item[1]):
        print(f"  {seconds:6.2f} s  {name}")
    print(f"\n{len(total)} functions compiled (sesp's kernels and the numba library functions they use), "
          f"{sum(total.values()):.1f} s of compiling")  # fmt: skip
    print(f"wall: cold {cold:.1f} s, warm {warm:.1f} s (ratio {cold / warm:.2f}); compiled when warm: {len(again)}")


if __name__ == "__main__":
    main()
