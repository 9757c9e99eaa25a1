"""``--system rocking|FILE.toml`` of ``contactvib continue`` and ``contactvib hbm``: the branches of
a structure with contact elements, by shooting continuation (folds, period doublings,
Neimark–Sacker points, the period-2 branches) and by harmonic balance. The system, its level and
its linear modes are read as ``attractors --system`` reads them (:mod:`contactvib.cli.system`)."""

from __future__ import annotations

import json

import click
import numpy as np

from contactvib.cli.common import (
    InputError,
    checked_output_folder,
    ctrl_c,
    echo_json,
    mapped_options,
    parse_int,
    parse_number,
    show_value,
)
from contactvib.cli.system import load_system_option as _load
from contactvib.cli.system import modes_text as _modes_text
from contactvib.cli.system import option_given as _given
from contactvib.cli.system import system_operating_point as _excitation

__all__ = ["system_continue", "system_bifurcations", "system_hbm"]


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


def _frequency_range(system, cont) -> tuple[float, float]:
    """--fmin/--fmax [Hz], by default half the lowest to 1.5 times the highest linear mode."""
    modes = system.linear_modes()
    f_lo = 0.5 * float(modes[modes > 0].min()) if np.any(modes > 0) else 1.0
    f_hi = 1.5 * float(modes.max()) if np.any(modes > 0) else 100.0
    fmin = parse_number("--fmin", "f_min", cont["fmin"]) if _given("fmin") else f_lo
    fmax = parse_number("--fmax", "f_max", cont["fmax"]) if _given("fmax") else f_hi
    if not (0.0 < fmin < fmax):
        raise InputError(f"--fmin/--fmax = {fmin:g}/{fmax:g} Hz: must be 0 < --fmin < --fmax")
    return fmin, fmax


def _settings(cont, fmin, fmax, lo=0.0, hi=1e9):
    """The SystemContinuationSettings of the continuation options."""
    from contactvib.continuation.system_shooting import SystemContinuationSettings

    n_pts = parse_int("--max-points", cont["max_points"], 2, symbol="max_points")
    rtol = parse_number("--rtol", "rtol", cont["rtol"])
    app_max = parse_number("--app-max", "app_max_um", cont["app_max"]) if _given("app_max") else 1e15
    return mapped_options({"fmin_hz": "--fmin", "fmax_hz": "--fmax", "max_points": "--max-points", "rtol": "--rtol",
                           "app_max_um": "--app-max", "pa_min_newton": "--pa-min", "pa_max_newton": "--pa-max"},
                          SystemContinuationSettings, fmin_hz=fmin, fmax_hz=fmax, pa_min_newton=lo, pa_max_newton=hi,
                          max_points=n_pts, rtol=rtol, tol=max(100 * rtol, 1e-10), app_max_um=app_max)


def system_continue(pa, pa_newton, from_fe, attractor, parameter, pa_min, pa_max, coordinate, out, as_json,
                    cont) -> None:
    """``contactvib continue --system ...``: the branches through the orbits at --from-fe,
    continued in f_e (or P_a), with folds, period doublings and Neimark–Sacker points."""
    for param, option in _NOT_SYSTEM_CONTINUE.items():
        if _given(param):
            raise InputError(f"--system and {option}: {option} draws over the slider's resonance dataset")
    if cont.get("level_kind", "force") != "force":
        raise InputError(f"--system and --excitation {cont['level_kind']}: a system is driven by the force "
                         "P_a cos(2 pi f_e t) [N] (--pa-newton) or, for rocking, --pa [Q]")
    system, model, label = _load(cont["settings"])
    Q = None if model is None else model.Q
    fmin, fmax = _frequency_range(system, cont)
    fe_text = from_fe if _given("from_fe") else repr(fmin if parameter == "fe" else 0.5 * (fmin + fmax))
    p, f_e, level = _excitation(model, label, pa if _given("pa") else None, pa_newton, fe_text, "--from-fe")
    by_pa = parameter == "pa"
    if not by_pa and not (fmin <= f_e <= fmax):
        raise InputError(f"--from-fe = {f_e:g} Hz: must lie in [--fmin, --fmax] = [{fmin:g}, {fmax:g}] Hz")
    lo, hi = _level_range("--pa-min", "--pa-max", pa_min, pa_max, Q) if by_pa else (0.0, 1e9)
    if by_pa and not (lo <= p <= hi):
        raise InputError(f"--pa/--pa-newton: the seed's level {p:g} N must lie in [--pa-min, --pa-max] = "
                         f"[{lo:g}, {hi:g}] N")
    j = _coordinate(system, coordinate)
    n_pick = None if attractor is None else parse_int("--attractor", attractor, 0)
    s = _settings(cont, fmin, fmax, lo, hi)
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
        found = find_system_attractors(system, p, f_e, nonperiodic=False, seeds=False)
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


def _on_branch(branches, z, k: int, fe: float, tol: float = 0.05) -> bool:
    """Whether the period-``k`` orbit through ``z`` [SI] at ``fe`` lies on one of ``branches``:
    the state interpolated between two neighbouring points that bracket ``fe`` is within ``tol``
    of ``z`` (relative to |z|∞: the interpolation between the continuation's points is good to
    ~1e-2, distinct coexisting orbits differ by order 1)."""
    scale = max(float(np.max(np.abs(z))), 1e-300)
    for b in branches:
        if b.period != k:
            continue
        f = b.fe_hz
        for i in range(len(f) - 1):
            lo, hi = sorted((f[i], f[i + 1]))
            if lo <= fe <= hi:
                w = 0.0 if hi == lo else (fe - f[i]) / (f[i + 1] - f[i])
                zi = b.state[i] + w * (b.state[i + 1] - b.state[i])
                if float(np.max(np.abs(zi - z))) <= tol * scale:
                    return True
    return False


def system_bifurcations(pa_levels, pa_newton, seed_fe, coordinate, out, as_json, cont) -> None:
    """``contactvib bifurcations --system ...``: every branch through the attractors found at the
    seed frequencies (default: the linear modes inside the range), for each level, with the
    period-2k branches of their period doublings; an attractor on a branch already followed is
    not followed again."""
    from contactvib.continuation.system_branch import stop_dict
    from contactvib.continuation.system_shooting import continue_system_orbit
    from contactvib.errors import ComputationError
    from contactvib.steady.system_attractors import find_system_attractors

    system, model, label = _load(cont["settings"])
    Q = None if model is None else model.Q
    fmin, fmax = _frequency_range(system, cont)
    if pa_newton is not None and pa_levels:
        raise InputError("--pa and --pa-newton: give one of them, not both")
    texts = [pa_newton] if pa_newton is not None or not pa_levels else list(pa_levels)
    levels = [_excitation(model, label, None if pa_newton is not None or t is None else t,
                          pa_newton if pa_newton is not None else None, repr(fmin))[::2] for t in texts]
    if seed_fe is None:
        modes = system.linear_modes()
        seeds = [float(f) for f in modes if fmin <= f <= fmax] or [0.5 * (fmin + fmax)]
    else:
        seeds = [parse_number("--seed-fe", "f_e", t) for t in seed_fe.split(",") if t.strip()]
        bad = [f for f in seeds if not fmin <= f <= fmax]
        if not seeds or bad:
            raise InputError(f"--seed-fe: every seed frequency must lie in [--fmin, --fmax] = [{fmin:g}, {fmax:g}] Hz")
    j = _coordinate(system, coordinate)
    s = _settings(cont, fmin, fmax)
    outp = checked_output_folder(out)
    all_branches, msgs = [], []
    with ctrl_c():
        for p, level in levels:
            branches = []
            for fe in seeds:
                for a in find_system_attractors(system, p, fe, nonperiodic=False, seeds=False):
                    if _on_branch(branches, a.orbit.z, a.orbit.k, fe):
                        continue
                    try:
                        branches.append(continue_system_orbit(system, p, fe, a.orbit.z, a.orbit.k, settings=s,
                                                              branch_id=f"b{len(branches)}", Q=Q,
                                                              coordinate=j))
                    except ComputationError as e:
                        msgs.append(f"{level}, {fe:g} Hz, period {a.orbit.k}: {e}")
            if not cont["no_switch"]:
                branches += _switched(system, branches, s, "f_e", Q, j, msgs.append)
            stem = label.rsplit("/", 1)[-1].removesuffix(".toml")
            _write_system(branches, outp, f"{stem}_pa{p:.4g}N", f"{label}: {level}, all branches", "f_e", system, j)
            all_branches += branches
            if not as_json:
                n_sp = sum(len(b.special) for b in branches)
                click.echo(f"system {label}, {level}: {len(branches)} branches, {n_sp} special points")
    result = {"system": label, "coordinates": list(system.coordinates),
              "special_points": [sp.to_dict() for b in all_branches for sp in b.special],
              "stops": [stop_dict(st) for b in all_branches for st in b.stops], "cascades": []}
    (outp / "bifurcations.json").write_text(json.dumps(result, indent=1))
    if as_json:
        echo_json(result)
        return
    for m in msgs:
        click.echo(f"note: {m}")
    click.echo(f"wrote {outp}/")


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
