"""CLI commands ``section`` (Poincaré sections and impact maps at one operating point) and
``orbit-diagram`` (every attractor's stroboscopic points along f_e or P_a, coloured by λ1)."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import click

from contactvib.cli.common import (
    InputError,
    checked_output_folder,
    ctrl_c,
    echo_json,
    law_options,
    mapped_options,
    operating_point_options,
    parse_excitation,
    parse_int,
    parse_model,
    parse_number,
    search_options,
)
from contactvib.cli.steady import search_attractors

#: Figure formats of --out.
_FIGURE_SUFFIXES = (".png", ".svg", ".pdf")


def _checked_file(path: str | None, option: str, suffixes: tuple[str, ...]) -> Path | None:
    """``path`` (None: not given) with one of ``suffixes``, its folder created and writable."""
    if path is None:
        return None
    p = Path(path)
    checked_output_folder(p.parent if str(p.parent) else ".", option, file=path)
    if p.suffix.lower() not in suffixes:
        raise InputError(f"{option} = {path}: must end with {', '.join(suffixes)}")
    return p


def _periods(text: str, option: str = "--periods") -> int:
    from contactvib.steady.sections import check_section_periods

    return mapped_options({"n_periods": option}, check_section_periods, text)


@click.command()
@operating_point_options
@search_options
@click.option("--periods", default="1000", show_default=True,
              help="Excitation periods integrated per non-periodic attractor (a period-k orbit: its k periods).")
@click.option("--attractor", "only", default=None, metavar="I",
              help="Draw and write only attractor I (its number in the table, as contactvib attractors lists it).")
@click.option("--impacts", is_flag=True, help="Add the impact map: phase and velocity at each contact loss.")
@click.option("--out", default=None, metavar="FILE.png",
              help="Figure file (.png, .svg, .pdf); default section_pa<P>_fe<F>.png.")
@click.option("--csv", "csv_path", default=None, metavar="FILE.csv", help="Write one row per point (units header).")
@click.option("--json", "as_json", is_flag=True, help="Print the points as one JSON object.")
def section(pa, pa_newton, fe, settings, periods, impacts, out, csv_path, as_json, only, **search):
    """Stroboscopic Poincaré section (y, dy/dt at t = k/f_e) of every attractor at (P_a, f_e); with
    --impacts the impact map (excitation phase and dy/dt at each contact loss)."""
    from contactvib.cli.steady import search_settings

    model = parse_model(settings)
    exc = parse_excitation(model, pa, pa_newton, fe)
    n = _periods(periods)
    index = None if only is None else parse_int("--attractor", only, 0, symbol="attractor")
    starts, seed, kmax, max_periods, no_seeds = (search[k] for k in ("starts", "seed", "kmax", "max_periods",
                                                                      "no_seeds"))
    search_settings(starts, seed, kmax, max_periods)
    out = _checked_file(out or f"section_pa{exc.level[1]:g}_fe{exc.f_e:g}.png", "--out", _FIGURE_SUFFIXES)
    csv = _checked_file(csv_path, "--csv", (".csv",))
    found = search_attractors(model, exc, starts, seed, kmax, max_periods, no_seeds)
    from contactvib.steady.sections import poincare_sections

    if index is not None and index >= len(found):
        raise InputError(f"--attractor (attractor) = {index}: must be an integer in 0..{len(found) - 1} "
                         f"({len(found)} attractors found)")
    with ctrl_c():
        result = poincare_sections(exc, found, n_periods=n)
    if index is not None:
        result = dataclasses.replace(result, sections=[result[index]])
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.sections import section_figure

    save_figure(section_figure(result, impacts), out)
    if csv is not None:
        result.to_csv(csv, impacts)
    if as_json:
        echo_json(result.to_dict(impacts))
        return
    click.echo(f"{result.level}, f_e = {result.fe_hz:g} Hz: {len(found)} attractors")
    click.echo(f"{'#':>2} {'kind':>14} {'points':>7} {'losses':>7} {'lambda1 [1/period]':>19}")
    for s in result:
        kind = f"period {s.period}" if s.period is not None else s.kind
        click.echo(f"{s.index:>2} {kind:>14} {s.y_um.size:>7} {s.loss_phase_rad.size:>7} {s.lambda1:>19.4g}")
    for s in result:
        if s.search_kind:
            click.echo(f"   #{s.index}: {s.search_kind} by the search (periods up to --kmax); its section repeats "
                       f"after {s.period} periods and Newton shooting gives a stable period-{s.period} orbit")
    click.echo(str(out))
    if csv is not None:
        click.echo(str(csv))


#: The library's symbols of the orbit diagram's options.
_DIAGRAM_NAMES = {"f_from": "--fe-from", "f_to": "--fe-to", "df": "--fe-step", "pa_from": "--pa-from",
                  "pa_to": "--pa-to", "dpa": "--pa-step", "n_periods": "--periods", "search_every": "--search-every",
                  "n_starts": "--starts", "kmax": "--kmax", "vary": "--vary", "P_a/Q": "--pa", "f_e": "--fe"}


def _diagram_settings(vary, grid: dict, periods, search_every, starts, kmax):
    """The OrbitDiagramSettings of the options (the library checks them; we name the options)."""
    from contactvib.steady.orbit_diagram import OrbitDiagramSettings

    own, other = ("fe", "pa") if vary == "fe" else ("pa", "fe")
    for part in ("from", "to", "step"):
        if grid[f"{other}_{part}"] is not None:
            raise InputError(f"--{other}-{part}: belongs to --vary {other}; with --vary {vary} give "
                             f"--{own}-from, --{own}-to, --{own}-step")
    values = []
    for part in ("from", "to", "step"):
        text = grid[f"{own}_{part}"]
        if text is None:
            raise InputError(f"--{own}-{part}: needed with --vary {vary}")
        values.append(parse_number(f"--{own}-{part}", part, text))
    nums = {k: parse_number(_DIAGRAM_NAMES[k], k, t) for k, t in
            (("n_periods", periods), ("search_every", search_every), ("n_starts", starts), ("kmax", kmax))}
    return mapped_options(_DIAGRAM_NAMES, OrbitDiagramSettings, vary, *values, **nums)


def _progress_bar(total_hint: str):
    from tqdm import tqdm

    bar = []

    def progress(done, total):
        if not bar:
            bar.append(tqdm(total=total, unit="point", file=sys.stderr, leave=False, dynamic_ncols=True,
                            desc=total_hint))
        bar[0].update(done - bar[0].n)
        if done >= total:
            bar.pop().close()

    return progress


@click.command("orbit-diagram")
@law_options
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Override a model parameter by its symbol (as contactvib attractors --set).")
@click.option("--vary", type=click.Choice(["fe", "pa"]), default="fe", show_default=True,
              help="The parameter along the diagram: f_e (--fe-from/--fe-to/--fe-step at --pa) or P_a "
                   "(--pa-from/--pa-to/--pa-step at --fe).")
@click.option("--pa", default="0.75", show_default=True, metavar="Q", help="P_a [Q] held fixed with --vary fe.")
@click.option("--fe", default=None, metavar="HZ", help="f_e [Hz] held fixed with --vary pa.")
@click.option("--fe-from", default=None, metavar="HZ", help="First f_e [Hz] (--vary fe).")
@click.option("--fe-to", default=None, metavar="HZ", help="Last f_e [Hz], > --fe-from.")
@click.option("--fe-step", default=None, metavar="HZ", help="f_e step [Hz], > 0.")
@click.option("--pa-from", default=None, metavar="Q", help="First P_a [Q] (--vary pa).")
@click.option("--pa-to", default=None, metavar="Q", help="Last P_a [Q], > --pa-from.")
@click.option("--pa-step", default=None, metavar="Q", help="P_a step [Q], > 0.")
@click.option("--periods", default="64", show_default=True,
              help="Transient periods before each record, and strobe points recorded per attractor and grid point.")
@click.option("--search-every", default="8", show_default=True,
              help="A fresh attractor search every this many grid points (the first one always).")
@click.option("--starts", default="256", show_default=True, help="Random starts of each search.")
@click.option("--kmax", default="8", show_default=True, help="Largest period searched and detected.")
@click.option("--workers", default="2", show_default=True,
              help="Processes, each walking a contiguous part of the grid (one numba thread each); 1: one "
                   "process, the searches on the numba threads.")
@click.option("--measure", type=click.Choice(["y", "v-loss"]), default="y", show_default=True,
              help="Plot the stroboscopic y [um], or dy/dt at each contact loss [mm/s].")
@click.option("--ylim", nargs=2, default=None, metavar="LO HI", help="Vertical range of the figure [um or mm/s].")
@click.option("--out", default=None, metavar="FILE.png",
              help="Figure file (.png, .svg, .pdf); default orbit_diagram_<vary>.png.")
@click.option("--csv", "csv_path", default=None, metavar="FILE.csv", help="Write one row per point (units header).")
@click.option("--nc", "nc_path", default=None, metavar="FILE.nc", help="Write the Dataset as NetCDF.")
def orbit_diagram(settings, vary, pa, fe, measure, ylim, out, csv_path, nc_path, **grid):
    """Orbit diagram: every attractor's stroboscopic y (or dy/dt at contact loss) against f_e or P_a,
    each attractor followed from grid point to grid point, coloured by the largest Lyapunov
    exponent λ1 [1/period]."""
    from contactvib.model import WORKERS_MAX, Excitation

    model = parse_model(settings)
    n_workers = parse_int("--workers", grid.pop("workers"), 1, WORKERS_MAX, symbol="workers")
    sset = _diagram_settings(vary, grid, *(grid[k] for k in ("periods", "search_every", "starts", "kmax")))
    if vary == "fe":
        fixed = parse_number("--pa", "P_a/Q", pa)
    else:
        if fe is None:
            raise InputError("--fe: needed with --vary pa (the f_e [Hz] held fixed)")
        fixed = parse_number("--fe", "f_e", fe)
    ends = [(fixed, v) if vary == "fe" else (v, fixed) for v in (sset.start, sset.stop)]
    names = {**_DIAGRAM_NAMES, "f_e": "--fe-from" if vary == "fe" else "--fe",
             "P_a/Q": "--pa" if vary == "fe" else "--pa-to"}
    for p, f in ends:
        mapped_options(names, Excitation, model, p, f)
    lims = None if ylim is None else tuple(parse_number("--ylim", "y", t) for t in ylim)
    if lims is not None and not lims[0] < lims[1]:
        raise InputError(f"--ylim {ylim[0]} {ylim[1]}: LO must be < HI")
    out = _checked_file(out or f"orbit_diagram_{vary}.png", "--out", _FIGURE_SUFFIXES)
    csv = _checked_file(csv_path, "--csv", (".csv",))
    nc = _checked_file(nc_path, "--nc", (".nc",))
    from contactvib.steady.orbit_diagram import orbit_diagram as run

    kw = {"pa_over_q": fixed} if vary == "fe" else {"fe_hz": fixed}
    with ctrl_c():
        ds = mapped_options(names, run, model, settings=sset, workers=n_workers,
                            progress=_progress_bar("orbit diagram"), **kw)
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.sections import orbit_diagram_figure
    from contactvib.steady.orbit_diagram import write_csv

    fig = orbit_diagram_figure(ds, measure)
    if lims is not None:
        fig.axes[0].set_ylim(*lims)
    save_figure(fig, out)
    if csv is not None:
        write_csv(ds, csv, measure)
    if nc is not None:
        ds.to_netcdf(nc)
    n_att = len(set(ds["attractor"].values.tolist()))
    chaotic = int((ds["lambda1"].values > 0.0).sum())
    click.echo(f"{sset.grid().size} grid points, {n_att} attractors followed, {ds.sizes['point']} strobe points "
               f"({chaotic} with lambda1 > 0), {ds.sizes['loss']} contact losses")
    for path in (out, csv, nc):
        if path is not None:
            click.echo(str(path))
