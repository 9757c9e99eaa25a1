"""Progress inside a running P_a level: the sweep of a level (:func:`.sweep.trace_level`) calls
:func:`report_points` with the frequency points it has done, and whoever runs the level decides
where the news goes (a leaf module: the sweep, the backends and the Dask worker all use it).

A process-wide sink (:func:`sink_for_process`) serves a pool worker or levels run in this
process (:func:`contactvib.sweeps.backends.run_levels`); a thread's own sink (:func:`points_to`)
serves a Dask task (tasks of other runs share the worker) or the page of ``contactvib explore``
(whose level runs in one of its threads).
"""

from __future__ import annotations

import threading
from contextlib import contextmanager

__all__ = ["report_points", "points_to", "sink_for_process"]

#: Where this process sends ``(pa, points)`` for a running level (None: nowhere): set in a pool
#: worker, or by :func:`contactvib.sweeps.backends.run_levels` for levels run here.
_POINTS_SINK = None
_THREAD = threading.local()  # .sink: a Dask task's own (tasks of other runs share the worker)


def report_points(pa: float, points: int) -> None:
    """Tell the parent that the level ``pa`` has ``points`` frequency points done (a no-op when
    nobody listens; never fails a level)."""
    sink = getattr(_THREAD, "sink", None) or _POINTS_SINK
    if sink is not None:
        try:
            sink((float(pa), int(points)))
        except Exception:  # progress is news, not a result
            pass


def sink_for_process(sink):
    """Send this process's reports (those of threads without their own sink) to ``sink``, a
    callable of one ``(pa, points)`` tuple or None; returns the previous sink."""
    global _POINTS_SINK
    previous, _POINTS_SINK = _POINTS_SINK, sink
    return previous


@contextmanager
def points_to(sink):
    """Within (in this thread): :func:`report_points` calls ``sink((pa, points))``, before any
    sink of the run (a Dask task's topic; the page of ``contactvib explore``, whose level runs in
    one of its threads)."""
    previous = getattr(_THREAD, "sink", None)
    _THREAD.sink = sink
    try:
        yield
    finally:
        _THREAD.sink = previous
