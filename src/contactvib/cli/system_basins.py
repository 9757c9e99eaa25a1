"""``contactvib basins --system ...``: the basins of a structure of several coordinates on a 2-D
slice of its state space (:mod:`contactvib.steady.system_basins`).

Thin: the options are checked here (one line, exit 2) before anything is computed.
"""

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
    parse_int,
    parse_number,
    scoped_options,
)
from contactvib.cli.progress import start_progress_bar
from contactvib.cli.system import (
    load_system_option,
    modes_text,
    option_given,
    parse_system_state,
    system_operating_point,
)

__all__ = ["system_basins_command", "GRID_DEFAULT_TEXT", "slice_options", "slice_values"]

#: --slice, --a-range and --b-range of the command being run.
_SLICE: contextvars.ContextVar = contextvars.ContextVar("contactvib_slice", default=None)

#: The grid with --system unless --grid is given.
GRID_DEFAULT_TEXT = "100x100"
#: Options of system_basins(), by the library's symbols.
_OPTIONS = {"slice": "--slice", "n_a": "--grid", "n_b": "--grid", "grid": "--grid", "a_min": "--a-range",
            "a_max": "--a-range", "b_min": "--b-range", "b_max": "--b-range", "kmax": "--kmax",
            "max_periods": "--max-periods", "n_starts": "--starts", "P_a": "--pa-newton", "f_e": "--fe",
            "base_state": "--through"}


def slice_options(f):
    """--slice, --a-range, --b-range (kept out of the command's signature: :func:`slice_values`)."""
    f = scoped_options(_SLICE, ("slice_", "a_range", "b_range", "through"), f)
    f = click.option("--through", "through", nargs=2, default=None, metavar="Q1,Q2,.. QDOT1,QDOT2,..",
                     help="With --system: the state the slice passes through (positions in um or urad, rates in "
                          "mm/s or mrad/s): the components the grid does not vary keep its values (default: the "
                          "static state, at rest).")(f)
    f = click.option("--b-range", "b_range", nargs=2, default=None, metavar="MIN MAX",
                     help="With --system: the range of the second --slice component [its display unit].")(f)
    f = click.option("--a-range", "a_range", nargs=2, default=None, metavar="MIN MAX",
                     help="With --system: the range of the first --slice component [its display unit] (default: "
                          "the attractor search's box).")(f)
    return click.option("--slice", "slice_", default=None, metavar="A,B",
                        help="With --system: the two state components the grid varies, each a coordinate "
                             "(displacement, um or urad) or a coordinate with _dot (its rate, mm/s or mrad/s), e.g. "
                             "q1,q1_dot or y,theta; the other components stay at the static state, at rest. Default: "
                             "the first contact's coordinate and its rate.")(f)


def slice_values() -> dict:
    """{"--slice": ..., "--a-range": ..., "--b-range": ..., "--through": ...} of the command being run
    (None: not given)."""
    v = _SLICE.get() or {}
    return {"--slice": v.get("slice_"), "--a-range": v.get("a_range"), "--b-range": v.get("b_range"),
            "--through": v.get("through")}


def _range(option: str, lo_sym: str, hi_sym: str, values):
    """(min, max) of a two-number range option, or None."""
    if values is None:
        return None
    return parse_number(option, lo_sym, values[0]), parse_number(option, hi_sym, values[1])


def system_basins_command(pa, pa_newton, fe, settings, grid, kmax, max_periods, starts, out, as_json,
                          parse_grid) -> None:
    """``contactvib basins --system ...``: the table and OUT/system_basins.nc and its figure, or the
    JSON contract with --json. ``parse_grid``: the ``NxM`` parser of ``basins``."""
    from contactvib.steady.system_attractors import STARTS_DEFAULT
    from contactvib.steady.system_basins import check_system_basins, system_basins

    for name, option in (("y_range", "--y-range"), ("ydot_range", "--ydot-range")):
        if option_given(name):
            raise InputError(f"--system and {option}: name the slice's components with --slice and their ranges "
                             f"with --a-range and --b-range")
    given = slice_values()
    slice_, a_range, b_range = given["--slice"], given["--a-range"], given["--b-range"]
    system, model, label = load_system_option(settings)
    base = None if given["--through"] is None else np.concatenate(parse_system_state(system, given["--through"],
                                                                                     "--through"))
    p, f_e, level = system_operating_point(model, label, pa, pa_newton, fe)
    axes = None if slice_ is None else tuple(s.strip() for s in slice_.split(","))
    n = parse_grid(grid if option_given("grid") else GRID_DEFAULT_TEXT)
    box = None
    a, b = _range("--a-range", "a_min", "a_max", a_range), _range("--b-range", "b_min", "b_max", b_range)
    kw = {"n_starts": parse_int("--starts", starts, 1, symbol="n_starts") if option_given("starts") else STARTS_DEFAULT,
          "kmax": parse_int("--kmax", kmax, 1),
          "max_periods": None if str(max_periods).strip().lower() == "auto"
          else parse_int("--max-periods", max_periods, 1, symbol="max_periods")}
    checked = mapped_options(_OPTIONS, check_system_basins, system, axes, n, None, base, kw["kmax"],
                             kw["max_periods"], kw["n_starts"], 0)
    axes, grid_ = checked[0], checked[2]
    if a is not None or b is not None:
        from contactvib.steady.system_basins import default_slice_box

        default = default_slice_box(system, p, f_e, axes, base)
        box = (a or default[0], b or default[1])
        mapped_options(_OPTIONS, check_system_basins, system, axes, grid_, box, base, kw["kmax"], kw["max_periods"],
                       kw["n_starts"], 0)
    folder = None if (out is None and as_json) else checked_output_folder(out or "basins")
    if not as_json:
        click.echo(f"system {label}: {level}, f_e = {f_e:g} Hz; {modes_text(system, model)}")
    with ctrl_c(), start_progress_bar("basin grid") as progress:
        bmap = mapped_options(_OPTIONS, system_basins, system, p, f_e, axes=axes, grid=grid_, box=box,
                              base_state=base, progress=progress, **kw)
    paths = [] if folder is None else _write(bmap, folder)
    if as_json:
        echo_json(bmap.to_json())
        return
    _table(bmap)
    for path in paths:
        click.echo(f"wrote {path}")


def _write(bmap, folder) -> list:
    """OUT/system_basins.nc (atomic) and OUT/system_basins_pa…N_fe….png."""
    from contactvib.plotting.basins import system_basins_figure
    from contactvib.plotting.figures import save_figure
    from contactvib.sweeps.dataset import write_atomic

    s = bmap.search
    nc = folder / "system_basins.nc"
    write_atomic(bmap.to_dataset(), nc)
    png = save_figure(system_basins_figure(bmap), folder / f"system_basins_pa{s.pa_newton:g}N_fe{s.fe_hz:g}.png")
    return [nc, png]


def _table(bmap) -> None:
    (na, nb), (ua, ub) = bmap.axes, bmap.units
    click.echo(f"{bmap.a.size}x{bmap.b.size} starts at phase 0: {na} in [{bmap.a[0]:.4g}, {bmap.a[-1]:.4g}] {ua}, "
               f"{nb} in [{bmap.b[0]:.4g}, {bmap.b[-1]:.4g}] {ub}; the other components "
               + ("at the --through state" if bmap.base_given else "at the static state, at rest"))
    click.echo(f"{'label':>5} {'period':>6} {'minima':>6} {'stable':>6} {'fraction':>9} {'stderr':>8}")
    for r in bmap.fractions():
        if r["label"] < 0 and r["fraction"] == 0.0:
            continue
        per = "-" if r["label"] < 0 else (str(r["period"]) if r["period"] is not None else
                                           {"chaotic": "chaos", "quasi-periodic": "q-per"}[r["attractor_type"]])
        mins = "-" if r["minima_per_period"] is None else str(r["minima_per_period"])
        stable = "-" if r["label"] < 0 else ("yes" if bmap.attractors[r["label"]].stable else "no")
        click.echo(f"{r['label']:>5} {per:>6} {mins:>6} {stable:>6} {r['fraction']:>9.2%} {r['stderr']:>8.2%}")
