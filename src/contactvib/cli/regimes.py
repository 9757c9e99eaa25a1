"""CLI command ``map``: regime maps of a resonance dataset over (f_e, P_a), with the fold and
period-doubling curves of the 1/m resonances on top.

Thin: check the dataset, the orders, the curves folder and the output folder (one-line errors,
exit 2), call :func:`contactvib.sweeps.regimes.regime_maps` (and
:func:`~contactvib.sweeps.regimes.evolution_curves` for ``--orders``), write ``map.nc`` and one
PNG per map.
"""

from __future__ import annotations

import json
from pathlib import Path

import click

from contactvib.cli.common import InputError, LevelsCommand, checked_output_folder, open_dataset_argument, parse_int
from contactvib.model import EVOLUTION_ORDER_MAX

__all__: list = []


class OrdersCommand(LevelsCommand):
    """``--orders 2 3``: the values right after ``--orders`` are its orders."""

    multi = ("--orders", "orders m of the 1/m resonances")


def _model_of(ds, path):
    from contactvib import ContactModel
    from contactvib.model import ParameterError

    try:
        return ContactModel(**json.loads(ds.attrs["model"]))
    except (KeyError, TypeError, ValueError, ParameterError) as e:
        raise InputError(f"DATASET = {path}: its 'model' attribute is missing or damaged "
                         f"({type(e).__name__})") from None


@click.command("map", cls=OrdersCommand)
@click.argument("dataset", type=click.Path())
@click.option("--orders", multiple=True, metavar="M [M ...]",
              help=f"Compute the fold and period-doubling curves of these 1/m resonances (1..{EVOLUTION_ORDER_MAX}) "
                   "by two-parameter continuation over the dataset's P_a range and overlay them "
                   "(minutes per order; default: none).")
@click.option("--curves", "curves_dir", default=None, type=click.Path(), metavar="FOLDER",
              help="Overlay the curves saved by `contactvib evolution --out FOLDER` (evolution_order*.json).")
@click.option("--out", default="map", show_default=True, type=click.Path(file_okay=False),
              help="Output folder: map.nc and one map_<quantity>.png per map.")
def map_(dataset, orders, curves_dir, out):
    """Regime maps over (f_e, P_a) of a dataset with many levels: coexisting attractors, highest
    resonance order, contact loss, chaos, largest period (and the lowest and highest friction
    ratio of a dataset swept with --friction)."""
    from contactvib.sweeps.regimes import load_curves

    ms = sorted({parse_int("--orders", t, 1, EVOLUTION_ORDER_MAX) for t in orders})
    if ms and curves_dir is not None:
        raise InputError("--curves: give either --orders (compute the curves) or --curves (reuse them)")
    curves = []
    if curves_dir is not None:
        try:
            curves = load_curves(curves_dir)
        except LookupError as e:
            raise InputError(f"--curves = {e}") from None
    data = open_dataset_argument(dataset)
    path, ds = data.path, data.ds
    with data:
        levels = data.levels
        model = _model_of(ds, path) if ms else None
        if ms and ds.attrs.get("excitation", "force") != "force":
            raise InputError(f"--orders: the curves are continued in P_a; DATASET = {path} holds base-motion "
                             f"levels ({ds.attrs['level_symbol']} [{ds.attrs['level_unit']}])")
        if ms and len(levels) < 2:
            raise InputError(f"--orders: the curves need a range of P_a; DATASET = {path} has one level")
        outp = checked_output_folder(out)
        run(ds, outp, curves, model, ms, (levels[0], levels[-1]) if levels else None)


def run(ds, outp: Path, curves, model, orders, pa_range):
    """Compute (curves for ``orders``, the maps), write, print the summary."""
    import numpy as np
    import xarray as xr

    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.regimes import regime_figure
    from contactvib.sweeps.dataset import write_atomic
    from contactvib.sweeps.regimes import (
        FRICTION_MAPS,
        MAP_VARIABLES,
        count_changes,
        curve_crossings,
        curves_dataset,
        evolution_curves,
        regime_maps,
    )

    if orders:
        curves = evolution_curves(model, orders, *pa_range, out=outp, log=None)
    maps = regime_maps(ds)
    write_atomic(xr.merge([maps, curves_dataset(curves)], combine_attrs="override"), outp / "map.nc")
    names = [n for n in MAP_VARIABLES + FRICTION_MAPS if n in maps]  # friction: datasets swept with it
    for name in names:
        save_figure(regime_figure(maps, name, curves), outp / f"map_{name}.png")
    n = maps["n_attractors"].values
    nl = maps.sizes["pa_over_q"]
    chaos = f", chaos at {int(maps['chaotic'].values.sum())} grid points" if "chaotic" in maps else ""
    click.echo(f"{nl} level{'s' * (nl != 1)} x {maps.sizes['fe_hz']} frequencies: "
               f"{int(n.min())}..{int(n.max())} coexisting attractors{chaos}")
    folds = [c for c in curves if c.type == "fold"]
    if folds:
        df = float(maps.attrs["df_hz"])
        hits = total = 0
        for p in maps["pa_over_q"].values:
            changes = count_changes(maps, p)
            for f in np.concatenate([curve_crossings(c, p) for c in folds]):
                total += 1
                hits += bool(changes.size and np.min(np.abs(changes - f)) <= df)
        click.echo(f"{len(curves)} curves; {hits} of {total} fold crossings of the levels lie within one grid "
                   f"step ({df:g} Hz) of a change of the count")
    click.echo(f"wrote {outp / 'map.nc'} and {len(names)} figures map_*.png")
