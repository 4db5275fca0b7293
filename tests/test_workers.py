"""The worker processes of sweeps and Ψ searches (:mod:`sesp.workers`)."""

import os

import numba

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
