"""``--system rocking|FILE.toml`` of ``contactvib simulate`` and ``contactvib attractors``: a
structure of several coordinates with contact elements instead of the paper's slider.

``rocking`` is the two-contact slide unit of the model's law (:func:`contactvib.model.rocking_system`,
``--set a=, J=, e=`` besides every law option); a TOML file is read by
:func:`contactvib.model.load_system`, whose errors name the key (one line, exit 2).
"""

from __future__ import annotations

import contextvars
import json
import math
import sys

import click
import numpy as np

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
from contactvib.model import ParameterError

__all__ = ["system_option", "system_given", "system_attractors", "system_simulate", "system_continue",
           "system_hbm"]

#: The --system option of the command being run.
_SYSTEM: contextvars.ContextVar = contextvars.ContextVar("contactvib_system", default=None)
#: Options of the paper's slider that a system file does not take (click names), and those no
#: system takes.
_MODEL_ONLY = {"law": "--law", "law_file": "--law-file", "damping": "--damping", "preload": "--preload",
               "model_file": "--model"}
_NOT_SYSTEM = {"base_um": "--base-um", "base_g": "--base-g", "harmonic": "--harmonic", "random_psd": "--random-psd",
               "band": "--band", "duration": "--duration", "no_seeds": "--no-seeds"}
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
          else parse_int("--max-periods", max_periods, 1, symbol="max_periods")}
    bar = []

    def progress(done, total):  # a bar on a terminal's stderr, gone when the search ends
        if not done and sys.stderr.isatty():
            from tqdm import tqdm

            bar.append(tqdm(total=total, unit="start", file=sys.stderr, leave=False, desc="attractor search"))
        elif bar:
            bar[0].update(done - bar[0].n)

    try:
        with ctrl_c():
            return mapped_options(_SEARCH, find_system_attractors, system, p, f_e, progress=progress, **kw)
    finally:
        while bar:
            bar.pop().close()


def _no_periodic(result, fatal: bool = False) -> None:
    """One line on stderr when no start settled on a periodic orbit; with ``fatal`` (``attractors``
    and ``simulate``, as the slider's commands) an error, exit status 1."""
    if not len(result):
        click.echo(f"contactvib: {'error: ' if fatal else ''}no periodic attractor of period <= "
                   f"{result.settings['kmax']}: all {result.n_starts} starts unsettled within "
                   f"{result.settings['max_periods']} periods ({result.n_failed} failed) - a non-periodic motion "
                   f"or a long transient; raise --max-periods or --kmax", err=True)
        if fatal:
            click.get_current_context().exit(1)


def system_attractors(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, as_json) -> None:
    """``contactvib attractors --system ...``: the table, or the JSON contract with --json."""
    system, model, label = _load(settings)
    p, f_e, level = _excitation(model, label, pa, pa_newton, fe)
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
    click.echo(head)
    for i, a in enumerate(result):
        d = a.to_dict()
        row = (f"{i:>2} {d['period']:>6} {d['minima_per_period']:>6} {d['floquet_abs_max']:>8.4f} "
               f"{'yes' if d['stable'] else 'no':>6} {d['basin_fraction']:>7.2%}")
        row += "".join(f" {x['app']:>18.5g}" for x in d["dofs"])
        row += "".join(f" {c['contact_loss_fraction']:>12.3f} {c['mean_force_n']:>14.5g}" for c in d["contacts"])
        click.echo(row)
    if result.n_unsettled:
        click.echo(f"   unsettled within {result.settings['max_periods']} periods: {result.n_unsettled} of "
                   f"{result.n_starts} starts")


def _from_state(system, from_state) -> tuple:
    """(q0, qdot0) [SI] of --from-state Q1,Q2,.. QDOT1,QDOT2,.. in display units."""
    from contactvib.steady.system_orbits import DISPLAY_UNITS

    out = []
    for text, col, what in zip(from_state, (1, 3), ("positions", "rates")):
        parts = [s for s in text.split(",") if s.strip()]
        if len(parts) != system.n:
            raise InputError(f"--from-state {text}: expected {system.n} {what} separated by commas "
                             f"({', '.join(system.coordinates)})")
        out.append([parse_number("--from-state", f"{c}", s) / DISPLAY_UNITS[u][col]
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
    from contactvib.steady.system_orbits import simulate_system

    system, model, label = _load(settings)
    p, f_e, level = _excitation(model, label, pa, pa_newton, fe)
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
        n = a.period * max(1, math.ceil(4 / a.period))
        h = simulate_system(system, p, f_e, a.orbit.z[:system.n], a.orbit.z[system.n:], n_periods=n)
        paths = _draw(h, f"{label}: {level}, f_e = {f_e:g} Hz, attractor {i} (period {a.period})",
                      out / f"attractor{i}_{tag}")
        click.echo(f"{paths[0]}  {paths[1]}  period={a.period} minima={a.minima_per_period} "
                   f"|mu|max={a.floquet_abs_max:.4f}")
    click.echo(str(out / "attractors.json"))
    _no_periodic(result, fatal=True)


#: Options of ``continue`` that no system continuation takes (click names).
_NOT_SYSTEM_CONTINUE = {"dataset": "--dataset"}


def _level_range(option_lo, option_hi, lo_text, hi_text, Q) -> tuple[float, float]:
    """--pa-min/--pa-max of a continuation in P_a: [N] (file systems), or [Q] with Q given."""
    lo = parse_number(option_lo, "pa_min", lo_text)
    hi = parse_number(option_hi, "pa_max", hi_text)
    unit = "N" if Q is None else "Q"
    if not (0.0 <= lo < hi):
        raise InputError(f"{option_lo}/{option_hi} = {lo:g}/{hi:g}: must be 0 <= {option_lo} < {option_hi} [{unit}]")
    return (lo, hi) if Q is None else (lo * Q, hi * Q)


def _coordinate(system, text) -> int:
    if text is None:
        return 0
    if text in system.coordinates:
        return system.coordinates.index(text)
    raise InputError(f"--coordinate {text}: must be one of {', '.join(system.coordinates)}")


def system_continue(pa, pa_newton, from_fe, attractor, parameter, pa_min, pa_max, coordinate, out, as_json,
                    cont) -> None:
    """``contactvib continue --system ...``: the branches through the orbits at --from-fe,
    continued in f_e (or P_a), with folds, period doublings and Neimark–Sacker points."""
    from contactvib.continuation.system_shooting import SystemContinuationSettings

    for param, option in _NOT_SYSTEM_CONTINUE.items():
        if _given(param):
            raise InputError(f"--system and {option}: {option} draws over the slider's resonance dataset")
    if cont.get("level_kind", "force") != "force":
        raise InputError(f"--system and --excitation {cont['level_kind']}: a system is driven by the force "
                         "P_a cos(2 pi f_e t) [N] (--pa-newton) or, for rocking, --pa [Q]")
    system, model, label = _load(cont["settings"])
    Q = None if model is None else model.Q
    modes = system.linear_modes()
    f_lo = 0.5 * float(modes[modes > 0].min()) if np.any(modes > 0) else 1.0
    f_hi = 1.5 * float(modes.max()) if np.any(modes > 0) else 100.0
    fmin = parse_number("--fmin", "f_min", cont["fmin"]) if _given("fmin") else f_lo
    fmax = parse_number("--fmax", "f_max", cont["fmax"]) if _given("fmax") else f_hi
    if not (0.0 < fmin < fmax):
        raise InputError(f"--fmin/--fmax = {fmin:g}/{fmax:g} Hz: must be 0 < --fmin < --fmax")
    fe_text = from_fe if _given("from_fe") else repr(fmin if parameter == "fe" else 0.5 * (fmin + fmax))
    p, f_e, level = _excitation(model, label, pa if _given("pa") else None, pa_newton, fe_text, "--from-fe")
    by_pa = parameter == "pa"
    if not by_pa and not (fmin <= f_e <= fmax):
        raise InputError(f"--from-fe = {f_e:g} Hz: must lie in [--fmin, --fmax] = [{fmin:g}, {fmax:g}] Hz")
    lo, hi = _level_range("--pa-min", "--pa-max", pa_min, pa_max, Q) if by_pa else (0.0, 1e9)
    if by_pa and not (lo <= p <= hi):
        raise InputError(f"--pa/--pa-newton: the seed's level {p:g} N must lie in [--pa-min, --pa-max] = "
                         f"[{lo:g}, {hi:g}] N")
    n_pts = parse_int("--max-points", cont["max_points"], 2, symbol="max_points")
    rtol = parse_number("--rtol", "rtol", cont["rtol"])
    app_max = parse_number("--app-max", "app_max", cont["app_max"]) if _given("app_max") else 1e15
    j = _coordinate(system, coordinate)
    n_pick = None if attractor is None else parse_int("--attractor", attractor, 0)
    s = mapped_options({"fmin_hz": "--fmin", "fmax_hz": "--fmax", "max_points": "--max-points", "rtol": "--rtol",
                        "app_max": "--app-max", "pa_min": "--pa-min", "pa_max": "--pa-max"},
                       SystemContinuationSettings, fmin_hz=fmin, fmax_hz=fmax, pa_min=lo, pa_max=hi,
                       max_points=n_pts, rtol=rtol, tol=max(100 * rtol, 1e-10), app_max=app_max)
    outp = checked_output_folder(out)
    msgs = []
    with ctrl_c():
        branches = _system_branches(system, p, f_e, s, "P_a" if by_pa else "f_e", n_pick, Q, j, msgs)
        if not cont["no_switch"]:
            branches += _switched(system, branches, s, "P_a" if by_pa else "f_e", Q, j, msgs)
    stem = label.rsplit("/", 1)[-1].removesuffix(".toml")
    tag = f"{stem}_pa{p:.4g}N_fe{f_e:g}" + ("_in_pa" if by_pa else "")
    title = (f"{label}: f_e = {f_e:g} Hz, branches in $P_a$" if by_pa
             else f"{label}: {level}, branches in $f_e$")
    paths, fig = _write_system(branches, outp, tag, title, "P_a_newton" if by_pa else "f_e", system, j)
    specials = [sp.to_dict() for b in branches for sp in b.special]
    from contactvib.continuation.system_branch import stop_dict

    stops = [stop_dict(st) for b in branches for st in b.stops]
    if as_json:
        echo_json({"system": label, "coordinates": list(system.coordinates), "special_points": specials,
                   "stops": stops})
        return
    click.echo(f"system {label}: {level}; {_modes_text(system, model)}")
    unit = branches[0].units[j] if branches else ""
    for b in branches:
        st = "; ".join((f"{x.fe_hz:.6g} Hz" if not by_pa else f"{x.pa_over_q:.6g} N") + f": {x.reason}"
                       for x in b.stops)
        click.echo(f"{b.branch}: period {b.period}, {len(b)} points, f_e {b.fe_hz.min():.5g}-{b.fe_hz.max():.5g} Hz, "
                   f"{system.coordinates[j]} A_pp {b.app_um.min():.4g}-{b.app_um.max():.4g} {unit}; stops: {st}")
        for sp in b.special:
            at = f"f_e = {sp.fe_hz:.6f} Hz" if not by_pa else f"P_a = {sp.pa_newton:.6g} N"
            extra = f"  theta/2pi = {sp.angle_over_2pi:.4f}" if sp.type == "neimark-sacker" else ""
            click.echo(f"    {sp.type:<16} {at}  A_pp = {sp.app_um:.5g} {unit}  "
                       f"|mu| = {', '.join(f'{abs(m):.4f}' for m in sp.floquet_multipliers)}{extra}")
    for m in msgs:
        click.echo(f"note: {m}")
    click.echo(f"wrote {len(paths)} branch files and {fig}")


def _system_branches(system, p, f_e, s, parameter, n_pick, Q, j, log) -> list:
    """The branches through the seeds at (p, f_e): the orbit Newton shooting reaches from the
    linear response, or (where it fails, or with --attractor) the attractors of the search."""
    from contactvib.continuation.system_shooting import continue_system_orbit, linear_seed
    from contactvib.errors import ComputationError
    from contactvib.steady.system_attractors import find_system_attractors
    from contactvib.steady.system_orbits import periodic_orbit

    seeds = []
    if n_pick is None:
        try:
            seeds = [periodic_orbit(system, p, f_e, linear_seed(system, p, f_e), 1, rtol=s.rtol)]
        except ComputationError as e:
            log(f"no period-1 orbit from the linear response at {f_e:g} Hz ({e}); seeds from the attractor search")
    if not seeds:
        found = find_system_attractors(system, p, f_e)
        if n_pick is not None and n_pick >= len(found):
            raise InputError(f"--attractor (attractor) = {n_pick}: must be an index 0..{len(found) - 1} of the "
                             f"{len(found)} attractors found at {f_e:g} Hz")
        seeds = [a.orbit for a in found] if n_pick is None else [found.attractors[n_pick].orbit]
    if not seeds:
        raise InputError(f"--from-fe = {f_e:g} Hz: no periodic orbit to continue there (the attractor search "
                         "settled nowhere); choose another --from-fe")
    branches = []
    for i, orbit in enumerate(seeds):
        try:
            branches.append(continue_system_orbit(system, p, f_e, orbit.z, orbit.k, parameter=parameter,
                                                  settings=s, branch_id=f"b{i}", Q=Q, coordinate=j))
        except ComputationError as e:
            log(f"seed {i} (period {orbit.k}): {e}")
    return branches


def _switched(system, branches, s, parameter, Q, j, log) -> list:
    """The period-2k branches born at the period doublings of ``branches`` (one per doubling;
    a doubling where a switched branch already ends is skipped)."""
    from contactvib.continuation.system_switch import switch_system_period_doubling
    from contactvib.errors import ComputationError

    out = []
    todo = [sp for b in branches for sp in b.special if sp.type == "period-doubling"]
    for i, sp in enumerate(todo):
        q = sp.fe_hz if parameter == "f_e" else sp.pa_newton
        ends = [st.fe_hz if parameter == "f_e" else st.pa_over_q for b in out for st in b.stops]
        if any(abs(e - q) <= 1e-4 * abs(q) for e in ends):
            continue
        try:
            out.append(switch_system_period_doubling(system, sp, parameter=parameter, settings=s, Q=Q, coordinate=j,
                                                     branch_id=f"{sp.branch}.pd{i + 1}"))
        except ComputationError as e:
            log(f"period doubling at f_e = {sp.fe_hz:.6g} Hz: {e}")
    return out


def _write_system(branches, out, tag, title, parameter, system, j):
    from contactvib.plotting.branches import branches_figure
    from contactvib.plotting.figures import save_figure

    paths = []
    for b in branches:
        path = out / f"branch_{b.branch}_{tag}.nc"
        b.to_netcdf(path)
        paths.append(path)
    payload = {"special_points": [sp.to_dict() for b in branches for sp in b.special]}
    (out / f"special_points_{tag}.json").write_text(json.dumps(payload, indent=1))
    unit = branches[0].units[j] if branches else "um"
    ylabel = f"peak-to-peak amplitude of {system.coordinates[j]} [{unit.replace('u', 'µ', 1)}]"
    fig = save_figure(branches_figure(branches, title, parameter, ylabel=ylabel), out / f"branches_{tag}.png")
    return paths, fig


def _level(model, label, pa, pa_newton) -> tuple[float, str]:
    """(P_a [N], a text of the level) of --pa or --pa-newton (:func:`_excitation` without f_e)."""
    p, _f, text = _excitation(model, label, pa, pa_newton, "1")
    return p, text


def system_hbm(pa, pa_newton, settings, harmonics, n_time, fmin, fmax, energy_tol, plot, measure, out,
               as_json) -> None:
    """``contactvib hbm --system ...``: the harmonic-balance branch of a system across
    [--fmin, --fmax], continued from --fmin upwards (folds passed), with the Floquet multipliers of
    each point from one shooting period; the figure of one coordinate (--plot) by --measure."""
    import json

    from contactvib.frequency.system_hb import system_hb_continuation
    from contactvib.model import HARMONICS_MAX

    system, model, label = _load(settings)
    p, level = _level(model, label, pa, pa_newton)
    H = parse_int("--harmonics", harmonics, 1, HARMONICS_MAX)
    nt = None if n_time is None else parse_int("--n-time", n_time, 4 * H + 2, symbol="n_time")
    f1 = parse_number("--fmin", "f_min", fmin)
    f2 = parse_number("--fmax", "f_max", fmax)
    if not 0.0 < f1 < f2:
        raise InputError(f"--fmax (f_max) = {show_value(f2)}: must be > --fmin = {show_value(f1)} > 0 Hz")
    etol = parse_number("--energy-tol", "energy_tol", energy_tol)
    names = list(system.coordinates)
    coord = plot or names[0]
    if coord not in names:
        raise InputError(f"--plot {coord}: not a coordinate of --system {label} (its coordinates: {', '.join(names)})")
    outp = checked_output_folder(out)
    with ctrl_c():
        br = mapped_options({"fmin_hz": "--fmin", "fmax_hz": "--fmax", "harmonics": "--harmonics",
                             "n_time": "--n-time", "energy_tol": "--energy-tol"},
                            system_hb_continuation, system, p, fmin_hz=f1, fmax_hz=f2, harmonics=H, n_time=nt,
                            energy_tol=etol)
    payload = {"system": label, "coordinates": names, **br.to_dict()}
    (outp / "branch.json").write_text(json.dumps(payload))
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.system import system_hb_figure

    tag = f"{label.rsplit('/', 1)[-1].removesuffix('.toml')}_pa{p:.4g}N_H{H}"
    fig = system_hb_figure([("", br)], names.index(coord), measure,
                           f"Harmonic balance of {label.rsplit('/', 1)[-1]}, {level}, H = {H}")
    path = save_figure(fig, outp / f"hbm_{tag}_{coord}_{measure}.png")
    if as_json:
        echo_json(payload)
        return
    st = br.stable
    click.echo(f"system {label}: {level}; {len(br.solutions)} points, f_e {br.fe_hz.min():.4g}.."
               f"{br.fe_hz.max():.4g} Hz, {int((~st).sum())} unstable; {br.stop_reason}")
    click.echo(_modes_text(system, model))
    click.echo(str(path))
