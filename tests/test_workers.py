"""The worker processes of sweeps and Ψ searches (:mod:`sesp.workers`)."""

import os
import signal
import subprocess
import sys
import time

import numba
import pytest

from sesp.workers import start_pool


def test_workers_have_every_thread_and_wait_passively(threads, monkeypatch):
    """Each worker process gets all of this process's numba threads (one left alone uses every core), and its
    OpenMP threads wait without spinning unless the user's environment says otherwise; both can be asked."""
    every = numba.config.NUMBA_NUM_THREADS
    cases = [(1, None, {}, 1, "PASSIVE"), (every, "ACTIVE", {}, every, "ACTIVE"),
             (every, None, dict(threads=1, passive=False), 1, None)]  # fmt: skip
    for here, policy, asked, there, waits in cases:
        threads(here)
        if policy is None:
            monkeypatch.delenv("OMP_WAIT_POLICY", raising=False)
        else:
            monkeypatch.setenv("OMP_WAIT_POLICY", policy)
        pool = start_pool(1, **asked)
        try:
            assert pool.submit(numba.get_num_threads).result() == there
            assert pool.submit(os.getenv, "OMP_WAIT_POLICY").result() == waits
        finally:
            pool.shutdown()


RUNNER = """
import os, time
from sesp.workers import start_pool

if __name__ == "__main__":
    pool = start_pool(1)  # as the search over openings starts its pool: no initializer, no cleanup of its own
    print(pool.submit(os.getpid).result(), flush=True)
    pool.submit(time.sleep, 120)
    time.sleep(120)
"""


def _running(pid):
    """Whether process ``pid`` runs (a zombie, exited and not yet reaped by whoever adopted it, does not)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="reads process states from /proc (Linux)")
def test_a_worker_busy_when_its_runner_is_killed_exits_too(tmp_path):
    """A runner killed by SIGKILL (a batch scheduler, say) runs no cleanup; its workers see it gone and exit,
    even one in the middle of a job, rather than computing on for nobody."""
    script = tmp_path / "runner.py"
    script.write_text(RUNNER)
    with subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True) as runner:
        worker = int(runner.stdout.readline())
        assert _running(worker)
        runner.send_signal(signal.SIGKILL)
        runner.wait(10)
    deadline = time.monotonic() + 10
    while _running(worker) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _running(worker)
