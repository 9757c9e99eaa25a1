"""CLI command ``atlas``: many P_a levels, each ``resonance``'s level, on a local process pool or
a Dask cluster, stored as compressed chunks and one compressed ``atlas.nc``.

Thin: parse and validate (one-line errors, exit 2), call :func:`contactvib.sweeps.atlas.atlas_dataset`.
"""

from __future__ import annotations

import click

from contactvib.cli.common import (
    InputError,
    LevelsCommand,
    checked_option,
    checked_output_folder,
    mapped_options,
    parse_int,
    parse_levels,
)
from contactvib.cli.friction import friction_spec_option
from contactvib.cli.sweeps import (
    keep_chunks_option,
    refuse_system_only,
    sweep_inputs,
    sweep_levels,
    sweep_options,
    system_sweep_options,
    writing_into,
)
from contactvib.cli.system import system_given
from contactvib.model import WORKERS_MAX, ParameterError

__all__: list = []

#: The defaults of the P_a range (the reference atlas: 96 levels from 0.05 Q to 1 Q).
_RANGE_DEFAULTS = {"pa_min": "0.05", "pa_max": "1.0", "npa": "96"}
_RANGE_OPTIONS = {"pa_min": "--pa-min", "pa_max": "--pa-max", "npa": "--npa"}


def _atlas_levels(pa, pa_min, pa_max, npa, model=None, st=None) -> list[float]:
    """The levels: the explicit ``--pa`` list, or ``--npa`` levels from ``--pa-min`` to ``--pa-max``
    (P_a [Q]; U [µm] or A [g] with ``--excitation base-um``/``base-g``, each checked up to f_max)."""
    from contactvib.sweeps.atlas import atlas_levels
    from contactvib.sweeps.resonance import check_sweep_level

    if st is not None and st.excitation != "force":
        if pa:
            return sweep_levels(pa, model, st)
        kw = {**_RANGE_DEFAULTS, **{k: v for k, v in (("pa_min", pa_min), ("pa_max", pa_max),
                                                       ("npa", npa)) if v is not None}}
        levels = mapped_options(_RANGE_OPTIONS, atlas_levels, kw["pa_min"], kw["pa_max"], kw["npa"], st.excitation)
        for v in levels:
            checked_option("--pa-max" if v == levels[-1] else "--pa-min", check_sweep_level, model, v, st)
        return levels

    given = {k: v for k, v in (("pa_min", pa_min), ("pa_max", pa_max), ("npa", npa)) if v is not None}
    if pa:
        if given:
            raise InputError(f"--pa: give the levels either as a list (--pa) or as a range "
                             f"({', '.join(_RANGE_OPTIONS[k] for k in given)}), not both")
        return parse_levels(pa)
    kw = {**_RANGE_DEFAULTS, **given}
    return mapped_options(_RANGE_OPTIONS, atlas_levels, kw["pa_min"], kw["pa_max"], kw["npa"])


def _backend(workers, dask_workers, scheduler):
    """The backend of the options: the local pool (``--workers``), a LocalCluster
    (``--dask-workers``) or a running cluster (``--scheduler``); one of them."""
    from contactvib.sweeps.backends import DaskBackend, LocalPool

    if dask_workers is not None and scheduler is not None:
        raise InputError("--dask-workers: give either --dask-workers (a local Dask cluster) or "
                         "--scheduler (a running one), not both")
    if (dask_workers is not None or scheduler is not None) and workers is not None:
        option = "--dask-workers" if dask_workers is not None else "--scheduler"
        raise InputError(f"--workers: sizes the local process pool; with {option} the Dask "
                         "workers run the levels (leave --workers out)")
    if scheduler is not None:
        return checked_option("--scheduler", DaskBackend, scheduler=scheduler)
    if dask_workers is not None:
        return DaskBackend(n_workers=parse_int("--dask-workers", dask_workers, 1, WORKERS_MAX, "dask_workers"))
    return LocalPool(workers)


@click.command(cls=LevelsCommand)
@click.option("--pa", multiple=True, metavar="Q [Q ...]",
              help="Explicit levels P_a [Q] (instead of --pa-min/--pa-max/--npa); several values after one --pa.")
@click.option("--pa-min", default=None, metavar="Q", help="Lowest level P_a [Q]  [default: 0.05]")
@click.option("--pa-max", default=None, metavar="Q", help="Highest level P_a [Q]  [default: 1.0]")
@click.option("--npa", default=None, metavar="N",
              help="Levels from --pa-min to --pa-max, evenly spaced (rounded to 1e-9 Q)  [default: 96]")
@sweep_options
@friction_spec_option
@click.option("--dask-workers", default=None, metavar="N",
              help="Run the levels on a local Dask cluster (LocalCluster) of N single-threaded worker processes.")
@click.option("--scheduler", default=None, metavar="ADDRESS",
              help="Run the levels on a running Dask cluster, e.g. tcp://HOST:8786 (dask-jobqueue on SLURM/PBS: "
                   "pass its cluster.scheduler_address).")
@click.option("--out", default="atlas", show_default=True, type=click.Path(file_okay=False),
              help="Output folder: atlas.nc (NetCDF4, zlib level 4, chunked along point); .chunks/ (one "
                   "compressed file per level) while it runs.")
@keep_chunks_option
@system_sweep_options
def atlas(pa, pa_min, pa_max, npa, dask_workers, scheduler, out, keep_chunks, **sweep):
    """The evolution atlas: resonance's sweep at many P_a levels, locally or on Dask, resumable."""
    if system_given():
        from contactvib.cli.system_sweeps import system_atlas

        sweep.pop("plot"), sweep.pop("measure")
        workers = None if sweep["workers"] is None else parse_int("--workers", sweep["workers"], 1, WORKERS_MAX)
        return system_atlas(pa, (pa_min, pa_max, npa), sweep.pop("pa_newton"), out,
                            _backend(workers, dask_workers, scheduler), {**sweep, "keep_chunks": keep_chunks})
    refuse_system_only(sweep)
    model, st, n_workers = sweep_inputs(sweep)
    levels = _atlas_levels(pa, pa_min, pa_max, npa, model, st)
    backend = _backend(n_workers, dask_workers, scheduler)
    from contactvib.sweeps.atlas import atlas_dataset
    from contactvib.sweeps.resonance import remove_chunks

    out = checked_output_folder(out)
    try:
        with writing_into(out):
            ds = atlas_dataset(model, levels, st, out, resume=sweep["resume"], backend=backend,
                               progress=not sweep["no_progress"])
            if not keep_chunks:  # atlas.nc holds every level: the resume data would double the folder
                remove_chunks(out, levels)
    except ParameterError as e:
        if e.symbol != "scheduler":
            raise
        raise InputError(f"--scheduler = {scheduler}: {e.allowed}") from None
    n = len(set(levels))
    click.echo(f"{ds.sizes['point']} attractor points, {ds.sizes['branch']} branches on {n} "
               f"level{'s' * (n != 1)} -> {out / 'atlas.nc'}")
