"""CLI command ``friction``: friction under normal contact vibration at one operating
point, or against f_e (``--fe-range``) or the drive velocity (``--vd-range``)."""

from __future__ import annotations

import contextvars

import click
import numpy as np

from contactvib.cli.common import (
    InputError,
    checked_output_folder,
    ctrl_c,
    echo_json,
    mapped_options,
    operating_point_options,
    parse_excitation,
    parse_model,
    parse_positive,
    scoped_options,
    search_options,
)
from contactvib.cli.steady import excitation_text, search_attractors, search_settings

#: The tangential model's options (kept out of the signature by ``_friction_options``).
_FRICTION: contextvars.ContextVar = contextvars.ContextVar("contactvib_friction", default=None)
#: FrictionModel's symbols, by option.
_FRICTION_NAMES = {"mu": "--mu", "kt_ratio": "--kt-ratio", "kt_law": "--kt-law", "k_d": "--kd", "c_d": "--cd",
                   "v_d": "--vd", "beta": "--beta", "v_min": "--vd-range VMIN", "v_max": "--vd-range VMAX",
                   "n_vd": "--nvd", "F_T": "--ft", "drive": "--drive"}
#: Largest number of frequencies of --fe-range.
FE_POINTS_MAX = 10000


def _friction_options(f):
    """--vd, --mu, --kt-ratio, --kt-law, --kd, --cd, --beta, and the grids --fe-range/--df and
    --vd-range/--nvd."""
    names = ("vd", "mu", "kt_ratio", "kt_law", "kd", "cd", "beta", "fe_range", "df", "vd_range", "nvd", "drive", "ft")
    f = scoped_options(_FRICTION, names, f)
    opts = [
        ("--ft", dict(default=None, metavar="N",
                      help="The constant tangential force F_T [N] of --drive force (c_d: a damper to the ground).")),
        ("--drive", dict(default="velocity", show_default=True, type=click.Choice(["velocity", "force"]),
                         help="velocity: a drive spring k_d whose end moves at v_d; force: a constant tangential "
                              "force --ft (the slider creeps at the mean velocity the vibration lets through).")),
        ("--nvd", dict(default="13", show_default=True, help="Drive velocities of --vd-range (log-spaced).")),
        ("--vd-range", dict(nargs=2, default=None, metavar="VMIN VMAX",
                            help="Friction against the drive velocity [mm/s] at --fe: OUT/friction_vd.png, .csv.")),
        ("--df", dict(default="20", show_default=True, help="Frequency step [Hz] of --fe-range.")),
        ("--fe-range", dict(nargs=2, default=None, metavar="FMIN FMAX",
                            help="Friction against f_e [Hz] at the level --pa (every attractor at each f_e): "
                                 "OUT/friction_fe.png, .csv.")),
        ("--beta", dict(default="1", show_default=True,
                        help="Hess & Soom exponent: slip limit mu W (R/W)^beta, 0 < beta <= 1 (1: Coulomb mu R).")),
        ("--cd", dict(default="30", show_default=True, metavar="N_S_M", help="Drive damper c_d [N s/m], >= 0.")),
        ("--kd", dict(default="1e5", show_default=True, metavar="N_M", help="Drive spring k_d [N/m], > 0.")),
        ("--kt-law", dict(default="normal", show_default=True, type=click.Choice(["normal", "constant"]),
                          help="k_t follows the normal stiffness dF_s/dy(y(t)), or is held at dF_s/dy(y0).")),
        ("--kt-ratio", dict(default=None, metavar="RATIO",
                            help="Tangential over normal contact stiffness [default: Mindlin's 2(1 - nu)/(2 - nu) "
                                 "= 0.8235 of a Hertz contact at nu = 0.3].")),
        ("--mu", dict(default="0.3", show_default=True, help="Coulomb friction coefficient mu, > 0.")),
        ("--vd", dict(default="0.1", show_default=True, metavar="MM_S",
                      help="Drive velocity v_d [mm/s] of the drive spring's end, >= 0 (0: the spring at rest holds "
                           "the slider, stretched to mu W at the start).")),
    ]
    for name, kw in opts:
        f = click.option(name, **kw)(f)
    return f


#: The entries of a sweep's ``--friction`` (FrictionModel fields), by their symbols in messages.
SPEC_KEYS = {"mu": "mu", "kt_ratio": "kt_ratio", "kt_law": "kt_law", "kd": "k_d", "cd": "c_d", "vd": "v_d",
             "beta": "beta", "drive": "drive", "ft": "F_T"}


def friction_spec_option(f):
    """``--friction mu=…,kt_ratio=…,vd=…`` of ``resonance`` and ``atlas``: friction columns in the dataset."""
    return click.option(
        "--friction", "friction", default=None, metavar="NAME=VALUE,...",
        help="Add friction columns (friction ratio, stick and free fractions, tangential "
             "oscillation of every periodic point) with these tangential parameters, the defaults of "
             "`contactvib friction` otherwise: mu (0.3), kt_ratio (0.8235), kt_law (normal|constant), kd [N/m] "
             "(1e5), cd [N s/m] (30), vd [mm/s] (0.1), beta (1), drive (velocity|force), ft [N]; "
             "`--friction default` for all defaults.")(f)


def friction_spec(text):
    """The FrictionModel of ``--friction`` (``NAME=VALUE`` pairs separated by commas, or
    ``default``), or None when not given; one-line InputErrors naming ``--friction NAME``."""
    from contactvib.friction import FrictionModel

    if text is None:
        return None
    kw = {}
    if text.strip() not in ("default", ""):
        for item in text.split(","):
            name, eq, value = (part.strip() for part in item.partition("="))
            if not eq or name not in SPEC_KEYS or not value:
                raise InputError(f"--friction: {item.strip()!r} is not NAME=VALUE of a friction parameter "
                                 f"({', '.join(SPEC_KEYS)}), or 'default'")
            if name in kw:
                raise InputError(f"--friction: {name} given twice")
            kw[name] = value
    names = {sym: f"--friction {key}" for key, sym in SPEC_KEYS.items()}
    if kw.get("drive", "velocity") == "force" and "ft" not in kw:
        raise InputError("--friction drive=force: needs the tangential force ft=N")
    return mapped_options(names, FrictionModel, **kw)


def _friction_model():
    from contactvib.friction import FrictionModel

    o = _FRICTION.get() or {}
    kw = {} if o["kt_ratio"] is None else {"kt_ratio": o["kt_ratio"]}
    if o["drive"] == "force":
        if o["ft"] is None:
            raise InputError("--drive force: needs the tangential force --ft N")
        if o["vd_range"] is not None:
            raise InputError("--vd-range: belongs to the velocity drive, not to --drive force")
        kw.update(drive="force", ft=o["ft"])
    elif o["ft"] is not None:
        raise InputError("--ft: belongs to --drive force (a constant tangential force), not to the velocity drive")
    return mapped_options(_FRICTION_NAMES, FrictionModel, mu=o["mu"], kt_law=o["kt_law"], kd=o["kd"], cd=o["cd"],
                   vd=o["vd"], beta=o["beta"], **kw)


def _frequencies(o) -> np.ndarray:
    fmin, fmax = mapped_options({"f_min": "--fe-range FMIN", "f_max": "--fe-range FMAX"}, _frequency_range_values,
                         *o["fe_range"])
    df = parse_positive("--df", "df", o["df"], "Hz")
    n = int(np.floor((fmax - fmin) / df + 1e-9)) + 1
    if n > FE_POINTS_MAX:
        raise InputError(f"--df = {o['df']}: {n} frequencies over --fe-range; at most {FE_POINTS_MAX}")
    return fmin + df * np.arange(n)


def _frequency_range_values(fmin, fmax):
    from contactvib.model import check_frequency_range

    return check_frequency_range(fmin, fmax)


def _belongs(o) -> None:
    """--df and --nvd given without their grid are refused (they would be ignored)."""
    ctx = click.get_current_context()
    for name, grid in (("df", "fe_range"), ("nvd", "vd_range")):
        given = ctx.get_parameter_source(name) not in (None, click.core.ParameterSource.DEFAULT)
        if given and o[grid] is None:
            raise InputError(f"--{name}: belongs to --{grid.replace('_', '-')}; give that grid with it")


def _grid_excitation(model, pa, pa_newton, f):
    """The excitation at a frequency of --fe-range (its checks named by --fe-range)."""
    try:
        return parse_excitation(model, pa, pa_newton, repr(float(f)))
    except InputError as e:
        raise InputError(f"--fe-range: at {f:g} Hz: {e}") from None


def _header(model, exc, fm) -> str:
    drive = (f"F_T = {fm.ft:g} N ({fm.ft / (fm.mu * model.W):.4g} mu W), c_d = {fm.cd:g} N s/m" if fm.drive == "force"
             else f"k_d = {fm.kd:g} N/m, c_d = {fm.cd:g} N s/m, v_d = {fm.vd:g} mm/s")
    beta = f", beta = {fm.beta:g}" if fm.beta != 1.0 else ""
    return (f"{excitation_text(exc)}, f_e = {exc.f_e:g} Hz, f_n0 = {model.f_n0:.1f} Hz; friction: mu = {fm.mu:g}, "
            f"k_t = {fm.kt_ratio:.4g} dF_s/dy ({fm.kt_law}), {drive}{beta}")


_HEAD = (f"{'#':>2} {'period':>6} {'A_pp [um]':>10} {'gap':>6} {'ratio':>8} {'reduction':>9} {'stick':>6} "
         f"{'slip':>6} {'free':>6} {'u_pp [um]':>10} {'T_t':>4}")


def _point_row(i, a, r, force=False) -> str:
    if r is None:
        return f"{i:>2} {'-' if a.period is None else a.period:>6} {a.app_um:>10.5g} {a.contact_loss_fraction:>6.3f} " \
               f"{'-':>8}   (non-periodic: no friction)"
    t_t = str(r.tangential_period) if r.settled else "-"
    return (f"{i:>2} {a.period:>6} {a.app_um:>10.5g} {a.contact_loss_fraction:>6.3f} {r.friction_ratio:>8.4f} "
            f"{r.friction_reduction:>9.2%} {r.stick_fraction:>6.3f} {r.slip_fraction:>6.3f} {r.free_fraction:>6.3f} "
            f"{r.mean_velocity_mm_s if force else r.tangential_app_um:>10.4g} {t_t:>4}")


def _one_point(model, exc, found, fm, out, as_json) -> None:
    from contactvib.errors import ComputationError
    from contactvib.friction import friction_at

    results = []
    with ctrl_c():
        for a in found:
            try:
                results.append(friction_at(exc, a, friction=fm))
            except ComputationError:
                results.append(None)
    if as_json:
        items = [{"period": a.period, "app_um": a.app_um, "contact_loss_fraction": a.contact_loss_fraction,
                  "basin_fraction": a.basin_fraction, **({} if r is None else r.to_dict())}
                 for a, r in zip(found, results)]
        echo_json({"fn0_hz": model.f_n0, "y0_um": model.units.y_um, "pa_over_q": exc.pa_over_q, "fe_hz": exc.f_e,
                    "friction": fm.parameters(), "model": model.parameters(), "attractors": items})
    else:
        force = fm.drive == "force"
        click.echo(_header(model, exc, fm))
        click.echo(_HEAD.replace(" u_pp [um]", "v [mm/s]".rjust(10)) if force else _HEAD)
        for i, (a, r) in enumerate(zip(found, results)):
            click.echo(_point_row(i, a, r, force))
        if any(r is not None and not r.settled for r in results):
            click.echo("   T_t '-': the tangential motion did not become periodic within its period limit")
    if out is not None:
        _write_point(found, results, out, not as_json)


def _write_point(found, results, out, echo) -> None:
    """OUT/friction_<i>.png (the steady tangential motion of attractor i) and OUT/friction.json;
    their paths on stdout when ``echo``."""
    import json

    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.friction import friction_history_figure

    for i, r in enumerate(results):
        if r is not None:
            fig = friction_history_figure(r.history(), r, f"#{i} (period {found[i].period}, "
                                                           f"A_pp {found[i].app_um:.3g} um): ")
            png = save_figure(fig, out / f"friction_{i}.png")
            if echo:
                click.echo(str(png))
    path = out / "friction.json"
    path.write_text(json.dumps([None if r is None else r.to_dict() for r in results]))
    if echo:
        click.echo(str(path))


def _sweep_out(sweep, x, out, as_json) -> None:
    if out is not None:
        from contactvib.plotting.figures import save_figure
        from contactvib.plotting.friction import friction_sweep_figure

        stem = "friction_fe" if x == "fe_hz" else "friction_vd"
        sweep.to_csv(out / f"{stem}.csv")
        png = save_figure(friction_sweep_figure(sweep, x), out / f"{stem}.png")
        if not as_json:
            click.echo(str(out / f"{stem}.csv"))
            click.echo(str(png))
    if as_json:
        echo_json(sweep.to_dict())


def _print_sweep_rows(rows) -> None:
    for i in range(len(rows["fe_hz"])):
        click.echo(f"{rows['fe_hz'][i]:>8g} {rows['vd_mm_s'][i]:>9.4g} {int(rows['attractor'][i]):>2} "
                   f"{int(rows['period'][i]):>6} {rows['app_um'][i]:>10.5g} {rows['contact_loss_fraction'][i]:>6.3f} "
                   f"{rows['friction_ratio'][i]:>8.4f} {rows['stick_fraction'][i]:>6.3f}")


_SWEEP_HEAD = (f"{'f_e [Hz]':>8} {'v_d[mm/s]':>9} {'#':>2} {'period':>6} {'A_pp [um]':>10} {'gap':>6} "
               f"{'ratio':>8} {'stick':>6}")


@click.command()
@operating_point_options
@search_options
@_friction_options
@click.option("--out", "out", default=None, type=click.Path(file_okay=False),
              help="Folder for the figures (time histories, or the friction against f_e or v_d), CSV and JSON.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of the table.")
def friction(pa, pa_newton, fe, settings, starts, seed, kmax, max_periods, no_seeds, out, as_json):
    """Friction under normal contact vibration: the slider dragged along the slideway by a drive
    spring moving at v_d, a Jenkins contact (tangential stiffness k_t, Coulomb slip at mu R(t)),
    R(t) the normal contact force of each normal attractor."""
    model = parse_model(settings)
    exc = parse_excitation(model, pa, pa_newton, fe)
    fm = _friction_model()
    o = _FRICTION.get() or {}
    if o["fe_range"] is not None and o["vd_range"] is not None:
        raise InputError("--fe-range and --vd-range: give one of them")
    _belongs(o)
    excs = None if o["fe_range"] is None else [_grid_excitation(model, pa, pa_newton, f) for f in _frequencies(o)]
    from contactvib.friction.sweep import check_velocities, friction_vs_frequency, friction_vs_velocity

    vds = None if o["vd_range"] is None else mapped_options(_FRICTION_NAMES, check_velocities, *o["vd_range"], o["nvd"])
    search = search_settings(starts, seed, kmax, max_periods)
    out = None if out is None else checked_output_folder(out)
    if excs is not None:
        if not as_json:
            click.echo(_header(model, excs[0], fm).replace(f", f_e = {excs[0].f_e:g} Hz", ""))
            click.echo(_SWEEP_HEAD)

        def show(_exc, new):
            if not as_json and new:
                _print_sweep_rows({k: [r[k] for r in new] for k in new[0]})
        with ctrl_c():
            sweep = friction_vs_frequency(model, excs, fm, {**search, "seeds": not no_seeds}, on_point=show)
        _sweep_out(sweep, "fe_hz", out, as_json)
        return
    found = search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds)
    if vds is not None:
        with ctrl_c():
            sweep = friction_vs_velocity(model, exc, list(found), vds, fm)
        if not as_json:
            click.echo(_header(model, exc, fm))
            click.echo(_SWEEP_HEAD)
            _print_sweep_rows(sweep.rows)
        _sweep_out(sweep, "vd_mm_s", out, as_json)
        return
    _one_point(model, exc, list(found), fm, out, as_json)


__all__ = ["friction"]
