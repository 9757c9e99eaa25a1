"""CLI commands ``continue``, ``bifurcations`` and ``evolution`` (periodic-orbit continuation).

Thin: parse and validate (one-line errors, exit 2), call :mod:`contactvib.periodic`, write NetCDF
branch files and figures, print a summary or the JSON contract
``{"special_points": [...], "stops": [{"fe_hz", "reason"}, ...]}``.
"""

from __future__ import annotations

from pathlib import Path

import click

from contactvib.cli.common import InputError, _frequency_range, _int, _model, _number, _pa_level

__all__ = []


def _settings(fmin, fmax, max_points, app_max, rtol, pa_range=(0.0, 2.0)):
    from contactvib.model import ParameterError
    from contactvib.continuation.shooting import ContinuationSettings

    lo, hi = _frequency_range(fmin, fmax)
    n = _int("--max-points", max_points, 2)
    a = _number("--app-max", "A_pp,max", app_max)
    if a <= 0:
        raise InputError(f"--app-max (A_pp,max) = {a:g}: must be > 0 um")
    r = _number("--rtol", "rtol", rtol)
    if not (1e-14 <= r <= 1e-6):
        raise InputError(f"--rtol (rtol) = {r:g}: must be in [1e-14, 1e-6]")
    try:
        return ContinuationSettings(fmin=lo, fmax=hi, pa_min=pa_range[0], pa_max=pa_range[1],
                                    max_points=n, app_max_um=a, rtol=r, tol=max(100 * r, 1e-11))
    except ParameterError as e:
        raise InputError(f"{e.symbol} = {e.value}: {e.allowed}") from None


def _continuation_options(f):
    f = click.option("--rtol", default="1e-12", show_default=True,
                     help="Integrator tolerance of the shooting (1e-14..1e-6).")(f)
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
    f = click.option("--dataset", default=None, type=click.Path(), metavar="FILE",
                     help="Resonance dataset (paper.nc, resonance.nc): also draw the branches over "
                          "its resonance graph (overlay_<tag>.png).")(f)
    return f


def _open_dataset(path, levels):
    """The resonance dataset for the overlay, checked before any computation (or None)."""
    if path is None:
        return None
    import xarray as xr

    if not Path(path).is_file():
        raise InputError(f"--dataset = {path}: no such file")
    try:
        ds = xr.load_dataset(path)
    except Exception as e:  # not NetCDF, damaged
        raise InputError(f"--dataset = {path}: not a readable NetCDF dataset ({type(e).__name__})") from None
    if "branch_label" not in ds:
        raise InputError(f"--dataset = {path}: not a contactvib resonance dataset")
    import numpy as np

    stored = np.unique(ds["pa_over_q"].values)
    for p in levels:
        if np.min(np.abs(stored - p)) > 1e-6:
            raise InputError(f"--pa (P_a/Q) = {p:g}: not in --dataset; stored levels: "
                             + ", ".join(f"{v:g}" for v in stored))
    return ds


def _write(bset, out: Path, tag: str, title: str, model, ds=None, pa=None, parameter="f_e"):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contactvib.plotting.branches import plot_branches

    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for b in bset:
        p = out / f"branch_{b.branch.replace('/', '_')}.nc"
        b.to_netcdf(p)
        paths.append(p)
    if len(bset.special_points):
        bset.special_table().to_netcdf(out / f"special_points_{tag}.nc")
    (out / f"special_points_{tag}.json").write_text(bset.to_json(indent=1))
    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    plot_branches(bset, ax, title=title, parameter=parameter)
    fig.tight_layout()
    fig_path = out / f"branches_{tag}.png"
    fig.savefig(fig_path, dpi=130)
    plt.close(fig)
    if ds is not None:  # continuation (stable solid, unstable dashed) over the sweep's attractors
        from contactvib.plotting.figures import resonance_graph

        fig, ax = plt.subplots(figsize=(8.0, 5.0))
        resonance_graph(ds, pa, ax=ax, annotate=False)
        for line in ax.lines:
            line.set_alpha(0.45)
        plot_branches(bset, ax, title=f"{title}, over the sweep's attractors (faint)")
        fig.tight_layout()
        fig.savefig(out / f"overlay_{tag}.png", dpi=130)
        plt.close(fig)
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
@click.option("--pa", default="0.65", show_default=True, metavar="Q",
              help="Excitation amplitude P_a as a multiple of Q = M g.")
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
def continue_(pa, from_fe, attractor, parameter, pa_min, pa_max, settings, no_switch, dataset,
              fmin, fmax, max_points, app_max, rtol, out, as_json):
    """Continue branches of periodic orbits in f_e (or P_a) from the attractors at one point."""
    model = _model(settings)
    p = _pa_level(pa)
    by_pa = parameter == "pa"
    if by_pa and dataset is not None:
        raise InputError("--dataset draws over a resonance graph in f_e: not with --parameter pa")
    ds = _open_dataset(dataset, [p])
    fe = _number("--from-fe", "f_e", from_fe)
    if fe <= 0:
        raise InputError(f"--from-fe (f_e) = {fe:g}: must be > 0 Hz")
    lo = _pa_level(pa_min, "--pa-min")
    hi = _pa_level(pa_max, "--pa-max")
    if by_pa and not lo < hi:
        raise InputError(f"--pa-min (P_a/Q) = {lo:g}: must be < --pa-max = {hi:g}")
    if by_pa and not lo <= p <= hi:
        raise InputError(f"--pa (P_a/Q) = {p:g}: must lie in [--pa-min, --pa-max] = [{lo:g}, {hi:g}]")
    s = _settings(fmin, fmax, max_points, app_max, rtol, (lo, hi) if by_pa else (0.0, 2.0))
    if not by_pa and not (s.fmin <= fe <= s.fmax):
        raise InputError(f"--from-fe (f_e) = {fe:g}: must lie in [--fmin, --fmax] = [{s.fmin:g}, {s.fmax:g}] Hz")
    n = None if attractor is None else _int("--attractor", attractor, 0)
    from contactvib.steady.attractors import find_attractors
    from contactvib.continuation.diagram import continue_attractors

    found = find_attractors(model, model.excitation(p, fe))
    if n is not None and n >= len(found):
        raise InputError(f"--attractor (N) = {n}: must be an index 0..{len(found) - 1} of the "
                         f"{len(found)} attractors found at {fe:g} Hz")
    msgs = []
    bset = continue_attractors(model, p, fe, n, s, switch=not no_switch, attractors=found,
                               log=msgs.append, parameter="P_a" if by_pa else "f_e")
    tag = f"pa{p:g}_fe{fe:g}" + ("_in_pa" if by_pa else "")
    title = (f"$f_e$ = {fe:g} Hz, branches in $P_a$ from the attractors at {p:g} Q" if by_pa
             else f"$P_a$ = {p:g} Q, branches from the attractors at {fe:g} Hz")
    paths, fig = _write(bset, Path(out), tag, title, model, ds, p,
                        parameter="P_a" if by_pa else "f_e")
    if as_json:
        click.echo(bset.to_json())
        return
    _summary(bset, "P_a" if by_pa else "f_e")
    for m in msgs:
        click.echo(f"note: {m}")
    click.echo(f"wrote {len(paths)} branch files and {fig}")


@click.command(context_settings={"allow_extra_args": True})
@click.option("--pa", default="0.65", show_default=True, metavar="Q [Q ...]",
              help="Excitation amplitudes P_a [Q]; several values after one --pa.")
@click.option("--seed-fe", default=None, metavar="HZ,HZ,...",
              help="Seed frequencies [Hz] of the attractor searches (comma-separated).")
@_continuation_options
@click.option("--out", default="bif", show_default=True, type=click.Path(file_okay=False),
              help="Output folder.")
@click.option("--json", "as_json", is_flag=True, help="Print the JSON contract.")
@click.pass_context
def bifurcations(ctx, pa, seed_fe, settings, no_switch, dataset, fmin, fmax, max_points, app_max,
                 rtol, out, as_json):
    """All branches, seeded from every attractor at several frequencies, for each P_a."""
    model = _model(settings)
    levels = [_pa_level(t) for t in [pa, *ctx.args]]
    ds = _open_dataset(dataset, levels)
    s = _settings(fmin, fmax, max_points, app_max, rtol)
    from contactvib.continuation.diagram import DEFAULT_SEED_FE

    if seed_fe is None:
        seeds = [f for f in DEFAULT_SEED_FE if s.fmin <= f <= s.fmax]
    else:
        seeds = [_number("--seed-fe", "f_e", t) for t in seed_fe.split(",") if t.strip()]
        for f in seeds:
            if not (s.fmin <= f <= s.fmax):
                raise InputError(f"--seed-fe (f_e) = {f:g}: must lie in [--fmin, --fmax] = "
                                 f"[{s.fmin:g}, {s.fmax:g}] Hz")
    if not seeds:
        raise InputError("--seed-fe: no seed frequency inside [--fmin, --fmax]")
    from contactvib.continuation.branch import BranchSet
    from contactvib.continuation.diagram import bifurcation_diagram

    allb = BranchSet([])
    for p in levels:
        bset = bifurcation_diagram(model, p, seeds, s, switch=not no_switch)
        _write(bset, Path(out), f"pa{p:g}", f"$P_a$ = {p:g} Q: all branches", model, ds, p)
        allb.branches.extend(bset.branches)
        if not as_json:
            click.echo(f"P_a = {p:g} Q: {len(bset)} branches, {len(bset.special_points)} special points")
    (Path(out) / "bifurcations.json").write_text(allb.to_json(indent=1))
    if as_json:
        click.echo(allb.to_json())
    else:
        click.echo(f"wrote {out}/")


@click.command()
@click.option("--order", default="2", show_default=True, help="m of the 1/m resonance (1..8).")
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
    model = _model(settings)
    m = _int("--order", order, 1, 8)
    lo = _pa_level(pa_min, "--pa-min")
    hi = _pa_level(pa_max, "--pa-max")
    if hi <= lo:
        raise InputError(f"--pa-max (P_a/Q) = {hi:g}: must be > --pa-min = {lo:g}")
    n = _int("--levels", levels, 2, 50)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from contactvib.continuation.evolution import evolution as run
    from contactvib.plotting.branches import plot_evolution

    msgs = []
    res = run(model, m, lo, hi, n, log=msgs.append)
    outp = Path(out)
    outp.mkdir(parents=True, exist_ok=True)
    (outp / f"evolution_order{m}.json").write_text(res.to_json(indent=1))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    plot_evolution(res, ax, title=f"evolution of the 1/{m} resonance: folds and period doublings")
    fig.tight_layout()
    fig.savefig(outp / f"evolution_order{m}.png", dpi=130)
    plt.close(fig)
    if as_json:
        click.echo(res.to_json())
        return
    for line in msgs:
        click.echo(line)
    for k, (f, p) in res.extremes.items():
        click.echo(f"{k}: f_e = {f:.5g} Hz, P_a = {p:.4g} Q")
    click.echo(f"wrote {outp}/evolution_order{m}.png and .json")
