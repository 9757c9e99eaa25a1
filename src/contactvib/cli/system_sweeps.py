"""``contactvib resonance --system ...`` and ``contactvib atlas --system ...``: the force levels of a
structure of several coordinates swept over f_e (:mod:`contactvib.sweeps.system_resonance`), and
``query`` of its dataset.

Thin: the options are checked here (one line, exit 2) before anything is computed; the grid's
default with ``--system`` is coarse (module constants), the searches' starts default to
:data:`STARTS_DEFAULT`.
"""

from __future__ import annotations

import math

import click

from contactvib.cli.common import (
    InputError,
    checked_output_folder,
    mapped_options,
    parse_frequency_range,
    parse_int,
    parse_number,
    show_value,
)
from contactvib.model import WORKERS_MAX

__all__ = ["system_resonance", "system_atlas", "echo_system_query", "STARTS_DEFAULT", "GRID_POINTS"]

#: Multi-start starts per search with --system (unless --starts is given).
STARTS_DEFAULT = 6
#: The default grid with --system: f_min = 0.2 × the lowest linear mode, f_max = 1.25 × the highest,
#: about GRID_POINTS points (Δf rounded to one significant digit), a search every SEARCH_EVERY points.
GRID_POINTS = 60
SEARCH_EVERY = 10
#: Sweep options that have no meaning for a system (click names → option).
_NOT_FOR_SYSTEMS = {"multistart_per_octave": "--multistart-per-octave", "friction": "--friction",
                    "fill_in_per_octave": "--fill-in-per-octave", "fill_in_starts": "--fill-in-starts"}


def _given(name: str) -> bool:
    ctx = click.get_current_context()
    return ctx.get_parameter_source(name) not in (None, click.core.ParameterSource.DEFAULT) \
        and ctx.params.get(name) not in (None, (), False)


def _grid(system, fmin, fmax, df) -> tuple[float, float, float]:
    """(f_min, f_max, Δf) [Hz] of the options, or the default grid about the linear modes."""
    modes = system.linear_modes()
    lo_d, hi_d = 0.2 * float(modes[0]), 1.25 * float(modes[-1])
    if not (lo_d > 0.0 and math.isfinite(hi_d)):
        lo_d, hi_d = 30.0, 2000.0
    lo, hi = parse_frequency_range(fmin if _given("fmin") else f"{lo_d:.4g}", fmax if _given("fmax") else f"{hi_d:.4g}")
    if _given("df"):
        step = parse_number("--df", "df", df)
    else:
        raw = (hi - lo) / GRID_POINTS
        step = float(f"{raw:.1g}")
    if not step > 0.0:
        raise InputError(f"--df (df) = {show_value(step)}: must be > 0 Hz")
    if step > hi - lo and hi > lo:
        raise InputError(f"--df (df) = {show_value(step)}: larger than the range --fmin..--fmax "
                         f"({lo:g}..{hi:g} Hz): the grid would hold one point")
    return lo, hi, step


def _settings(system, sweep: dict):
    """SystemSweepSettings of the sweep options."""
    from contactvib.sweeps.system_sweep import SystemSweepSettings

    for name, option in _NOT_FOR_SYSTEMS.items():
        if _given(name):
            raise InputError(f"--system and {option}: {option} belongs to the paper's slider's sweep")
    if sweep.get("level_kind", "force") != "force":
        raise InputError(f"--system and --excitation {sweep['level_kind']}: a system is swept in its force level")
    lo, hi, step = _grid(system, sweep["fmin"], sweep["fmax"], sweep["df"])
    starts = parse_int("--starts", sweep["starts"], 1, symbol="n_starts") if _given("starts") else STARTS_DEFAULT
    kw = dict(fmin_hz=lo, fmax_hz=hi, df_hz=step, search_every=SEARCH_EVERY, n_starts=starts,
              seed=parse_int("--seed", sweep["seed"], 0),
              kmax=parse_int("--kmax", sweep["kmax"], 1) if _given("kmax") else SystemSweepSettings.kmax)
    return mapped_options({"f_min": "--fmin", "f_max": "--fmax", "df": "--df", "n_starts": "--starts",
                           "kmax": "--kmax", "seed": "--seed"}, SystemSweepSettings, **kw)


def _levels(system, model, label, pa, pa_newton) -> tuple[list[float], object]:
    """The levels (P_a/Q with the rocking unit's Q, else P_a [N]) of --pa or --pa-newton."""
    from contactvib.cli.common import parse_levels

    if pa_newton and _given("pa"):
        raise InputError("--pa and --pa-newton: give one of them, not both")
    if model is None and _given("pa"):
        raise InputError(f"--system {label} and --pa: a system file defines no Q; give the force level "
                         f"--pa-newton [N]")
    if model is None and not pa_newton:
        raise InputError(f"--system {label}: give the force level --pa-newton [N]")
    if pa_newton:
        levels = [parse_number("--pa-newton", "P_a", t) for t in pa_newton]
        for v in levels:
            if not (v > 0.0 and math.isfinite(v)):
                raise InputError(f"--pa-newton (P_a) = {show_value(v)}: must be a finite force > 0 N")
        return levels, None
    return parse_levels(pa), model


def _coordinate(system, label, plot) -> list[int]:
    names = list(system.coordinates)
    if plot is None:
        return list(range(len(names)))
    if plot not in names:
        raise InputError(f"--plot {plot}: not a coordinate of --system {label} (its coordinates: {', '.join(names)})")
    return [names.index(plot)]


def _inputs(settings, pa, pa_newton, plot, sweep):
    from contactvib.cli.system import load_given_system
    from contactvib.sweeps.system_resonance import system_description

    system, model, label = load_given_system(settings)
    levels, q_model = _levels(system, model, label, pa, pa_newton)
    coords = _coordinate(system, label, plot)
    st = _settings(system, sweep)
    workers = None if sweep["workers"] is None else parse_int("--workers", sweep["workers"], 1, WORKERS_MAX)
    if label == "rocking":
        text, params = "rocking", {}
        for item in settings:
            key, _eq, value = item.partition("=")
            if key.strip() in ("a", "J", "e"):
                params[key.strip()] = float(value)
    else:
        from pathlib import Path

        text, params = Path(label).read_text(), {}
    desc = system_description(system, label, text, q_model, params)
    return system, levels, coords, st, workers, desc, label


def system_resonance(pa, pa_newton, plot, measure, out, sweep: dict) -> None:
    """``contactvib resonance --system ...``: resonance.nc and one figure per level."""
    from contactvib.sweeps.backends import LocalPool
    from contactvib.sweeps.system_resonance import system_resonance_dataset

    system, levels, coords, st, workers, desc, label = _inputs(sweep["settings"], pa, pa_newton, plot, sweep)
    outp = checked_output_folder(out)
    ds = _run(system_resonance_dataset, system, levels, st, desc, outp, "resonance", sweep, LocalPool(workers), False)
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.system import system_resonance_figure

    var, unit = ds.attrs["level_variable"], ds.attrs["level_unit"]
    for v in levels:
        one = ds.isel(point=(abs(ds[var].values - v) <= 1e-9))
        fig = system_resonance_figure(one, coords, measure, f"{label.rsplit('/', 1)[-1]}: P_a = {v:g} {unit}")
        tag = "_".join(system.coordinates[j] for j in coords)
        click.echo(str(save_figure(fig, outp / f"resonance_{v:g}{unit}_{tag}_{measure}.png")))
    click.echo(f"{_points(ds)}, {ds.sizes['branch']} branches on {len(levels)} "
               f"level{'s' * (len(levels) != 1)}; grid {st.fmin_hz:g}..{st.fmax_hz:g} Hz step {st.df_hz:g} Hz "
               f"-> {outp / 'resonance.nc'}")


def _points(ds) -> str:
    """"N attractor points" and, where there are, "(M non-periodic)"."""
    m = int((ds["period"].values == 0).sum())
    return f"{ds.sizes['point']} attractor points" + (f" ({m} non-periodic)" if m else "")


def _run(fn, system, levels, st, desc, outp, name, sweep, backend, compress):
    from contactvib.cli.errors import RunInterrupted
    from contactvib.interrupts import Interrupted
    from contactvib.model import ParameterError
    from contactvib.sweeps.resonance import OutputLocked

    try:
        return fn(system, levels=levels, settings=st, desc=desc, out=outp, name=name, resume=sweep["resume"],
                  backend=backend, progress=not sweep["no_progress"], compress=compress)
    except OutputLocked as e:
        raise InputError(f"--out = {e.out}: another contactvib run is writing there ({e.lock})") from None
    except Interrupted as e:
        raise RunInterrupted(e.summary("--resume")) from None
    except ParameterError as e:
        if e.symbol not in ("resume", "scheduler"):
            raise
        raise InputError(f"--{e.symbol} = {e.value}: {e.allowed}") from None


def system_atlas(pa, pa_range, pa_newton, out, backend, sweep: dict) -> None:
    """``contactvib atlas --system rocking ...``: atlas.nc (compressed); its chunks are removed once it
    is written unless ``sweep["keep_chunks"]``."""
    from contactvib.sweeps.system_resonance import remove_system_chunks, system_resonance_dataset

    pa_min, pa_max, npa = pa_range
    given = [o for o, v in zip(("--pa-min", "--pa-max", "--npa"), pa_range) if v is not None]
    if given and (pa or pa_newton):
        raise InputError(f"{given[0]}: give the levels either as a list ({'--pa' if pa else '--pa-newton'}) or as "
                         f"a range (--pa-min, --pa-max, --npa [Q]), not both")
    system, levels, _c, st, _w, desc, label = _inputs(sweep["settings"], pa or ("0.65",), pa_newton, None, sweep)
    if not pa and not pa_newton:
        from contactvib.sweeps.atlas import atlas_levels

        if desc.get("q_newton") is None:
            raise InputError(f"--system {label}: give the force levels --pa-newton [N]")
        kw = {"pa_min": pa_min or "0.05", "pa_max": pa_max or "1.0", "npa": npa or "8"}
        levels = mapped_options({"pa_min": "--pa-min", "pa_max": "--pa-max", "npa": "--npa"}, atlas_levels,
                                kw["pa_min"], kw["pa_max"], kw["npa"])
    outp = checked_output_folder(out)
    ds = _run(system_resonance_dataset, system, levels, st, desc, outp, "atlas", sweep, backend, True)
    if not sweep.get("keep_chunks"):
        remove_system_chunks(outp, levels)
    click.echo(f"{_points(ds)}, {ds.sizes['branch']} branches on {len(levels)} "
               f"level{'s' * (len(levels) != 1)} -> {outp / 'atlas.nc'}")


def _lambda1(a: dict) -> str:
    """λ1 [1/s] of a query record, with its standard error where it has one ("-" where the
    dataset has no exponents)."""
    lam, se = a.get("lyapunov_per_s"), a.get("lyapunov_stderr_per_s")
    if not lam or lam[0] is None:
        return "-"
    return f"{lam[0]:.4g} +- {se[0]:.2g}" if se and se[0] else f"{lam[0]:.4g}"


def echo_system_query(res: dict, p: float, f: float) -> None:
    """The table of ``contactvib query`` for a system dataset's grid point (the columns of
    ``attractors --system``: a non-periodic attractor's period "chaos" or "q-per")."""
    click.echo(f"{res['level_symbol']} = {res['level']:g} {res['level_unit']}, f_e = {res['fe_hz']:g} Hz "
               f"(requested {p:g}, {f:g} Hz); system {res['system_label']}")
    atts = res["attractors"]
    if not atts:
        return
    head = f"{'#':>2} {'period':>6} {'minima':>6} {'|mu|max':>8}"
    head += "".join(f" {d['name'] + ' A_pp [' + d['unit'] + ']':>18}" for d in atts[0]["dofs"])
    head += "".join(f" {c['name'] + ' open':>12}" for c in atts[0]["contacts"])
    head += f" {'type':>14} {'lambda1 [1/s]':>22}  branch (found by)"
    click.echo(head)
    for i, a in enumerate(atts):
        kind = a.get("attractor_type", "periodic")
        if a["period"] is not None:
            row = f"{i:>2} {a['period']:>6} {a['minima_per_period']:>6} {a['floquet_abs_max']:>8.4f}"
        else:
            row = f"{i:>2} {_SHORT.get(kind, kind):>6} {'-':>6} {'-':>8}"
        row += "".join(f" {d['app']:>18.5g}" for d in a["dofs"])
        row += "".join(f" {c['contact_loss_fraction']:>12.3f}" for c in a["contacts"])
        row += f" {kind:>14} {_lambda1(a):>22}"
        click.echo(row + f"  {a['branch']} ({a['found_by']})")


#: A non-periodic attractor's entry in the period column.
_SHORT = {"chaotic": "chaos", "quasi-periodic": "q-per"}
