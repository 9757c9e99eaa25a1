"""Where a sweep's time goes: wall and CPU seconds per named stage of a level (a leaf module).

The sweep marks its stages with :func:`stage` (``with stage("trace"): ...``); nothing is measured
unless a caller records with :func:`recording`, which is what ``benchmarks/bench_paper_profile.py``
does. Times are exclusive: a stage entered inside another (a trace started by a multi-start
probe) is counted for itself, not again for its parent. It changes nothing computed.
"""

from __future__ import annotations

import time
from contextlib import contextmanager

__all__ = ["stage", "recording", "for_level"]

_TIMES: dict | None = None  # (level, name) -> [wall_s, cpu_s, calls] while recording
_STACK: list = []  # [(level, name), wall_start, cpu_start] of the open stages
_LEVEL: list = [None]  # the P_a level [Q] being computed (None: the whole run's stages)


def _charge(entry, wall: float, cpu: float) -> None:
    acc = _TIMES.setdefault(entry[0], [0.0, 0.0, 0])
    acc[0] += wall - entry[1]
    acc[1] += cpu - entry[2]


@contextmanager
def stage(name: str):
    """Count the time spent inside as stage ``name`` (exclusive of stages opened inside)."""
    if _TIMES is None:
        yield
        return
    wall, cpu = time.perf_counter(), time.process_time()
    if _STACK:  # the parent's time so far is its own; it resumes when this stage ends
        _charge(_STACK[-1], wall, cpu)
    key = (_LEVEL[-1], name)
    _STACK.append([key, wall, cpu])
    try:
        yield
    finally:
        wall, cpu = time.perf_counter(), time.process_time()
        entry = _STACK.pop()
        _charge(entry, wall, cpu)
        _TIMES[key][2] += 1
        if _STACK:
            _STACK[-1][1], _STACK[-1][2] = wall, cpu


@contextmanager
def for_level(pa_over_q: float):
    """Within: the stages belong to the level ``pa_over_q`` [Q]."""
    _LEVEL.append(float(pa_over_q))
    try:
        yield
    finally:
        _LEVEL.pop()


@contextmanager
def recording():
    """Within: every :func:`stage` of this process is timed into the yielded dict
    ``{(level, name): {"wall_s", "cpu_s", "calls"}}`` (filled when the block ends; level None
    for the stages of the whole run)."""
    global _TIMES
    previous, _TIMES = _TIMES, {}
    out: dict = {}
    try:
        yield out
    finally:
        times, _TIMES = _TIMES, previous
        out.update({k: {"wall_s": v[0], "cpu_s": v[1], "calls": v[2]} for k, v in times.items()})
