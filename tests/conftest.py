"""Shared fixtures, the full-strength switch and the report of tests whose duration contradicts their marker.

``SESP_FULL_TESTS=1 pytest`` runs every test at full strength: the variants marked ``full`` (a second base
grid or grid parity for a rule that a faster test already checks) and the fault tests at their full counts.
"""

import subprocess
import sys

import numba
import pytest

from cases import FULL

# Kernels compiled (or loaded from numba's cache) before the test processes start, in two processes side by side:
# the certified count's, and the field's, A_ex's and B₃'s. Without it each test process compiles what its first
# tests need, and both compile the certified kernels at the same time.
WARM_UP = (
    "import math, sesp; sesp.certified_components(sesp.SeSP(n=4, opening=math.radians(170)), resolution=1e-2,"
    " progress=False)",
    "import math, sesp; from sesp.virial import third_virial;"
    " sesp.analyze(sesp.SeSP(n=2, opening=1.0), sesp.Grid(16, nphi=8), segments=16,"
    " keep=['excluded_area', 'classes', 'allowed', 'crossings', 'entangled']);"
    " sesp.excluded_area(sesp.SeSP(n=8, opening=1.0), rtol=1e-2, progress=False);"
    " third_virial(sesp.SeSP(n=2, opening=1.0), rtol=None, nodes=21, nphi=2, segments=16, progress=False);"
    " sesp.overlaps(sesp.SeSP(), None, [0.0], [0.0], [0.0])",
)


def pytest_configure(config):
    """Warm numba's cache once, before the test processes start (not in them, not for one process alone)."""
    if hasattr(config, "workerinput") or not getattr(config.option, "numprocesses", None):
        return
    runs = [subprocess.Popen([sys.executable, "-c", code]) for code in WARM_UP]
    for run in runs:
        run.wait()


SLOW_OVER = 5.0  # s on an idle 2-core machine: a test that takes longer is marked slow
FAST_UNDER = 1.0  # s: a test marked slow that takes less is not


def pytest_collection_modifyitems(config, items):
    # slow tests first: two processes then share out the long ones before the short ones fill the gaps
    items.sort(key=lambda item: "slow" not in item.keywords)
    if FULL:
        return
    skip = pytest.mark.skip(reason="full-strength variant: SESP_FULL_TESTS=1 runs it")
    for item in items:
        if "full" in item.keywords:
            item.add_marker(skip)


_durations = {}


def pytest_runtest_logreport(report):
    if report.when in ("setup", "call") and not report.skipped:
        _durations[report.nodeid] = _durations.get(report.nodeid, 0.0) + report.duration
        if report.when == "call":
            _durations[report.nodeid, "slow"] = "slow" in report.keywords


def pytest_terminal_summary(terminalreporter):
    """List the tests whose marker their duration contradicts (a hint to re-mark them, not a failure: the
    machine's load moves durations)."""
    wrong = []
    for key, seconds in _durations.items():
        if isinstance(key, tuple) or (key, "slow") not in _durations:
            continue
        slow = _durations[key, "slow"]
        if (slow and seconds < FAST_UNDER) or (not slow and seconds > SLOW_OVER):
            wrong.append(f"{seconds:7.1f} s  {'slow' if slow else 'not slow'}  {key}")
    if wrong:
        terminalreporter.section("markers that durations contradict")
        for line in sorted(wrong, reverse=True):
            terminalreporter.write_line(line)


@pytest.fixture
def threads():
    """Set numba's thread count for a test, restoring it afterwards."""
    before = numba.get_num_threads()
    yield numba.set_num_threads
    numba.set_num_threads(before)


@pytest.fixture(autouse=True)
def _private_cache(tmp_path_factory, monkeypatch):
    """Every test keeps counted openings (sesp topology's cache) in a folder of its own, not in ~/.cache."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("cache")))
