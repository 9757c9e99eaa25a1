"""Command-line interface (thin: parse, validate, call the public API, print, write).

Bad input stops before any computation with one line on stderr,
``contactvib: error: --fe (f_e) = -5: must be > 0 Hz``, and exit status 2.
"""

from __future__ import annotations

import sys
from pathlib import Path

import click

from .model import PAPER_DEFAULTS, PARAMETER_UNITS, ContactModel, Excitation, ParameterError

# Heavy modules (numba kernels, matplotlib) are imported inside the commands.


class InputError(Exception):
    """A user input error: printed as one line, no traceback, no usage banner."""


def _checked(option: str, func, *args):
    try:
        return func(*args)
    except ParameterError as e:
        raise InputError(f"{option} ({e.symbol}) = {_show(e.value)}: {e.allowed}") from None


def _show(value) -> str:
    try:
        return f"{float(value):g}"
    except (TypeError, ValueError):
        return str(value)


def _number(option: str, symbol: str, text: str) -> float:
    from .model import check_finite

    return _checked(option, check_finite, symbol, text)


def _model(settings: tuple[str, ...]) -> ContactModel:
    overrides = {}
    for item in settings:
        if "=" not in item:
            raise InputError(f"--set {item}: expected NAME=VALUE with NAME one of {', '.join(PAPER_DEFAULTS)}")
        name, value = (s.strip() for s in item.split("=", 1))
        if name not in PAPER_DEFAULTS:
            raise InputError(f"--set {name} ({name}) = {value}: unknown parameter; known: "
                             f"{', '.join(PAPER_DEFAULTS)}")
        overrides[name] = _number(f"--set {name}", name, value)
    for name, value in overrides.items():
        try:
            ContactModel(**{name: value})
        except ParameterError as e:
            if e.symbol == name:  # the parameter's own range; combinations are checked below
                raise InputError(f"--set {name} ({e.symbol}) = {_show(e.value)}: {e.allowed}") from None
    # a combination out of range (the damping ratio) names every --set the user gave
    given = " ".join(f"--set {k}={_show(v)}" for k, v in overrides.items()) or "the paper's parameters"
    return _checked(given, ContactModel.from_overrides, overrides)


def _excitation(model: ContactModel, pa: str | None, pa_newton: str | None, fe: str) -> Excitation:
    fe_v = _number("--fe", "f_e", fe)
    if pa is not None and pa_newton is not None:
        raise InputError("--pa and --pa-newton: give one of them, not both")
    if pa_newton is not None:
        p = _number("--pa-newton", "P_a", pa_newton)
        if p < 0:
            raise InputError(f"--pa-newton (P_a) = {_show(p)}: must be >= 0 N")
        pa_q = p / model.Q
    else:
        pa_q = _number("--pa", "P_a/Q", pa if pa is not None else "0.65")
        if pa_q < 0:
            raise InputError(f"--pa (P_a/Q) = {_show(pa_q)}: must be >= 0 (multiple of Q = M g)")
    if fe_v <= 0:
        raise InputError(f"--fe (f_e) = {_show(fe_v)}: must be > 0 Hz")
    return model.excitation(pa_q, fe_v)


def _frequency_range(fmin: str, fmax: str) -> tuple[float, float]:
    """--fmin/--fmax [Hz], checked: 0 < f_min < f_max."""
    lo = _number("--fmin", "f_min", fmin)
    hi = _number("--fmax", "f_max", fmax)
    if lo <= 0:
        raise InputError(f"--fmin (f_min) = {lo:g}: must be > 0 Hz")
    if hi <= lo:
        raise InputError(f"--fmax (f_max) = {hi:g}: must be > --fmin = {lo:g} Hz")
    return lo, hi


def _pa_level(text: str, option: str = "--pa") -> float:
    """A P_a level [Q] that must be > 0."""
    v = _number(option, "P_a/Q", text)
    if v <= 0:
        raise InputError(f"{option} (P_a/Q) = {v:g}: must be > 0 (multiple of Q = M g)")
    return v


def _int(option: str, text: str, lower: int, upper: int | None = None) -> int:
    v = _number(option, option.lstrip("-"), text)
    if v != int(v) or v < lower or (upper is not None and v > upper):
        rng = f">= {lower}" if upper is None else f"in {lower}..{upper}"
        raise InputError(f"{option} ({option.lstrip('-')}) = {_show(text)}: must be an integer {rng}")
    return int(v)


def _operating_point_options(f):
    f = click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
                     help="Override a model parameter by its paper symbol: "
                          + ", ".join(f"{k} [{PARAMETER_UNITS[k]}]" for k in PAPER_DEFAULTS))(f)
    f = click.option("--fe", default="360", show_default=True, metavar="HZ",
                     help="Excitation frequency f_e [Hz], > 0.")(f)
    f = click.option("--pa-newton", default=None, metavar="N",
                     help="Excitation amplitude P_a in newtons (instead of --pa).")(f)
    f = click.option("--pa", default=None, metavar="Q",
                     help="Excitation amplitude P_a as a multiple of Q = M g (default 0.65).")(f)
    return f


def _search_options(f):
    f = click.option("--no-seeds", is_flag=True, help="Skip the ballistic seeds (box starts only).")(f)
    f = click.option("--max-periods", default="400", show_default=True,
                     help="Transient limit per start [excitation periods].")(f)
    f = click.option("--kmax", default="8", show_default=True, help="Largest period searched (1..64).")(f)
    f = click.option("--seed", default="0", show_default=True, help="Random seed of the start box.")(f)
    f = click.option("--starts", default="512", show_default=True, help="Random starts in the box.")(f)
    return f


def _find(model, exc, starts, seed, kmax, max_periods, no_seeds):
    from .attractors import find_attractors

    kw = dict(n_starts=_int("--starts", starts, 1), seed=_int("--seed", seed, 0),
              kmax=_int("--kmax", kmax, 1, 64), seeds=not no_seeds)
    kw["max_periods"] = _int("--max-periods", max_periods, 4 * kw["kmax"])
    return find_attractors(model, exc, **kw)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="contactvib")
def cli():
    """contactvib: primary and superharmonic contact resonances (Kostek 2013).

    Units: y in µm (positive = contact deflection, negative = gap), ẏ in mm/s, t in ms,
    f in Hz, P_a in multiples of Q = M g. Defaults are the paper's parameters.
    """


@cli.command()
@_operating_point_options
@_search_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the documented contract).")
def attractors(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, as_json):
    """All coexisting attractors at one operating point (P_a, f_e)."""
    model = _model(settings)
    exc = _excitation(model, pa, pa_newton, fe)
    result = _find(model, exc, starts, seed, kmax, max_periods, no_seeds)
    if as_json:
        click.echo(result.to_json())
        return
    click.echo(f"P_a = {exc.pa_over_q:g} Q ({exc.P_a:.4g} N), f_e = {exc.f_e:g} Hz, "
               f"f_n0 = {model.f_n0:.1f} Hz, y0 = {model.y0 * 1e6:.4f} um; "
               f"{result.n_box} box starts + {result.n_seeds} seeds")
    head = (f"{'#':>2} {'period':>6} {'minima':>6} {'A_pp [um]':>11} {'y_min [um]':>11} "
            f"{'y_max [um]':>10} {'gap [frac]':>10} {'|mu|max':>8} {'basin':>7}")
    click.echo(head)
    for i, a in enumerate(result):
        per = "-" if a.period is None else str(a.period)
        mins = "-" if a.minima_per_period is None else str(a.minima_per_period)
        mu = "-" if a.floquet_abs_max is None else f"{a.floquet_abs_max:.4f}"
        click.echo(f"{i:>2} {per:>6} {mins:>6} {a.app_um:>11.5g} {a.ymin_um:>11.5g} {a.ymax_um:>10.5g} "
                   f"{a.contact_loss_fraction:>10.3f} {mu:>8} {a.basin_fraction:>7.2%}")


@cli.command()
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
    out = Path(out)
    if from_state is not None:
        y = _number("--from-state", "y", from_state[0])
        yd = _number("--from-state", "ydot", from_state[1])
        n = _int("--periods", periods, 1)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .plotting import attractor_figure, plot_phase_portrait, plot_time_history
    from .simulate import attractor_history, simulate as run

    out.mkdir(parents=True, exist_ok=True)
    tag = f"pa{exc.pa_over_q:g}_fe{exc.f_e:g}"
    if from_state is not None:
        h = run(model, exc, y, yd, n_periods=n)
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.8), gridspec_kw={"width_ratios": [1.6, 1]})
        plot_time_history(h, a1)
        plot_phase_portrait(h, a2)
        fig.suptitle(f"$P_a$ = {exc.pa_over_q:g} Q, $f_e$ = {exc.f_e:g} Hz, from y = {y:g} µm, "
                     f"ẏ = {yd:g} mm/s", fontsize=10)
        fig.tight_layout()
        path = out / f"trajectory_{tag}.png"
        fig.savefig(path, dpi=130)
        plt.close(fig)
        click.echo(str(path))
        return
    result = _find(model, exc, starts, seed, kmax, max_periods, no_seeds)
    (out / "attractors.json").write_text(result.to_json(indent=1))
    for i, a in enumerate(result):
        hist = attractor_history(model, exc, a)
        fig = attractor_figure(hist, a)
        path = out / f"attractor{i}_{tag}.png"
        fig.savefig(path, dpi=130)
        plt.close(fig)
        click.echo(f"{path}  period={a.period} minima={a.minima_per_period} A_pp={a.app_um:.4g} um")


def main(argv=None) -> int:
    """Entry point of the ``contactvib`` console script."""
    try:
        rv = cli.main(args=argv, prog_name="contactvib", standalone_mode=False)
        return rv if isinstance(rv, int) else 0
    except InputError as e:
        click.echo(f"contactvib: error: {e}", err=True)
    except click.exceptions.Abort:
        click.echo("contactvib: interrupted", err=True)
        return 130
    except click.ClickException as e:
        click.echo(f"contactvib: error: {e.format_message()}", err=True)
    return 2


from . import cli_perturbation  # noqa: E402,F401
from . import cli_continuation  # noqa: E402,F401
from . import cli_resonance  # noqa: E402,F401

if __name__ == "__main__":  # python -m contactvib.cli: use the package's module (commands registered there)
    from contactvib.cli import main as _main

    sys.exit(_main())
