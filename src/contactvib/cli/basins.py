"""CLI command ``basins`` (basins of attraction on a grid of initial states at one operating point)."""

from __future__ import annotations

from pathlib import Path

import click

from contactvib.cli.common import (
    InputError,
    checked_option,
    checked_output_folder,
    ctrl_c,
    echo_json,
    model_blamed,
    operating_point_options,
    option_error,
    parse_excitation,
    parse_max_periods,
    parse_model,
    parse_number,
)
from contactvib.cli.system import system_given, system_option
from contactvib.cli.system_basins import slice_options, slice_values
from contactvib.model import ParameterError

#: Options of basins(), by the library's symbols.
_BASIN_OPTIONS = {"n_y": "--grid", "n_ydot": "--grid", "grid": "--grid", "y_min": "--y-range",
                  "y_max": "--y-range", "ydot_min": "--ydot-range", "ydot_max": "--ydot-range",
                  "kmax": "--kmax", "max_periods": "--max-periods", "n_starts": "--starts",
                  "seed": "--seed", "f_e": "--fe", "h_n": "--set h_n"}


def _grid(text: str) -> tuple[str, str]:
    """``"400x400"`` → ("400", "400") (the numbers are checked by the library)."""
    parts = text.strip().lower().split("x")
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise InputError(f"--grid = {text}: expected NxM, the grid points in y and in ydot, e.g. 400x400")
    return parts[0].strip(), parts[1].strip()


def _box(y_range, ydot_range, model, exc):
    """The box ((y_min, y_max), (ydot_min, ydot_max)) [µm, mm/s]; a range not given is the search's."""
    from contactvib.steady.basins import default_box

    if y_range is None and ydot_range is None:
        return None
    dy, dv = default_box(model, exc)
    y = dy if y_range is None else (parse_number("--y-range", "y_min", y_range[0]),
                                    parse_number("--y-range", "y_max", y_range[1]))
    v = dv if ydot_range is None else (parse_number("--ydot-range", "ydot_min", ydot_range[0]),
                                       parse_number("--ydot-range", "ydot_max", ydot_range[1]))
    return y, v


@click.command()
@system_option
@operating_point_options
@click.option("--grid", "grid", default="400x400", show_default=True, metavar="NxM",
              help="Grid points in y and in dy/dt (each >= 2); with --system along the two --slice components "
                   "(default 100x100).")
@slice_options
@click.option("--y-range", nargs=2, default=None, metavar="YMIN YMAX",
              help="Initial displacements y [µm] (default: the attractor search's box).")
@click.option("--ydot-range", nargs=2, default=None, metavar="VMIN VMAX",
              help="Initial velocities dy/dt [mm/s] (default: the attractor search's box).")
@click.option("--kmax", default="8", show_default=True, help="Largest period searched.")
@click.option("--max-periods", default="auto", show_default=True,
              help="Transient limit per start [excitation periods]; auto: as the attractor search.")
@click.option("--starts", default="512", show_default=True,
              help="Random starts of the attractor search (with --system default 64).")
@click.option("--out", "out", default=None, type=click.Path(file_okay=False),
              help="Output folder for basins.nc and the figure [default: basins; none with --json].")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the documented contract).")
def basins(pa, pa_newton, fe, settings, grid, y_range, ydot_range, kmax, max_periods, starts, out, as_json):
    """Basins of attraction: which attractor each initial state (y, dy/dt) reaches; with --system, on a
    2-D slice of the system's state space (--slice)."""
    from contactvib.steady.basins import check_basins
    from contactvib.steady.transients import check_damped

    if system_given():
        from contactvib.cli.system_basins import system_basins_command

        system_basins_command(pa, pa_newton, fe, settings, grid, kmax, max_periods, starts, out, as_json, _grid)
        return
    for option, value in slice_values().items():
        if value is not None:
            raise InputError(f"{option} belongs to --system (a slice of a system's state space); the paper's slider "
                             f"takes --y-range and --ydot-range")
    model = parse_model(settings)
    exc = parse_excitation(model, pa, pa_newton, fe)
    box = _box(y_range, ydot_range, model, exc)
    mp = parse_max_periods(max_periods)
    try:  # the bounds keep their symbols: "--y-range (y_max) = -1: must be > y_min = 1 µm"
        checked = check_basins(_grid(grid), box, kmax, mp, starts)
    except ParameterError as e:
        raise option_error(_BASIN_OPTIONS.get(e.symbol, e.symbol), e) from None
    checked_option("--set h_n", check_damped, model, "basins of attraction")
    if out is None and not as_json:
        out = "basins"
    new = out is not None and not Path(out).exists()
    folder = None if out is None else checked_output_folder(out)
    from contactvib.steady.basins import basins as run

    grid_, box_, kmax_, mp_, starts_, seed_ = checked
    try:
        with ctrl_c():
            bmap = run(exc, grid=grid_, box=box_, kmax=kmax_, max_periods=mp_, n_starts=starts_, seed=seed_)
    except ParameterError as e:  # a --set that moved f_n0 out of reach is named (not --fe)
        _remove_if_empty(folder if new else None)
        blamed = model_blamed(model, e, _grid_within_reach(exc, grid_[0] * grid_[1], mp_))
        raise (blamed or option_error(_BASIN_OPTIONS.get(e.symbol, e.symbol), e, _BASIN_OPTIONS)) from None
    except BaseException:
        _remove_if_empty(folder if new else None)
        raise
    paths = [] if folder is None else _write(bmap, folder)
    if as_json:
        echo_json(bmap.to_json())
        return
    _table(bmap, exc, model)
    for p in paths:
        click.echo(f"wrote {p}")


def _remove_if_empty(folder) -> None:
    """Remove ``folder`` (made by this command for its output) if nothing was written into it."""
    if folder is not None and folder.is_dir() and not any(folder.iterdir()):
        folder.rmdir()


def _grid_within_reach(exc, n_grid: int, max_periods):
    """Whether the grid's integration at ``exc``'s excitation is within the work limit for a
    model (a test for ``model_blamed``)."""
    import dataclasses

    from contactvib.steady.attractors import default_max_periods
    from contactvib.steady.transients import WORK_MAX_STEPS, check_work

    def accepts(model):
        e = dataclasses.replace(exc, model=model)
        return check_work(e, n_grid, max_periods or default_max_periods(e)) <= WORK_MAX_STEPS

    return accepts


def _write(bmap, folder) -> list:
    """OUT/basins.nc (atomic) and OUT/basins_pa…_fe….png."""
    from contactvib.plotting.basins import basins_figure
    from contactvib.plotting.figures import save_figure
    from contactvib.sweeps.dataset import write_atomic

    s = bmap.search
    nc = folder / "basins.nc"
    write_atomic(bmap.to_dataset(), nc)
    png = save_figure(basins_figure(bmap), folder / f"basins_pa{s.pa_over_q:g}_fe{s.fe_hz:g}.png")
    return [nc, png]


def _table(bmap, exc, model) -> None:
    ny, nv = bmap.y_um.size, bmap.ydot_mm_s.size
    click.echo(f"P_a = {exc.pa_over_q:g} Q, f_e = {exc.f_e:g} Hz, f_n0 = {model.f_n0:.1f} Hz; "
               f"{ny}x{nv} starts, y in [{bmap.y_um[0]:.4g}, {bmap.y_um[-1]:.4g}] um, "
               f"dy/dt in [{bmap.ydot_mm_s[0]:.4g}, {bmap.ydot_mm_s[-1]:.4g}] mm/s")
    click.echo(f"{'label':>5} {'period':>6} {'minima':>6} {'A_pp [um]':>10} {'fraction':>9} {'stderr':>8}")
    for r in bmap.fractions():
        if r["label"] < 0 and r["fraction"] == 0.0:
            continue
        kind = "-" if r["label"] < 0 else bmap.attractors[r["label"]].kind
        per = {"chaotic": "chaos", "quasi-periodic": "q-per"}.get(kind, "-") if r["period"] is None \
            else str(r["period"])
        mins = "-" if r["minima_per_period"] is None else str(r["minima_per_period"])
        app = "-" if r["app_um"] is None else f"{r['app_um']:.4g}"
        click.echo(f"{r['label']:>5} {per:>6} {mins:>6} {app:>10} {r['fraction']:>9.2%} {r['stderr']:>8.2%}")
