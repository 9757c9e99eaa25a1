"""Resonance graphs of several P_a levels: parallel level sweeps, resumable chunks, one dataset.

Each P_a level is one task (:func:`contactvib.trace_level`); tasks run in a process pool
(one numba thread per process: the only level of parallelism) or on a Dask cluster
(``contactvib.sweeps.backends``), and each finished level is written
atomically to ``OUT/.chunks/`` as NetCDF, so an interrupted run loses at most the levels in
progress and ``resume=True`` recomputes nothing that was finished. The merged dataset is written
atomically to ``OUT/<name>.nc``.

Resume is safe: a chunk is named by its exact level (``repr``) and stores it; a finished chunk
of a requested level made with another model or other settings is refused (ParameterError
``resume``) before anything is computed. One run at a time writes into a folder: it holds an
exclusive lock on ``OUT/.lock`` (a second run fails at once, ParameterError ``out``), at its
start removes the temporary files ``.*.tmp<pid>`` of runs that are no longer running, and removes
the lock file when it ends. The commands ``paper`` and ``resonance`` remove the chunks once the
dataset and figures are written (:func:`remove_chunks`; ``--keep-chunks`` keeps them).

Interrupts are clean (:mod:`contactvib.interrupts`): SIGINT stops the run between kernel
calls, terminates the workers and raises :class:`Interrupted` (a KeyboardInterrupt saying how
many levels were kept); workers ignore SIGINT and end when the parent process ends, even by
SIGKILL.
"""

from __future__ import annotations

import json
import os
import re
from contextlib import contextmanager
from pathlib import Path

from contactvib.call_forms import old_form
from contactvib.interrupts import Interrupted, check_interrupt, deferred_sigint
from contactvib.model import (
    LEVEL_KINDS,
    WORKERS_MAX,
    ContactModel,
    ParameterError,
    check_int,
    check_pa_level,
    check_range,
    level_text,
)
from contactvib.steady.transients import check_damped
from contactvib.sweeps.stage_times import for_level, stage
from contactvib.sweeps.sweep import SweepSettings, frequency_grid

__all__ = ["resonance_dataset", "check_sweep_level", "chunk_path", "remove_chunks", "sweep_bar_format",
           "COMPILING_MESSAGE", "output_lock", "ResumeMismatch", "OutputLocked",
           "Interrupted"]

#: Chunk attribute holding the exact level P_a/Q the chunk was computed for.
_LEVEL_ATTR = "chunk_pa_over_q"
_TMP = re.compile(r"^\..+\.tmp(\d+)$")


class ResumeMismatch(ParameterError):
    """``resume``: a finished chunk was made with another model or other settings."""

    def __init__(self, chunk: Path, name: str, stored, requested):
        self.chunk, self.name, self.stored, self.requested = Path(chunk), name, stored, requested
        self.difference = f"made with {name} = {_show(stored)}, not {_show(requested)}"
        super().__init__("resume", str(chunk),
                         f"{self.difference} (use another output folder, or delete the chunk)")


class OutputLocked(ParameterError):
    """``out``: another run holds the output folder's lock file."""

    def __init__(self, out: Path, lock: Path):
        self.out, self.lock = Path(out), Path(lock)
        super().__init__("out", str(out), f"another contactvib run is writing there ({lock})")


def _show(v) -> str:
    """A stored value in a message: floats shortest (4.0 -> 4), a dict as NAME=VALUE pairs (the
    friction parameters), others as text."""
    if isinstance(v, dict):
        return ",".join(f"{k}={_show(x)}" for k, x in v.items())
    if isinstance(v, float):
        return f"{v:g}" if float(f"{v:g}") == v else repr(v)
    return str(v)


def chunk_path(out: Path, pa_over_q: float) -> Path:
    """Path of the finished-level chunk for P_a [Q] under the output folder (named by the exact
    level, ``repr``: 0.5 -> ``level_pa0.5.nc``, so that distinct levels never share a chunk)."""
    return Path(out) / ".chunks" / f"level_pa{float(pa_over_q)!r}.nc"


#: What a run whose kernels are not compiled yet prints first (measured on 2 cores: ``paper`` takes
#: 54–60 s with a warm cache, 82 s on its first run after a fresh install).
COMPILING_MESSAGE = ("compiling the kernels (first run only: about 30 s more on 2 cores; "
                     "the time left shows once a level is done)…")
#: The bar of a run that compiles first: no time left (tqdm's {remaining}), which the compilation
#: would inflate many times over, until a level is done.
_BAR_WITHOUT_ETA = "{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed}{postfix}]"


def sweep_bar_format(cold: bool) -> str | None:
    """The tqdm ``bar_format`` of the sweeps' bar: without the time left while the kernels of a
    cold cache compile (``cold``), tqdm's default (None) otherwise."""
    return _BAR_WITHOUT_ETA if cold else None


def remove_chunks(out: Path, levels, path=chunk_path) -> int:
    """Remove the finished-level chunks of ``levels`` (at ``path(out, level)``, default
    :func:`chunk_path`) from ``OUT/.chunks`` (once the merged dataset holding them is written) and
    the folder when it is left empty; chunks of other levels stay. Returns the number of files
    removed."""
    n = 0
    for pa in levels:
        try:
            path(out, pa).unlink()
            n += 1
        except FileNotFoundError:
            pass
    try:
        (Path(out) / ".chunks").rmdir()
    except OSError:  # absent, or holds other levels' chunks
        pass
    return n


_HELD: dict[str, list] = {}  # resolved folder -> [open lock file, depth] held by this process


@contextmanager
def output_lock(out):
    """Hold the exclusive lock ``OUT/.lock`` while writing into ``out`` (re-entrant within this
    process); raise ``OutputLocked`` at once if another run holds it. On entry (outermost)
    the temporary files ``.*.tmp<pid>`` of dead processes in ``OUT`` and ``OUT/.chunks`` are
    removed."""
    out = Path(out)
    key = str(out.resolve())
    if key in _HELD:
        _HELD[key][1] += 1
        try:
            yield
        finally:
            _HELD[key][1] -= 1
        return
    out.mkdir(parents=True, exist_ok=True)
    lock = out / ".lock"
    f = _locked_file(out, lock)
    try:
        _HELD[key] = [f, 1]
        try:
            _remove_stale_temporaries(out)
            yield
        finally:
            del _HELD[key]
            try:  # removed while still held: a run that opened it meanwhile sees another file
                lock.unlink()
            except OSError:
                pass
    finally:
        f.close()  # releases the lock


def _locked_file(out: Path, lock: Path):
    """``lock`` opened and locked exclusively (``OutputLocked`` if another run holds it). A file
    unlinked by the holder between our open and our lock is not the lock any more: open it again."""
    try:
        import fcntl
    except ImportError:  # not POSIX: no lock
        return open(lock, "a+")
    while True:
        f = open(lock, "a+")
        try:
            fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            raise OutputLocked(out, lock) from None
        try:
            if os.stat(lock).st_ino == os.fstat(f.fileno()).st_ino:
                return f
        except FileNotFoundError:
            pass
        f.close()


def _pid_running(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return True
    return True


def _remove_stale_temporaries(out: Path) -> list[Path]:
    """Remove ``.*.tmp<pid>`` files in ``out`` and ``out/.chunks`` whose process is not running."""
    removed = []
    for folder in (out, out / ".chunks"):
        if not folder.is_dir():
            continue
        for p in folder.iterdir():
            m = _TMP.match(p.name)
            if m and p.is_file() and not _pid_running(int(m.group(1))):
                try:
                    p.unlink()
                    removed.append(p)
                except OSError:
                    pass
    return removed


def _run_level(model_params: dict, pa: float, settings: dict, chunk: str | None, on_level=None,
               compress: bool = False, seeds=()):
    from contactvib.sweeps.dataset import level_dataset, write_atomic
    from contactvib.sweeps.sweep import trace_level

    model = ContactModel(**model_params)
    st = SweepSettings.from_dict(settings)
    with for_level(pa):
        level = trace_level(model, pa_over_q=pa, settings=st, **({"seeds": seeds} if len(seeds) else {}))
        with stage("level dataset"):
            ds = level_dataset(model, level, settings)
        if st.friction is not None:  # the tangential motion under every periodic point
            from contactvib.friction.columns import with_friction

            ds = with_friction(ds, model, level, st)
        if chunk is not None:
            with stage("chunk write"):
                write_atomic(ds.assign_attrs({_LEVEL_ATTR: float(pa)}), chunk, compress=compress)
        return ds, (on_level(model, ds) if on_level is not None else None)


def _compile_late_first(model_params: dict, settings: dict) -> None:
    """A pool worker's first task on a first run (:func:`.sweep.compile_late_kernels_first`)."""
    from contactvib.sweeps.sweep import compile_late_kernels_first

    compile_late_kernels_first(ContactModel(**model_params), SweepSettings.from_dict(settings))


def _chunk_matches(path: Path, model: ContactModel, settings: dict, pa: float) -> bool:
    """Whether the chunk at ``path`` is the finished level ``pa`` of this model and settings.

    False for an unreadable or foreign file, another layout version, a chunk without the
    ``dof``/``contact`` variables or another level (these are recomputed); ``ResumeMismatch``
    naming the first difference for another model or other settings.
    """
    import xarray as xr

    from contactvib.sweeps.dataset import FORMAT

    try:
        with xr.open_dataset(path) as ds:
            attrs = dict(ds.attrs)
            has_dofs = "contact_mean_force_n" in ds  # chunks written before the dof/contact variables
        if (attrs.get("format") != FORMAT or float(attrs.get(_LEVEL_ATTR, "nan")) != float(pa)
                or not has_dofs):
            return False
        stored_settings = json.loads(attrs["settings"])
        stored_model = json.loads(attrs["model"])
    except Exception:  # unreadable or foreign file: recompute it
        return False
    for stored, requested in ((stored_settings, settings), (stored_model, model.parameters())):
        _same_or_refuse(path, stored, requested)
    return True


def _same_or_refuse(path: Path, stored: dict, requested: dict, prefix: str = "") -> None:
    """:class:`ResumeMismatch` naming the first entry where ``stored`` and ``requested`` differ
    (a dict entry, e.g. the friction parameters, by its own entries: ``friction.mu``)."""
    for name in list(requested) + [k for k in stored if k not in requested]:
        a, b = stored.get(name, "nothing"), requested.get(name, "nothing")
        if isinstance(a, dict) and isinstance(b, dict):
            _same_or_refuse(path, a, b, f"{prefix}{name}.")
        elif name not in stored or name not in requested or a != b:
            raise ResumeMismatch(path, prefix + name, a, b)


def check_sweep_level(model: ContactModel, level, settings: SweepSettings) -> float:
    """A sweep level, > 0, whose excitation is allowed over the whole grid: P_a/Q, or for base
    motion U [µm] / A [g] whose inertial force stays within the allowed P_a at f_max."""
    if settings.excitation == "force":
        return check_pa_level(level)
    sym, unit, _name = LEVEL_KINDS[settings.excitation]
    value = check_range(sym, level, 0.0, False, unit)
    settings.excitation_at(model, value, settings.fmax_hz)  # raises, naming U or A, if too strong
    return value


@old_form("model", "pa_levels", "settings", "out", "name", "resume", "workers", "progress", "on_level",
          "level_results", "backend", "compress", renamed={"pa_levels": "levels"})
def resonance_dataset(model: ContactModel, *, levels, settings: SweepSettings, out=None,
                      name: str = "resonance", resume: bool = False, workers: int | None = None,
                      progress: bool = True, on_level=None, level_results: dict | None = None,
                      backend=None, compress: bool = False):
    """Sweep every level in ``levels`` over the settings' frequency grid.

    Parameters
    ----------
    model : ContactModel
    levels : sequence of float
        The levels: P_a/Q, or U [µm] or A [g] as ``settings.excitation`` says (``pa_levels``
        before 0.2.0).
    settings : SweepSettings
    out : path or None
        Output folder; ``OUT/<name>.nc`` and the chunks ``OUT/.chunks/`` are written there.
    resume : bool
        Reuse finished chunks of the same model and settings; a finished chunk of a requested
        level made with another model or settings raises ParameterError ``resume``
        (``ResumeMismatch``) before anything is computed. Without resume, chunks are
        recomputed and overwritten.
    workers : int or None
        Processes, 1..``WORKERS_MAX`` (default: ``min(levels, CPU count)``); 1 runs in this
        process. Ignored with a ``backend``.
    on_level : callable or None
        ``on_level(model, level_dataset)`` (picklable) run in the worker right after each level
        (in this process for resumed levels), e.g. to draw the level's figures while other
        levels are still sweeping; its return values go into ``level_results[P_a]``.
    backend : LocalPool, DaskBackend or None
        Where the levels run (``contactvib.sweeps.backends``); default ``LocalPool(workers)``.
        Every backend writes the same chunks and the same dataset.
    compress : bool
        Write the chunks and ``OUT/<name>.nc`` as NetCDF4 with zlib compression (level 4,
        chunked along ``point``; ``contactvib.sweeps.dataset.write_atomic``): the atlas.

    Returns
    -------
    xarray.Dataset
        Layout in ``contactvib.sweeps.dataset`` (the documentation's data formats page).

    Raises
    ------
    ParameterError
        ``out`` (``OutputLocked``) when another run is writing into ``out``; ``scheduler``
        when no Dask scheduler answers at the backend's address.
    Interrupted
        (a KeyboardInterrupt) on SIGINT / Ctrl-C, raised within about a second of the running
        kernel call, after the workers are terminated (running levels are not waited for) and
        the lock is released; ``n_kept`` finished levels stay in ``OUT/.chunks`` for
        ``resume=True``.
    """
    check_damped(model, "a resonance sweep")
    if workers is not None:
        workers = check_int("workers", workers, 1, WORKERS_MAX)
    if backend is None:
        from contactvib.sweeps.backends import LocalPool

        backend = LocalPool(workers)
    given, levels = levels, []
    for v in given:
        v = check_sweep_level(model, v, settings)
        if any(abs(v - w) < 1e-9 for w in levels):
            continue
        levels.append(v)
    if not levels:
        raise ParameterError("P_a/Q", "", "give at least one level")
    sd = settings.to_dict()
    if out is None:
        return _resonance(model, levels, sd, None, (name, compress), resume, backend, progress,
                          on_level, level_results)
    out = Path(out)
    with output_lock(out):
        return _resonance(model, levels, sd, out, (name, compress), resume, backend, progress,
                          on_level, level_results)


def _resonance(model, levels, sd, out, store, resume, backend, progress, on_level, level_results):
    """The sweeps of :func:`resonance_dataset` (``store``: the dataset's name and whether it is
    compressed); a KeyboardInterrupt becomes :class:`Interrupted` once the workers are stopped."""
    import time

    from contactvib.sweeps.dataset import merge_levels, write_atomic

    name, compress = store
    started = time.time()
    done: dict = {}
    try:
        with deferred_sigint():  # SIGINT never raised inside numba (see interrupts.py)
            if out is not None and resume:
                _reuse_chunks(model, levels, sd, out, on_level, level_results, done)
            _sweep_levels(model, [pa for pa in levels if pa not in done], sd, out, backend,
                          progress, on_level, level_results, done, len(levels), store)
            if sd.get("level_seeds"):
                _sweep_seeded_levels(model, sd, out, on_level, level_results, done, compress)
            with stage("merge levels"):
                ds = merge_levels([done[pa] for pa in levels])
            if out is not None:
                with stage("NetCDF write"):
                    write_atomic(ds, out / f"{name}.nc", compress=compress)
    except KeyboardInterrupt:
        raise _interrupted(out, levels, done, started) from None
    return ds


def _sweep_seeded_levels(model, sd, out, on_level, level_results, done, compress):
    """``SweepSettings.level_seeds``: sweep again, in this process, each level that lacks an
    orbit a neighbouring level holds (:func:`contactvib.sweeps.level_seeds.level_seeds`), with all its
    seeds so far; its chunk is rewritten. Repeated while a pass finds new seeds (an orbit a level
    gained may reach the next level), at most once per level. A level already swept with them
    has none left (a resumed run)."""
    from contactvib.sweeps.level_seeds import level_seeds

    st = SweepSettings.from_dict(sd)
    seeds: dict = {}
    for _pass in range(len(done)):
        new = level_seeds(model, done, st)
        if not new:
            return
        for pa in sorted(new):
            seeds.setdefault(pa, []).extend(new[pa])
            chunk = None if out is None else str(chunk_path(out, pa).absolute())
            done[pa], extra = _run_level(model.parameters(), pa, sd, chunk, on_level, compress, seeds[pa])
            if level_results is not None:
                level_results[pa] = extra
            check_interrupt()


def _reuse_chunks(model, levels, sd, out, on_level, level_results, done):
    import xarray as xr

    reuse = [pa for pa in levels
             if chunk_path(out, pa).exists() and _chunk_matches(chunk_path(out, pa), model, sd, pa)]
    for pa in reuse:  # every chunk checked before any figure is drawn
        # without the file's encoding: a string width read from one chunk (<U12) would
        # truncate the longer labels of the other levels when the merged dataset is written
        done[pa] = xr.load_dataset(chunk_path(out, pa)).drop_encoding()
        done[pa].attrs.pop(_LEVEL_ATTR, None)
        if on_level is not None and level_results is not None:
            level_results[pa] = on_level(model, done[pa])
        check_interrupt()


def _sweep_levels(model, todo, sd, out, backend, progress, on_level, level_results, done, n_levels, store):
    """Sweep the levels ``todo`` into ``done`` (and ``level_results``) on ``backend``
    (:func:`contactvib.sweeps.backends.run_levels`: this process, a local pool or Dask)."""
    from tqdm import tqdm

    from contactvib.sweeps.backends import kernel_cache_cold, run_levels

    name, compress = store
    n_points = frequency_grid(SweepSettings.from_dict(sd)).size
    points = {pa: 0 for pa in todo}  # frequency points done in each level still to finish
    n_done = n_levels - len(todo)
    cold = bool(todo) and kernel_cache_cold()
    bar = tqdm(total=n_levels * n_points, initial=n_done * n_points, unit="f_e point", desc=name,
               disable=not progress, leave=False, unit_scale=True, bar_format=sweep_bar_format(cold))
    bar.set_postfix_str(f"{n_done}/{n_levels} levels")
    if progress and cold:
        import sys

        bar.write(COMPILING_MESSAGE, file=sys.stderr)

    def advance(pa, n, final=False):
        """Level ``pa`` has ``n`` frequency points done (the bar never moves back; a running
        level stays one point short of its grid until its dataset has arrived)."""
        n = n if final else min(n, n_points - 1)
        if pa in points and n > points[pa]:
            bar.update(n - points[pa])
            points[pa] = n

    def finished(pa, result):
        done[pa], extra = result
        if out is not None and not chunk_path(out, pa).exists():  # a cluster without our file system
            from contactvib.sweeps.dataset import write_atomic

            write_atomic(done[pa].assign_attrs({_LEVEL_ATTR: float(pa)}), chunk_path(out, pa), compress=compress)
        if level_results is not None:
            level_results[pa] = extra
        bar.bar_format = None  # a level done: the rate, and the time left from it, are the sweeps'
        advance(pa, n_points, final=True)
        points.pop(pa, None)
        n_finished = n_levels - len(points)
        bar.set_postfix_str(f"{n_finished}/{n_levels} levels, {level_text(pa, sd.get('excitation', 'force'))} done, "
                            f"{bar.n}/{bar.total} f_e points")

    # absolute: a worker of a running cluster need not share this process's working directory
    tasks = {pa: (model.parameters(), pa, sd, str(chunk_path(out, pa).absolute()) if out is not None else None,
                  on_level, compress) for pa in todo}
    try:
        run_levels(tasks, _run_level, backend, finished, advance,
                   warm_up=(_compile_late_first, (model.parameters(), sd)) if cold else None)
    finally:
        bar.close()


def _interrupted(out, levels, done, started: float) -> Interrupted:
    """The :class:`Interrupted` of a run: the requested levels whose chunks are finished (reused
    or written since ``started``)."""
    if out is None:
        return Interrupted(0, None)
    kept = 0
    for pa in levels:
        c = chunk_path(out, pa)
        try:
            kept += pa in done or c.stat().st_mtime >= started
        except OSError:
            pass
    return Interrupted(kept, out / ".chunks")
