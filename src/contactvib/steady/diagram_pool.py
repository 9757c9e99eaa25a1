"""The parts of an orbit diagram's grid walked in worker processes.

The grid is cut into ``workers`` contiguous parts that overlap by one grid point; each part is
walked (:func:`contactvib.steady.follow.walk_grid`: up from its own search, then down) in
a spawned process with one numba thread, the one level of parallelism. At each overlap point the
attractors of the later part are matched with those already there
(:func:`~contactvib.steady.follow.same_attractor`), so that a followed attractor keeps its
id across the parts.
"""

from __future__ import annotations

import os

import numpy as np

from contactvib.interrupts import check_interrupt, end_with_parent
from contactvib.steady.follow import same_attractor, walk_grid

__all__ = ["split_grid", "walk_in_pool", "merge_parts"]


def _init(parent: int) -> None:
    """A worker: one numba thread, SIGINT ignored (the parent stops the pool), ends with ``parent``."""
    import signal

    import numba

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    end_with_parent(parent)
    numba.set_num_threads(1)


def split_grid(n: int, workers: int) -> list[tuple[int, int]]:
    """``workers`` index ranges ``(first, last)``, inclusive, covering ``0..n−1``, each next one
    starting at the previous one's last index."""
    edges = sorted({round(j * (n - 1) / workers) for j in range(workers + 1)})
    return list(zip(edges[:-1], edges[1:]))


def merge_parts(parts: list[tuple[int, int]], results: list, n: int) -> list:
    """One list of attractors per grid point from the parts' lists: ids renumbered 0, 1, … in order
    of appearance, an attractor of a later part that is one of the overlap point's attractors
    taking that one's id, duplicates at a point dropped."""
    per_point: list[list] = [[] for _ in range(n)]
    next_id = 0
    for (first, _last), res in zip(parts, results):
        mapping: dict[int, int] = {}
        for t in res[0] if first > 0 else ():
            match = next((o for o in per_point[first] if same_attractor(t, o)), None)
            if match is not None:
                mapping[t.id] = match.id
        for i, kept in enumerate(res):
            for t in kept:
                if t.id not in mapping:
                    mapping[t.id], next_id = next_id, next_id + 1
                t.id = mapping[t.id]
                if not any(same_attractor(t, o) for o in per_point[first + i]):
                    per_point[first + i].append(t)
    return per_point


def _stop(pool) -> None:
    """Terminate the pool's workers at once (pending parts cancelled)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for p in processes:
        p.terminate()
    pool.shutdown(wait=False, cancel_futures=True)
    for p in processes:
        p.join(5.0)


def walk_in_pool(model, settings, fixed: float, grid: np.ndarray, rtol: float, workers: int, progress=None) -> list:
    """:func:`~contactvib.steady.follow.walk_grid` over ``workers`` parts of ``grid`` in as
    many processes; ``progress(done, total)`` after each part."""
    import multiprocessing as mp
    from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait

    parts = split_grid(grid.size, workers)
    pool = ProcessPoolExecutor(max_workers=len(parts), mp_context=mp.get_context("spawn"), initializer=_init,
                               initargs=(os.getpid(),))
    try:
        futs = [pool.submit(walk_grid, model, settings, fixed, grid[a:b + 1], rtol) for a, b in parts]
        pending, done = set(futs), 0
        while pending:  # polled: a deferred SIGINT is honoured within 0.2 s
            ready, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            done += len(ready)
            if ready and progress is not None:
                progress(done, len(futs))
            check_interrupt()
        results = [f.result() for f in futs]
    except BaseException:
        _stop(pool)
        raise
    pool.shutdown(wait=False)
    return merge_parts(parts, results, grid.size)
