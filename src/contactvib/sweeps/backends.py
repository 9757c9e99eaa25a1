"""Where the levels of a sweep run: this process, a local process pool, or a Dask cluster.

The unit of work is one P_a level: ``fn(*args)`` (in practice
:func:`contactvib.sweeps.resonance._run_level`) sweeps it, writes its chunk atomically itself and
returns ``(level dataset, extra)``. :func:`run_levels` hands every task to a backend and calls
``finished(pa, result)`` in this process as each one ends, so that every backend produces the
same chunks and the same merged dataset:

- :class:`LocalPool` (the default): ``workers`` spawned processes, one numba thread each (the
  only level of parallelism), or this process for one worker or one level;
- :class:`DaskBackend`: a ``dask.distributed`` ``LocalCluster`` of ``n_workers`` single-threaded
  worker processes whose numba threads share the cores (``cores // n_workers`` each), or a
  running cluster at ``scheduler`` (``Client(address)``; one numba thread per task). Each worker
  imports the kernels once when it joins (a worker plugin, :mod:`contactvib.sweeps.dask_worker`),
  not once per task. A task re-run after a worker died rewrites its chunk with the same bytes
  through the same atomic rename: never a duplicated or partial chunk.

Progress inside running levels: a level's task calls :func:`.level_progress.report_points` with
the frequency points it has done; the pool's workers send them through a ``multiprocessing`` queue, Dask's
through the worker's event log (``log_event`` / ``Client.subscribe_topic``), and ``run_levels``
hands them to ``progress(pa, points)`` in this process while it waits; a thread may send its own
levels' reports elsewhere (:func:`.level_progress.points_to`).

SIGINT (deferred by the caller, :mod:`contactvib.interrupts`) is honoured within 0.2 s while
waiting: the pool's workers are terminated, the Dask tasks cancelled and a LocalCluster closed.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from contactvib.interrupts import check_interrupt, end_with_parent
from contactvib.model import WORKERS_MAX, ParameterError, check_int
from contactvib.sweeps.level_progress import points_to, report_points, sink_for_process

__all__ = ["LocalPool", "DaskBackend", "run_levels", "check_scheduler_address", "kernel_cache_cold",
           "report_points", "points_to"]

_ADDRESS = re.compile(r"^(?:(tcp|tls|ws|wss|ucx)://)?([A-Za-z0-9._\-]+|\[[0-9A-Fa-f:.]+\]):(\d{1,5})$")

#: Seconds to wait for a running scheduler to answer before refusing its address.
CONNECT_TIMEOUT_S = 3.0

def check_scheduler_address(address) -> str:
    """A Dask scheduler address ``[tcp://]HOST:PORT`` (``tls://``, ``ws://``, ``wss://``,
    ``ucx://`` too); ParameterError ``scheduler`` otherwise."""
    text = str(address).strip()
    m = _ADDRESS.match(text)
    if m is None or not 1 <= int(m.group(3)) <= 65535:
        raise ParameterError("scheduler", address, "expected a Dask scheduler address tcp://HOST:PORT")
    return text if m.group(1) else f"tcp://{text}"


@dataclass(frozen=True)
class LocalPool:
    """A local process pool of ``workers`` processes (None: one per CPU core, at most one per
    level; 1: this process)."""

    workers: int | None = None

    def __post_init__(self):
        if self.workers is not None:
            object.__setattr__(self, "workers", check_int("workers", self.workers, 1, WORKERS_MAX))


@dataclass(frozen=True)
class DaskBackend:
    """A Dask cluster: a running one at ``scheduler`` (``tcp://HOST:PORT``), or else a
    ``LocalCluster`` of ``n_workers`` single-threaded worker processes (default: one per core)."""

    scheduler: str | None = None
    n_workers: int | None = None

    def __post_init__(self):
        if self.scheduler is not None and self.n_workers is not None:
            raise ParameterError("dask_workers", self.n_workers, "give a scheduler or a worker count, not both")
        if self.scheduler is not None:
            object.__setattr__(self, "scheduler", check_scheduler_address(self.scheduler))
        if self.n_workers is not None:
            object.__setattr__(self, "n_workers", check_int("dask_workers", self.n_workers, 1, WORKERS_MAX))


def run_levels(tasks: dict, fn, backend, finished, progress=None, warm_up=None) -> None:
    """Run ``fn(*tasks[pa])`` for every level ``pa`` of ``tasks`` on ``backend`` (a
    :class:`LocalPool`, a :class:`DaskBackend`, or None: the default pool), calling
    ``finished(pa, result)`` in this process as each ends and ``progress(pa, points)`` as the
    running levels report frequency points done (:func:`.level_progress.report_points`); highest
    levels first (the slowest). ``warm_up = (call, args)``, given on a first run: a local pool of two or more
    workers runs ``call(*args)`` before the levels, on one worker while another starts the first
    level, so the two compile different kernels at once (its result is dropped).

    Raises ParameterError ``scheduler`` when no scheduler answers at the address."""
    backend = LocalPool() if backend is None else backend
    progress = progress or (lambda pa, points: None)
    order = sorted(tasks, key=lambda p: -p)
    if isinstance(backend, DaskBackend):
        return _run_on_dask(order, tasks, fn, backend, finished, progress)
    n_workers = backend.workers or min(len(order), os.cpu_count() or 1)
    if n_workers <= 1 or len(order) <= 1:
        previous = sink_for_process(lambda item: progress(*item))
        try:
            for pa in tasks:
                finished(pa, fn(*tasks[pa]))
                check_interrupt()
        finally:
            sink_for_process(previous)
        return None
    return _run_in_pool(order, tasks, fn, n_workers, finished, progress, warm_up)


def kernel_cache_cold() -> bool:
    """Whether the kernels will be compiled by this run: their cache folder for the current
    sources (:mod:`contactvib._kernels`) holds no index file yet."""
    from numba.core import config

    from contactvib._kernels import kernel_cache_dir

    folder = kernel_cache_dir() or (Path(config.CACHE_DIR) if config.CACHE_DIR else None)
    if folder is None or not folder.is_dir():
        return True
    return next(folder.rglob("*.nbi"), None) is None


# ------------------------------------------------------------------ local process pool

def _worker_init(parent: int | None = None):
    """A pool worker: one numba thread, SIGINT ignored (the parent handles it and terminates
    the workers), ends when ``parent`` does (even on SIGKILL)."""
    import signal

    import numba

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if parent is not None:
        end_with_parent(parent)
    numba.set_num_threads(1)


def _pool_worker_init(parent: int, points) -> None:
    """A pool worker (:func:`_worker_init`) that sends its levels' points done through the
    queue ``points``."""
    _worker_init(parent)
    points.cancel_join_thread()  # a worker never waits at exit for news nobody reads
    sink_for_process(points.put)


def _drain_points(points, progress) -> None:
    """Hand every ``(pa, points)`` waiting in the queue to ``progress``."""
    import queue

    while True:
        try:
            item = points.get_nowait()
        except (queue.Empty, OSError, EOFError, ValueError):
            return
        progress(*item)


def _run_in_pool(order, tasks, fn, n_workers, finished, progress, warm_up=None):
    import multiprocessing as mp
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    _quiet_resource_tracker()
    ctx = mp.get_context("spawn")
    points = ctx.Queue()
    pool = ProcessPoolExecutor(max_workers=n_workers, mp_context=ctx,
                               initializer=_pool_worker_init, initargs=(os.getpid(), points))
    try:
        warm = [pool.submit(warm_up[0], *warm_up[1])] if warm_up is not None else []
        futs = {pool.submit(fn, *tasks[pa]): pa for pa in order}
        pending = set(futs) | set(warm)
        while pending:  # polled: a deferred SIGINT is honoured within 0.2 s
            ready, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            _drain_points(points, progress)
            for fut in ready:
                if fut in futs:
                    finished(futs[fut], fut.result())
            check_interrupt()
    except BaseException:
        _stop_pool(pool)
        raise
    # every level is in: the workers end (about 0.6 s of interpreter teardown each) while this
    # process merges and writes; the interpreter's exit joins them
    pool.shutdown(wait=False)


def _quiet_resource_tracker() -> None:
    """Start multiprocessing's resource tracker (if not running) without warnings: when this
    process is killed (SIGKILL) it still removes the pool's semaphores, but silently instead of
    two lines about "leaked semaphore objects" on the terminal."""
    import sys

    try:
        from multiprocessing import resource_tracker
    except ImportError:  # not POSIX
        return
    sys.warnoptions.append("ignore::UserWarning")  # passed on as -W to the tracker it starts
    try:
        resource_tracker.ensure_running()
    finally:
        sys.warnoptions.remove("ignore::UserWarning")


def _stop_pool(pool) -> None:
    """Stop a process pool at once: pending levels cancelled, running ones terminated (SIGTERM),
    workers joined; SIGINT is ignored meanwhile (main thread)."""
    import signal
    import threading

    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        processes = list((getattr(pool, "_processes", None) or {}).values())
        manager = getattr(pool, "_executor_manager_thread", None)
        results = getattr(pool, "_result_queue", None)
        for p in processes:
            p.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        for p in processes:
            p.join(5.0)
            if p.is_alive():
                p.kill()
                p.join(5.0)
        # A worker terminated while sending a level leaves the pool's thread reading a partial
        # message forever (and the interpreter's exit joins that thread): with every worker
        # gone, closing this process's end for writing gives it end-of-file instead.
        if results is not None and getattr(results, "_writer", None) is not None:
            results._writer.close()
        if manager is not None:
            manager.join(10.0)
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)


# ------------------------------------------------------------------ Dask

def _run_on_dask(order, tasks, fn, backend: DaskBackend, finished, progress):
    import time

    from contactvib.sweeps.dask_worker import dask_task, open_client

    if backend.scheduler is None:
        _quiet_resource_tracker()  # a LocalCluster's processes: silent when this one is killed
    client, cluster, threads = open_client(backend, CONNECT_TIMEOUT_S)
    topic = f"contactvib-points-{os.getpid()}-{time.time_ns()}"
    reported: dict = {}  # pa -> points, written by the client's thread, read here
    client.subscribe_topic(topic, lambda event: reported.__setitem__(*event[1]))
    futs = {}
    try:
        # one graph of all the levels (one map): the scheduler queues them together and starts
        # them in this order (highest level, the slowest, first) as workers free up. One submit
        # per level would have it place the first few at once, two per worker, before it saw
        # how many were coming. Keys unique per run: a rerun recomputes (its chunk may be gone)
        stamp = f"{os.getpid()}-{time.time_ns()}"
        n = len(order)
        columns = [list(c) for c in zip(*(tasks[pa] for pa in order))]
        mapped = client.map(dask_task, [threads] * n, [topic] * n, [fn] * n, *columns,
                            key=[f"contactvib-level-pa{pa!r}-{stamp}" for pa in order], pure=False)
        futs = dict(zip(mapped, order))
        pending = list(futs)
        while pending:  # polled: a deferred SIGINT is honoured within 0.2 s
            for pa, points in list(reported.items()):
                progress(pa, points)
            still = []
            for fut in pending:
                if fut.done():
                    finished(futs[fut], fut.result())
                else:
                    still.append(fut)
            pending = still
            check_interrupt()
            if pending:
                time.sleep(0.1)
    except BaseException:
        _close_quietly(client, cluster, list(futs))
        raise
    _close_quietly(client, cluster, [])


def _close_quietly(client, cluster, futures) -> None:
    """Cancel ``futures`` and close the client (and the LocalCluster this run started), with
    SIGINT ignored meanwhile and the cluster's shutdown messages silenced."""
    import logging
    import signal
    import threading

    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    level = logging.getLogger("distributed").level
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    try:
        if futures:
            try:
                client.cancel(futures)
            except Exception:  # the cluster may be gone already
                pass
        client.close(timeout=10)
        if cluster is not None:
            cluster.close(timeout=10)
    finally:
        logging.getLogger("distributed").setLevel(level)
        if main:
            signal.signal(signal.SIGINT, previous)
