"""CLI commands ``perturbation`` (series solution vs numerics) and ``hbm`` (harmonic balance)."""

from __future__ import annotations

import json

import click

from contactvib.cli.common import (
    checked_output_folder,
    echo_json,
    feasible_frequencies,
    law_options,
    level_kind_option,
    operating_point_options,
    parse_excitation,
    parse_frequency_range,
    parse_int,
    parse_levels,
    parse_model,
    parse_positive,
)
from contactvib.cli.errors import InputError, checked_option
from contactvib.cli.system import system_given, system_option
from contactvib.model import HARMONICS_MAX, LEVEL_TAGS, PA_NOTE, check_range, excitation_at, level_text
from contactvib.model.checks import PA_MAX

_CONV_TERMS_MAX = 80
#: The one line ``--order`` (the deprecated name of ``--terms``) prints on stderr.
ORDER_DEPRECATED = "contactvib: warning: --order is deprecated, use --terms"


@click.command()
@operating_point_options
@click.option("--terms", default="40", show_default=True, metavar="N",
              help="Number of terms N of the series in P_a/Q (1..400).")
@click.option("--order", default=None, hidden=True, metavar="N",
              help="Deprecated name of --terms.")
@click.option("--summation", type=click.Choice(["pade", "plain"]), default="pade",
              show_default=True, help="Padé per harmonic (converges near resonances) or the "
                                      "plain partial sum.")
@click.option("--out", default=None, type=click.Path(file_okay=False),
              help="Folder for the overlay and convergence figures (and convergence.csv).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the documented contract).")
def perturbation(pa, pa_newton, fe, settings, terms, order, summation, out, as_json):
    """Perturbation series of the steady state, its validity, and a comparison with the numerics."""
    model = parse_model(settings)
    exc = parse_excitation(model, pa, pa_newton, fe)
    from contactvib.frequency.perturbation import (
        MAX_TERMS,
        convergence_table,
        perturbation_series,
        steady_counterpart,
    )

    n = _parse_terms(terms, order, MAX_TERMS)
    if out is not None:
        out = checked_output_folder(out)
    if order is not None:
        click.echo(ORDER_DEPRECATED, err=True)

    res = perturbation_series(exc, terms=n, summation=summation)
    if as_json and out is None:
        echo_json(res.to_json())
        return
    num = steady_counterpart(model, exc, res)
    if as_json:
        echo_json(res.to_json())
    else:
        click.echo(f"P_a = {exc.pa_over_q:g} Q, f_e = {exc.f_e:g} Hz, f_n0 = {model.f_n0:.1f} Hz, "
                   f"N = {n} terms ({summation} summation)")
        click.echo(f"  series:    A_pp = {res.app_um:.6g} um, y_min = {res.ymin_um:.6g} um, "
                   f"y_max = {res.ymax_um:.6g} um, estimated A_pp error {res.error_estimate_um:.2g} um")
        click.echo("  valid:     " + ("yes" if res.valid else f"NO: {res.reason}"))
        click.echo(f"  numerics:  A_pp = {num.app_um:.6g} um, y_min = {num.ymin_um:.6g} um "
                   f"(period {num.period}, {num.minima_per_period} minima, "
                   f"{'loses contact' if num.loses_contact else 'contact kept'}); "
                   f"relative A_pp difference {abs(res.app_um - num.app_um) / num.app_um:.2e}")
        h = ", ".join(f"{a:.4g}" for a in res.harmonics_um[:7])
        click.echo(f"  harmonics [um], k = 0..6 (k = 0: mean shift): {h}")
    if out is None:
        return
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.frequency import convergence_figure, overlay_figure
    from contactvib.steady.simulate import attractor_history

    tag = f"pa{exc.pa_over_q:g}_fe{exc.f_e:g}"
    hist_num = attractor_history(exc, num, n_periods=2, samples_per_period=1000)
    series = res.history(n_periods=2, samples_per_period=1000) if res.valid else None
    note = "" if res.valid else f"perturbation series not drawn: {res.reason}"
    head = (f"$P_a$ = {exc.pa_over_q:g} Q, $f_e$ = {exc.f_e:g} Hz: perturbation (N = {n}, "
            f"{summation}) vs numerics; $A_{{pp}}$ {res.app_um:.4g} vs {num.app_um:.4g} µm")
    if not res.valid:
        head = (f"$P_a$ = {exc.pa_over_q:g} Q, $f_e$ = {exc.f_e:g} Hz: numerics, $A_{{pp}}$ = "
                f"{num.app_um:.4g} µm; perturbation series (N = {n}) INVALID, not drawn:\n"
                + res.reason.split(";")[0])
        note = ""
    p1 = save_figure(overlay_figure(hist_num, series, head, note), out / f"perturbation_{tag}.png")
    terms_list = sorted(set(range(2, min(max(n, 8), _CONV_TERMS_MAX) + 1, 2)) | {1})
    tables = {s: convergence_table(model, exc, terms_list, num.app_um, s) for s in ("plain", "pade")}
    lines = ["terms,app_plain_um,relerr_plain,estimate_plain_um,app_pade_um,relerr_pade,estimate_pade_um"]
    for rp, rq in zip(tables["plain"], tables["pade"]):
        lines.append(f"{rp[0]},{rp[1]:.12g},{rp[2]:.3e},{rp[3]:.3e},{rq[1]:.12g},{rq[2]:.3e},{rq[3]:.3e}")
    p2 = out / f"convergence_{tag}.csv"
    p2.write_text("\n".join(lines) + "\n")
    fig = convergence_figure({"plain": tables["plain"], "Padé": tables["pade"]},
                             f"$P_a$ = {exc.pa_over_q:g} Q, $f_e$ = {exc.f_e:g} Hz: series vs "
                             f"shooting ($A_{{pp}}$ = {num.app_um:.5g} µm)")
    p3 = save_figure(fig, out / f"convergence_{tag}.png")
    if not as_json:
        for p in (p1, p2, p3):
            click.echo(str(p))


def _parse_terms(terms, order, max_terms: int) -> int:
    """N from ``--terms``, or from ``--order`` (its deprecated name; the warning comes after every
    check, so that a refusal stays one line)."""
    if order is None:
        return parse_int("--terms", terms, 1, max_terms)
    if click.get_current_context().get_parameter_source("terms") != click.core.ParameterSource.DEFAULT:
        raise InputError("--order: the deprecated name of --terms; give --terms only")
    return parse_int("--order", order, 1, max_terms, symbol="terms")


@click.command()
@law_options
@click.option("--pa", default="0.65", show_default=True, metavar="Q",
              help="Excitation amplitude P_a as a multiple of Q = M g.")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a model parameter by its paper symbol (as for `attractors`).")
@click.option("--harmonics", default="32", show_default=True, metavar="H",
              help=f"Number of harmonics H (1..{HARMONICS_MAX}).")
@click.option("--fmin", default="300", show_default=True, metavar="HZ", help="Lowest f_e [Hz].")
@click.option("--fmax", default="2000", show_default=True, metavar="HZ", help="Highest f_e [Hz].")
@click.option("--energy-tol", default="1e-8", show_default=True,
              help="Stop a branch when the top quarter of the harmonics holds more than this "
                   "share of the energy.")
@click.option("--out", default="hbm", show_default=True, type=click.Path(file_okay=False),
              help="Output folder for the branch figure and branch.json.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object instead of the table.")
@level_kind_option
@system_option
@click.option("--pa-newton", default=None, metavar="N",
              help="With --system: the force level P_a [N] (a system file defines no Q).")
@click.option("--n-time", default=None, metavar="N",
              help="With --system: time samples of the AFT per period (default 128 H: a contact that closes "
                   "for a small part of the period needs many).")
@click.option("--plot", default=None, metavar="NAME",
              help="With --system: the coordinate drawn (default the first).")
@click.option("--measure", type=click.Choice(["app", "h1"]), default="app", show_default=True,
              help="With --system: draw the peak-to-peak value (app) or the first harmonic's amplitude (h1).")
def hbm(pa, settings, harmonics, fmin, fmax, energy_tol, out, as_json, level_kind, **system_options):
    """Harmonic-balance branches A_pp(f_e), continued from --fmin upwards and from --fmax down
    (with --system: the branch of a structure with contacts, from --fmin upwards)."""
    so = system_options
    if system_given():
        from contactvib.cli.system_branches import system_hbm

        ctx = click.get_current_context()
        given = {n: ctx.get_parameter_source(n) != click.core.ParameterSource.DEFAULT for n in ("pa", "energy_tol")}
        return system_hbm(pa if given["pa"] else None, so["pa_newton"], settings, harmonics, so["n_time"], fmin, fmax,
                          energy_tol if given["energy_tol"] else "1e-3", so["plot"], so["measure"], out, as_json)
    for option in ("pa_newton", "n_time", "plot"):
        if so[option] is not None:
            raise InputError(f"--{option.replace('_', '-')}: an option of --system only")
    model = parse_model(settings)
    if level_kind == "force":
        pa_q = checked_option("--pa", check_range, "P_a/Q", pa, 0.0, True, PA_NOTE)
        pa_q = checked_option("--pa", check_range, "P_a/Q", pa_q, None, unit=PA_NOTE, upper=PA_MAX)
    else:
        pa_q = parse_levels((pa,), level_kind)[0]
    H = parse_int("--harmonics", harmonics, 1, HARMONICS_MAX)
    f1, f2 = parse_frequency_range(fmin, fmax)
    feasible_frequencies(model, f1, f2)
    if level_kind != "force":  # the inertial force at the top of the range must be allowed
        checked_option("--pa", excitation_at, model, pa_q, f2, level_kind)
    etol = parse_positive("--energy-tol", "energy_tol", energy_tol)
    outp = checked_output_folder(out)
    from contactvib.frequency.harmonic_balance import HBSettings, hb_continuation

    hs = HBSettings(energy_tol=etol)
    kw = {"pa_over_q": pa_q, "fmin_hz": f1, "fmax_hz": f2, "harmonics": H, "settings": hs, "excitation": level_kind}
    branches = [("from fmin", hb_continuation(model, **kw)),
                ("from fmax", hb_continuation(model, from_fmax=True, **kw))]
    # the perturbation series seeds the small-amplitude parts: the paper's law under a force
    series = _series_points(model, pa_q, f1, f2) if model.is_paper_family and level_kind == "force" else ([], [])
    branches += _branches_from_series(model, pa_q, f1, f2, H, etol, series, branches)
    payload = {"pa_over_q": pa_q, "harmonics": H, "fmin_hz": f1, "fmax_hz": f2,
               **({} if level_kind == "force" else {"excitation": level_kind}),
               "model": model.parameters(),
               "branches": [dict(b.to_dict(), start=name) for name, b in branches]}
    (outp / "branch.json").write_text(json.dumps(payload))
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.frequency import hbm_figure

    sym, rest = level_text(pa_q, level_kind, 6).split(" = ")
    base = "" if level_kind == "force" else " (base motion)"
    law = "" if model.is_paper_family else f"\n{model.describe_law()}"
    fig = hbm_figure([(f"HB (H = {H}) {name}", b) for name, b in branches], series, model.f_n0,
                     (f1, f2), f"Harmonic balance, ${sym}$ = {rest}{base} (dots: loss of contact){law}")
    path = save_figure(fig, outp / f"hbm_branch_{LEVEL_TAGS[level_kind]}{pa_q:g}_H{H}.png")
    if as_json:
        echo_json(payload)
        return
    for name, b in branches:
        click.echo(f"branch {name}: {len(b)} points, f_e {b.fe_hz.min():.1f}..{b.fe_hz.max():.1f} Hz, "
                   f"A_pp {b.app_um.min():.4g}..{b.app_um.max():.4g} um, "
                   f"{int((~b.stable).sum())} unstable points; {b.stop_reason}")
    click.echo(str(path))


def _series_points(model, pa_q, f1, f2, terms: int = 40, n: int = 120):
    """Frequencies and A_pp of the valid perturbation series on a log grid (small amplitudes)."""
    import numpy as np

    from contactvib.frequency.perturbation import perturbation_series

    fs, apps = [], []
    for f in np.geomspace(f1, f2, n):
        r = perturbation_series(model.excitation(pa_q, float(f)), terms=terms)
        if r.valid:
            fs.append(float(f))
            apps.append(r.app_um)
    return fs, apps


def _passes(branch, f, app, rtol=0.02):
    """Whether a branch passes through (f, app): some segment spans f at A_pp within rtol."""
    fe, a = branch.fe_hz, branch.app_um
    for i in range(fe.size - 1):
        lo, hi = sorted((fe[i], fe[i + 1]))
        if lo <= f <= hi:
            w = 0.0 if hi == lo else (f - fe[i]) / (fe[i + 1] - fe[i])
            if abs(a[i] + w * (a[i + 1] - a[i]) - app) <= rtol * app:
                return True
    return False


def _branches_from_series(model, pa_q, f1, f2, H, etol, series, branches):
    """Continue, both ways, from the middle of each run of valid series points that no branch
    found yet (the small-amplitude parts between the superharmonic resonances)."""
    import numpy as np

    from contactvib.frequency.harmonic_balance import HBSettings, hb_continuation, hb_solve
    from contactvib.frequency.perturbation import perturbation_series

    fs, apps = series
    grid = np.geomspace(f1, f2, 120)
    idx = [int(np.argmin(np.abs(grid - f))) for f in fs]
    runs, cur = [], []
    for i, j in enumerate(idx):
        if cur and j != idx[i - 1] + 1:
            runs.append(cur)
            cur = []
        cur.append(i)
    if cur:
        runs.append(cur)
    new = []
    for run in runs:
        mid = run[len(run) // 2]
        f, a = fs[mid], apps[mid]
        if any(_passes(b, f, a) for _name, b in branches + new):
            continue
        c = perturbation_series(model.excitation(pa_q, f), terms=40).sum_coefficients
        X = np.zeros(2 * H + 1)
        X[0] = 1.0 + c[0].real
        k = min(H, c.size - 1)
        X[1:2 * k + 1:2] = 2.0 * c[1:k + 1].real
        X[2:2 * k + 1:2] = -2.0 * c[1:k + 1].imag
        start = hb_solve(model.excitation(pa_q, f), harmonics=H, start=X, stability=False)
        for down in (False, True):
            new.append((f"from {f:.0f} Hz {'down' if down else 'up'}",
                        hb_continuation(model, pa_over_q=pa_q, fmin_hz=f1, fmax_hz=f2, harmonics=H,
                                        settings=HBSettings(energy_tol=etol),
                                        start=start, from_fmax=down, f_start=f)))
    return new
