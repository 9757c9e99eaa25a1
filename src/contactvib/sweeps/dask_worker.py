"""The Dask side of :mod:`contactvib.sweeps.backends` (the only module that imports
``dask.distributed``): the client of a running or a local cluster, the worker plugin that loads
the kernels once per worker, and the task wrapper that sets the task's numba threads."""

from __future__ import annotations

import logging
import os
import warnings

import dask
from distributed import Client, LocalCluster
from distributed.diagnostics.plugin import WorkerPlugin

from contactvib.model import ParameterError

__all__ = ["open_client", "dask_task", "KernelWarmUp", "LOCAL_CLUSTER_CONFIG"]

#: Dask settings of the LocalCluster that ``--dask-workers`` starts (its nannies pass them on to
#: their workers). No dashboard, so no use for the workers' statistical profiler, which samples
#: every thread's stack every 10 ms; nor for its system monitor. A worker saturation of 1: the
#: scheduler hands a worker its next level only when it is free, in the order the levels were
#: mapped (highest P_a, the slowest, first). With Dask's default 1.1 each single-threaded
#: worker holds two levels from the start, and a slow level can end up queued behind another.
LOCAL_CLUSTER_CONFIG = {"distributed.worker.profile.enabled": False,
                        "distributed.admin.system-monitor.interval": "5s",
                        "distributed.admin.system-monitor.gil.enabled": False,
                        "distributed.scheduler.worker-saturation": 1.0}


class KernelWarmUp(WorkerPlugin):
    """Run once by every worker when it joins the cluster (also by workers that join later):
    imports the sweep and its compiled kernels, so that their numba cache is opened once per
    worker process and stays loaded for all its levels. The workers of a LocalCluster started
    by contactvib also ignore SIGINT (this process handles Ctrl-C and closes the cluster) and
    end when this process ends, even by SIGKILL."""

    name = "contactvib-kernels"

    def __init__(self, parent: int | None = None):
        self.parent = parent

    def setup(self, worker):
        import signal
        import threading

        if self.parent is not None:
            from contactvib.interrupts import end_with_parent

            if threading.current_thread() is threading.main_thread():
                signal.signal(signal.SIGINT, signal.SIG_IGN)
            end_with_parent(self.parent)
        import contactvib.sweeps.dataset  # noqa: F401
        import contactvib.sweeps.sweep  # noqa: F401  (the kernels and their cache)


def dask_task(threads: int, topic: str, fn, *args):
    """``fn(*args)`` on a worker with ``threads`` numba threads (set per task: numba's thread
    count belongs to the calling thread); the level's points done
    (:func:`contactvib.sweeps.level_progress.report_points`) go to the event topic ``topic``."""
    import numba
    from distributed import get_worker

    from contactvib.sweeps.level_progress import points_to

    numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
    worker = get_worker()
    with points_to(lambda item: worker.log_event(topic, list(item))):
        return fn(*args)


def open_client(backend, timeout: float):
    """``(client, cluster or None, numba threads per task)`` for a :class:`DaskBackend`.

    A running scheduler must answer within ``timeout`` s, else ParameterError ``scheduler``; its
    tasks run with one numba thread each (one task per worker thread: one level of
    parallelism). A LocalCluster has ``n_workers`` single-threaded worker processes (default:
    one per core), each task with ``cores // n_workers`` numba threads, so that all of them
    together use every core once."""
    cores = os.cpu_count() or 1
    if backend.scheduler is not None:
        try:
            client = Client(backend.scheduler, timeout=timeout, set_as_default=False)
        except Exception:  # refused, timed out, or another kind of server answering there
            raise ParameterError("scheduler", backend.scheduler,
                                 f"no Dask scheduler answers there within {timeout:g} s") from None
        client.register_plugin(KernelWarmUp(None))
        return client, None, 1
    n = backend.n_workers or cores
    with warnings.catch_warnings(), dask.config.set(LOCAL_CLUSTER_CONFIG):
        # its HTTP server takes another port when 8787 is taken: no news
        warnings.filterwarnings("ignore", message="Port .* is already in use")
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR)
    client = Client(cluster, set_as_default=False)
    client.register_plugin(KernelWarmUp(os.getpid()))
    return client, cluster, max(1, cores // n)
