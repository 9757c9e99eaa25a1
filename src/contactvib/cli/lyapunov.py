"""CLI command ``lyapunov``: the Lyapunov spectrum [1/s] of every attractor at one operating point,
or of one trajectory (``--y0-um``/``--v0-mm-s``; with ``--system``, ``--from-state``)."""

from __future__ import annotations

import contextvars

import click

from contactvib.cli.common import (
    InputError,
    ctrl_c,
    echo_json,
    mapped_options,
    operating_point_options,
    parse_excitation,
    parse_model,
    parse_number,
    scoped_options,
    search_options,
)
from contactvib.cli.steady import search_attractors
from contactvib.cli.system import system_given, system_lyapunov, system_option

#: What a trajectory's spectrum says by itself (no section test): λ1 > 3 stderr, |λ1| ≤ 3 stderr, below.
TRAJECTORY_TYPES = {"chaotic": "chaotic", "quasi-periodic": "neutral", "converging": "converging"}
#: The spectrum's options by the library's symbols.
_NAMES = {"periods": "--periods", "batches": "--batches", "transient_periods": "--transient"}


def spectrum_settings(periods, batches, transient) -> dict:
    """--periods, --batches, --transient checked by the library (too few periods for an error
    bar is one line naming --periods)."""
    from contactvib.steady.lyapunov import check_periods

    kw = {s: parse_number(o, s, t) for (s, o), t in zip(_NAMES.items(), (periods, batches, transient))
          if t is not None}
    p, b = mapped_options(_NAMES, check_periods, kw["periods"], kw["batches"])
    out = {"periods": p, "batches": b}
    if "transient_periods" in kw:
        from contactvib.model import check_int

        out["transient_periods"] = mapped_options(_NAMES, check_int, "transient_periods",
                                                  kw["transient_periods"], 0, 100_000_000)
    return out


def spectrum_row(i, kind: str, period, spec) -> str:
    """One row of the table: the exponents [1/s] with their standard errors, their sum against
    the damping average, the Kaplan–Yorke dimension."""
    lam = "  ".join(f"{v:+.5g} ± {s:.2g}" for v, s in zip(spec.exponents_per_s, spec.stderr_per_s))
    ky = "-" if spec.kaplan_yorke_dimension is None else f"{spec.kaplan_yorke_dimension:.4f}"
    damp = "-" if spec.damping_average_per_s != spec.damping_average_per_s else f"{spec.damping_average_per_s:+.6g}"
    per = "-" if period is None else str(period)
    return f"{i:>2} {kind:>14} {per:>6} {spec.method:>8}  {lam}  sum {spec.sum_per_s:+.6g}  damping {damp}  D_KY {ky}"


#: The trajectory's start options of the command being run (kept out of its signature).
_START: contextvars.ContextVar = contextvars.ContextVar("contactvib_lyapunov_start", default=None)


def _start_options(f):
    """--y0-um, --v0-mm-s, --from-state: one trajectory instead of the attractors; --transient."""
    f = scoped_options(_START, ("y0_um", "v0_mm_s", "from_state", "transient"), f)
    f = click.option("--transient", default=None, metavar="N",
                     help="Periods integrated before the average (default: 0 from an attractor, 2000 from a "
                          "state).")(f)
    f = click.option("--from-state", nargs=2, default=None, metavar="Q1,.. QDOT1,..",
                     help="With --system: one trajectory from this state (um or urad, mm/s or mrad/s).")(f)
    f = click.option("--v0-mm-s", "v0_mm_s", default=None, help="Start of one trajectory: ẏ [mm/s] (with --y0-um).")(f)
    return click.option("--y0-um", "y0_um", default=None, help="Start of one trajectory: y [um] (with --v0-mm-s).")(f)


@click.command()
@system_option
@operating_point_options
@search_options
@click.option("--periods", default="20000", show_default=True,
              help="Excitation periods of Benettin's average (at least 10 per batch).")
@click.option("--batches", default="20", show_default=True,
              help="Batches of the average for the standard errors (>= 10).")
@_start_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the documented contract).")
def lyapunov(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, periods, batches, as_json):
    """Lyapunov spectrum [1/s] of every attractor at (P_a, f_e), or of one trajectory.

    Benettin's QR method on the period map (its monodromy with the saltation at the contact
    switches) for a non-periodic motion, ln|mu|/T of the Floquet multipliers for a periodic
    orbit; each exponent with the standard error of its batch means. The sum of the exponents
    equals minus the time average of the contact's damping rate S h_n y^l / M (printed as
    "damping"). Chaotic: lambda_1 > 3 standard errors."""
    y0_um, v0_mm_s, from_state, transient = (_START.get()[k] for k in ("y0_um", "v0_mm_s", "from_state", "transient"))
    kw = spectrum_settings(periods, batches, transient)
    if system_given():
        if y0_um is not None or v0_mm_s is not None:
            raise InputError("--system and --y0-um/--v0-mm-s: a system's trajectory starts at --from-state")
        system_lyapunov(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, from_state, kw, as_json)
        return
    if from_state is not None:
        raise InputError("--from-state: belongs to --system; the slider's trajectory starts at --y0-um/--v0-mm-s")
    if (y0_um is None) != (v0_mm_s is None):
        raise InputError("--y0-um and --v0-mm-s: give both (the start y [um], ẏ [mm/s]) or neither")
    model = parse_model(settings)
    exc = parse_excitation(model, pa, pa_newton, fe)
    from contactvib.steady.lyapunov import lyapunov_spectrum

    rows = []
    if y0_um is not None:
        from contactvib.steady.simulate import check_start

        y, yd = parse_number("--y0-um", "y", y0_um), parse_number("--v0-mm-s", "ydot", v0_mm_s)
        state = mapped_options({"y": "--y0-um", "ydot": "--v0-mm-s"}, check_start, model, y, yd, 1)[:2]
        with ctrl_c():
            spec = mapped_options(_NAMES, lyapunov_spectrum, exc, state, **kw)
        rows.append((None, TRAJECTORY_TYPES[spec.attractor_type], None, spec))
    else:
        result = search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds)
        with ctrl_c():
            for i, a in enumerate(result):
                spec = mapped_options(_NAMES, lyapunov_spectrum, exc, a, **kw)
                rows.append((i, a.attractor_type, a.period, spec))
    if as_json:
        echo_json({"pa_over_q": exc.pa_over_q, "fe_hz": exc.f_e, "units": {"lyapunov": "1/s"},
                   "spectra": [{"attractor": i, "attractor_type": t, "period": k, **s.to_dict()}
                               for i, t, k, s in rows]})
        return
    click.echo(f"P_a = {exc.pa_over_q:g} Q, f_e = {exc.f_e:g} Hz: exponents [1/s] ± standard error")
    for i, t, k, s in rows:
        click.echo(spectrum_row("-" if i is None else i, t, k, s))
