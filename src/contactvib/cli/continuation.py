"""CLI commands ``continue``, ``bifurcations`` and ``evolution`` (periodic-orbit continuation).

Thin: parse and validate (one-line errors, exit 2), call :mod:`contactvib.continuation`, write NetCDF
branch files and figures, print a summary or the JSON contract
``{"special_points": [...], "stops": [{"fe_hz", "reason"}, ...]}``.
"""

from __future__ import annotations

import json
from pathlib import Path

import click

from contactvib.cli.common import (
    InputError,
    LevelsCommand,
    checked_option,
    checked_output_folder,
    ctrl_c,
    echo_json,
    feasible_frequencies,
    law_options,
    level_kind_option,
    mapped_options,
    parse_frequency_range,
    parse_int,
    parse_levels,
    parse_model,
    parse_number,
    parse_pa_level,
    parse_positive,
)
from contactvib.cli.system import system_given, system_option
from contactvib.cli.system_branches import system_continue
from contactvib.model import EVOLUTION_ORDER_MAX, LEVEL_KINDS, LEVEL_TAGS, SHOOTING_RTOL_RANGE, check_range, level_text
from contactvib.model.checks import PA_MAX, PA_NOTE

__all__ = []

#: Options of the continuation, by ContinuationSettings' symbols (and the range's bound names).
_CONTINUATION_OPTIONS = {"fmin_hz": "--fmin", "fmax_hz": "--fmax", "f_min": "--fmin", "f_max": "--fmax",
                         "max_points": "--max-points", "app_max_um": "--app-max", "rtol": "--rtol",
                         "pa_min": "--pa-min", "pa_max": "--pa-max"}


def continuation_settings(cont: dict, pa_range=(0.0, 2.0)):
    """ContinuationSettings of the continuation options ``cont`` (the library checks them; we
    name the options)."""
    from contactvib.continuation.settings import BRANCH_POINTS_MIN
    from contactvib.continuation.shooting import ContinuationSettings

    lo, hi = parse_frequency_range(cont["fmin"], cont["fmax"])
    n = parse_int("--max-points", cont["max_points"], BRANCH_POINTS_MIN, symbol="max_points")
    a = parse_number("--app-max", "app_max_um", cont["app_max"])
    r = checked_option("--rtol", check_range, "rtol", cont["rtol"], SHOOTING_RTOL_RANGE[0], True,
                 upper=SHOOTING_RTOL_RANGE[1])
    return mapped_options(_CONTINUATION_OPTIONS, ContinuationSettings, fmin_hz=lo, fmax_hz=hi,
                   pa_min=pa_range[0], pa_max=pa_range[1], max_points=n, app_max_um=a, rtol=r,
                   tol=max(100 * r, 1e-11), excitation=cont.get("level_kind", "force"))


def _below_app_max(starts, app_max_um: float, fe: float) -> None:
    """Refuse an --app-max below the A_pp of every periodic start: no branch could leave it."""
    periodic = [a.app_um for a in starts if a.period is not None]
    if periodic and min(periodic) >= app_max_um:
        raise InputError(f"--app-max (app_max_um) = {app_max_um:g}: must be > {min(periodic):.4g} µm, the smallest "
                         f"A_pp of the periodic attractors to continue at {fe:g} Hz (a branch stops above "
                         f"--app-max, so none could start)")


def _in_range(option: str, symbol: str, text_or_value, lo: float, hi: float, names: tuple[str, str],
              unit: str = "") -> float:
    """A value that must lie in [lo, hi], the range set by the options ``names``."""
    return checked_option(option, check_range, symbol, text_or_value, lo, True, unit, upper=hi,
                    lower_name=names[0], upper_name=names[1], names=_CONTINUATION_OPTIONS)


def _pa_range(pa_min: str, pa_max: str) -> tuple[float, float]:
    """--pa-min < --pa-max, both P_a levels > 0 [Q]."""
    lo = parse_pa_level(pa_min, "--pa-min")
    hi = checked_option("--pa-max", check_range, "P_a/Q", pa_max, lo, False, lower_name="pa_min",
                  names=_CONTINUATION_OPTIONS)
    hi = checked_option("--pa-max", check_range, "P_a/Q", hi, None, unit=PA_NOTE, upper=PA_MAX)
    return lo, hi


def _continuation_options(f):
    f = law_options(f)
    """The options every continuation command takes; the command receives them as keyword
    arguments (``**cont``)."""
    f = level_kind_option(f)
    f = click.option("--rtol", default="1e-12", show_default=True,
                     help=f"Integrator tolerance of the shooting ({SHOOTING_RTOL_RANGE[0]:g}.."
                          f"{SHOOTING_RTOL_RANGE[1]:g}).")(f)
    f = click.option("--app-max", default="2000", show_default=True, metavar="UM",
                     help="Amplitude bound: a branch stops when A_pp exceeds it [µm].")(f)
    f = click.option("--max-points", default="2000", show_default=True,
                     help="Largest number of points per direction of a branch.")(f)
    f = click.option("--fmax", default="2000", show_default=True, metavar="HZ",
                     help="Upper end of the f_e range [Hz].")(f)
    f = click.option("--fmin", default="30", show_default=True, metavar="HZ",
                     help="Lower end of the f_e range [Hz].")(f)
    f = click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
                     help="Override a model parameter by its paper symbol (M, g, S, c_n, m2, h_n, l).")(f)
    f = click.option("--no-switch", is_flag=True,
                     help="Do not switch onto period-2k branches at period doublings.")(f)
    f = click.option("--dataset", default=None, type=click.Path(), metavar="DATASET",
                     help="Resonance dataset (paper.nc, resonance.nc, atlas.nc, or their folder): also draw "
                          "the branches over its resonance graph (overlay_<tag>.png).")(f)
    return f


def level_title_text(level: float, kind: str) -> str:
    """A level as a figure title writes it (mathtext symbol): "$P_a$ = 0.65 Q", "$U$ = 0.05 µm"."""
    text = level_text(level, kind, 6)
    sym, rest = text.split(" = ", 1)
    return f"${sym}$ = {rest}" + ("" if kind == "force" else " (base motion)")


def _open_dataset(path, levels, kind: str = "force"):
    """The resonance dataset for the overlay, checked before any computation (or None): its
    levels must be of the same kind (``--excitation``) and include ``levels``."""
    if path is None:
        return None
    from contactvib.cli.common import open_dataset_argument

    data = open_dataset_argument(path, "--dataset", load=True)
    stored_kind = data.kind
    if stored_kind != kind:
        raise InputError(f"--dataset = {path}: its levels are {LEVEL_KINDS[stored_kind][0]} "
                         f"(--excitation {stored_kind}), not {LEVEL_KINDS[kind][0]} (--excitation {kind})")
    for p in levels:
        if data.match(p) is None:
            raise InputError(f"--pa ({LEVEL_KINDS[kind][0]}) = {p:g}: not in --dataset; stored levels: "
                             + data.levels_text())
    return data.ds


def _write(bset, out: Path, tag: str, title: str, ds=None, pa=None, parameter="f_e"):
    """Branch files, special points (NetCDF, JSON) and the branch figure (plus the overlay on
    ``ds``'s resonance graph)."""
    from contactvib.plotting.branches import branches_figure, branches_over_dataset_figure
    from contactvib.plotting.figures import save_figure

    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for b in bset:
        p = out / f"branch_{b.branch.replace('/', '_')}.nc"
        b.to_netcdf(p)
        paths.append(p)
    if len(bset.special_points):
        bset.special_table().to_netcdf(out / f"special_points_{tag}.nc")
    (out / f"special_points_{tag}.json").write_text(bset.to_json(indent=1))
    fig_path = save_figure(branches_figure(bset, title, parameter), out / f"branches_{tag}.png")
    if ds is not None:  # continuation (stable solid, unstable dashed) over the sweep's attractors
        save_figure(branches_over_dataset_figure(bset, ds, pa, title), out / f"overlay_{tag}.png")
    return paths, fig_path


def _summary(bset, parameter="f_e"):
    for b in bset:
        if parameter == "f_e":
            st = "; ".join(f"{s.fe_hz:.6g} Hz: {s.reason}" for s in b.stops)
            rng = f"f_e {b.fe_hz.min():.5g}–{b.fe_hz.max():.5g} Hz"
        else:
            st = "; ".join(f"{s.pa_over_q:.6g} Q: {s.reason}" for s in b.stops)
            rng = f"P_a {b.pa_over_q.min():.5g}–{b.pa_over_q.max():.5g} Q"
        click.echo(f"{b.branch}: period {b.period}, {len(b)} points, {rng}, "
                   f"A_pp {b.app_um.min():.4g}–{b.app_um.max():.4g} um; stops: {st}")
        for sp in b.special:
            at = (f"f_e = {sp.fe_hz:12.6f} Hz" if parameter == "f_e"
                  else f"P_a = {sp.pa_over_q:10.6f} Q")
            click.echo(f"    {sp.type:<16} {at}  A_pp = {sp.app_um:10.5g} um  "
                       f"|mu| = {', '.join(f'{abs(m):.4f}' for m in sp.floquet_multipliers)}")


@click.command("continue")
@system_option
@click.option("--pa", default="0.65", show_default=True, metavar="Q",
              help="Excitation amplitude P_a as a multiple of Q = M g.")
@click.option("--pa-newton", default=None, metavar="N",
              help="Excitation amplitude P_a [N] of a --system (the level of a system file).")
@click.option("--coordinate", default=None, metavar="NAME",
              help="With --system: the coordinate whose A_pp is drawn (default the first).")
@click.option("--from-fe", "from_fe", default="1200", show_default=True, metavar="HZ",
              help="Frequency of the seed: the attractors found there are continued.")
@click.option("--attractor", default=None, metavar="N",
              help="Seed index in the attractor list (as `attractors --json`); default: every one.")
@click.option("--parameter", type=click.Choice(["fe", "pa"]), default="fe", show_default=True,
              help="Continue in the frequency f_e (at fixed --pa) or in the amplitude P_a "
                   "(at fixed --from-fe, between --pa-min and --pa-max).")
@click.option("--pa-min", default="0.05", show_default=True, metavar="Q",
              help="Lower end of the P_a range [Q] (--parameter pa).")
@click.option("--pa-max", default="1.0", show_default=True, metavar="Q",
              help="Upper end of the P_a range [Q] (--parameter pa).")
@_continuation_options
@click.option("--out", default="branch", show_default=True, type=click.Path(file_okay=False),
              help="Output folder (NetCDF branch files, special points, figure).")
@click.option("--json", "as_json", is_flag=True, help="Print the JSON contract.")
def continue_(pa, pa_newton, coordinate, from_fe, attractor, parameter, pa_min, pa_max, out, as_json, **cont):
    """Continue branches of periodic orbits in f_e (or P_a) from the attractors at one point.

    With --system (rocking or a TOML file) the structure's period-1 orbit at --from-fe (Newton
    shooting from the linear response, else the attractors there) is continued between --fmin and
    --fmax (default: half the lowest to 1.5 times the highest linear mode; --from-fe defaults to
    --fmin) with its folds, period doublings and Neimark-Sacker points; --pa-min/--pa-max are in N
    with --pa-newton, in Q with --pa (rocking). No branch switching at period doublings there.
    """
    if system_given():
        system_continue(pa, pa_newton, from_fe, attractor, parameter, pa_min, pa_max, coordinate, out, as_json,
                        cont)
        return
    if pa_newton is not None:
        raise InputError("--pa-newton: the force level [N] of --system; the slider's continuation takes --pa [Q]")
    if coordinate is not None:
        raise InputError("--coordinate: names a coordinate of --system; the slider has one (y)")
    model = parse_model(cont["settings"])
    dataset = cont["dataset"]
    kind = cont["level_kind"]
    by_pa = parameter == "pa"
    if by_pa and kind != "force":
        raise InputError(f"--parameter pa: continuation in P_a needs a force level, not --excitation {kind}; "
                         "continue in f_e instead")
    p = parse_levels((pa,), kind)[0]
    if by_pa and dataset is not None:
        raise InputError("--dataset draws over a resonance graph in f_e: not with --parameter pa")
    ds = _open_dataset(dataset, [p], kind)
    fe = parse_positive("--from-fe", "f_e", from_fe, "Hz")
    lo, hi = (_pa_range(pa_min, pa_max) if by_pa
              else (parse_pa_level(pa_min, "--pa-min"), parse_pa_level(pa_max, "--pa-max")))
    if by_pa:
        _in_range("--pa", "P_a/Q", p, lo, hi, ("pa_min", "pa_max"))
    s = continuation_settings(cont, (lo, hi) if by_pa else (0.0, 2.0))
    if not by_pa:
        _in_range("--from-fe", "f_e", fe, s.fmin_hz, s.fmax_hz, ("f_min", "f_max"), "Hz")
    n = None if attractor is None else parse_int("--attractor", attractor, 0)
    feasible_frequencies(model, s.fmin_hz, s.fmax_hz)
    exc = checked_option("--from-fe" if kind == "force" else "--pa", s.excitation_at, model, p, fe)
    checked_output_folder(out)
    from contactvib.continuation.diagram import continue_attractors
    from contactvib.steady.attractors import find_attractors

    with ctrl_c():
        found = find_attractors(exc)
    if n is not None and n >= len(found):
        raise InputError(f"--attractor (attractor) = {n}: must be an index 0..{len(found) - 1} "
                         f"of the {len(found)} attractors found at {fe:g} Hz")
    _below_app_max(found if n is None else [found[n]], s.app_max_um, fe)
    msgs = []
    bset = continue_attractors(model, pa_over_q=p, fe_hz=fe, attractor=n, settings=s,
                               switch=not cont["no_switch"], attractors=found,
                               log=msgs.append, parameter="P_a" if by_pa else "f_e")
    tag = f"{LEVEL_TAGS[kind]}{p:g}_fe{fe:g}" + ("_in_pa" if by_pa else "")
    title = (f"$f_e$ = {fe:g} Hz, branches in $P_a$ from the attractors at {p:g} Q" if by_pa
             else f"{level_title_text(p, kind)}, branches from the attractors at {fe:g} Hz")
    paths, fig = _write(bset, Path(out), tag, title, ds, p,
                        parameter="P_a" if by_pa else "f_e")
    if as_json:
        echo_json(bset.to_json())
        return
    _summary(bset, "P_a" if by_pa else "f_e")
    for m in msgs:
        click.echo(f"note: {m}")
    click.echo(f"wrote {len(paths)} branch files and {fig}")


@click.command(cls=LevelsCommand)
@system_option
@click.option("--pa", multiple=True, default=("0.65",), show_default=True, metavar="Q [Q ...]",
              help="Excitation amplitudes P_a [Q]; several values after one --pa.")
@click.option("--pa-newton", default=None, metavar="N",
              help="With --system: the force level P_a [N] (a system file defines no Q).")
@click.option("--coordinate", default=None, metavar="NAME",
              help="With --system: the coordinate whose A_pp the figures draw (default the first).")
@click.option("--seed-fe", default=None, metavar="HZ,HZ,...",
              help="Seed frequencies [Hz] of the attractor searches (comma-separated).")
@click.option("--cascade-fe", default=None, metavar="HZ",
              help="Also follow the period-doubling cascade of every attractor at this f_e [Hz] "
                   "(its period detected with no cap), doubling after doubling, and report the "
                   "Feigenbaum ratios (JSON 'cascades').")
@click.option("--cascade-direction", type=click.Choice(["up", "down"]), default="up", show_default=True,
              help="Direction in f_e in which the cascades are followed.")
@_continuation_options
@click.option("--out", default="bif", show_default=True, type=click.Path(file_okay=False),
              help="Output folder.")
@click.option("--json", "as_json", is_flag=True, help="Print the JSON contract.")
def bifurcations(pa, seed_fe, cascade_fe, cascade_direction, out, as_json, **cont):
    """All branches, seeded from every attractor at several frequencies, for each P_a; with
    --cascade-fe, the period-doubling cascades from that frequency."""
    if system_given():
        from contactvib.cli.system_branches import system_bifurcations

        if cascade_fe is not None:
            raise InputError("--system and --cascade-fe: cascades are followed for the paper's slider")
        given = click.get_current_context().get_parameter_source("pa") != click.core.ParameterSource.DEFAULT
        return system_bifurcations(pa if given else None, cont.pop("pa_newton"), seed_fe, cont.pop("coordinate"),
                                   out, as_json, cont)
    for option in ("pa_newton", "coordinate"):
        if cont.pop(option) is not None:
            raise InputError(f"--{option.replace('_', '-')}: an option of --system only")
    model = parse_model(cont["settings"])
    kind = cont["level_kind"]
    levels = parse_levels(pa, kind)
    ds = _open_dataset(cont["dataset"], levels, kind)
    s = continuation_settings(cont)
    from contactvib.continuation.diagram import DEFAULT_SEED_FE

    if seed_fe is None:
        seeds = [f for f in DEFAULT_SEED_FE if s.fmin_hz <= f <= s.fmax_hz]
    else:
        seeds = [_in_range("--seed-fe", "f_e", t, s.fmin_hz, s.fmax_hz, ("f_min", "f_max"), "Hz")
                 for t in seed_fe.split(",") if t.strip()]
    if not seeds:
        raise InputError("--seed-fe: no seed frequency inside [--fmin, --fmax]")
    if cascade_fe is not None:
        cascade_fe = _in_range("--cascade-fe", "f_e", cascade_fe, s.fmin_hz, s.fmax_hz, ("f_min", "f_max"), "Hz")
        if kind != "force":
            raise InputError("--cascade-fe: cascades are followed under a force level (--pa), not "
                             f"under --level-kind {kind}")
    feasible_frequencies(model, s.fmin_hz, s.fmax_hz)
    checked_output_folder(out)
    from contactvib.continuation.branch import BranchSet
    from contactvib.continuation.cascade import cascades_at
    from contactvib.continuation.diagram import bifurcation_diagram

    allb = BranchSet([])
    cascades = []
    for p in levels:
        bset = bifurcation_diagram(model, pa_over_q=p, seed_fe=seeds, settings=s, switch=not cont["no_switch"])
        _write(bset, Path(out), f"{LEVEL_TAGS[kind]}{p:g}", f"{level_title_text(p, kind)}: all branches", ds, p)
        allb.branches.extend(bset.branches)
        if not as_json:
            click.echo(f"{level_text(p, kind, 6)}: {len(bset)} branches, {len(bset.special_points)} special points")
        if cascade_fe is not None:
            limit = s.fmax_hz if cascade_direction == "up" else s.fmin_hz
            found = cascades_at(model, pa_over_q=p, fe_hz=cascade_fe, direction=1 if cascade_direction == "up" else -1,
                                fe_limit_hz=limit)
            cascades.extend(found)
            if not as_json:
                for c in found:
                    click.echo(f"  cascade: periods {', '.join(map(str, c.periods))} double at "
                               f"{', '.join(f'{f:.6f}' for f in c.pd_fe_hz)} Hz; delta "
                               f"{', '.join(f'{d:.4f}' for d in c.delta) or '-'} ({c.stop})")
    result = {**allb.to_dict(), "cascades": [c.to_dict() for c in cascades]}
    (Path(out) / "bifurcations.json").write_text(json.dumps(result, indent=1))
    if as_json:
        echo_json(json.dumps(result))
    else:
        click.echo(f"wrote {Path(out)}/")


@click.command()
@law_options
@click.option("--order", default="2", show_default=True,
              help=f"m of the 1/m resonance (1..{EVOLUTION_ORDER_MAX}).")
@click.option("--pa-min", default="0.3", show_default=True, metavar="Q", help="Lowest P_a [Q].")
@click.option("--pa-max", default="0.9", show_default=True, metavar="Q", help="Highest P_a [Q].")
@click.option("--levels", default="7", show_default=True,
              help="P_a levels of the one-parameter runs (>= 2).")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a model parameter by its paper symbol.")
@click.option("--out", default="evo", show_default=True, type=click.Path(file_okay=False),
              help="Output folder.")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def evolution(order, pa_min, pa_max, levels, settings, out, as_json):
    """Two-parameter continuation of the folds and period doublings of the 1/m resonance."""
    model = parse_model(settings)
    m = parse_int("--order", order, 1, EVOLUTION_ORDER_MAX)
    lo, hi = _pa_range(pa_min, pa_max)
    n = parse_int("--levels", levels, 2, symbol="n_levels")
    outp = checked_output_folder(out)
    from contactvib.continuation.evolution import evolution as run
    from contactvib.plotting.branches import evolution_figure
    from contactvib.plotting.figures import save_figure

    msgs = []
    res = run(model, order=m, pa_min=lo, pa_max=hi, n_levels=n, log=msgs.append)
    (outp / f"evolution_order{m}.json").write_text(res.to_json(indent=1))
    save_figure(evolution_figure(res, f"evolution of the 1/{m} resonance: folds and period doublings"),
                outp / f"evolution_order{m}.png")
    if as_json:
        echo_json(res.to_json())
        return
    for line in msgs:
        click.echo(line)
    for k, (f, p) in res.extremes.items():
        click.echo(f"{k}: f_e = {f:.5g} Hz, P_a = {p:.4g} Q")
    click.echo(f"wrote {Path(outp)}/evolution_order{m}.png and .json")
