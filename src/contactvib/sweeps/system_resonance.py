"""Resonance graphs and atlases of a :class:`~contactvib.model.system.System`: its force levels
swept (:func:`~contactvib.sweeps.system_sweep.sweep_system_level`) on the backends of the 1-DOF
sweeps (:mod:`contactvib.sweeps.backends`: this process, the local process pool, a Dask
cluster), one chunk per level in ``OUT/.chunks/`` (atomic, reused by ``resume``), and the merged
dataset ``OUT/<name>.nc`` (:mod:`contactvib.sweeps.system_dataset`), under the folder's lock
(:func:`contactvib.sweeps.resonance.output_lock`).
"""

from __future__ import annotations

import json
from pathlib import Path

from contactvib.interrupts import check_interrupt, deferred_sigint
from contactvib.model import ParameterError
from contactvib.sweeps.system_sweep import SystemSweepSettings

__all__ = ["system_resonance_dataset", "system_description", "remove_system_chunks"]

#: Chunk attribute holding the exact level the chunk was computed for.
_LEVEL_ATTR = "chunk_level"
#: Attributes a reused chunk must share with the run.
_SAME = ("system", "system_parameters", "settings", "level_variable")


def system_description(system, label: str, text: str, model=None, parameters: dict | None = None) -> dict:
    """The :class:`~contactvib.sweeps.system_dataset.SystemDescription` of ``system``: ``label``
    for messages, ``text`` for the dataset's ``system`` attribute ("rocking" or the TOML text),
    ``model`` the rocking unit's slider (its Q = M g makes the levels P_a/Q), ``parameters`` the
    unit's a, J, e."""
    from contactvib.sweeps.system_dataset import SystemDescription

    d = SystemDescription(label=label, text=text, parameters=json.dumps(parameters or {}, sort_keys=True))
    if model is not None:
        d.update(q_newton=float(model.Q), model=json.dumps(model.parameters()), fn0_hz=float(model.f_n0),
                 y0_um=float(model.units.y_um))
    return d


def _run_system_level(system, level: float, settings: dict, desc: dict, chunk: str | None, compress: bool):
    """One level (P_a/Q with a Q, else P_a [N]): sweep, dataset, chunk; returns (dataset, None)."""
    from contactvib.sweeps.dataset import write_atomic
    from contactvib.sweeps.system_dataset import system_level_dataset
    from contactvib.sweeps.system_sweep import sweep_system_level

    st = SystemSweepSettings(**settings)
    pa_newton = level * desc["q_newton"] if desc.get("q_newton") else level
    lv = sweep_system_level(system, pa_newton, st)
    ds = system_level_dataset(system, lv, st, {**desc, "level": level})
    if chunk is not None:
        write_atomic(ds.assign_attrs({_LEVEL_ATTR: float(level)}), chunk, compress=compress)
    return ds, None


def _chunk(out: Path, level: float) -> Path:
    return Path(out) / ".chunks" / f"level_{float(level)!r}.nc"


def remove_system_chunks(out: Path, levels) -> int:
    """:func:`contactvib.sweeps.resonance.remove_chunks` for a system's level chunks."""
    from contactvib.sweeps.resonance import remove_chunks

    return remove_chunks(out, levels, _chunk)


def _reusable(path: Path, attrs: dict, level: float) -> bool:
    """Whether the chunk at ``path`` is this run's finished ``level``; ParameterError ``resume``
    for a chunk of another system or other settings."""
    import xarray as xr

    try:
        with xr.open_dataset(path) as ds:
            stored = dict(ds.attrs)
    except Exception:  # unreadable or foreign: recompute
        return False
    if float(stored.get(_LEVEL_ATTR, "nan")) != float(level):
        return False
    for key in _SAME:
        if stored.get(key) != attrs.get(key):
            raise ParameterError("resume", str(path), f"made with another {key.replace('_', ' ')} (use another "
                                                      "output folder, or delete the chunk)")
    return True


def system_resonance_dataset(system, *, levels, settings: SystemSweepSettings, desc: dict, out=None,
                             name: str = "resonance", resume: bool = False, backend=None, progress: bool = True,
                             compress: bool = False):
    """Sweep every level of ``levels`` (P_a/Q where ``desc`` has a Q, else P_a [N]) over the grid
    of ``settings`` on ``backend`` (default: the local process pool); the merged Dataset, also
    written to ``OUT/<name>.nc`` with its chunks when ``out`` is given (NetCDF4 + zlib with
    ``compress``). ``resume`` reuses finished chunks of the same system and settings."""
    from contactvib.sweeps.backends import LocalPool, run_levels
    from contactvib.sweeps.dataset import write_atomic
    from contactvib.sweeps.resonance import output_lock
    from contactvib.sweeps.system_dataset import merge_system_levels

    if not isinstance(settings, SystemSweepSettings):
        raise ParameterError("settings", settings, "must be a SystemSweepSettings")
    levels = sorted({float(v) for v in levels})
    if not levels:
        raise ParameterError("P_a", "", "give at least one level")
    backend = LocalPool() if backend is None else backend
    sd = settings.to_dict()
    done: dict = {}

    def run(out):
        probe = {"system": desc["text"], "system_parameters": desc.get("parameters", "{}"),
                 "settings": json.dumps(sd), "level_variable": "pa_over_q" if desc.get("q_newton") else "pa_newton"}
        if out is not None and resume:
            import xarray as xr

            for v in levels:
                if _chunk(out, v).exists() and _reusable(_chunk(out, v), probe, v):
                    done[v] = xr.load_dataset(_chunk(out, v)).drop_encoding()
                    done[v].attrs.pop(_LEVEL_ATTR, None)
        tasks = {v: (system, v, sd, dict(desc), None if out is None else str(_chunk(out, v).absolute()), compress)
                 for v in levels if v not in done}

        from tqdm import tqdm

        bar = tqdm(total=len(levels), initial=len(done), unit="level", desc=name, disable=not progress, leave=False)

        def finished(v, result):
            done[v] = result[0]
            bar.update(1)
            check_interrupt()

        try:
            run_levels(tasks, _run_system_level, backend, finished)
        finally:
            bar.close()
        ds = merge_system_levels([done[v] for v in levels])
        if out is not None:
            write_atomic(ds, Path(out) / f"{name}.nc", compress=compress)
        return ds

    with deferred_sigint():
        if out is None:
            return run(None)
        with output_lock(out):
            return run(Path(out))

