"""Resonance graphs of several P_a levels: parallel level sweeps, resumable chunks, one dataset.

Each P_a level is one task (:func:`contactvib.sweep.trace_level`); tasks run in a process pool
(one numba thread per process: the only level of parallelism) and each finished level is written
atomically to ``OUT/.chunks/`` as NetCDF, so an interrupted run loses at most the levels in
progress and ``resume=True`` recomputes nothing that was finished. The merged dataset is written
atomically to ``OUT/<name>.nc``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from contactvib.model import WORKERS_MAX, ContactModel, ParameterError, check_int, check_pa_level
from contactvib.sweeps.sweep import SweepSettings

__all__ = ["resonance_dataset", "chunk_path"]


def chunk_path(out: Path, pa_over_q: float) -> Path:
    """Path of the finished-level chunk for P_a [Q] under the output folder."""
    return Path(out) / ".chunks" / f"level_pa{pa_over_q:.6f}.nc"


def _worker_init():
    import numba

    numba.set_num_threads(1)


def _run_level(model_params: dict, pa: float, settings: dict, chunk: str | None, on_level=None):
    from contactvib.sweeps.dataset import level_dataset, write_atomic
    from contactvib.sweeps.sweep import trace_level

    model = ContactModel(**model_params)
    st = SweepSettings(**settings)
    level = trace_level(model, pa, st)
    ds = level_dataset(model, level, settings)
    if chunk is not None:
        write_atomic(ds, chunk)
    return ds, (on_level(model, ds) if on_level is not None else None)


def _chunk_matches(path: Path, model: ContactModel, settings: dict) -> bool:
    import xarray as xr

    from contactvib.sweeps.dataset import FORMAT

    try:
        with xr.open_dataset(path) as ds:
            return (ds.attrs.get("format") == FORMAT
                    and json.loads(ds.attrs["settings"]) == settings
                    and json.loads(ds.attrs["model"]) == model.parameters())
    except Exception:  # unreadable or foreign file: recompute it
        return False


def resonance_dataset(model: ContactModel, pa_levels, settings: SweepSettings, out=None,
                      name: str = "resonance", resume: bool = False, workers: int | None = None,
                      progress: bool = True, on_level=None, level_results: dict | None = None):
    """Sweep every P_a level in ``pa_levels`` [Q] over the settings' frequency grid.

    Parameters
    ----------
    out : path or None
        Output folder; ``OUT/<name>.nc`` and the chunks ``OUT/.chunks/`` are written there.
    resume : bool
        Reuse finished chunks of the same model and settings.
    workers : int or None
        Processes, 1..``WORKERS_MAX`` (default: ``min(levels, CPU count)``); 1 runs in this
        process.
    on_level : callable or None
        ``on_level(model, level_dataset)`` (picklable) run in the worker right after each level
        (in this process for resumed levels), e.g. to draw the level's figures while other
        levels are still sweeping; its return values go into ``level_results[P_a]``.

    Returns
    -------
    xarray.Dataset
        Layout in :mod:`contactvib.dataset`.
    """
    import xarray as xr
    from tqdm import tqdm

    from contactvib.sweeps.dataset import merge_levels, write_atomic

    if workers is not None:
        workers = check_int("workers", workers, 1, WORKERS_MAX)
    levels = []
    for v in pa_levels:
        v = check_pa_level(v)
        if any(abs(v - w) < 1e-9 for w in levels):
            continue
        levels.append(v)
    if not levels:
        raise ParameterError("P_a/Q", "", "give at least one level")
    sd = settings.to_dict()
    out = Path(out) if out is not None else None
    done = {}
    if out is not None and resume:
        for pa in levels:
            c = chunk_path(out, pa)
            if c.exists() and _chunk_matches(c, model, sd):
                done[pa] = xr.load_dataset(c)
                if on_level is not None and level_results is not None:
                    level_results[pa] = on_level(model, done[pa])
    todo = [pa for pa in levels if pa not in done]
    n_workers = workers or min(len(todo), os.cpu_count() or 1)
    bar = tqdm(total=len(levels), initial=len(done), unit="level", desc="resonance",
               disable=not progress, leave=False)
    try:
        if n_workers <= 1 or len(todo) <= 1:
            for pa in todo:
                c = str(chunk_path(out, pa)) if out is not None else None
                done[pa], extra = _run_level(model.parameters(), pa, sd, c, on_level)
                if level_results is not None:
                    level_results[pa] = extra
                bar.update(1)
                bar.set_postfix_str(f"P_a = {pa:g} Q done")
        else:
            import multiprocessing as mp
            from concurrent.futures import ProcessPoolExecutor, as_completed

            ctx = mp.get_context("spawn")
            with ProcessPoolExecutor(max_workers=n_workers, mp_context=ctx,
                                     initializer=_worker_init) as pool:
                futs = {pool.submit(_run_level, model.parameters(), pa, sd,
                                    str(chunk_path(out, pa)) if out is not None else None,
                                    on_level): pa
                        for pa in sorted(todo, key=lambda p: -p)}
                try:
                    for fut in as_completed(futs):
                        pa = futs[fut]
                        done[pa], extra = fut.result()
                        if level_results is not None:
                            level_results[pa] = extra
                        bar.update(1)
                        bar.set_postfix_str(f"P_a = {pa:g} Q done")
                except BaseException:
                    for f in futs:
                        f.cancel()
                    raise
    finally:
        bar.close()
    ds = merge_levels([done[pa] for pa in levels])
    if out is not None:
        write_atomic(ds, out / f"{name}.nc")
    return ds
