"""CLI commands ``attractors`` and ``simulate`` (steady states at one operating point)."""

from __future__ import annotations

import click

from contactvib.cli.common import (
    _ctrl_c,
    _echo_json,
    _excitation,
    _int,
    _mapped,
    _max_periods,
    _model,
    _number,
    _operating_point_options,
    _output_folder,
    _search_options,
)

#: Options of the attractor search, by find_attractors' parameter names.
_SEARCH_OPTIONS = {"n_starts": "--starts", "seed": "--seed", "kmax": "--kmax",
                   "max_periods": "--max-periods"}


def _search(starts, seed, kmax, max_periods) -> dict:
    """The search options, checked by the library (ranges and memory; we name the options)."""
    from contactvib.steady.attractors import check_search

    kw = {name: _number(option, name, text) for (name, option), text
          in zip(_SEARCH_OPTIONS.items(), (starts, seed, kmax))}
    kw["max_periods"] = _max_periods(max_periods)
    return dict(zip(_SEARCH_OPTIONS, _mapped(_SEARCH_OPTIONS, check_search, **kw)))


def _find(model, exc, starts, seed, kmax, max_periods, no_seeds):
    """find_attractors with the search options (it checks them; we name the options)."""
    from contactvib.steady.attractors import find_attractors

    kw = _search(starts, seed, kmax, max_periods)
    names = {**_SEARCH_OPTIONS, "h_n": "--set h_n", "f_e": "--fe"}
    with _ctrl_c():
        return _mapped(names, find_attractors, model, exc, seeds=not no_seeds, **kw)


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
@_operating_point_options
@_search_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the documented contract).")
def attractors(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, as_json):
    """All coexisting attractors at one operating point (P_a, f_e)."""
    model = _model(settings)
    exc = _excitation(model, pa, pa_newton, fe)
    result = _find(model, exc, starts, seed, kmax, max_periods, no_seeds)
    if as_json:
        _echo_json(result.to_json())
        _none_settled(result)
        return
    click.echo(f"P_a = {exc.pa_over_q:g} Q ({exc.P_a:.4g} N), f_e = {exc.f_e:g} Hz, "
               f"f_n0 = {model.f_n0:.1f} Hz, y0 = {model.units.y_um:.4f} um; "
               f"{result.n_box} box starts + {result.n_seeds} seeds")
    head = (f"{'#':>2} {'period':>6} {'minima':>6} {'A_pp [um]':>11} {'y_min [um]':>11} "
            f"{'y_max [um]':>10} {'gap [frac]':>10} {'|mu|max':>8} {'basin':>7}")
    click.echo(head)
    for i, a in enumerate(result):
        per = {"chaotic": "chaos", "quasi-periodic": "q-per"}.get(a.kind, "-") if a.period is None \
            else str(a.period)
        mins = "-" if a.minima_per_period is None else str(a.minima_per_period)
        mu = "-" if a.floquet_abs_max is None else f"{a.floquet_abs_max:.4f}"
        click.echo(f"{i:>2} {per:>6} {mins:>6} {a.app_um:>11.5g} {a.ymin_um:>11.5g} {a.ymax_um:>10.5g} "
                   f"{a.contact_loss_fraction:>10.3f} {mu:>8} {a.basin_fraction:>7.2%}")
    if result.n_unsettled:
        click.echo(f"   unsettled within {result.settings['max_periods']} periods: "
                   f"{result.n_unsettled} starts ({result.unsettled_fraction:.2%} of the box)")
    _none_settled(result)


@click.command()
@_operating_point_options
@_search_options
@click.option("--out", "out", default="simulate", show_default=True, type=click.Path(file_okay=False),
              help="Output folder for the figures and attractors.json.")
@click.option("--from-state", nargs=2, default=None, metavar="Y_UM YDOT_MM_S",
              help="Simulate one trajectory from this state instead of the attractors.")
@click.option("--periods", default="20", show_default=True,
              help="Periods to simulate with --from-state.")
def simulate(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, out,
             from_state, periods):
    """Time histories and phase portraits (one figure per attractor, as Figs. 4–9)."""
    model = _model(settings)
    exc = _excitation(model, pa, pa_newton, fe)
    if from_state is not None:
        y = _number("--from-state", "y", from_state[0])
        yd = _number("--from-state", "ydot", from_state[1])
        n = _int("--periods", periods, 1, symbol="n_periods")
        from contactvib.steady.simulate import check_start

        y, yd, n, _ = _mapped({"y": "--from-state", "ydot": "--from-state", "n_periods": "--periods"},
                              check_start, model, y, yd, n)
    else:
        _search(starts, seed, kmax, max_periods)
    from contactvib.plotting.figures import attractor_figure, history_figure, save_figure
    from contactvib.steady.simulate import attractor_history
    from contactvib.steady.simulate import simulate as run

    out = _output_folder(out)
    tag = f"pa{exc.pa_over_q:g}_fe{exc.f_e:g}"
    if from_state is not None:
        h = _mapped({"n_periods": "--periods", "f_e": "--fe"}, run, model, exc, y, yd, n_periods=n)
        fig = history_figure(h, f"$P_a$ = {exc.pa_over_q:g} Q, $f_e$ = {exc.f_e:g} Hz, from "
                                f"y = {y:g} µm, ẏ = {yd:g} mm/s")
        path = save_figure(fig, out / f"trajectory_{tag}.png")
        click.echo(str(path))
        return
    result = _find(model, exc, starts, seed, kmax, max_periods, no_seeds)
    _none_settled(result)
    (out / "attractors.json").write_text(result.to_json(indent=1))
    for i, a in enumerate(result):
        hist = attractor_history(model, exc, a)
        path = save_figure(attractor_figure(hist, a), out / f"attractor{i}_{tag}.png")
        click.echo(f"{path}  period={a.period} minima={a.minima_per_period} A_pp={a.app_um:.4g} um")

