"""Read untrusted netCDF files in a separate process, so that a file that crashes the netCDF/HDF5 library
(a double free, a segmentation fault: damaged headers can do this) kills that process and not the caller.

:func:`probe` starts this file as a script (``python fileprobe.py``: only the standard library, numpy and
netCDF4 are imported, so a start costs about 0.2 s), sends it paths and reads one verdict per path. The
child first bounds what a file may expand to (:func:`check_expansion`), then reads every attribute and
every variable, as a load would. A child that dies or stalls marks its current file as failed and is
replaced for the rest.

What this proves: the same library calls that a load makes succeeded in another process on the same bytes.
It does not prove that the file is a valid sesp file (:func:`sesp.dataset.validate` does that) or that the
file was not changed between the probe and the load.
"""

from __future__ import annotations

import json
import os
import select
import signal
import subprocess
import sys
from pathlib import Path

# A variable stored with deflate cannot expand more than about 1032-fold (the format's limit); nothing sesp
# writes is stored otherwise. Variables that a file declares but never stores (read as fill values) would
# expand without limit: they are refused before anything is read.
MAX_EXPANSION = 1100
EXPANSION_SLACK = 1 << 20  # bytes: small files (headers, coordinates) may exceed the ratio

PROBE_TIMEOUT = 120.0  # seconds for one file, from when the reading process has started
START_TIMEOUT = 60.0  # seconds for a reading process to start (its imports: about 0.2 s, more on a loaded machine)
READY = "ready"  # a reading process's first line, once it can read


def check_expansion(nc, size: int) -> None:
    """Raise ValueError if the variables of the open netCDF4 ``nc`` take more memory than a file of ``size``
    bytes can hold (:data:`MAX_EXPANSION`); nothing is read but the header."""
    total = 0
    for name, var in nc.variables.items():
        itemsize = getattr(var.dtype, "itemsize", None)
        if not itemsize:  # variable-length strings and other non-numeric types
            raise ValueError(f"variable {name!r} has non-numeric type {var.dtype}")
        count = 1
        for n in var.shape:
            count *= int(n)
        total += count * itemsize
    limit = MAX_EXPANSION * size + EXPANSION_SLACK
    if total > limit:
        raise ValueError(
            f"its variables would take {total / 2**20:.1f} MiB in memory, more than a file of {size} bytes"
            f" can hold ({limit / 2**20:.1f} MiB); values never stored, or a damaged header"
        )


def read_everything(path: str) -> None:
    """Open ``path`` with netCDF4 and read every attribute and variable (the child's work)."""
    import netCDF4

    with netCDF4.Dataset(path) as nc:
        check_expansion(nc, os.path.getsize(path))
        nc.set_auto_maskandscale(False)
        for attr in nc.ncattrs():
            nc.getncattr(attr)
        for var in nc.variables.values():
            for attr in var.ncattrs():
                var.getncattr(attr)
            var[...]


def _serve() -> None:
    """The child: READY once it has imported netCDF4, then one JSON path per line in, one JSON verdict (null,
    or the error's text) per line out."""
    import netCDF4  # noqa: F401  (before READY: a file's time is that of reading it)

    sys.stdout.write(json.dumps(READY) + "\n")
    sys.stdout.flush()
    for line in sys.stdin:
        try:
            read_everything(json.loads(line))
            verdict = None
        except Exception as err:  # any failure of the library is a verdict on the file
            verdict = f"{type(err).__name__}: {err}".replace("\n", " ")[:300]
        sys.stdout.write(json.dumps(verdict) + "\n")
        sys.stdout.flush()


def start_reader() -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-I", __file__],  # -I: nothing from the working folder or the user's site is imported
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        bufsize=1,
    )


def _line(child: subprocess.Popen, timeout: float) -> str | None:
    """The child's next line ("" where it ended), or None where it said nothing within ``timeout`` seconds."""
    ready, _, _ = select.select([child.stdout], [], [], timeout)
    return child.stdout.readline() if ready else None


def _started() -> subprocess.Popen:
    """A reading process that has said READY; RuntimeError, saying why, where it says nothing else within
    START_TIMEOUT, ends first, or says something else first."""
    child = start_reader()
    said = _line(child, START_TIMEOUT)
    if said is not None and said.strip() == json.dumps(READY):
        return child
    _stop(child)
    if said is None:
        why = f"it said nothing within {START_TIMEOUT:g} s"
    elif not said:
        why = f"it ended ({_status(child.returncode)})"
    else:
        why = f"its first line was {said.strip()[:80]!r}, not {json.dumps(READY)}"
    raise RuntimeError(f"the netCDF reading process did not start: {why} ({sys.executable})")


def _status(code: int) -> str:
    """A process's return code in words: the signal that ended it, or its exit status."""
    return signal.Signals(-code).name if code < 0 else f"exit status {code}"


def _death(child: subprocess.Popen) -> str:
    code = child.wait()
    if code < 0:
        return f"reading it crashed the netCDF/HDF5 library ({_status(code)})"
    return f"reading it ended the reading process ({_status(code)})"


def _stop(child: subprocess.Popen) -> None:
    if child.poll() is None:
        child.kill()
    child.wait()
    for stream in (child.stdin, child.stdout):
        try:
            stream.close()
        except OSError:
            pass


def probe(paths, timeout: float = PROBE_TIMEOUT) -> dict[Path, str | None]:
    """Read each file in a separate process; ``{path: None}`` when it read cleanly, else why it failed.
    ``timeout``: seconds to read one file, once the process reading it has started (START_TIMEOUT)."""
    paths = [Path(p) for p in paths]
    verdicts: dict[Path, str | None] = {}
    child = None
    try:
        for path in paths:
            if child is None:
                child = _started()
            try:
                child.stdin.write(json.dumps(str(path)) + "\n")
                child.stdin.flush()
            except BrokenPipeError:
                pass  # the child died: the read below finds out
            line = _line(child, timeout)
            if line:
                verdicts[path] = json.loads(line)
                continue
            verdicts[path] = _death(child) if line == "" else f"reading it did not finish within {timeout:g} s"
            _stop(child)
            child = None
    finally:
        if child is not None:
            _stop(child)
    return verdicts


if __name__ == "__main__":
    _serve()
