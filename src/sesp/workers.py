"""Worker processes for independent jobs (sweep points, counts at openings): started, and stopped on Ctrl-C."""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import threading
import time
from concurrent.futures import ProcessPoolExecutor

import numba

__all__ = ["start_pool", "stop_pool"]


def start_pool(
    workers: int, initializer=None, initargs=(), *, threads=None, passive=True, on_orphan=None
) -> ProcessPoolExecutor:
    """``workers`` processes, each with ``threads`` numba threads (default all of this process's), set up by
    ``initializer(*initargs)``. A worker never outlives this process: once it is gone (killed by SIGTERM or
    SIGKILL, say), each worker calls ``on_orphan()`` (a module-level function: its own cleanup) and exits.

    With ``passive``, each worker's threads wait without spinning (OpenMP's passive wait, unless
    ``OMP_WAIT_POLICY`` says otherwise): while several workers run, the system shares the cores among them at
    little cost, and a worker left alone (the last point of a sweep, the end of a bisection chain) uses every
    core (``benchmarks/worker_threads.py``). Each result is written by one thread per item, so it does not
    depend on the thread count."""
    ctx = multiprocessing.get_context("spawn")  # numba's thread pool is not fork-safe
    threads = numba.get_num_threads() if threads is None else threads
    setup = (threads, passive, os.getpid(), on_orphan, initializer, initargs)
    return _Pool(workers, mp_context=ctx, initializer=_setup, initargs=setup)


class _Pool(ProcessPoolExecutor):
    """A process pool whose workers start with SIGINT ignored (they are started by ``submit``, and inherit it):
    a Ctrl-C that reaches a worker while it imports sesp is not a traceback. :func:`_setup` restores the
    default once the worker is ready; the runner ignores SIGINT only for the moment a submit takes."""

    def submit(self, fn, /, *args, **kwargs):
        if threading.current_thread() is not threading.main_thread():
            return super().submit(fn, *args, **kwargs)
        before = signal.signal(signal.SIGINT, signal.SIG_IGN)
        try:
            return super().submit(fn, *args, **kwargs)
        finally:
            signal.signal(signal.SIGINT, before)


def _setup(threads, passive, runner, on_orphan, initializer, initargs):
    if passive:  # OpenMP reads it once, when numba starts its threads (in set_num_threads): so before that
        os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    numba.set_num_threads(threads)
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:  # ignored while it started (_Pool)
        signal.signal(signal.SIGINT, signal.default_int_handler)
    if initializer is not None:  # first: the watch's cleanup may rely on it (the sweep's SIGINT handler)
        initializer(*initargs)
    watch = threading.Thread(
        target=_stop_when_orphaned, args=(runner, on_orphan), daemon=True, name="sesp-orphan-watch"
    )
    watch.start()


def _stop_when_orphaned(runner: int, on_orphan, poll: float = 0.25):
    """In a worker: once the runner process is gone, call ``on_orphan`` and exit."""
    while os.getppid() == runner:
        time.sleep(poll)
    if on_orphan is not None:
        on_orphan()
    os._exit(1)


def stop_pool(pool, grace: float = 3.0, interrupt: bool = True):
    """Interrupt the workers so they remove what they were writing and leave, cancel what has not started,
    kill stragglers. The workers are told first: none is left reading a queue that the shutdown closes.
    ``interrupt`` False: kill them at once (they write nothing to remove)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    try:
        for process in processes:
            with contextlib.suppress(ProcessLookupError):  # it may end between the test and the signal
                if process.is_alive() and interrupt:
                    os.kill(process.pid, signal.SIGINT)
                elif process.is_alive():
                    process.kill()
        pool.shutdown(wait=False, cancel_futures=True)
        deadline = time.monotonic() + grace
        for process in processes:
            process.join(max(0.0, deadline - time.monotonic()))
    finally:  # also when a second Ctrl-C lands here
        for process in processes:
            if process.is_alive():
                process.kill()
        for process in processes:
            process.join(2.0)  # gone, so its lock is released and what it was writing can be removed
