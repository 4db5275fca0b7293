import contextlib
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from sesp import load
from sesp.cli import main
from sesp.shape import DEFAULT_SEGMENTS
from sesp.sweep import DEFAULT_GRID, SweepError, collect, load_spec, run

from cases import ROOT, SMALL, content_digest, point_files, write_sweep


def _digest(path) -> str:
    """The file's results, bit for bit (provenance attributes aside)."""
    return content_digest(path)


@pytest.mark.parametrize("sweep_file", sorted((ROOT / "sweeps").glob("*.toml")), ids=lambda p: p.name)
def test_shipped_sweep_files_are_valid(sweep_file):
    spec = load_spec(sweep_file)
    assert spec.points()


def test_spec_points_dims_and_units(tmp_path):
    spec = load_spec(write_sweep(tmp_path, SMALL.format(out=tmp_path / "o")))
    assert spec.dims == ["n", "opening"]
    assert len(spec.points()) == 8
    np.testing.assert_allclose(spec.particle["opening"], np.radians([30, 60, 90, 120]))
    hashes = [p.hash for p in spec.points()]
    assert len(set(hashes)) == 8
    assert hashes == [p.hash for p in load_spec(write_sweep(tmp_path, SMALL.format(out=tmp_path / "o"))).points()]


def test_radians_and_degrees_name_the_same_points(tmp_path):
    deg = load_spec(write_sweep(tmp_path, SMALL.format(out="o")))
    rad_text = (
        SMALL.format(out="o")
        .replace('angles = "degrees"', 'angles = "radians"')
        .replace("{ start = 30, stop = 120, step = 30 }", str([math.radians(v) for v in (30, 60, 90, 120)]))
    )
    rad = load_spec(write_sweep(tmp_path, rad_text, "r.toml"))
    assert [p.hash for p in deg.points()] == [p.hash for p in rad.points()]


@pytest.mark.parametrize(
    "edit, words",
    [
        (("nphi = 16", "nphi = 16\ncolour = 3"), ["unknown key 'colour'", "[grid]"]),
        (("[output]", "[plots]\nx = 1\n[output]"), ["unknown section [plots]"]),
        (("opening = { start = 30, stop = 120, step = 30 }\n", ""), ["missing key 'opening'"]),
        (("degrees", "gradians"), ["angles"]),
        (("stop = 120", "stop = 400"), ["opening", "360 degrees", "[0, 360) degrees"]),
        (("stop = 120", "stop = inf"), ["finite"]),
        (("step = 30", "step = 1e-9"), ["values", "limit"]),
        (("step = 30", "num = 1000000000"), ["values", "limit"]),
        (
            ("n = [2, 8]", "n = { start = 1, stop = 1000, num = 1000 }\nm = { start = 1, stop = 1000, num = 1000 }"),
            ["parameter points", "limit"],
        ),
        (("n = [2, 8]", "n = [2, -8]"), ["n must be"]),
        (("n = [2, 8]", "n = []"), ["empty"]),
        (("n = [2, 8]", 'n = ["two"]'), ["[particle] n", "expected numbers"]),
        (("step = 30", "step = -30"), ["step > 0"]),
        (("segments = 24", "segments = 2.5"), ["integers"]),
        (("nx = 24", "nx = 2"), ["nx"]),
        (('"classes"]', '"classes", "pictures"]'), ["keep"]),
        (('"classes"]', '"classes"]\nresolution = -1'), ["[output] resolution must be in [1e-09, 1] b"]),
        (("rtol = 1e-3", "rtol = 2.0"), ["[output] rtol must be in [1e-12, 0.5]"]),
        (('"classes"]', '"classes"]\nthird_virial_rtol = 0'), ["[output] third_virial_rtol must be in"]),
        (("nx = 24", "nx = 24 24"), ["not valid TOML"]),
    ],
)
def test_bad_sweep_files_name_file_and_key(tmp_path, edit, words):
    text = SMALL.format(out="o").replace(*edit)
    path = write_sweep(tmp_path, text)
    with pytest.raises(SweepError) as err:
        load_spec(path)
    assert str(path) in str(err.value)
    for word in words:
        assert word in str(err.value)


def test_run_collects_labelled_dataset_and_skips_finished_points(tmp_path):
    path = write_sweep(tmp_path, SMALL.format(out=tmp_path / "out"))
    target = run(path, workers=1, progress=False)
    ds = xr.open_dataset(target)
    sizes = {"n": 2, "opening": 4, "phi": 16, "y": 24, "x": 24, "k": 9, "order": 5}
    assert dict(ds.sizes) == sizes  # k: spectrum orders 0..8 of the refined A_ex(φ); order: k = 1, 2, 3, 4, 6
    np.testing.assert_array_equal(ds.k, np.arange(9))
    assert ds.excluded_area.dims == ("n", "opening", "phi")
    assert ds.opening.attrs["units"] == "rad"
    np.testing.assert_allclose(ds.opening_degrees, [30, 60, 90, 120])
    assert ds.classes.attrs["flag_meanings"] == "free spooning entangled excluded"
    assert float(ds.segments) == 24 and ds.segments.dims == ()  # fixed parameters are scalar coordinates
    ds.close()
    stamps = {p.name: p.stat().st_mtime_ns for p in point_files(tmp_path / "out")}
    run(path, workers=1, progress=False)
    assert {p.name: p.stat().st_mtime_ns for p in point_files(tmp_path / "out")} == stamps


def test_collect_refuses_incomplete_folder(tmp_path):
    path = write_sweep(tmp_path, SMALL.format(out=tmp_path / "out"))
    run(path, workers=1, progress=False, collect_result=False)
    point_files(tmp_path / "out")[0].unlink()
    with pytest.raises(SweepError, match="1 of 8 points are not computed"):
        collect(tmp_path / "out")


KILL_SWEEP = (
    SMALL.replace("stop = 120, step = 30", "stop = 165, step = 15")
    .replace("nx = 24", "nx = 64")
    .replace("nphi = 16", "nphi = 64")
    .replace("segments = 24", "segments = 64")
)


@pytest.mark.slow
def test_killed_sweep_resumes_without_recomputing(tmp_path):
    """SIGKILL a real sweep process part-way, rerun, compare with an uninterrupted run."""
    path = write_sweep(tmp_path, KILL_SWEEP.format(out=tmp_path / "killed"))
    folder = tmp_path / "killed"
    proc = subprocess.Popen(
        [sys.executable, "-m", "sesp", "-q", "sweep", str(path), "--workers", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    deadline = time.monotonic() + 120
    while len(point_files(folder)) < 3 and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()
    done = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in point_files(folder)}
    assert 3 <= len(done) < 20, "the kill should land part-way through the sweep"
    run(path, workers=1, progress=False)
    after = {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in point_files(folder)}
    assert all(after[name] == stamp for name, stamp in done.items())  # not recomputed
    assert len(after) == 20
    fresh = run(path, output=tmp_path / "fresh", workers=1, progress=False)
    assert _digest(folder / "small.nc") == _digest(fresh)
    for a, b in zip(point_files(folder), point_files(tmp_path / "fresh")):
        assert a.name == b.name and _digest(a) == _digest(b)
    assert not list(folder.glob(".*.tmp"))


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@pytest.mark.filterwarnings("ignore::ResourceWarning")
@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_dask_cluster_and_local_processes_write_identical_files(tmp_path):
    distributed = pytest.importorskip("distributed")
    path = write_sweep(tmp_path, SMALL.format(out="unused"))
    local = run(path, output=tmp_path / "local", workers=2, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        remote = run(path, output=tmp_path / "dask", scheduler=cluster.scheduler_address, progress=False)
    assert _digest(local) == _digest(remote)
    for a, b in zip(point_files(tmp_path / "local"), point_files(tmp_path / "dask")):
        assert a.name == b.name and _digest(a) == _digest(b)


POLYLINE_MIXTURE = """
[sweep]
name = "mixture"
output = "{out}"
angles = "degrees"

[particle]
vertices = [[-1.0, 0.0], [1.0, 0.0]]

[other]
n = 2
opening = [0, 90]

[grid]
nx = 32
nphi = 8

[output]
rtol = 1e-3
"""


def test_sweep_of_a_polyline_and_a_sesp_mixture(tmp_path):
    path = write_sweep(tmp_path, POLYLINE_MIXTURE.format(out=tmp_path / "out"))
    spec = load_spec(path)
    assert spec.dims == ["other_opening"]
    points = spec.points()
    particle, other = points[1].particles()
    assert other.opening == pytest.approx(math.pi / 2) and particle.segments == 1
    ds = xr.open_dataset(run(path, workers=1, progress=False))
    assert ds.excluded_area.dims == ("other_opening", "phi")
    # needle of length L = 2 against a unit circle (R = 1, L = 2R: it never fits inside):
    # A_ex = πR² + 2RL = π + 4 at every φ, to the coarse grid's accuracy
    closed = ds.excluded_area.sel(other_opening=0).values
    np.testing.assert_allclose(closed, math.pi + 4, rtol=0.05)
    ds.close()


def test_vertices_and_shape_keys_are_exclusive(tmp_path):
    text = POLYLINE_MIXTURE.replace(
        "vertices = [[-1.0, 0.0], [1.0, 0.0]]", "vertices = [[-1.0, 0.0], [1.0, 0.0]]\nn = 2"
    )
    with pytest.raises(SweepError, match="vertices"):
        load_spec(write_sweep(tmp_path, text.format(out=tmp_path / "out")))


def test_output_folder_is_relative_to_the_sweep_file(tmp_path, monkeypatch):
    (tmp_path / "sub").mkdir()
    monkeypatch.chdir(tmp_path)
    spec = load_spec(write_sweep(tmp_path / "sub", SMALL.format(out="results/x")))
    assert spec.output == tmp_path / "sub" / "results" / "x"
    assert load_spec(tmp_path / "sub" / "s.toml", output="elsewhere").output == Path("elsewhere")
    bad = SMALL.format(out="o").replace('output = "o"', 'output = ["a", "b"]')
    with pytest.raises(SweepError, match="output must be a folder name"):
        load_spec(write_sweep(tmp_path, bad, "bad.toml"))
    with pytest.raises(SweepError, match="name must be"):
        load_spec(
            write_sweep(tmp_path, SMALL.format(out="o").replace('name = "small"', f'name = "{"x" * 300}"'), "n.toml")
        )


def _children(pid: int) -> set:
    """Process ids of pid's children (Linux /proc)."""
    found = set()
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            found |= {int(c) for c in (task / "children").read_text().split()}
        except OSError:
            pass
    return found


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.slow
def test_ctrl_c_stops_a_local_sweep_within_seconds_and_keeps_what_finished(tmp_path):
    """SIGINT to the runner alone (not its group), --workers 2: it stops its workers, says how to resume.

    46 points of about 1 s each: on two workers the sweep outlasts its first point file by about 20 s (6.8 s to
    the first file, 28 s in all, on a slow 2-core machine), so it is still running where this process, on a
    loaded machine, notices that file late."""
    text = KILL_SWEEP.replace("nx = 64", "nx = 192").replace("nphi = 64", "nphi = 128").replace("step = 15", "step = 6")
    path = write_sweep(tmp_path, text.format(out=tmp_path / "out"))
    total = 2 * len(range(30, 166, 6))  # n = 2 and 8, openings 30°, 36°, ..., 162°
    proc = subprocess.Popen(
        [sys.executable, "-m", "sesp", "-q", "sweep", str(path), "--workers", "2"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        env={**os.environ, "PYTHONFAULTHANDLER": "1"},  # SIGABRT then prints every thread's stack
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),  # as from a shell, even if ignored here
    )
    children, deadline = set(), time.monotonic() + 120
    while not point_files(tmp_path / "out") and time.monotonic() < deadline and proc.poll() is None:
        children |= _children(proc.pid)  # the workers start long before the first point file
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)  # at once: under load a scan of /proc here let the sweep run to its end
    start = time.monotonic()
    assert children, "the sweep should have been running with its workers"
    try:
        _, err = proc.communicate(timeout=30)
    except subprocess.TimeoutExpired:  # say where the runner is stuck
        os.kill(proc.pid, signal.SIGABRT)
        _, err = proc.communicate()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGKILL)  # its workers
        pytest.fail(f"the runner was still there 30 s after SIGINT; its threads:\n{err}")
    assert time.monotonic() - start < 10
    assert proc.returncode == 130 and "Run the same command again to resume" in err and "Traceback" not in err
    time.sleep(0.5)
    assert not [pid for pid in children if _alive(pid) and "spawn" in Path(f"/proc/{pid}/cmdline").read_text()]
    done = point_files(tmp_path / "out")
    assert 1 <= len(done) < total
    assert not list((tmp_path / "out").glob(".*.tmp"))
    run(path, workers=2, progress=False)  # resumes (each point on one of two workers, as the interrupted run)
    assert len(point_files(tmp_path / "out")) == total


def test_a_sweep_file_needs_only_its_particles(tmp_path):
    """Output folder, angle unit, grid, segments and keep default to the documented values."""
    path = write_sweep(tmp_path, "[particle]\nn = 8\nopening = [60, 90]\n", "bare.toml")
    spec = load_spec(path)
    assert spec.output == tmp_path / "results" / "bare"
    assert spec.grid == DEFAULT_GRID == {"nx": 128, "nphi": 128}
    assert list(spec.keep) == ["excluded_area"]
    assert spec.particle["opening"] == (math.radians(60), math.radians(90))
    assert spec.particle["segments"] == (DEFAULT_SEGMENTS,)


@pytest.mark.slow
def test_a_sweep_keeps_the_phases_and_b3_and_plots_them(tmp_path):
    """keep "phases" and "third_virial": the first transition and B₃ per point, drawn by `sesp plot phases`;
    n = 8 at 90° orders nematically and continuously (benchmarks/phase_diagram.py: 1.384 b⁻²)."""
    path = write_sweep(tmp_path, PHASES_SWEEP.format(out=tmp_path / "out"))
    collected = run(path, workers=1, progress=False)
    ds = load(collected)
    point = ds.sel(opening=math.radians(90))  # one n: a scalar coordinate of the collected file
    assert int(point.transition_order) == 2 and int(point.continuous) == 1
    assert float(point.transition_density) == pytest.approx(1.384, rel=2e-3)
    assert 0.5 < float(point.reduced_third_virial) < 1.0 and float(point.third_virial_coefficient_error) > 0
    assert main(["plot", "phases", str(collected), "-o", str(tmp_path / "phases.png")]) == 0
    assert (tmp_path / "phases.png").stat().st_size > 10_000


PHASES_SWEEP = """
[sweep]
output = "{out}"

[particle]
n = [8]
opening = {{ start = 90, stop = 180, step = 90 }}
segments = 64

[grid]
nx = 16
nphi = 64

[output]
keep = ["excluded_area", "phases", "third_virial"]
"""
