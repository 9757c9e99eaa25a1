"""``--system rocking|FILE.toml`` of ``contactvib simulate`` and ``contactvib attractors``: a
structure of several coordinates with contact elements instead of the paper's slider.

``rocking`` is the two-contact slide unit of the model's law (:func:`contactvib.model.rocking_system`,
``--set a=, J=, e=`` besides every law option); a TOML file is read by
:func:`contactvib.model.load_system`, whose errors name the key (one line, exit 2).
"""

from __future__ import annotations

import contextvars
import math

import click

from contactvib.cli.common import (
    InputError,
    checked_output_folder,
    ctrl_c,
    echo_json,
    mapped_options,
    parse_int,
    parse_model,
    parse_number,
    scoped_options,
    show_value,
)
from contactvib.cli.progress import start_progress_bar
from contactvib.model import ParameterError

__all__ = ["system_option", "system_given", "system_attractors", "system_simulate", "load_system_option",
           "system_operating_point", "option_given", "modes_text", "system_label", "system_lyapunov",
           "load_given_system", "parse_system_state"]

#: The --system option of the command being run.
_SYSTEM: contextvars.ContextVar = contextvars.ContextVar("contactvib_system", default=None)
#: Options of the paper's slider that a system file does not take (click names), and those no
#: system takes.
_MODEL_ONLY = {"law": "--law", "law_file": "--law-file", "damping": "--damping", "preload": "--preload",
               "model_file": "--model"}
_NOT_SYSTEM = {"base_um": "--base-um", "base_g": "--base-g", "harmonic": "--harmonic", "random_psd": "--random-psd",
               "band": "--band", "duration": "--duration"}
_SEARCH = {"n_starts": "--starts", "seed": "--seed", "kmax": "--kmax", "max_periods": "--max-periods"}


def system_option(f):
    """--system rocking|FILE.toml (kept out of the command's signature)."""
    f = scoped_options(_SYSTEM, ("system",), f)
    return click.option("--system", default=None, metavar="rocking|FILE.toml",
                        help="A structure of several coordinates with contact elements instead of the paper's slider: "
                             "rocking (the slide unit on two patches of area S/2 at +-a; --set a=[m], J=[kg m^2], "
                             "e=[m], the force's offset) or a TOML system file (docs: formats); with a file the "
                             "force level is --pa-newton [N]. With --system the search's defaults are 64 starts "
                             "and, for --max-periods auto, 1.5 times the slowest linear decay to 1e-7 (at least "
                             "400 periods), and --from-state takes Q1,Q2,.. QDOT1,QDOT2,.. in um or urad, "
                             "mm/s or mrad/s.")(f)


def system_given() -> bool:
    """Whether --system was given to the command being run."""
    return (_SYSTEM.get() or {}).get("system") is not None


def _given(name: str) -> bool:
    ctx = click.get_current_context()
    return ctx.get_parameter_source(name) not in (None, click.core.ParameterSource.DEFAULT) \
        and ctx.params.get(name) not in (None, (), False)


def _load(settings: tuple):
    """(System, the slider's ContactModel or None, the system's label) of --system."""
    from contactvib.model.rocking import ROCKING_PARAMETERS, rocking_system

    name = _SYSTEM.get()["system"]
    for param, option in _NOT_SYSTEM.items():
        if _given(param):
            raise InputError(f"--system and {option}: {option} belongs to the paper's slider, not to a system")
    if name == "rocking":
        own, rest = {}, []
        for item in settings:
            key = item.split("=", 1)[0].strip()
            if key in ROCKING_PARAMETERS and "=" in item:
                own[key] = parse_number(f"--set {key}", key, item.split("=", 1)[1])
            else:
                rest.append(item)
        model = parse_model(tuple(rest))
        system = mapped_options({k: f"--set {k}" for k in ROCKING_PARAMETERS}, rocking_system, model, **own)
        return system, model, "rocking"
    for param, option in _MODEL_ONLY.items():
        if _given(param):
            raise InputError(f"--system {name} and {option}: a system file carries its own laws; {option} belongs "
                             f"to the paper's slider or --system rocking")
    if settings:
        raise InputError(f"--system {name} and --set {settings[0]}: a system file carries its own parameters")
    from contactvib.model.system_file import load_system

    try:
        return load_system(name), None, name
    except ParameterError as e:
        raise InputError(f"--system {name}: {e.symbol}" + ("" if e.value is None else f" = {show_value(e.value)}")
                         + f": {e.allowed}") from None


def load_given_system(settings: tuple):
    """(System, the slider's ContactModel or None, the system's label) of --system and --set."""
    return _load(settings)


def _excitation(model, label, pa, pa_newton, fe, fe_option="--fe") -> tuple[float, float, str]:
    """(P_a [N], f_e [Hz], a text of the level) of --pa or --pa-newton and --fe; ``model`` the
    slider of --system rocking (Q = M g), None for a file (no Q)."""
    from contactvib.model.system import check_excitation

    Q = None if model is None else model.Q
    if pa is not None and pa_newton is not None:
        raise InputError("--pa and --pa-newton: give one of them, not both")
    if Q is None and pa is not None:
        raise InputError(f"--system {label} and --pa: a system file defines no Q; give the force level "
                         f"--pa-newton [N]")
    if Q is None and pa_newton is None:
        raise InputError(f"--system {label}: give the force level --pa-newton [N]")
    f_e = parse_number(fe_option, "f_e", fe)
    if pa_newton is not None:
        p = parse_number("--pa-newton", "P_a", pa_newton)
        text = f"P_a = {p:.4g} N"
    else:
        ratio = parse_number("--pa", "P_a/Q", "0.65" if pa is None else pa)
        p = ratio * Q
        text = f"P_a = {ratio:g} Q ({p:.4g} N)"
    p, f_e = mapped_options({"P_a": "--pa-newton" if pa_newton is not None else "--pa", "f_e": fe_option},
                            check_excitation, p, f_e)
    return p, f_e, text


def _modes_text(system, model) -> str:
    f = system.linear_modes()
    text = "linear modes: " + ", ".join(f"{x:.4g}" for x in f) + " Hz"
    if model is not None:
        K = system.tangent_stiffness(system.static_state())
        heave, pitch = (math.sqrt(K[j, j] / system.M[j, j]) / (2.0 * math.pi) for j in (0, 1))
        text += f" (heave {heave:.4g} Hz, pitch {pitch:.4g} Hz uncoupled; f_n0 = {model.f_n0:.4g} Hz)"
    return text


def _search(system, p, f_e, starts, seed, kmax, max_periods):
    from contactvib.steady.system_attractors import STARTS_DEFAULT, find_system_attractors

    kw = {"n_starts": STARTS_DEFAULT if not _given("starts") else parse_int("--starts", starts, 1, symbol="n_starts"),
          "seed": parse_int("--seed", seed, 0), "kmax": parse_int("--kmax", kmax, 1),
          "max_periods": None if max_periods.strip().lower() == "auto"
          else parse_int("--max-periods", max_periods, 1, symbol="max_periods"),
          "seeds": not _given("no_seeds")}
    with ctrl_c(), start_progress_bar("attractor search") as progress:
        return mapped_options(_SEARCH, find_system_attractors, system, p, f_e, progress=progress, **kw)


def _check_bounded(system) -> None:
    """Refuse, before any output, a system whose motion grows without bound."""
    from contactvib.steady.system_attractors import check_bounded

    mapped_options({"system.damping": "--system"}, check_bounded, system)


def _no_periodic(result, fatal: bool = False) -> None:
    """One line on stderr when no start settled on an attractor; with ``fatal`` (``attractors``
    and ``simulate``, as the slider's commands) an error, exit status 1."""
    if not len(result):
        why = ", ".join(f"{v} {k}" for k, v in result.unsettled_reasons.items())
        click.echo(f"contactvib: {'error: ' if fatal else ''}no attractor: all {result.n_starts} starts unsettled "
                   f"({why or 'none judged'}; {result.n_failed} failed) after {result.settings['max_periods']} "
                   f"periods without a period <= {result.settings['kmax']} - a long transient or a motion "
                   f"the search cannot label; raise --max-periods or --kmax", err=True)
        if fatal:
            click.get_current_context().exit(1)


def system_attractors(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, as_json) -> None:
    """``contactvib attractors --system ...``: the table, or the JSON contract with --json."""
    system, model, label = _load(settings)
    p, f_e, level = _excitation(model, label, pa, pa_newton, fe)
    _check_bounded(system)
    if not as_json:
        units = ", ".join(f"{c} [{u}]" for c, u in zip(system.coordinates, system.units))
        click.echo(f"system {label}: {system.n} coordinates ({units}), contacts "
                   f"{', '.join(c.name for c in system.contacts) or 'none'}; {level}, f_e = {f_e:g} Hz")
        click.echo(_modes_text(system, model))
    result = _search(system, p, f_e, starts, seed, kmax, max_periods)
    if as_json:
        d = result.to_dict()
        echo_json({"system": label, "coordinates": list(system.coordinates), **d})
        _no_periodic(result, fatal=True)
        return
    _table(result)
    _no_periodic(result, fatal=True)


def _table(result) -> None:
    if not len(result):
        return
    a0 = result.attractors[0].to_dict()
    head = f"{'#':>2} {'period':>6} {'minima':>6} {'|mu|max':>8} {'stable':>6} {'basin':>7}"
    head += "".join(f" {d['name'] + ' A_pp [' + d['unit'] + ']':>18}" for d in a0["dofs"])
    head += "".join(f" {c['name'] + ' open':>12} {c['name'] + ' <F> [N]':>14}" for c in a0["contacts"])
    head += f" {'type':>14} {'lambda1 [1/s]':>22}"
    click.echo(head)
    for i, a in enumerate(result):
        d = a.to_dict()
        if a.orbit is not None:
            row = (f"{i:>2} {d['period']:>6} {d['minima_per_period']:>6} {d['floquet_abs_max']:>8.4f} "
                   f"{'yes' if d['stable'] else 'no':>6} {d['basin_fraction']:>7.2%}")
        else:
            per = {"chaotic": "chaos", "quasi-periodic": "q-per"}[a.attractor_type]
            row = f"{i:>2} {per:>6} {'-':>6} {'-':>8} {'-':>6} {d['basin_fraction']:>7.2%}"
        row += "".join(f" {x['app']:>18.5g}" for x in d["dofs"])
        row += "".join(f" {c['contact_loss_fraction']:>12.3f} {c['mean_force_n']:>14.5g}" for c in d["contacts"])
        lam, se = a.lyapunov_per_s[0], a.lyapunov_stderr_per_s[0]
        row += f" {a.attractor_type:>14} {f'{lam:.4g} +- {se:.2g}' if se > 0 else f'{lam:.4g}':>22}"
        click.echo(row)
    if result.n_unsettled:
        why = ", ".join(f"{v} {k}" for k, v in result.unsettled_reasons.items())
        click.echo(f"   unsettled within {result.settings['max_periods']} periods: {result.n_unsettled} of "
                   f"{result.n_starts} starts ({why})")


def _from_state(system, from_state, option: str = "--from-state") -> tuple:
    """(q0, qdot0) [SI] of ``option`` Q1,Q2,.. QDOT1,QDOT2,.. in display units."""
    from contactvib.steady.system_orbits import DISPLAY_UNITS

    out = []
    for text, col, what in zip(from_state, (1, 3), ("positions", "rates")):
        parts = [s for s in text.split(",") if s.strip()]
        if len(parts) != system.n:
            raise InputError(f"{option} {text}: expected {system.n} {what} separated by commas "
                             f"({', '.join(system.coordinates)})")
        out.append([parse_number(option, f"{c}", s) / DISPLAY_UNITS[u][col]
                    for s, c, u in zip(parts, system.coordinates, system.units)])
    return tuple(out)


def _draw(h, title: str, path_stem) -> list:
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.system import contact_forces_figure, system_history_figure

    return [save_figure(system_history_figure(h, title), f"{path_stem}.png"),
            save_figure(contact_forces_figure(h, title), f"{path_stem}_forces.png")]


def system_simulate(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, out, from_state, periods) -> None:
    """``contactvib simulate --system ...``: one trajectory (--from-state) or every attractor's
    orbit; per run a figure of the coordinates (time histories, phase portraits) and one of the
    contact forces."""
    from contactvib.steady.system_attractors import NONPERIODIC_MEASURE_PERIODS
    from contactvib.steady.system_orbits import simulate_system

    system, model, label = _load(settings)
    p, f_e, level = _excitation(model, label, pa, pa_newton, fe)
    if from_state is None:
        _check_bounded(system)
    tag = f"{label.rsplit('/', 1)[-1].removesuffix('.toml')}_pa{p:.4g}N_fe{f_e:g}"
    if from_state is not None:
        q0, v0 = _from_state(system, from_state)
        n = parse_int("--periods", periods, 1, symbol="n_periods")
        out = checked_output_folder(out)
        with ctrl_c():
            h = mapped_options({"n_periods": "--periods", "q0, qdot0": "--from-state"}, simulate_system,
                               system, p, f_e, q0, v0, n_periods=n)
        for path in _draw(h, f"{label}: {level}, f_e = {f_e:g} Hz, from {from_state[0]} / {from_state[1]}",
                          out / f"trajectory_{tag}"):
            click.echo(str(path))
        return
    result = _search(system, p, f_e, starts, seed, kmax, max_periods)
    out = checked_output_folder(out)
    (out / "attractors.json").write_text(result.to_json(indent=1))
    for i, a in enumerate(result):
        n = a.period * max(1, math.ceil(4 / a.period)) if a.period else NONPERIODIC_MEASURE_PERIODS
        h = simulate_system(system, p, f_e, a.state[:system.n], a.state[system.n:], n_periods=n)
        what = f"period {a.period}" if a.period else a.attractor_type
        paths = _draw(h, f"{label}: {level}, f_e = {f_e:g} Hz, attractor {i} ({what})", out / f"attractor{i}_{tag}")
        click.echo(f"{paths[0]}  {paths[1]}  period={a.period} minima={a.minima_per_period} "
                   f"|mu|max={a.floquet_abs_max:.4f}" if a.period else
                   f"{paths[0]}  {paths[1]}  {a.attractor_type} lambda1={a.lyapunov_per_s[0]:.4g} 1/s")
    click.echo(str(out / "attractors.json"))
    _no_periodic(result, fatal=True)


#: The public names of the helpers that the other ``--system`` commands share
#: (:mod:`contactvib.cli.system_branches`): the option's system, its operating point, whether an
#: option was given, the linear modes' line.
load_system_option = _load
parse_system_state = _from_state
system_operating_point = _excitation
option_given = _given
modes_text = _modes_text


def system_label() -> str:
    """The --system value of the command being run ("rocking" or the file's path)."""
    return _SYSTEM.get()["system"]


def system_lyapunov(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, from_state, kw: dict,
                    as_json) -> None:
    """``contactvib lyapunov --system ...``: the 2n exponents [1/s] of every attractor (Floquet for a
    periodic one, Benettin's from a point of the others) or, with --from-state, of one trajectory
    (Benettin; ``kw``: periods, batches, transient_periods, checked)."""
    from contactvib.steady.lyapunov import system_lyapunov_spectrum

    system, model, label = _load(settings)
    p, f_e, level = _excitation(model, label, pa, pa_newton, fe)
    if from_state is None:
        _check_bounded(system)
    names = {"periods": "--periods", "batches": "--batches", "transient_periods": "--transient"}
    if from_state is not None:
        q0, v0 = _from_state(system, from_state)
        with ctrl_c():
            spec = mapped_options(names, system_lyapunov_spectrum, system, p, f_e, [*q0, *v0], **kw)
        rows = [("-", "trajectory", None, spec)]
    else:
        result = _search(system, p, f_e, starts, seed, kmax, max_periods)
        rows = [(i, a.attractor_type, a.period or None, system_lyapunov_spectrum(system, p, f_e, a, **kw))
                for i, a in enumerate(result)]
    if as_json:
        echo_json({"system": label, "pa_newton": p, "fe_hz": f_e, "units": {"lyapunov": "1/s"},
                   "spectra": [{"attractor": None if i == "-" else i, "attractor_type": t, "period": k,
                                **s.to_dict()} for i, t, k, s in rows]})
        return
    click.echo(f"system {label}: {level}, f_e = {f_e:g} Hz: exponents [1/s] ± standard error")
    for i, t, k, s in rows:
        lam = "  ".join(f"{v:+.5g} ± {e:.2g}" for v, e in zip(s.exponents_per_s, s.stderr_per_s))
        click.echo(f"{i:>2} {t:>10} {'-' if k is None else k:>6} {s.method:>8}  {lam}  sum {s.sum_per_s:+.6g}")

