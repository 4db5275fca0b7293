"""Parameter sweeps: TOML files in, one labelled dataset out.

A sweep file names the parameters that vary (lists or ranges), the grid and
which outputs to keep. Every parameter point becomes one netCDF file named by
a stable hash of its parameters, written atomically, so an interrupted sweep
resumes where it stopped and loses nothing. ``collect`` combines the point
files into one Dataset whose dimensions are the swept parameters.

Sweep file
----------
.. code-block:: toml

    [sweep]                     # optional, and so is each of its keys
    name = "quick"              # default: the file's stem
    output = "results/quick"    # folder for point files and the collected file, relative to this file
                                # (default: results/<the file's stem>)
    angles = "degrees"          # "degrees" (default) or "radians": unit of every angle here

    [particle]                  # a value, a list, or a range table
    n = [2, 8]
    opening = { start = 0, stop = 180, step = 45 }   # stop included if on the step
    aspect = 1.0
    thickness = 0.0             # D in b (bent wire, printed arc); a list sweeps it
    segments = 128

    [other]                     # optional: a different second particle (mixtures)
    n = 4

A particle given by its vertices instead (needles, staples, any thin
polyline; in b, in the particle's own frame) takes ``vertices`` in place of
the shape keys, in ``[particle]`` or ``[other]``:

.. code-block:: toml

    [particle]
    vertices = [[-1.0, 0.0], [1.0, 0.0]]

    [grid]                      # optional; default nx = 128, nphi = 128
    nx = 128
    nphi = 64                   # ny optional (default nx)

    [output]                    # optional; default keep = ["excluded_area"]
    keep = ["excluded_area", "classes", "topology"]   # and/or "phases", "third_virial", "allowed" (the field)
    resolution = 1e-5           # b: the resolution of the topology count (default 1e-5)
    rtol = 1e-5                 # relative error bar of <A_ex> (default 1e-5, as `sesp area`)
    third_virial_rtol = 1e-3    # relative error bar of B3, where kept (default 1e-3, as `sesp virial`)

The shortest sweep file names its particles alone:

.. code-block:: toml

    [particle]
    n = 8
    opening = [60, 90, 120]

Ranges are ``{start, stop, step}`` or ``{start, stop, num}``.
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import itertools
import json
import logging
import math
import os
import signal
import tempfile
import threading
import time
import tomllib
from concurrent.futures import as_completed
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import xarray as xr

from .analysis import KEEP, analyze, check_keep, check_memory
from .certified import RESOLUTION
from .checks import check_resolution, check_rtol
from .dataset import SHAPE_KEYS, base_attrs, parameter_attrs
from .fileprobe import probe
from .grid import Grid
from .io import load, save
from .measures import RTOL
from .pair import Pair
from .persistence import sweep_lives
from .progress import progress_bar
from .regions import summarize
from .shape import DEFAULT_SEGMENTS, Polyline, SeSP
from .units import link_errors
from .virial import B3_RTOL
from .workers import start_pool, stop_pool

__all__ = ["SweepSpec", "SweepPoint", "load_spec", "run", "collect", "compute_point", "KEEP"]

log = logging.getLogger(__name__)

SCHEMA = {
    "sweep": {"name": str, "output": str, "angles": str},
    "particle": {
        "n": float,
        "m": float,
        "aspect": float,
        "opening": float,
        "thickness": float,
        "segments": int,
        "vertices": list,
    },
    "other": {"n": float, "m": float, "aspect": float, "opening": float, "thickness": float, "vertices": list},
    "grid": {"nx": int, "ny": int, "nphi": int},
    "output": {"keep": list, "resolution": float, "rtol": float, "third_virial_rtol": float},
}
REQUIRED = {"particle": ("n", "opening")}
# What a sweep file may leave out: the output folder (results/<file stem>, beside the file), degrees, this grid
# (the quick sweep's: 128 x 128 positions, 128 orientations) and, in [output], the excluded area alone.
DEFAULT_ANGLES = "degrees"
DEFAULT_GRID = {"nx": 128, "nphi": 128}
MANIFEST = "sweep.json"
# Version of what a point file holds: points written under another version are recomputed, not mixed in.
POINT_FORMAT = 5


class SweepError(ValueError):
    """A sweep file or folder that cannot be used; the message names file and key."""


def _values(path, section, key, raw, kind):
    """The tuple of values a sweep key takes (a scalar gives one value)."""
    where = f"{path}: [{section}] {key}"
    if isinstance(raw, dict):
        extra = set(raw) - {"start", "stop", "step", "num"}
        if extra or not {"start", "stop"} <= set(raw) or ("step" in raw) == ("num" in raw):
            raise SweepError(f"{where}: a range needs start, stop and one of step or num")
        numbers = [raw[k] for k in ("start", "stop", "step") if k in raw]
        if any(isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) for v in numbers):
            raise SweepError(f"{where}: start, stop and step must be finite numbers, got {raw}")
        start, stop = float(raw["start"]), float(raw["stop"])
        if "step" in raw:
            step = float(raw["step"])
            if step <= 0 or stop < start:
                raise SweepError(f"{where}: range needs step > 0 and stop >= start, got {raw}")
            count = math.floor((stop - start) / step + 1e-9) + 1
            _check_count(where, count)
            values = [start + i * step for i in range(count)]
        else:
            num = raw["num"]
            if isinstance(num, bool) or not isinstance(num, int) or num < 1:
                raise SweepError(f"{where}: num must be an integer >= 1, got {num!r}")
            _check_count(where, num)
            values = np.linspace(start, stop, num).tolist()
    elif isinstance(raw, list):
        if not raw:
            raise SweepError(f"{where}: an empty list sweeps nothing")
        values = raw
    else:
        values = [raw]
    out = []
    for v in values:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise SweepError(f"{where}: expected numbers, got {v!r}")
        if kind is int and int(v) != v:
            raise SweepError(f"{where}: expected integers, got {v!r}")
        out.append(kind(v))
    if len(set(out)) != len(out):
        raise SweepError(f"{where}: repeated values {out}")
    return tuple(out)


def _vertices(path, section, raw) -> tuple:
    """A polyline's vertices from a sweep file: one value (not swept), a tuple of (x, y) pairs."""
    where = f"{path}: [{section}] vertices"
    try:
        polyline = Polyline(raw)
    except (ValueError, TypeError) as err:
        raise SweepError(f"{where}: {err}") from None
    return tuple(tuple(float(c) for c in v) for v in polyline.vertices)


MAX_VALUES = 100_000  # values one key may take
MAX_POINTS = 1_000_000  # parameter points of one sweep


def _check_count(where, count):
    if count > MAX_VALUES:
        raise SweepError(f"{where}: the range has {count} values, over the limit of {MAX_VALUES}")


def _check_opening_unit(path, section, values, angles):
    """Openings in the unit the file uses, checked before conversion so the message quotes the user's value."""
    top, unit = (360.0, "degrees") if angles == "degrees" else (2 * math.pi, "radians")
    for v in values:
        if not 0.0 <= v < top:
            raise SweepError(f"{path}: [{section}] opening = {v:g} {unit} is out of range [0, {top:g}) {unit}")


def _check_schema(path, doc):
    for section, body in doc.items():
        if section not in SCHEMA:
            raise SweepError(f"{path}: unknown section [{section}]; allowed: {', '.join(SCHEMA)}")
        if not isinstance(body, dict):
            raise SweepError(f"{path}: [{section}] must be a table")
        for key in body:
            if key not in SCHEMA[section]:
                raise SweepError(f"{path}: unknown key {key!r} in [{section}]; allowed: {', '.join(SCHEMA[section])}")
    for section, keys in REQUIRED.items():
        body = doc.get(section, {})
        if section == "particle" and "vertices" in body:
            keys = ()
        for key in keys:
            if key not in body:
                raise SweepError(f"{path}: missing key {key!r} in [{section}]")


@dataclass(frozen=True)
class SweepSpec:
    """A checked sweep: parameter values (angles in radians), grid and outputs."""

    name: str
    output: Path
    particle: dict  # key -> tuple of values
    other: dict | None
    grid: dict
    keep: tuple
    source: str
    resolution: float = RESOLUTION
    rtol: float = RTOL
    third_virial_rtol: float = B3_RTOL

    @property
    def dims(self) -> list[str]:
        """Names of the swept parameters, in file order (other's prefixed ``other_``)."""
        names = [k for k, v in self.particle.items() if len(v) > 1]
        if self.other:
            names += [f"other_{k}" for k, v in self.other.items() if len(v) > 1]
        return names

    def _axes(self):
        axes = dict(self.particle)
        if self.other:
            axes.update({f"other_{k}": v for k, v in self.other.items()})
        return axes

    def coords(self) -> dict:
        axes = self._axes()
        return {d: list(axes[d]) for d in self.dims}

    def fixed(self) -> dict:
        """Parameters that take a single value, by name (a polyline's vertices excepted)."""
        return {k: v[0] for k, v in self._axes().items() if len(v) == 1 and not k.endswith("vertices")}

    def points(self) -> list[SweepPoint]:
        """Every parameter point, in a stable order, each with its index."""
        axes = self._axes()
        names = list(axes)
        out = []
        for combo in itertools.product(*(axes[k] for k in names)):
            values = dict(zip(names, combo))
            particle = {k: values[k] for k in self.particle}
            other = {k[6:]: values[k] for k in axes if k.startswith("other_")} or None
            index = tuple(axes[d].index(values[d]) for d in self.dims)
            out.append(
                SweepPoint(
                    particle,
                    other,
                    dict(self.grid),
                    tuple(self.keep),
                    index,
                    resolution=self.resolution,
                    rtol=self.rtol,
                    third_virial_rtol=self.third_virial_rtol,
                )  # fmt: skip
            )
        return out


@dataclass(frozen=True)
class SweepPoint:
    """One parameter point of a sweep: the two particles' parameters, the grid, what to keep.

    Angles are in radians. ``index`` is the point's position along the
    sweep's swept dimensions; :attr:`hash` names its file.
    """

    particle: dict
    other: dict | None
    grid: dict
    keep: tuple
    index: tuple = ()
    resolution: float = RESOLUTION  # b: of the topology count, where kept
    rtol: float = RTOL  # relative error bar of <A_ex>
    third_virial_rtol: float = B3_RTOL  # relative error bar of B₃, where kept

    def payload(self) -> dict:
        """What the point's results depend on (the input of :attr:`hash`)."""
        payload = {
            "particle": self.particle,
            "other": self.other,
            "grid": self.grid,
            "keep": list(self.keep),
            "rtol": self.rtol,
        }
        if "topology" in self.keep:
            payload["resolution"] = self.resolution
        if "third_virial" in self.keep:
            payload["third_virial_rtol"] = self.third_virial_rtol
        return payload

    @property
    def hash(self) -> str:
        """Stable 16-hex-digit name of the point."""
        return point_hash(self.payload())

    def to_json(self) -> str:
        return json.dumps({**self.payload(), "hash": self.hash, "index": list(self.index)})

    def particles(self) -> tuple:
        """(particle, other or None): SeSPs from shape keys, Polylines from vertices.

        ``other`` takes the particle's shape keys it does not set itself (a
        new ``n`` without ``m`` sets ``m`` too).
        """
        particle = _particle(self.particle)
        if not self.other:
            return particle, None
        if "vertices" in self.other:
            return particle, _particle(self.other)
        shape = {k: self.particle[k] for k in (*SHAPE_KEYS, "thickness") if k in self.particle}
        merged = {**shape, **self.other}
        if "n" in self.other and "m" not in self.other:
            merged.pop("m", None)
        return particle, _particle(merged)

    def pair(self) -> Pair:
        particle, other = self.particles()
        return Pair.of(particle, other, segments=self.particle.get("segments", DEFAULT_SEGMENTS))


def _particle(params: dict):
    shape = {k: params[k] for k in SHAPE_KEYS if k in params}
    thickness = params.get("thickness", 0.0)
    if "vertices" in params:
        if shape:
            raise ValueError(f"give vertices or the shape keys {SHAPE_KEYS}, not both (got {sorted(shape)})")
        return Polyline(params["vertices"], thickness=thickness)
    return SeSP(**shape, thickness=thickness)


def point_hash(payload: dict) -> str:
    """Stable 16-hex-digit name of a parameter point (angles in radians)."""
    names = ("particle", "other", "grid", "keep", "resolution", "rtol", "third_virial_rtol")
    payload = {k: payload[k] for k in names if k in payload}
    payload["format"] = POINT_FORMAT
    text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _output_folder(path: Path, in_file, override) -> Path:
    """The sweep's output folder: ``override`` as given (relative to the current folder), else the file's
    ``output``, relative to the sweep file."""
    if override is not None:
        return Path(override)
    if not isinstance(in_file, str) or not in_file or "\0" in in_file:
        raise SweepError(f"{path}: [sweep] output must be a folder name (a string), got {in_file!r}")
    out = Path(in_file)
    return out if out.is_absolute() else Path(os.path.normpath(path.parent / out))


def load_spec(path, *, output: str | os.PathLike | None = None) -> SweepSpec:
    """Read and check a sweep file; every error names the file and the key.

    Every particle and grid of the sweep is built here, so a value out of
    range is reported before any work starts. The file's ``output`` folder
    is taken relative to the sweep file; ``output`` overrides it (relative
    to the current folder).
    """
    path = Path(path)
    try:
        text = path.read_text()
        doc = tomllib.loads(text)
    except FileNotFoundError:
        raise SweepError(f"{path}: no such sweep file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise SweepError(f"{path}: not valid TOML ({err})") from None
    _check_schema(path, doc)
    head = doc.get("sweep", {})
    angles = head.get("angles", DEFAULT_ANGLES)
    if angles not in ("degrees", "radians"):
        raise SweepError(f"{path}: [sweep] angles must be 'degrees' or 'radians', got {angles!r}")
    to_rad = math.radians if angles == "degrees" else float

    def section(name):
        body = doc.get(name)
        if body is None:
            return None
        vals = {
            k: (_vertices(path, name, v),) if k == "vertices" else _values(path, name, k, v, SCHEMA[name][k])
            for k, v in body.items()
        }
        if "opening" in vals:
            _check_opening_unit(path, name, vals["opening"], angles)
            vals["opening"] = tuple(to_rad(v) for v in vals["opening"])
        return vals

    particle = section("particle")
    particle.setdefault("segments", (DEFAULT_SEGMENTS,))
    other = section("other")
    grid = {**DEFAULT_GRID, **{k: v[0] for k, v in (section("grid") or {}).items()}}
    for k, v in doc.get("grid", {}).items():
        if isinstance(v, (list, dict)):
            raise SweepError(f"{path}: [grid] {k} must be a single integer")
    try:
        keep = check_keep(doc.get("output", {}).get("keep", ["excluded_area"]))
    except ValueError as err:
        raise SweepError(f"{path}: [output] {err}") from None
    wanted = doc.get("output", {})
    resolution, rtol = wanted.get("resolution", RESOLUTION), wanted.get("rtol", RTOL)
    third_virial_rtol = wanted.get("third_virial_rtol", B3_RTOL)
    try:  # the checks Python and the command line use
        check_resolution(resolution)
        check_rtol(rtol, "<A_ex>")
        check_rtol(third_virial_rtol, "B3", "third_virial_rtol")
    except ValueError as err:
        raise SweepError(f"{path}: [output] {err}") from None
    spec = SweepSpec(
        name=_string(path, "name", head.get("name", path.stem)),
        output=_output_folder(path, head.get("output", f"results/{path.stem}"), output),
        particle=particle,
        other=other,
        grid=grid,
        keep=keep,
        source=text,
        resolution=float(resolution),
        rtol=float(rtol),
        third_virial_rtol=float(third_virial_rtol),
    )
    _check_name(path, spec.name)
    total = math.prod(len(v) for part in (spec.particle, spec.other or {}) for v in part.values())
    if total > MAX_POINTS:
        raise SweepError(f"{path}: the sweep has {total} parameter points, over the limit of {MAX_POINTS}")
    _check_values(path, spec)
    return spec


def _check_values(path, spec: SweepSpec):
    """Build every particle and the grid once, naming the file on failure."""
    try:
        check_memory(Grid(**spec.grid), spec.keep)
        for point in spec.points():
            point.pair()
    except (ValueError, MemoryError) as err:
        raise SweepError(f"{path}: [grid] {err}" if isinstance(err, MemoryError) else f"{path}: {err}") from None


def _string(path, key, value) -> str:
    if not isinstance(value, str):
        raise SweepError(f"{path}: [sweep] {key} must be a string, got {value!r}")
    return value


def _check_name(path, name):
    plain = name and len(name) <= 200 and "/" not in name and "\0" not in name and not name.startswith(".")
    if not plain:
        raise SweepError(f"{path}: [sweep] name must be a plain file name of at most 200 characters, got {name!r}")


def common_half_width(spec: SweepSpec) -> float:
    """One box for every point (the largest needed), so maps share coordinates."""
    grid = Grid(**spec.grid)
    cells = min(grid.nx, grid.ny)
    reach = max(point.pair().reach for point in spec.points())
    return reach * cells / (cells - 2)


def compute_point(point: SweepPoint) -> xr.Dataset:
    """The results of one parameter point (:func:`sesp.analyze`), labelled as a sweep point."""
    out = analyze(point.pair(), Grid(**point.grid), keep=point.keep, resolution=point.resolution, rtol=point.rtol,
                  third_virial_rtol=point.third_virial_rtol)  # fmt: skip
    # a SeSP is rebuilt from its parameters; a polyline's vertices must stay
    rebuilt = [f"{p}_vertices" for p in ("particle", "other") if out.attrs[f"{p}_kind"] == "SeSP"]
    out = out.drop_vars(rebuilt)
    out.attrs.update({**base_attrs("sesp.point"), "point_hash": point.hash, "point": point.to_json()})
    return out


def _lock_path(folder, point) -> Path:
    return Path(folder) / f".{point.hash}.lock"


def _claim(folder, point) -> int | None:
    """Hold the point's lock: an ``flock`` that the operating system releases when its holder dies.

    Returns the open lock file (keep it open while computing), or None when
    another process holds the lock. Its holder removes the lock file before releasing it, whether the point
    was written or not; a lock taken on a file so removed is no lock, and is refused.
    """
    path = _lock_path(folder, point)
    fd = os.open(path, os.O_CREAT | os.O_RDWR, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        held = os.fstat(fd)
        now = os.stat(path)
    except (BlockingIOError, FileNotFoundError):
        os.close(fd)
        return None
    if (held.st_dev, held.st_ino) != (now.st_dev, now.st_ino):  # its holder removed it as we opened it
        os.close(fd)
        return None
    return fd


def _release(folder, point, lock: int):
    """Remove the point's lock file, then release the lock (removed while held: see :func:`_claim`)."""
    _lock_path(folder, point).unlink(missing_ok=True)
    os.close(lock)


def temporaries(folder, stem: str) -> list[Path]:
    """The temporaries :func:`sesp.io.save` leaves in ``folder`` when stopped while writing ``<stem>.nc``."""
    return list(Path(folder).glob(f".{stem}.nc.*.tmp"))


def run_point(point: SweepPoint, folder: str) -> str | None:
    """Compute one point and write ``folder/<hash>.nc`` atomically; return its path.

    Returns None, computing nothing, when another live runner holds the point,
    or when this worker process has been told to stop.
    """
    if _STOPPING:
        return None
    path = Path(folder) / f"{point.hash}.nc"
    lock = _claim(folder, point)
    if lock is None:
        return None
    global _WRITING
    _WRITING = (folder, point.hash)
    try:
        for stale in temporaries(folder, point.hash):  # left by a killed writer; the lock is ours
            stale.unlink(missing_ok=True)
        if not _finished(path):
            result = compute_point(point)
            with _SAVING:  # the orphan watch waits for a write under way (see _leave_orphaned)
                save(result, path)
    finally:
        _WRITING = None
        _release(folder, point, lock)
    return str(path)


def load_point(path: Path, *, isolate: bool = True) -> xr.Dataset:
    """A sweep point file, checked to be the point its name says: its recorded parameters hash to its name.

    ``isolate`` as in :func:`sesp.load`: off only for files already probed or written by this sweep.
    """
    ds = load(path, isolate=isolate)
    try:
        recorded = json.loads(ds.attrs["point"])
        ok = ds.attrs["sesp_format"] == "sesp.point" and ds.attrs["point_hash"] == path.stem
        ok = ok and point_hash(recorded) == path.stem
    except (KeyError, TypeError, ValueError):
        ok = False
    if not ok:
        raise SweepError(f"{path}: not the sweep point its name says (altered, swapped or foreign file)")
    return ds


def _finished(path: Path) -> bool:
    if not path.is_file():
        return False
    try:
        load_point(path, isolate=False)  # files from an earlier run were probed by set_aside_unreadable
        return True
    except (ValueError, OSError):
        log.warning("%s is unreadable or not its point, and will be recomputed", path)
        return False


def set_aside_unreadable(folder: Path, points) -> list[Path]:
    """Read every existing point file in one separate process (:func:`sesp.fileprobe.probe`); move each file
    that fails there to ``<hash>.nc.damaged``, so that it is recomputed and never opened in this process, where
    a damaged file could crash the netCDF/HDF5 library. Returns the files moved."""
    existing = [folder / f"{p.hash}.nc" for p in points if (folder / f"{p.hash}.nc").is_file()]
    moved = []
    for path, why in probe(existing).items():
        if why is not None:
            aside = path.with_name(path.name + ".damaged")
            os.replace(path, aside)
            log.warning("%s cannot be read (%s); moved to %s, the point will be recomputed", path, why, aside.name)
            moved.append(aside)
    return moved


def warm_up():
    """Compile (or load from cache) the field's kernels once, on a dask worker before it takes points."""
    summarize(SeSP(n=2, opening=1.0), Grid(8, nphi=2), segments=4, entangled=True)
    return os.getpid()


_STOPPING = False  # set in a worker process once it was interrupted: it starts no further point
_WRITING = None  # (folder, point hash) while this process holds a point's lock
_SAVING = threading.Lock()  # held while a point file is written


def _interrupted(signum, frame):
    """SIGINT in a worker: an idle worker leaves at once; one computing a point raises, so that the point's
    cleanup runs, and :func:`_point_in_worker` then leaves. Either way it leaves silently, never back in the
    pool's loop, whose queue the stopping runner may close under it: the runner reports the interruption."""
    global _STOPPING
    _STOPPING = True
    if _WRITING is None:
        os._exit(130)
    raise KeyboardInterrupt


def _point_in_worker(point: SweepPoint, folder: str) -> str | None:
    try:
        return run_point(point, folder)
    except KeyboardInterrupt:  # what it was writing is removed, its lock released
        os._exit(130)


def _init_worker():
    signal.signal(signal.SIGINT, _interrupted)


def _leave_orphaned(grace: float = 5.0):
    """In a worker whose runner is gone (killed by SIGKILL, say; :func:`~sesp.workers.start_pool` watches):
    stop as on Ctrl-C, which removes the file being written and releases its lock, then exit."""
    os.kill(os.getpid(), signal.SIGINT)
    time.sleep(grace)  # a kernel call finishes its slice before the interrupt is seen
    # Still not stopped. A write under way ends first (complete, or removed by the interrupt): netCDF, in C,
    # would otherwise create the temporary again after it was removed here. Then remove what is left of the
    # point (its lock is ours until we exit) and exit, holding the lock so that no write starts. The wait is
    # bounded: an interrupt can leave the lock held (between its acquire and the with block), and a worker
    # must never outlive its runner.
    _SAVING.acquire(timeout=grace)
    if _WRITING is not None:
        folder, point_hash = _WRITING
        for stale in temporaries(folder, point_hash):
            stale.unlink(missing_ok=True)
    os._exit(1)


def _execute_local(todo, folder, workers, bar):
    """Compute ``todo`` in this process (``workers`` <= 1) or in worker processes, which then write every
    point file: a runner killed by SIGKILL leaves none half-written, its workers remove theirs."""
    if workers <= 1:
        for point in todo:
            run_point(point, str(folder))
            bar.update()
        return
    workers = min(workers, len(todo))
    pool = start_pool(workers, _init_worker, on_orphan=_leave_orphaned)
    try:  # the first point alone: it compiles (or loads) the kernels the points use, once, for every worker
        for batch in (todo[:1], todo[1:]):
            for future in as_completed([pool.submit(_point_in_worker, p, str(folder)) for p in batch]):
                future.result()
                bar.update()
    except BaseException:  # Ctrl-C, or a failed point: stop now, not after every queued point
        stop_pool(pool)
        remove_stale_temporaries(folder, todo)
        raise
    pool.shutdown()


@contextlib.contextmanager
def folder_lock(folder: Path):
    """Hold an ``flock`` on the sweep folder itself while writing the files a runner owns (the manifest, the
    collected file), so that a runner can tell their temporaries from those of a concurrent writer."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def remove_runner_temporaries(folder: Path, name: str):
    """Remove the temporaries of the manifest and the collected file left by a runner that was killed."""
    with folder_lock(folder):
        for stale in [*folder.glob(f".{MANIFEST}.*.tmp"), *temporaries(folder, name)]:
            stale.unlink(missing_ok=True)


def remove_stale_temporaries(folder, points):
    """Remove the temporary files of points that no process is writing (their lock can be taken)."""
    for point in points:
        stale = temporaries(folder, point.hash)
        if not stale:
            continue
        lock = _claim(folder, point)
        if lock is None:  # another runner is writing this point now
            continue
        try:
            for path in stale:
                path.unlink(missing_ok=True)
        finally:
            _release(folder, point, lock)


def _execute_dask(todo, folder, scheduler, bar):
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise SweepError("--scheduler needs dask.distributed: pip install 'sesp[dask]'") from None
    with Client(scheduler) as client:
        client.run(warm_up)
        futures = client.map(run_point, todo, folder=str(folder), pure=False)
        for future in as_completed(futures):
            future.result()
            bar.update()


def write_manifest(spec: SweepSpec, points: list[dict], folder: Path):
    """Record dims, coordinates and point hashes, so ``collect`` needs only the folder."""
    manifest = {
        "name": spec.name,
        "dims": spec.dims,
        "coords": spec.coords(),
        "fixed": spec.fixed(),
        "points": [{"index": list(p.index), "hash": p.hash} for p in points],
        "keep": list(spec.keep),
        "source": spec.source,
    }
    with folder_lock(folder):
        _write_manifest(folder, manifest)


def _write_manifest(folder: Path, manifest: dict):
    fd, tmp = tempfile.mkstemp(prefix=f".{MANIFEST}.", suffix=".tmp", dir=folder)  # unique: runners may race
    try:
        with os.fdopen(fd, "w") as handle:
            handle.write(json.dumps(manifest, indent=1))
        os.replace(tmp, folder / MANIFEST)
    except OSError as err:
        Path(tmp).unlink(missing_ok=True)
        raise OSError(f"{folder / MANIFEST}: could not write the sweep manifest ({err})") from err
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run(
    path,
    *,
    output=None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    collect_result: bool = True,
) -> Path | None:
    """Run a sweep file: compute missing points, then collect them.

    Parameters
    ----------
    path : path-like
        The TOML sweep file.
    output : path-like, optional
        Overrides the file's output folder.
    workers : int, optional
        Local worker processes; default all cores (capped at the points left).
    scheduler : str, optional
        Address of a dask.distributed scheduler to run the points on instead.
    progress : bool
        Show a progress bar (points done, left, ETA).

    Returns
    -------
    Path or None
        The collected file ``<output>/<name>.nc``.
    """
    spec = load_spec(path, output=output)
    spec = with_common_box(spec)
    points = spec.points()
    folder = spec.output
    folder.mkdir(parents=True, exist_ok=True)
    write_manifest(spec, points, folder)
    remove_runner_temporaries(folder, spec.name)
    set_aside_unreadable(folder, points)
    todo = [p for p in points if not _finished(folder / f"{p.hash}.nc")]
    remove_stale_temporaries(folder, todo)  # left by a runner that was killed
    log.info("%s: %d points, %d done, %d to compute", spec.name, len(points), len(points) - len(todo), len(todo))
    if todo:
        done = len(points) - len(todo)
        with progress_bar(len(points), progress, spec.name, unit="point", initial=done, leave=True) as bar:
            if scheduler:
                _execute_dask(todo, folder, scheduler, bar)
            else:
                _execute_local(todo, folder, workers or os.cpu_count() or 1, bar)
    _wait_for_others(points, folder)
    if not collect_result:
        return None
    target = folder / f"{spec.name}.nc"
    with folder_lock(folder):
        save(collect(folder), target)
    return target


def _wait_for_others(points, folder, poll=0.2):
    """Finish points that another runner held: wait while it holds them, else compute them."""
    for point in points:
        path = folder / f"{point.hash}.nc"
        told = False
        while not _finished(path):
            if run_point(point, str(folder)) is None:
                if not told:
                    log.info("%s: waiting for another runner that is computing point %s", folder, point.hash)
                    told = True
                time.sleep(poll)


def with_common_box(spec: SweepSpec) -> SweepSpec:
    grid = dict(spec.grid)
    grid["half_width"] = common_half_width(spec)
    return replace(spec, grid=grid)


MANIFEST_KEYS = {"name": str, "dims": list, "coords": dict, "points": list, "keep": list, "source": str}


def read_manifest(folder: Path) -> dict:
    """The sweep manifest of ``folder``, checked; a read that meets a concurrent writer is retried."""
    path = folder / MANIFEST
    for attempt in range(5):
        try:
            manifest = json.loads(path.read_text())
            break
        except FileNotFoundError:
            raise SweepError(f"{folder}: no {MANIFEST}; is this a sweep output folder?") from None
        except (json.JSONDecodeError, UnicodeDecodeError) as err:
            if attempt == 4:
                raise SweepError(f"{path}: not a readable sweep manifest ({err})") from None
            time.sleep(0.1)
    wrong = [
        k
        for k, kind in MANIFEST_KEYS.items()
        if not isinstance(manifest, dict) or not isinstance(manifest.get(k), kind)
    ]
    if wrong or not manifest["points"]:
        raise SweepError(f"{path}: not a sesp sweep manifest (expected keys {sorted(MANIFEST_KEYS)} and points)")
    for entry in manifest["points"]:
        if not (
            isinstance(entry, dict) and isinstance(entry.get("hash"), str) and isinstance(entry.get("index"), list)
        ):
            raise SweepError(f"{path}: a point entry is malformed: {entry!r}")
    return manifest


def collect(folder) -> xr.Dataset:
    """Combine a sweep folder's point files into one Dataset over the swept parameters."""
    folder = Path(folder)
    manifest = read_manifest(folder)
    missing = [p["hash"] for p in manifest["points"] if not (folder / f"{p['hash']}.nc").is_file()]
    if missing:
        raise SweepError(
            f"{folder}: {len(missing)} of {len(manifest['points'])} points are not computed yet; "
            "run the sweep again to finish them"
        )
    unreadable = {p: why for p, why in probe(folder / f"{p['hash']}.nc" for p in manifest["points"]).items() if why}
    if unreadable:
        path, why = next(iter(unreadable.items()))
        raise SweepError(
            f"{path}: cannot be read ({why}); {len(unreadable)} point file(s) like it: run the sweep again, it"
            " sets them aside and recomputes them"
        )
    dims = manifest["dims"]
    shape = tuple(len(manifest["coords"][d]) for d in dims)
    arrays, first = {}, None
    for entry in manifest["points"]:
        ds = load_point(folder / f"{entry['hash']}.nc", isolate=False)  # probed above
        first = first if first is not None else ds
        for name, var in ds.data_vars.items():
            if name not in arrays:
                fill = np.nan if var.dtype.kind == "f" else 0
                arrays[name] = np.full(shape + var.shape, fill, dtype=var.dtype)
            arrays[name][tuple(entry["index"])] = var.values
    collected = _collected_dataset(manifest, dims, arrays, first)
    if "component_depth" in collected and "opening" in collected.component_depth.dims:  # each component over Ψ
        collected = collected.merge(sweep_lives(collected))
    return link_errors(collected)


def _parameter_coords(name, dims, values) -> dict:
    """A swept (dims = (name,)) or fixed (dims = ()) parameter's coordinate; openings also in degrees."""
    coords = {name: (dims, values, parameter_attrs(name))}
    if name.endswith("opening"):
        coords[f"{name}_degrees"] = (dims, np.degrees(values), parameter_attrs(f"{name}_degrees"))
    return coords


def _collected_dataset(manifest, dims, arrays, first) -> xr.Dataset:
    coords = {}
    for d in dims:
        coords.update(_parameter_coords(d, (d,), np.asarray(manifest["coords"][d], dtype=float)))
    for name, value in manifest.get("fixed", {}).items():
        coords.update(_parameter_coords(name, (), value))
    for name in first.dims:  # the points' own dimensions: phi, y, x, k, order, ...
        if name in first.coords:
            coords[name] = first[name]
    variables = {}
    for name, array in arrays.items():
        var = first[name]
        variables[name] = (tuple(dims) + var.dims, array, var.attrs)
    attrs = {
        **base_attrs("sesp.sweep"),
        "sweep_name": manifest["name"],
        "sweep_file": manifest["source"],
    }
    for key in ("nx", "ny", "nphi", "half_width"):
        if key in first.attrs:
            attrs[key] = first.attrs[key]
    return xr.Dataset(variables, coords=coords, attrs=attrs)
