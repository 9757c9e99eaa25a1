"""CLI commands ``resonance``, ``query`` and ``paper`` (frequency sweeps and the paper's figures).

Thin: parse and validate (one-line errors, exit 2), call :mod:`contactvib.sweeps.resonance` /
:mod:`contactvib.sweeps.paper` / :func:`contactvib.attractors_at`, print and write.
"""

from __future__ import annotations

import sys
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
from contactvib.cli.errors import ctrl_c
from contactvib.cli.friction import friction_spec_option
from contactvib.cli.system import system_given, system_option
from contactvib.model import KMAX_SWEEP_MAX, LEVEL_KINDS, WORKERS_MAX, level_text
from contactvib.sweeps.completeness import COMPLETENESS_STARTS
from contactvib.sweeps.settings import SweepSettings

__all__: list = []

#: The most grid points ``query --completeness`` searches again.
COMPLETENESS_POINTS_MAX = 100_000


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
        click.option("--fill-in-per-octave", default=f"{SweepSettings.fill_in_per_octave:g}", show_default=True,
                     help="Fill-in multi-start frequencies per octave between the multi-start ones "
                          "(0: none): they find the isolated branches a few Hz wide."),
        click.option("--fill-in-starts", default=str(SweepSettings.fill_in_starts), show_default=True,
                     help="Random starts per fill-in frequency (ballistic seeds are added; 0: no fill-in)."),
        click.option("--seed", default="0", show_default=True, help="Random seed of the start boxes."),
        click.option("--kmax", default=str(SweepSettings.kmax), show_default=True,
                     help=f"Largest period detected (1..{KMAX_SWEEP_MAX}; with --system: 8 unless given)."),
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


keep_chunks_option = click.option(
    "--keep-chunks", is_flag=True,
    help="Keep OUT/.chunks (one finished level per file) after a complete run, for a later --resume; "
         "by default they are removed once the dataset and figures are written.")


#: Options of the sweeps, by SweepSettings' symbols.
_SWEEP_OPTIONS = {"f_min": "--fmin", "f_max": "--fmax", "df": "--df", "kmax": "--kmax",
                  "multistart_per_octave": "--multistart-per-octave",
                  "n_starts": "--starts", "seed": "--seed", "fill_in_per_octave": "--fill-in-per-octave",
                  "fill_in_starts": "--fill-in-starts"}


def _sweep_settings(fmin, fmax, df, multistart_per_octave, starts, seed, kmax, fill_in_per_octave,
                    fill_in_starts, **_other):
    """SweepSettings of the sweep options (the dict of :func:`sweep_options`; the options that
    are not settings are ignored): the frequency range and the integers are checked by the
    library's checks, the rest by SweepSettings itself."""
    per_octave = multistart_per_octave
    level_kind = _other.get("level_kind", "force")
    from contactvib.cli.friction import friction_spec

    lo, hi = parse_frequency_range(fmin, fmax)
    kw = dict(fmin_hz=lo, fmax_hz=hi, df_hz=parse_positive("--df", "df", df, "Hz"),
              multistart_per_octave=parse_number("--multistart-per-octave", "multistart_per_octave",
                                            per_octave),
              n_starts=parse_int("--starts", starts, 0, symbol="n_starts"), seed=parse_int("--seed", seed, 0),
              fill_in_per_octave=parse_number("--fill-in-per-octave", "fill_in_per_octave", fill_in_per_octave),
              fill_in_starts=parse_int("--fill-in-starts", fill_in_starts, 0, symbol="fill_in_starts"),
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
              help="Output folder: resonance.nc, one resonance graph and one extrema diagram per level "
                   "(.chunks/ while it runs).")
@keep_chunks_option
@system_sweep_options
def resonance(pa, out, keep_chunks, **sweep):
    """Resonance graphs: up/down sweeps + seeds + multi-start over f_e for each P_a (Figs. 2, 3)."""
    if system_given():
        from contactvib.cli.system_sweeps import system_resonance

        return system_resonance(pa, sweep.pop("pa_newton"), sweep.pop("plot"), sweep.pop("measure"), out, sweep)
    refuse_system_only(sweep)
    model, st, n_workers = sweep_inputs(sweep)
    levels = sweep_levels(pa, model, st)
    from contactvib.interrupts import check_interrupt
    from contactvib.sweeps.paper import write_level_figures
    from contactvib.sweeps.resonance import remove_chunks, resonance_dataset

    out = checked_output_folder(out)
    with writing_into(out):
        ds = resonance_dataset(model, levels=levels, settings=st, out=out, resume=sweep["resume"], workers=n_workers,
                               progress=not sweep["no_progress"])
        for p in sorted(set(levels)):
            tag = _level_file_tag(p, st.excitation)
            write_level_figures(ds, p, out / f"resonance_{tag}.png", out / f"extrema_{tag}.png", model)
            check_interrupt()
        if not keep_chunks:
            remove_chunks(out, levels)
    click.echo(f"{ds.sizes['point']} attractor points, {ds.sizes['branch']} branches on "
               f"{len(set(levels))} levels -> {out / 'resonance.nc'}")


@click.command()
@click.argument("dataset", type=click.Path())
@click.option("--pa", default=None, metavar="Q", help="Stored P_a level [Q] (matched within 1e-6).")
@click.option("--fe", default=None, metavar="HZ", help="Frequency [Hz] (nearest grid point within half a step).")
@click.option("--completeness", default=None, metavar="N",
              help=f"Instead of --pa/--fe: search N random grid points again by brute force "
                   f"({COMPLETENESS_STARTS} starts each) and list the attractors the dataset lacks.")
@click.option("--seed", default="0", show_default=True, help="Random seed of --completeness (points and starts).")
@click.option("--no-progress", is_flag=True, help="No progress bar for --completeness.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (attractors contract + branch labels; "
                                                      "with --completeness its report).")
def query(dataset, pa, fe, completeness, seed, no_progress, as_json):
    """The attractors stored in a resonance dataset (a file, or an atlas/paper/resonance folder) at one
    (P_a, f_e), or with --completeness the attractors it lacks at random grid points."""
    if completeness is not None:
        if pa is not None or fe is not None:
            raise InputError("--completeness checks random grid points: not with --pa or --fe")
        n = parse_int("--completeness", completeness, 1, COMPLETENESS_POINTS_MAX)
        _completeness(dataset, n, parse_int("--seed", seed, 0), not no_progress and not as_json, as_json)
        return
    if pa is None or fe is None:
        raise InputError(f"{'--pa' if pa is None else '--fe'} is required (or --completeness N)")
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


def _completeness(dataset, n: int, seed: int, progress: bool, as_json: bool) -> None:
    """``query --completeness N``: the report of :func:`contactvib.sweeps.completeness.check_completeness`."""
    from contactvib.sweeps.completeness import check_completeness
    from contactvib.sweeps.stored import DatasetError

    data = open_dataset_argument(dataset)
    bar = []

    def advance(done, total):
        if not bar:
            from tqdm import tqdm

            bar.append(tqdm(total=total, unit="point", file=sys.stderr, leave=False, dynamic_ncols=True,
                            desc="completeness search", disable=None if progress else True))  # None: a terminal only
        else:
            bar[0].update(done - bar[0].n)

    with data, ctrl_c():
        try:
            report = check_completeness(data, n_points=n, seed=seed, progress=advance)
        except DatasetError as e:
            raise InputError(f"DATASET = {data.path}: {e}") from None
        finally:
            while bar:
                bar.pop().close()
    if as_json:
        echo_json({"completeness": report})
        return
    unit = data.level_unit
    click.echo(f"{report['points_checked']} grid points searched again ({report['n_starts']} starts each, "
               f"seed {seed}): {len(report['missing'])} missing attractor{'' if len(report['missing']) == 1 else 's'}, "
               f"{report['found_fraction']:.1%} of those found are stored")
    if report["missing"]:
        click.echo(f"{'level [' + unit + ']':>10} {'f_e [Hz]':>9} {'period':>6} {'minima':>6} "
                   f"{'A_pp [um]':>10} {'basin':>7}")
    for m in report["missing"]:
        per = "-" if m["period"] is None else str(m["period"])
        mins = "-" if m["minima_per_period"] is None else str(m["minima_per_period"])
        click.echo(f"{m['level']:>10g} {m['fe_hz']:>9g} {per:>6} {mins:>6} {m['app_um']:>10.5g} "
                   f"{m['basin_fraction']:>7.1%}")
    click.echo(f"same attractor: {report['rule']}")


@click.command()
@click.option("--out", default="paper", show_default=True, type=click.Path(file_okay=False),
              help="Output folder: paper.nc, fig2*/fig3* per level, fig4–fig9, index.md (.chunks/ while "
                   "it runs).")
@sweep_options
@keep_chunks_option
def paper(out, keep_chunks, **sweep):
    """Reproduce Kostek (2013) Figs. 2a–h, 3a–h and 4–9 with an index page (the paper's defaults)."""
    if sweep.get("level_kind", "force") != "force":
        raise InputError(f"--excitation {sweep['level_kind']}: the paper's levels are force amplitudes "
                         "P_a [Q]; sweep base motion with `contactvib resonance` or `atlas`")
    model, st, n_workers = sweep_inputs(sweep)
    folder = checked_output_folder(out)
    from contactvib.sweeps.paper import PAPER_LEVELS, reproduce_paper
    from contactvib.sweeps.resonance import remove_chunks

    with writing_into(folder):
        res = reproduce_paper(model, out=out, settings=st, resume=sweep["resume"],
                              workers=n_workers, progress=not sweep["no_progress"])
        if not keep_chunks:
            remove_chunks(folder, PAPER_LEVELS)
    ds = res.dataset
    click.echo(f"{ds.sizes['point']} attractor points, {ds.sizes['branch']} branches; "
               f"{res.timing['sweeps_and_figures_s']:.1f} s")
    click.echo(f"wrote {Path(out) / 'paper.nc'}, {2 * len(res.level_figures) + len(res.time_figures)} "
               f"figures and {res.index}")

