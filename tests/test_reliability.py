"""Faults survived and inputs refused: kills, disk full, read-only folders, concurrent runners, files."""

import fcntl
import json
import os
import random
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from sesp import Grid, SeSP, SespFileError, load, save, scan
from sesp.cli import main
from sesp.sweep import run

from cases import FULL, SMALL, content_digest
from cases import point_files as _point_files

# Reduced counts by default; SESP_FULL_TESTS=1 runs the full ones.
KILLS = 100 if FULL else 3  # SIGKILLs per case of the repeated-kill test (at most: fewer if the sweep ends first)
FLIPS = 1000 if FULL else 60  # damaged copies of a file in the bit-flip test

# A sesp scan with one bit of its header flipped: the netCDF/HDF5 library aborts (double free) when this file
# is opened in-process with xarray; sesp must refuse it without dying.
CRASHES_HDF5 = Path(__file__).parent / "data" / "crashes_hdf5.nc"

LOAD_EACH = """
import json, sys
from sesp import SespFileError, load
for path in json.loads(sys.argv[1]):
    try:
        load(path)
        print("read", flush=True)
    except SespFileError as err:
        print("refused", str(err).replace("\\n", " "), flush=True)
"""

# 28 points; 32 orientations are among the 128 that A_ex is refined on, so each point measures A_ex once
FAULT_SWEEP = (
    SMALL.replace("stop = 120, step = 30", "stop = 165, step = 10")
    .replace("nx = 24", "nx = 48")
    .replace("nphi = 16", "nphi = 32")
    .replace("segments = 24", "segments = 48")
)


def _digest(path) -> str:
    """The file's results, bit for bit (provenance attributes aside)."""
    return content_digest(path)


@pytest.fixture(scope="session")
def uninterrupted(tmp_path_factory):
    """The digest of FAULT_SWEEP run once without interruption: what every killed or shared run must end
    with. Made once for all test processes (the first to need it runs it under a lock; the others read it)."""
    shared = tmp_path_factory.getbasetemp().parent  # common to the processes of one pytest-xdist run
    with open(shared / "uninterrupted.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        known = shared / "uninterrupted.json"
        if not known.exists():
            folder = tmp_path_factory.mktemp("uninterrupted")
            path = folder / "s.toml"
            path.write_text(FAULT_SWEEP.format(out="killed"))  # relative to the sweep file: as in the test
            known.write_text(json.dumps(_digest(run(path, workers=1, progress=False))))
        return json.loads(known.read_text())


def _sweep_process(path, workers=1, stderr=subprocess.DEVNULL, **kw):
    return subprocess.Popen(
        [sys.executable, "-m", "sesp", "-q", "sweep", str(path), "--workers", str(workers)],
        stdout=subprocess.DEVNULL,
        stderr=stderr,
        start_new_session=True,
        **kw,
    )


def _live_processes_of_session(sid: int) -> list[int]:
    """Processes (zombies aside) in session ``sid``: a runner started with start_new_session and its workers."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue  # exited meanwhile
        if int(fields[3]) == sid and fields[0] != "Z":
            found.append(int(stat.parent.name))
    return found


def _wait_until_gone(sid: int, timeout: float = 30.0) -> list[int]:
    deadline = time.monotonic() + timeout
    while (left := _live_processes_of_session(sid)) and time.monotonic() < deadline:
        time.sleep(0.2)
    return left


def _wait_for_kill_moment(proc, folder, rng, timeout: float = 120.0) -> None:
    """Wait for a random moment in a sweep's life: half the time 0.3-2 s after its start (start-up, lock,
    manifest, first point), otherwise once one more point file is on disk than at the start, then up to one
    point's time more (so the kill lands while a point is computed or written). The second kind makes
    progress, so a sweep of many small points is killed many times however fast the machine."""
    if rng.random() < 0.5:
        time.sleep(rng.uniform(0.3, 2.0))
        return
    before = len(_point_files(folder)) if folder.exists() else 0
    deadline = time.monotonic() + timeout
    while proc.poll() is None and time.monotonic() < deadline:
        if folder.exists() and len(_point_files(folder)) > before:
            time.sleep(rng.uniform(0.0, 0.15))
            return
        time.sleep(0.01)


@pytest.mark.slow
@pytest.mark.parametrize("workers, kill", [(1, "group"), (2, "runner")])
def test_sweep_survives_repeated_sigkill(tmp_path, workers, kill, uninterrupted):
    """SIGKILL a real sweep at random moments, KILLS times (or until it ends; at least 3 times); the end result
    equals an uninterrupted run.

    With two workers only the runner's own PID is killed: its workers see it gone, remove the file they were
    writing and exit, and the resource tracker follows, so no process of the session and no point temporary
    is left (the runner's own, of the manifest or the collected file, are removed by the next run).
    """
    path = tmp_path / "s.toml"
    path.write_text(FAULT_SWEEP.format(out="killed"))
    folder = tmp_path / "killed"
    rng = random.Random(7 + workers)
    kills = 0
    while kills < KILLS:
        proc = _sweep_process(path, workers)
        _wait_for_kill_moment(proc, folder, rng)
        if proc.poll() is not None:
            break  # finished before this kill
        if kill == "group":
            os.killpg(proc.pid, signal.SIGKILL)
        else:
            os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        kills += 1
        assert _wait_until_gone(proc.pid) == []  # no worker, no resource tracker outlives the runner
        if kill == "runner":  # point files are written by the workers, and they removed what they were writing
            assert not list(folder.glob(f".{'[0-9a-f]' * 16}.nc.*.tmp"))
        for p in _point_files(folder):  # whatever is on disk is complete
            load(p)
    assert kills >= min(KILLS, 3)
    run(path, workers=1, progress=False)
    assert _digest(folder / "small.nc") == uninterrupted
    assert not list(folder.glob(".*.lock")) and not list(folder.glob(".*.tmp"))


def _limit_file_size():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a too-large write fails with EFBIG instead
    resource.setrlimit(resource.RLIMIT_FSIZE, (8_000, 8_000))


@pytest.mark.slow
def test_disk_full_leaves_no_file_taken_as_finished(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        SMALL.format(out=tmp_path / "out").replace(
            'keep = ["excluded_area", "classes"]', 'keep = ["excluded_area", "classes", "allowed"]'
        )
    )
    proc = _sweep_process(path, stderr=subprocess.PIPE, preexec_fn=_limit_file_size)
    _, err = proc.communicate(timeout=300)
    assert proc.returncode != 0
    assert b"Traceback" not in err and b"error" in err
    assert len(err.decode().strip().splitlines()) == 1, err.decode()  # one clear line
    leftovers = [*(tmp_path / "out").glob(".*.lock"), *(tmp_path / "out").glob(".*.tmp")]
    assert not leftovers, leftovers  # a failed write leaves no lock and no temporary
    for p in _point_files(tmp_path / "out"):
        load(p)  # anything that was written in full is valid
    run(path, workers=1, progress=False)  # and a rerun completes the sweep
    assert len(_point_files(tmp_path / "out")) == 8


def test_save_into_unwritable_place_is_a_clear_error(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    code = main(["-q", "scan", "--nx", "8", "--nphi", "2", "--segments", "8", "-o", str(blocker / "x.nc")])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and "file" in err


@pytest.mark.slow
def test_two_runners_on_one_folder(tmp_path, uninterrupted):
    path = tmp_path / "s.toml"
    path.write_text(FAULT_SWEEP.format(out="killed"))  # as the uninterrupted run: the same file text
    first, second = _sweep_process(path), _sweep_process(path)
    assert first.wait(timeout=600) == 0 and second.wait(timeout=600) == 0
    files = _point_files(tmp_path / "killed")
    assert len(files) == len({p.name for p in files}) == 2 * 14
    for p in files:
        load(p)
    assert _digest(tmp_path / "killed" / "small.nc") == uninterrupted


def test_loading_never_evaluates_attributes(tmp_path):
    ds = scan(SeSP(), Grid(8, nphi=2), segments=8)
    ds.attrs["particle_n"] = "__import__('os').system('touch pwned')"
    path = save(ds, tmp_path / "evil.nc")
    back = load(path)  # attributes come back as plain text
    assert back.attrs["particle_n"].startswith("__import__")
    assert not (tmp_path / "pwned").exists() and not Path("pwned").exists()


def test_sweep_names_cannot_escape_the_output_folder(tmp_path):
    from sesp.sweep import SweepError, load_spec

    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out="o").replace('name = "small"', 'name = "../../escape"'))
    with pytest.raises(SweepError, match="name"):
        load_spec(path)


@pytest.mark.parametrize(
    "mutate, word",
    [
        (lambda ds: ds.assign(allowed=ds.allowed.astype("float32")), "dtype"),
        (lambda ds: ds.rename({"allowed": "permitted"}), "missing variable"),
        (lambda ds: ds.assign_attrs(sesp_format="something.else"), "not a sesp dataset"),
        (lambda ds: ds.assign_attrs(nphi=5), "nphi"),
    ],
)
def test_malformed_files_are_refused(tmp_path, mutate, word):
    ds = scan(SeSP(), Grid(8, nphi=2), segments=8)
    bad = mutate(ds)
    path = tmp_path / "bad.nc"
    bad.to_netcdf(path)
    with pytest.raises(SespFileError, match=word):
        load(path)


def test_swapped_point_file_is_refused_by_collect_and_recomputed_by_a_rerun(tmp_path):
    from sesp.sweep import SweepError, collect

    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out=tmp_path / "out"))
    run(path, workers=1, progress=False)
    first, second = _point_files(tmp_path / "out")[:2]
    second.write_bytes(first.read_bytes())  # a point file under another point's name
    with pytest.raises(SweepError, match="not the sweep point its name says"):
        collect(tmp_path / "out")
    run(path, workers=1, progress=False)  # the swapped point is recomputed, not collected
    assert _digest(second) != _digest(first)


def test_lock_of_a_killed_runner_clears_at_once(tmp_path):
    """A runner killed while holding a point's lock: the OS releases its flock, a rerun does not wait."""
    from sesp.sweep import load_spec, with_common_box

    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out=tmp_path / "out"))
    point = with_common_box(load_spec(path)).points()[0]  # the points as the runner names them
    (tmp_path / "out").mkdir()
    lock = tmp_path / "out" / f".{point.hash}.lock"
    holder = subprocess.Popen(
        [sys.executable, "-c", f"import fcntl, os, time; fd = os.open({str(lock)!r}, os.O_CREAT | os.O_RDWR);"
         "fcntl.flock(fd, fcntl.LOCK_EX); print('held', flush=True); time.sleep(600)"],
        stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    assert holder.stdout.readline().strip() == "held"
    holder.send_signal(signal.SIGKILL)  # same PID reuse or not, nothing about the PID matters
    holder.wait()
    holder.stdout.close()
    start = time.monotonic()
    run(path, workers=1, progress=False)
    assert time.monotonic() - start < 60 and len(_point_files(tmp_path / "out")) == 8
    assert not list((tmp_path / "out").glob(".*.lock"))  # finished points leave no lock files


def test_concurrent_manifest_writers_and_readers(tmp_path):
    import threading

    from sesp.sweep import load_spec, read_manifest, write_manifest

    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out=tmp_path / "out"))
    spec = load_spec(path)
    (tmp_path / "out").mkdir()
    write_manifest(spec, spec.points(), tmp_path / "out")
    errors = []

    def work(write):
        try:
            for _ in range(30):
                if write:
                    write_manifest(spec, spec.points(), tmp_path / "out")
                else:
                    assert len(read_manifest(tmp_path / "out")["points"]) == 8
        except Exception as err:
            errors.append(err)

    threads = [threading.Thread(target=work, args=(w,)) for w in (True, True, False, False)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert not list((tmp_path / "out").glob(".sweep.json.*"))


def test_size_limits_are_checked_before_anything_is_created(tmp_path, capsys):
    from sesp.sweep import SweepError, load_spec

    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out=tmp_path / "out").replace("nx = 24", "nx = 65536"))
    with pytest.raises(SweepError, match=r"\[grid\].*memory"):
        load_spec(path)
    assert not (tmp_path / "out").exists()
    assert main(["scan", "--segments", "100000000", "-o", str(tmp_path / "x.nc")]) == 2
    assert "segments must be an integer in [1, 65536]" in capsys.readouterr().err


MEASURE_PEAK = """
import json, resource, sys, tracemalloc
from sesp import Grid, SeSP, analyze, scan
nx, nphi, keep = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3].split(",")
fields = dict(crossings="crossings" in keep, entangled="entangled" in keep)
from sesp.pair import Pair
pair = Pair.of(SeSP(), None, segments=64)  # built outside the measurement: its resampling is not the pass
tiny = Grid(8, nphi=2)
analyze(pair, tiny, keep=keep, rtol=1e-2) if sys.argv[4] == "analyze" else scan(pair, tiny, **fields)
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
tracemalloc.start()
grid = Grid(nx, nphi=nphi)
if sys.argv[4] == "analyze":
    analyze(pair, grid, keep=keep, rtol=1e-2)
else:
    scan(pair, grid, **fields)
traced = tracemalloc.get_traced_memory()[1]
rise = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - before
print(json.dumps({"traced": traced, "rise": rise}))
"""


@pytest.mark.parametrize(
    "nx, nphi, keep, how",
    [
        (1024, 1, "allowed", "scan"),  # one large slice: working buffers are several times the field
        (1024, 1, "allowed,crossings,entangled", "scan"),
        (384, 48, "allowed", "scan"),  # one chunk of slices and their mirror images
        (512, 8, "excluded_area,classes", "analyze"),
        (384, 16, "allowed,entangled,classes", "analyze"),
    ],
)
def test_memory_check_covers_the_measured_peak(nx, nphi, keep, how):
    """The pre-check's estimate is above the peak a pass really reaches (traced numpy and resident memory),
    so a limit just under the measured peak is refused, and it is not wildly above (a limit of 4x passes)."""
    from sesp.analysis import check_memory

    out = subprocess.run(
        [sys.executable, "-c", MEASURE_PEAK, str(nx), str(nphi), keep, how],
        capture_output=True, text=True, check=True, timeout=300,
    )  # fmt: skip
    peak = max(json.loads(out.stdout)["traced"], json.loads(out.stdout)["rise"])
    grid = Grid(nx, nphi=nphi).resolve(2.0)
    with pytest.raises(MemoryError, match="memory limit"):
        check_memory(grid, keep.split(","), limit=peak - 1)
    check_memory(grid, keep.split(","), limit=4 * peak)


def _load_each(paths) -> list[str]:
    """Load every file in one subprocess; its output lines, after asserting that it did not die."""
    out = subprocess.run(
        [sys.executable, "-c", LOAD_EACH, json.dumps([str(p) for p in paths])],
        capture_output=True, text=True, timeout=1200,
    )  # fmt: skip
    assert out.returncode == 0, f"the reading process died ({out.returncode}): {out.stderr[-500:]}"
    lines = out.stdout.splitlines()
    assert len(lines) == len(paths)
    return lines


@pytest.mark.slow
def test_single_bit_flips_are_read_or_refused_never_fatal(tmp_path):
    """FLIPS copies of a scan, each with one bit flipped (half in the header, half anywhere): each loads (the
    bit was slack) or is refused with SespFileError; no other exception, no native crash."""
    good = save(scan(SeSP(), Grid(16, nphi=4), segments=16), tmp_path / "good.nc").read_bytes()
    rng = random.Random(11)
    paths = []
    for i in range(FLIPS):
        data = bytearray(good)
        at = rng.randrange(min(len(data), 4096) if i % 2 == 0 else len(data))
        data[at] ^= 1 << rng.randrange(8)
        paths.append(tmp_path / f"flip{i}.nc")
        paths[-1].write_bytes(bytes(data))
    lines = _load_each(paths + [CRASHES_HDF5])
    assert all(line == "read" or line.startswith("refused") for line in lines)
    assert sum(line.startswith("refused") for line in lines) > FLIPS // 4  # the damage was real
    assert lines[-1].startswith("refused") and "not a readable netCDF file" in lines[-1]


def test_a_file_that_crashes_the_library_is_one_line_in_the_cli():
    out = subprocess.run(
        [sys.executable, "-m", "sesp", "info", str(CRASHES_HDF5)], capture_output=True, text=True, timeout=120
    )
    assert out.returncode == 2 and "Traceback" not in out.stderr and "not a readable netCDF file" in out.stderr


def test_huge_unstored_variable_is_refused_before_it_is_read(tmp_path):
    """A tiny file declaring a 4 GiB variable that was never written (fill values) is refused from its
    header: neither the probe nor the load allocates it."""
    import netCDF4

    path = tmp_path / "huge.nc"
    with netCDF4.Dataset(path, "w") as nc:
        for dim in ("phi", "y", "x"):
            nc.createDimension(dim, 1600)
        nc.createVariable("allowed", "u1", ("phi", "y", "x"), fill_value=1)
        nc.setncatts({"sesp_format": "sesp.scan", "sesp_format_version": 1})
    assert path.stat().st_size < 100_000
    start = time.monotonic()
    for isolate in (True, False):
        with pytest.raises(SespFileError, match="more than a file of"):
            load(path, isolate=isolate)
    assert time.monotonic() - start < 30
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss < 2 * 2**20  # KiB: this process stayed under 2 GiB


@pytest.mark.slow
def test_sweep_resume_sets_a_damaged_point_aside_and_recomputes_it(tmp_path):
    """A point file that crashes the library, met on resume: the runner survives, moves it aside, recomputes
    the point; collect before that refuses it in one line."""
    from sesp.sweep import SweepError, collect

    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out=tmp_path / "out"))
    run(path, workers=1, progress=False)
    victim = _point_files(tmp_path / "out")[3]
    victim.write_bytes(CRASHES_HDF5.read_bytes())
    with pytest.raises(SweepError, match="cannot be read"):
        collect(tmp_path / "out")
    proc = subprocess.run([sys.executable, "-m", "sesp", "-q", "sweep", str(path), "--workers", "1"], timeout=300)
    assert proc.returncode == 0
    assert victim.with_name(victim.name + ".damaged").is_file()
    fresh = run(path, output=tmp_path / "fresh", workers=1, progress=False)
    assert _digest(tmp_path / "out" / "small.nc") == _digest(fresh)


def test_a_rerun_removes_the_temporaries_a_killed_runner_owned(tmp_path):
    """A runner killed while writing the manifest, the collected file or a point leaves temporaries; the next
    run removes them all (the folder's flock tells them from a concurrent writer's)."""
    path = tmp_path / "s.toml"
    path.write_text(SMALL.format(out=tmp_path / "out"))
    run(path, workers=1, progress=False)
    point = _point_files(tmp_path / "out")[0]
    left = [".sweep.json.x1.tmp", ".small.nc.x2.tmp", f".{point.name}.x3.tmp"]
    for name in left:
        (tmp_path / "out" / name).write_text("half")
    point.unlink()  # so that the point is computed again, and its stale temporary found
    run(path, workers=1, progress=False)
    assert not list((tmp_path / "out").glob(".*.tmp"))


def _stand_in(code: str) -> subprocess.Popen:
    """A stand-in for the probe's reading process: Python running ``code``, piped as the probe's own."""
    pipes = dict(stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, bufsize=1)
    return subprocess.Popen([sys.executable, "-c", code], **pipes)


@pytest.mark.parametrize(
    "child, verdict",
    [
        ("import os, signal; os.kill(os.getpid(), signal.SIGSEGV)", "crashed the netCDF/HDF5 library (SIGSEGV)"),
        ("import sys; sys.exit(3)", "ended the reading process (exit status 3)"),
        ("import time; time.sleep(30)", "did not finish within 0.5 s"),
    ],
)
def test_a_reading_process_that_dies_or_hangs_is_a_verdict_on_its_file(tmp_path, monkeypatch, child, verdict):
    """The probe reads in a child process; whatever ends it once it has started (a signal, an exit, a hang) is
    reported for the file it was reading, and a fresh child reads the next one (its start not counted in the
    0.5 s: on a loaded machine the imports alone may take longer)."""
    from sesp import fileprobe

    start = fileprobe.start_reader
    children = iter([f"print('{json.dumps(fileprobe.READY)}', flush=True); {child}", None])

    def started():
        code = next(children)
        return start() if code is None else _stand_in(code)

    monkeypatch.setattr(fileprobe, "start_reader", started)
    good = tmp_path / "good.nc"
    save(scan(SeSP(n=2, opening=1.0), Grid(8, nphi=4), segments=8), good)
    verdicts = fileprobe.probe([tmp_path / "bad.nc", good], timeout=0.5)
    assert verdict in verdicts[tmp_path / "bad.nc"] and verdicts[good] is None


@pytest.mark.parametrize(
    "first, why",
    [
        ("print('hello', flush=True)", "its first line was 'hello'"),
        ("import sys; sys.exit(3)", "ended (exit status 3)"),
    ],
)
def test_a_reading_process_that_does_not_say_ready_is_no_verdict_on_a_file(tmp_path, monkeypatch, first, why):
    """A reading process whose first line is not READY (a stray line, or none: it ended) has not started: that
    is an error of the machine, raised as such, not a verdict on the file it would have read."""
    from sesp import fileprobe

    monkeypatch.setattr(fileprobe, "start_reader", lambda: _stand_in(first))
    with pytest.raises(RuntimeError, match="did not start") as raised:
        fileprobe.probe([tmp_path / "any.nc"], timeout=0.5)
    assert why in str(raised.value)


# A sweep that keeps every scalar answer: components, phases and B₃ (4 points of a few seconds each)
RICH_SWEEP = (
    SMALL.replace('keep = ["excluded_area", "classes"]',
                  'keep = ["excluded_area", "classes", "topology", "phases", "third_virial"]\n'
                  "resolution = 1e-2\nthird_virial_rtol = 0.5")
    .replace("n = [2, 8]", "n = [2]")
    .replace("nphi = 16", "nphi = 32")
)  # fmt: skip


@pytest.mark.slow
def test_a_sweep_keeping_topology_phases_and_b3_survives_kills_ctrl_c_and_a_damaged_point(tmp_path):
    """SIGKILL at random moments (3 times; 20 with SESP_FULL_TESTS=1), then Ctrl-C to the runner, then one
    finished point file replaced by one that crashes the netCDF library: the rerun sets it aside, recomputes
    it, and ends with the results of an uninterrupted run, bit for bit."""
    path = tmp_path / "s.toml"
    path.write_text(RICH_SWEEP.format(out="rich"))
    reference = _digest(run(path, output=tmp_path / "reference", workers=1, progress=False))
    folder, rng, kills = tmp_path / "rich", random.Random(3), 0
    while kills < (20 if FULL else 3):
        proc = _sweep_process(path, workers=2)
        _wait_for_kill_moment(proc, folder, rng)
        if proc.poll() is not None:
            break
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        kills += 1
        assert _wait_until_gone(proc.pid) == []
    proc = _sweep_process(path, workers=2, stderr=subprocess.PIPE,
                          preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    _wait_for_kill_moment(proc, folder, rng)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode in (0, 130) and b"Traceback" not in err
    finished = _point_files(folder)
    if finished:
        finished[0].write_bytes(CRASHES_HDF5.read_bytes())
    assert _digest(run(path, workers=2, progress=False)) == reference
    assert len(list(folder.glob("*.damaged"))) == (1 if finished else 0)
    assert not list(folder.glob(".*.lock")) and not list(folder.glob(".*.tmp"))


@pytest.mark.slow
def test_ctrl_c_during_a_topology_table_keeps_what_was_counted_and_a_rerun_resumes(tmp_path):
    """`sesp topology` over Ψ, SIGINT once the first run of openings is printed: exit 130 with the partial table
    and where the counts are kept; the same command then ends with the table of an uninterrupted run."""
    command = [sys.executable, "-m", "sesp", "topology", "--n", "2", "--opening-range", "150", "200", "--step", "10",
               "--width", "1", "--resolution", "1e-2", "--workers", "1"]  # fmt: skip
    proc = subprocess.Popen([*command, "--cache", str(tmp_path / "counts")], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))  # fmt: skip
    said = []
    for line in proc.stderr:  # each run of equal counts is said there as soon as it is settled
        said.append(line)
        if line.startswith("counted:"):
            break
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    err = "".join(said) + err
    assert proc.returncode == 130 and "Traceback" not in err, err
    assert "interrupted; the counts made are kept in" in err
    cached = len(list((tmp_path / "counts").rglob("*.json")))
    assert cached >= 1
    resumed = subprocess.run([*command, "-q", "--cache", str(tmp_path / "counts")], capture_output=True, text=True,
                             timeout=600)  # fmt: skip
    fresh = subprocess.run([*command, "-q", "--no-cache"], capture_output=True, text=True, timeout=600)
    assert resumed.returncode == fresh.returncode == 0

    def table(text):  # the lines of the table, its timing aside
        return [line for line in text.splitlines() if "openings counted" not in line]

    assert table(resumed.stdout) == table(fresh.stdout)
