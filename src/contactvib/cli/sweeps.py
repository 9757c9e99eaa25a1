"""CLI commands ``resonance``, ``query`` and ``paper`` (frequency sweeps and the paper's figures).

Thin: parse and validate (one-line errors, exit 2), call :mod:`contactvib.sweeps.resonance` /
:mod:`contactvib.sweeps.paper` / :func:`contactvib.attractors_at`, print and write.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import click

from contactvib.cli.common import (
    InputError,
    LevelsCommand,
    RunInterrupted,
    checked_option,
    checked_output_folder,
    echo_json,
    feasible_frequencies,
    law_options,
    level_kind_option,
    mapped_options,
    open_dataset_argument,
    parse_frequency_range,
    parse_int,
    parse_levels,
    parse_model,
    parse_number,
    parse_positive,
)
from contactvib.cli.friction import friction_spec_option
from contactvib.cli.system import system_given, system_option
from contactvib.model import KMAX_SWEEP_MAX, LEVEL_KINDS, WORKERS_MAX, level_text

__all__: list = []


def system_sweep_options(f):
    """--system with its level --pa-newton, the coordinate drawn (--plot) and the measure (--measure)."""
    for opt in reversed([
        system_option,
        click.option("--pa-newton", multiple=True, metavar="N",
                     help="With --system: a force level P_a [N] (repeat for several; a system file defines no Q)."),
        click.option("--plot", default=None, metavar="NAME",
                     help="With --system: the coordinate drawn (default: every coordinate, one panel each)."),
        click.option("--measure", type=click.Choice(["app", "h1"]), default="app", show_default=True,
                     help="With --system: draw the peak-to-peak value (app) or the amplitude at f_e (h1)."),
    ]):
        f = opt(f)
    return f


def refuse_system_only(sweep: dict) -> None:
    """One line for an option of --system given without it (and drop them from ``sweep``)."""
    for name in ("pa_newton", "plot", "measure"):
        value = sweep.pop(name, None)
        if value not in (None, (), "app"):
            raise InputError(f"--{name.replace('_', '-')}: an option of --system only")


@contextmanager
def writing_into(out: Path):
    """Hold the output folder's lock for the whole command (sweeps and figures); the library's
    lock and resume refusals become one-line errors (exit 2), Ctrl-C the one line
    ``contactvib: interrupted: N levels kept in OUT/.chunks; rerun with --resume`` (exit 130)."""
    from contactvib.interrupts import deferred_sigint
    from contactvib.sweeps.resonance import Interrupted, OutputLocked, ResumeMismatch, output_lock

    try:
        with output_lock(out), deferred_sigint():  # Ctrl-C between kernel calls and figures
            yield
    except Interrupted as e:
        raise RunInterrupted(e.summary("--resume")) from None
    except KeyboardInterrupt:  # after the sweeps (figures, index page): every level is kept
        n = len(list((out / ".chunks").glob("level_pa*.nc")))
        raise RunInterrupted(Interrupted(n, out / ".chunks").summary("--resume")) from None
    except OutputLocked as e:
        raise InputError(f"--out = {e.out}: another contactvib run is writing there ({e.lock})") from None
    except ResumeMismatch as e:
        raise InputError(f"--resume: {e.chunk} was {e.difference} "
                         "(use another --out, or delete the chunk)") from None


def sweep_options(f):
    f = law_options(f)
    """The options of a sweep; the command receives them as keyword arguments (``**sweep``)."""
    for opt in reversed([
        click.option("--fmin", default="30", show_default=True, metavar="HZ", help="Lowest f_e [Hz]."),
        click.option("--fmax", default="2000", show_default=True, metavar="HZ", help="Highest f_e [Hz]."),
        click.option("--df", default="1", show_default=True, metavar="HZ", help="Frequency step [Hz]."),
        click.option("--multistart-per-octave", default="8", show_default=True,
                     help="Multi-start frequencies per octave of f_e (0: sweeps only)."),
        click.option("--starts", default="24", show_default=True,
                     help="Random starts per multi-start frequency (ballistic seeds are added)."),
        click.option("--seed", default="0", show_default=True, help="Random seed of the start boxes."),
        click.option("--kmax", default="8", show_default=True,
                     help=f"Largest period detected (1..{KMAX_SWEEP_MAX})."),
        click.option("--workers", default=None, metavar="N",
                     help="Worker processes (default: one per CPU core, at most one per level)."),
        click.option("--resume", is_flag=True,
                     help="Reuse the finished levels in OUT/.chunks; refused if one was made with "
                          "another model or settings."),
        click.option("--no-progress", is_flag=True, help="No progress bar."),
        click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
                     help="Override a model parameter by its paper symbol (M, g, S, c_n, m2, h_n, l)."),
        level_kind_option,
    ]):
        f = opt(f)
    return f


#: Options of the sweeps, by SweepSettings' symbols.
_SWEEP_OPTIONS = {"f_min": "--fmin", "f_max": "--fmax", "df": "--df", "kmax": "--kmax",
                  "multistart_per_octave": "--multistart-per-octave",
                  "multistart_starts": "--starts", "seed": "--seed"}


def _sweep_settings(fmin, fmax, df, multistart_per_octave, starts, seed, kmax, **_other):
    """SweepSettings of the sweep options (the dict of :func:`sweep_options`; the options that
    are not settings are ignored): the frequency range and the integers are checked by the
    library's checks, the rest by SweepSettings itself."""
    per_octave = multistart_per_octave
    from contactvib.sweeps.sweep import SweepSettings

    level_kind = _other.get("level_kind", "force")
    from contactvib.cli.friction import friction_spec

    lo, hi = parse_frequency_range(fmin, fmax)
    kw = dict(fmin_hz=lo, fmax_hz=hi, df_hz=parse_positive("--df", "df", df, "Hz"),
              multistart_per_octave=parse_number("--multistart-per-octave", "multistart_per_octave",
                                            per_octave),
              multistart_starts=parse_int("--starts", starts, 0), seed=parse_int("--seed", seed, 0),
              kmax=parse_int("--kmax", kmax, 1, KMAX_SWEEP_MAX), excitation=level_kind,
              friction=friction_spec(_other.get("friction")))
    return mapped_options(_SWEEP_OPTIONS, SweepSettings, **kw)


def sweep_levels(pa: tuple, model, st) -> list[float]:
    """The levels of ``--pa``: P_a [Q] each > 0, or for ``--excitation base-um``/``base-g`` U [µm]
    or A [g] each > 0 whose inertial force stays within the allowed P_a up to ``--fmax``."""
    from contactvib.sweeps.resonance import check_sweep_level

    levels = parse_levels(pa, st.excitation)
    if st.excitation != "force":
        for v in levels:
            checked_option("--pa", check_sweep_level, model, v, st)
    return levels


def _level_file_tag(level: float, kind: str) -> str:
    """The level in a file name: ``pa0.65``, ``U0.05um``, ``A0.3g``."""
    return {"force": f"pa{level:.2f}", "base-um": f"U{level:g}um", "base-g": f"A{level:g}g"}[kind]


def sweep_inputs(sweep: dict):
    """The model, the SweepSettings and the worker count of the sweep options, all checked (the
    grid's ends must be frequencies the model can be integrated at)."""
    from contactvib.steady.transients import check_damped

    model = parse_model(sweep["settings"])
    checked_option("--set h_n", check_damped, model, "a resonance sweep")
    st = _sweep_settings(**sweep)
    n_workers = _workers(sweep["workers"])
    feasible_frequencies(model, st.fmin_hz, st.fmax_hz)
    return model, st, n_workers


def _workers(text):
    return None if text is None else parse_int("--workers", text, 1, WORKERS_MAX)


@click.command(cls=LevelsCommand)
@click.option("--pa", multiple=True, default=("0.65",), show_default=True, metavar="Q [Q ...]",
              help="Excitation amplitudes P_a [Q]; several values after one --pa.")
@sweep_options
@friction_spec_option
@click.option("--out", default="resonance", show_default=True, type=click.Path(file_okay=False),
              help="Output folder: resonance.nc, .chunks/, one resonance graph and one extrema "
                   "diagram per level.")
@system_sweep_options
def resonance(pa, out, **sweep):
    """Resonance graphs: up/down sweeps + seeds + multi-start over f_e for each P_a (Figs. 2, 3)."""
    if system_given():
        from contactvib.cli.system_sweeps import system_resonance

        return system_resonance(pa, sweep.pop("pa_newton"), sweep.pop("plot"), sweep.pop("measure"), out, sweep)
    refuse_system_only(sweep)
    model, st, n_workers = sweep_inputs(sweep)
    levels = sweep_levels(pa, model, st)
    from contactvib.interrupts import check_interrupt
    from contactvib.sweeps.paper import write_level_figures
    from contactvib.sweeps.resonance import resonance_dataset

    out = checked_output_folder(out)
    with writing_into(out):
        ds = resonance_dataset(model, levels=levels, settings=st, out=out, resume=sweep["resume"], workers=n_workers,
                               progress=not sweep["no_progress"])
        for p in sorted(set(levels)):
            tag = _level_file_tag(p, st.excitation)
            write_level_figures(ds, p, out / f"resonance_{tag}.png", out / f"extrema_{tag}.png", model)
            check_interrupt()
    click.echo(f"{ds.sizes['point']} attractor points, {ds.sizes['branch']} branches on "
               f"{len(set(levels))} levels -> {out / 'resonance.nc'}")


@click.command()
@click.argument("dataset", type=click.Path())
@click.option("--pa", required=True, metavar="Q", help="Stored P_a level [Q] (matched within 1e-6).")
@click.option("--fe", required=True, metavar="HZ", help="Frequency [Hz] (nearest grid point within half a step).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (attractors contract + branch labels).")
def query(dataset, pa, fe, as_json):
    """The attractors stored in a resonance dataset (a file, or an atlas/paper/resonance folder) at one (P_a, f_e)."""
    p = parse_number("--pa", "P_a/Q", pa)
    f = parse_positive("--fe", "f_e", fe, "Hz")
    from contactvib.sweeps.stored import DamagedDataset

    data = open_dataset_argument(dataset)
    path = data.path
    with data:
        try:
            res = data.attractors_at(p, f)
        except DamagedDataset as e:
            raise InputError(f"DATASET = {path}: {e}") from None
        except LookupError as e:
            raise InputError(str(e)) from None
        except (OSError, RuntimeError, ValueError, TypeError, IndexError) as e:  # unreadable values
            raise InputError(f"DATASET = {path}: damaged: its values cannot be read ({type(e).__name__}: "
                             f"{e}): recompute it") from None
    if as_json:
        echo_json(res)
        return
    if "system" in res:  # a system's dataset
        from contactvib.cli.system_sweeps import echo_system_query

        return echo_system_query(res, p, f)
    kind = res.get("excitation", "force")
    unit = LEVEL_KINDS[kind][1]
    click.echo(f"{level_text(res['pa_over_q'], kind, 6)}, f_e = {res['fe_hz']:g} Hz "
               f"(requested {p:g} {unit}, {f:g} Hz)")
    click.echo(f"{'#':>2} {'period':>6} {'minima':>6} {'A_pp [um]':>11} {'y_min [um]':>11} "
               f"{'gap [frac]':>10} {'basin':>7}  branch label (found by)")
    for i, a in enumerate(res["attractors"]):
        per = "-" if a["period"] is None else str(a["period"])
        mins = "-" if a["minima_per_period"] is None else str(a["minima_per_period"])
        basin = "-" if a["basin_fraction"] is None else f"{a['basin_fraction']:.1%}"
        click.echo(f"{i:>2} {per:>6} {mins:>6} {a['app_um']:>11.5g} {a['ymin_um']:>11.5g} "
                   f"{a['contact_loss_fraction']:>10.3f} {basin:>7}  {a['branch_label']} ({a['found_by']})")


@click.command()
@click.option("--out", default="paper", show_default=True, type=click.Path(file_okay=False),
              help="Output folder: paper.nc, .chunks/, fig2*/fig3* per level, fig4–fig9, index.md.")
@sweep_options
def paper(out, **sweep):
    """Reproduce Kostek (2013) Figs. 2a–h, 3a–h and 4–9 with an index page (the paper's defaults)."""
    if sweep.get("level_kind", "force") != "force":
        raise InputError(f"--excitation {sweep['level_kind']}: the paper's levels are force amplitudes "
                         "P_a [Q]; sweep base motion with `contactvib resonance` or `atlas`")
    model, st, n_workers = sweep_inputs(sweep)
    folder = checked_output_folder(out)
    from contactvib.sweeps.paper import reproduce_paper

    with writing_into(folder):
        res = reproduce_paper(model, out=out, settings=st, resume=sweep["resume"],
                              workers=n_workers, progress=not sweep["no_progress"])
    ds = res.dataset
    click.echo(f"{ds.sizes['point']} attractor points, {ds.sizes['branch']} branches; "
               f"{res.timing['sweeps_and_figures_s']:.1f} s")
    click.echo(f"wrote {Path(out) / 'paper.nc'}, {2 * len(res.level_figures) + len(res.time_figures)} "
               f"figures and {res.index}")

