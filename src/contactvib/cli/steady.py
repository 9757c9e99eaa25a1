"""CLI commands ``attractors`` and ``simulate`` (steady states at one operating point)."""

from __future__ import annotations

import contextvars
import sys

import click

from contactvib.cli.common import (
    InputError,
    checked_output_folder,
    ctrl_c,
    echo_json,
    mapped_options,
    model_blamed,
    operating_point_options,
    option_error,
    parse_excitation,
    parse_int,
    parse_max_periods,
    parse_model,
    parse_number,
    scoped_options,
    search_options,
)
from contactvib.cli.system import system_attractors, system_given, system_option, system_simulate
from contactvib.model import LEVEL_TAGS, ContactModel, ParameterError

#: Options of the attractor search, by find_attractors' parameter names.
_SEARCH_OPTIONS = {"n_starts": "--starts", "seed": "--seed", "kmax": "--kmax",
                   "max_periods": "--max-periods"}


def search_settings(starts, seed, kmax, max_periods) -> dict:
    """The search options, checked by the library (ranges and memory; we name the options)."""
    from contactvib.steady.attractors import check_search

    kw = {name: parse_number(option, name, text) for (name, option), text
          in zip(_SEARCH_OPTIONS.items(), (starts, seed, kmax))}
    kw["max_periods"] = parse_max_periods(max_periods)
    return dict(zip(_SEARCH_OPTIONS, mapped_options(_SEARCH_OPTIONS, check_search, **kw)))


def search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds, progress=None):
    """find_attractors with the search options (it checks them; we name the options);
    ``progress`` as find_attractors'."""
    from contactvib.steady.attractors import find_attractors

    kw = search_settings(starts, seed, kmax, max_periods)
    names = {**_SEARCH_OPTIONS, "h_n": "--set h_n", "f_e": "--fe"}
    with ctrl_c():
        try:
            return find_attractors(exc, seeds=not no_seeds, progress=progress, **kw)
        except ParameterError as e:
            blamed = model_blamed(model, e, _work_within_reach(exc, kw, no_seeds))
            raise (blamed or option_error(names.get(e.symbol, e.symbol), e, names)) from None
        finally:
            getattr(progress, "close", lambda: None)()  # the bar off stderr before any message


def _work_within_reach(exc, kw: dict, no_seeds: bool):
    """Whether the search of ``kw`` at ``exc``'s excitation is within the work limit for a
    model (a test for :func:`model_blamed`)."""
    import dataclasses

    from contactvib.steady.attractors import ballistic_seeds, default_max_periods
    from contactvib.steady.transients import WORK_MAX_STEPS, check_work

    def accepts(model):
        e = dataclasses.replace(exc, model=model)
        n = kw["n_starts"] + (0 if no_seeds else ballistic_seeds(e)[0].shape[0])
        return check_work(e, n, kw["max_periods"] or default_max_periods(e)) <= WORK_MAX_STEPS

    return accepts


def _header(model, exc, no_seeds, max_periods=None, header=True):
    """A progress callback of the search: it prints the table's header lines when the search
    starts (its inputs checked), so that they show what runs while it runs (``header``), and for
    a search estimated beyond :data:`~contactvib.steady.attractors.LONG_SEARCH_S` a bar on stderr
    with the starts done and the time left (tqdm's, from the measured rate); its title states the
    estimate as what it is, an upper bound (every start integrated to the transient limit; most
    settle long before); ``close()`` removes the bar."""
    from contactvib.steady.attractors import LONG_SEARCH_S, ballistic_seeds, default_max_periods
    from contactvib.steady.transients import check_work, duration_text, estimated_seconds

    bar = []

    def progress(done, total):
        if done:
            if bar:
                bar[0].update(done - bar[0].n)
                if done >= total:
                    close()
            return
        n_seeds = 0 if no_seeds else ballistic_seeds(exc)[0].shape[0]
        if header:
            u = model.units
            engages = f" past the contact's engagement at y = {u.y_offset_um:g} um" if u.y_offset_um else ""
            click.echo(f"{excitation_text(exc)}, f_e = {exc.f_e:g} Hz, "
                       f"f_n0 = {model.f_n0:.1f} Hz, y0 = {u.y_um:.4f} um{engages}; "
                       f"{total - n_seeds} box starts + {n_seeds} seeds")
            if not (model.is_paper_family and model.parameters() == ContactModel().parameters()):
                click.echo(f"model: {model.describe_law()}, zeta = {model.zeta:.4g}")
        seconds = estimated_seconds(check_work(exc, total, parse_max_periods(max_periods) or default_max_periods(exc)))
        if seconds > LONG_SEARCH_S:
            from tqdm import tqdm

            bar.append(tqdm(total=total, unit="start", file=sys.stderr, leave=False, dynamic_ncols=True,
                            desc=f"attractor search, at most {duration_text(seconds)}"))

    def close():
        while bar:
            bar.pop().close()

    progress.close = close
    return progress


def excitation_text(exc) -> str:
    """``P_a = 0.65 Q (1.343 N)``, with the harmonics, or the base motion and its inertial force."""
    if exc.kind == "base":
        sym, val, unit = exc.level
        return f"base motion {sym} = {val:g} {unit} (inertial force {exc.pa_over_q:.4g} Q)"
    text = f"P_a = {exc.pa_over_q:g} Q ({exc.P_a:.4g} N)"
    for k, a, ph in exc.harmonics:
        text += f" + {a:g} Q at {k} f_e ({ph:g} deg)"
    return text


def _none_settled(result) -> None:
    """Exit 1 with one line when no start reached an attractor (all unsettled or failed)."""
    if len(result):
        return
    n = result.n_box + result.n_seeds
    click.echo(f"contactvib: error: no attractor: none of the {n} starts settled within "
               f"{result.settings['max_periods']} periods ({result.n_unsettled} unsettled, "
               f"{result.n_failed} failed); raise --max-periods", err=True)
    click.get_current_context().exit(1)


@click.command()
@system_option
@operating_point_options
@search_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the documented contract).")
def attractors(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, as_json):
    """All coexisting attractors at one operating point (P_a, f_e)."""
    if system_given():
        system_attractors(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, as_json)
        return
    model = parse_model(settings)
    exc = parse_excitation(model, pa, pa_newton, fe)
    if as_json:
        result = search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds,
                       _header(model, exc, no_seeds, max_periods, header=False))
        echo_json(result.to_json())
        _none_settled(result)
        return
    result = search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds,
                   _header(model, exc, no_seeds, max_periods))
    base = any(a.slider_app_um is not None for a in result)
    head = (f"{'#':>2} {'period':>6} {'minima':>6} {'A_pp [um]':>11} {'y_min [um]':>11} "
            f"{'y_max [um]':>10} {'gap [frac]':>10} {'|mu|max':>8} {'basin':>7}"
            + (f" {'slider s_pp [um]':>16}" if base else ""))
    click.echo(head)
    for i, a in enumerate(result):
        per = {"chaotic": "chaos", "quasi-periodic": "q-per"}.get(a.kind, "-") if a.period is None \
            else str(a.period)
        mins = "-" if a.minima_per_period is None else str(a.minima_per_period)
        mu = "-" if a.floquet_abs_max is None else f"{a.floquet_abs_max:.4f}"
        click.echo(f"{i:>2} {per:>6} {mins:>6} {a.app_um:>11.5g} {a.ymin_um:>11.5g} {a.ymax_um:>10.5g} "
                   f"{a.contact_loss_fraction:>10.3f} {mu:>8} {a.basin_fraction:>7.2%}"
                   + (f" {a.slider_app_um:>16.5g}" if base else ""))
    if result.n_unsettled:
        click.echo(f"   unsettled within {result.settings['max_periods']} periods: "
                   f"{result.n_unsettled} starts ({result.unsettled_fraction:.2%} of the box)")
    _none_settled(result)


#: The random-force options of ``simulate`` (kept out of its signature by ``_random_options``).
_RANDOM: contextvars.ContextVar = contextvars.ContextVar("contactvib_random", default=None)
#: Options of ``simulate`` that belong to the attractors' excitation, trajectory or search: refused
#: with --random-psd (by click parameter name).
_NOT_RANDOM = {"pa": "--pa", "pa_newton": "--pa-newton", "base_um": "--base-um", "base_g": "--base-g",
               "harmonic": "--harmonic", "fe": "--fe", "from_state": "--from-state", "periods": "--periods",
               "starts": "--starts", "kmax": "--kmax", "max_periods": "--max-periods", "no_seeds": "--no-seeds"}
#: The library's symbols of the random force, by option.
_RANDOM_NAMES = {"S_F": "--random-psd", "f_lo": "--band FLO", "f_hi": "--band FHI", "seed": "--seed",
                 "duration": "--duration"}


def _random_options(f):
    """--random-psd, --band, --duration: a random force instead of the attractors."""
    f = scoped_options(_RANDOM, ("random_psd", "band", "duration"), f)
    f = click.option("--duration", default=None, metavar="S",
                     help="Duration [s] of the response to --random-psd, after its start transient (default 1).")(f)
    f = click.option("--band", nargs=2, default=None, metavar="FLO FHI",
                     help="Band [Hz] of the random force of --random-psd, 0 < FLO < FHI.")(f)
    f = click.option("--random-psd", default=None, metavar="SF",
                     help="Random band-limited Gaussian force of flat one-sided PSD SF [N^2/Hz] over --band "
                          "instead of the attractors (random phases from --seed): writes OUT/random.nc and "
                          "OUT/random_response.png.")(f)
    return f


def _random_force(seed):
    """The RandomForce and duration [s] of --random-psd, --band, --duration and --seed, or None
    without --random-psd (then --band and --duration are refused); the options that belong to
    the attractors are refused with it."""
    opts = _RANDOM.get() or {}
    if opts.get("random_psd") is None:
        for name in ("band", "duration"):
            if opts.get(name) is not None:
                raise InputError(f"--{name}: belongs to a random force; give --random-psd SF [N^2/Hz] with it")
        return None
    ctx = click.get_current_context()
    for name, option in _NOT_RANDOM.items():
        if ctx.get_parameter_source(name) not in (None, click.core.ParameterSource.DEFAULT):
            raise InputError(f"--random-psd and {option}: give one of them ({option} belongs to the attractors "
                             f"or trajectory of a harmonic excitation; a random force takes --band FLO FHI, "
                             f"--duration and --seed)")
    if opts.get("band") is None:
        raise InputError("--random-psd: needs its band --band FLO FHI [Hz]")
    from contactvib.steady.random_response import RandomForce

    sf = parse_number("--random-psd", "S_F", opts["random_psd"])
    lo, hi = (parse_number(f"--band {o}", s, t) for o, s, t in zip(("FLO", "FHI"), ("f_lo", "f_hi"), opts["band"]))
    seed = parse_int("--seed", seed, 0, symbol="seed")
    duration = 1.0 if opts.get("duration") is None else parse_number("--duration", "duration", opts["duration"])
    return mapped_options(_RANDOM_NAMES, RandomForce, sf, lo, hi, seed=seed), duration


def _simulate_random(model, force, duration, out) -> None:
    """random_response of ``model`` to ``force``: OUT/random.nc, OUT/random_response.png and the
    statistics on stdout."""
    from contactvib.steady.random_response import check_random, random_response

    mapped_options(_RANDOM_NAMES, check_random, model, force, duration)
    out = checked_output_folder(out)
    with ctrl_c():
        resp = random_response(model, force, duration)
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.random import random_figure

    nc = out / "random.nc"
    resp.to_dataset().to_netcdf(nc)
    png = save_figure(random_figure(resp), out / "random_response.png")
    click.echo(f"random force: S_F = {force.S_F:.4g} N^2/Hz over [{force.f_lo:g}, {force.f_hi:g}] Hz, RMS "
               f"{force.rms_n:.4g} N = {force.rms_n / model.Q:.3g} Q, {force.n} components, seed {force.seed}; "
               f"{duration:g} s after {resp.discard_s:.3g} s discarded")
    click.echo(f"response: RMS {resp.rms_um:.4g} um about the mean y = {resp.mean_um:.4g} um "
               f"(y0 = {resp.y0_um:.4g} um, f_n0 = {resp.f_n0_hz:.1f} Hz)")
    click.echo(f"contact loss probability: {resp.contact_loss_probability:.4f} (fraction of time with y <= 0)")
    click.echo(f"mean contact force: {resp.mean_contact_force_n:.5g} +- {resp.mean_contact_force_err_n:.2g} N "
               f"vs W = Q + F_pre = {resp.static_load_n:.5g} N ({resp.mean_force_deviation:+.2f} standard errors)")
    click.echo(str(nc))
    click.echo(str(png))


@click.command()
@system_option
@operating_point_options
@search_options
@click.option("--out", "out", default="simulate", show_default=True, type=click.Path(file_okay=False),
              help="Output folder for the figures and attractors.json.")
@click.option("--from-state", nargs=2, default=None, metavar="Y_UM YDOT_MM_S",
              help="Simulate one trajectory from this state instead of the attractors.")
@click.option("--periods", default="20", show_default=True,
              help="Periods to simulate with --from-state.")
@_random_options
def simulate(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, out,
             from_state, periods):
    """Time histories and phase portraits (one figure per attractor, as Figs. 4–9); with
    --random-psd the response to a random band-limited Gaussian force."""
    if system_given():
        system_simulate(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, out, from_state, periods)
        return
    model = parse_model(settings)
    random = _random_force(seed)
    if random is not None:
        _simulate_random(model, *random, out)
        return
    exc = parse_excitation(model, pa, pa_newton, fe)
    if from_state is not None:
        y = parse_number("--from-state", "y", from_state[0])
        yd = parse_number("--from-state", "ydot", from_state[1])
        n = parse_int("--periods", periods, 1, symbol="n_periods")
        from contactvib.steady.simulate import check_start

        y, yd, n, _ = mapped_options({"y": "--from-state", "ydot": "--from-state", "n_periods": "--periods"},
                              check_start, model, y, yd, n)
    else:
        search_settings(starts, seed, kmax, max_periods)
    from contactvib.plotting.figures import attractor_figure, history_figure, save_figure
    from contactvib.steady.simulate import attractor_history
    from contactvib.steady.simulate import simulate as run

    out = checked_output_folder(out)
    tag = f"{LEVEL_TAGS[exc.level_kind]}{exc.level[1]:g}_fe{exc.f_e:g}"
    if from_state is not None:
        h = mapped_options({"n_periods": "--periods", "f_e": "--fe"}, run, exc, y_um=y, ydot_mm_s=yd, n_periods=n)
        sym, rest = h.level.split(" = ", 1)
        fig = history_figure(h, f"${sym}$ = {rest}{' (base motion)' if h.base_um is not None else ''}, "
                                f"$f_e$ = {exc.f_e:g} Hz, from y = {y:g} µm, ẏ = {yd:g} mm/s")
        path = save_figure(fig, out / f"trajectory_{tag}.png")
        click.echo(str(path))
        return
    result = search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds)
    _none_settled(result)
    (out / "attractors.json").write_text(result.to_json(indent=1))
    for i, a in enumerate(result):
        hist = attractor_history(exc, a)
        path = save_figure(attractor_figure(hist, a), out / f"attractor{i}_{tag}.png")
        click.echo(f"{path}  period={a.period} minima={a.minima_per_period} A_pp={a.app_um:.4g} um")

