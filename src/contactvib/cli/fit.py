"""CLI command ``fit``: contact parameters from measurements (:func:`contactvib.fit`)."""

from __future__ import annotations

import json

import click

from contactvib.cli.common import (
    InputError,
    checked_option,
    checked_output_folder,
    ctrl_c,
    echo_json,
    option_error,
    parse_int,
    parse_model,
    parse_number,
)
from contactvib.model import PARAMETER_UNITS, ParameterError

#: Names --fix takes (the fitted products and exponents, a decay's initial state).
FIX_NAMES = ("S_c_n", "m2", "S_h_n", "l", "y_init_um", "v_init_mm_s")
#: Names --bounds takes (f_n0_hz and zeta bound S_c_n and S_h_n through the fit's coordinates).
BOUND_NAMES = ("f_n0_hz", "m2", "zeta", "l", "y_init_um", "v_init_mm_s")
_DATA_OPTIONS = {"static": "--static", "decay": "--decay", "frf": "--frf", "data": "--static/--decay/--frf"}


def _pairs(option: str, items, names) -> dict:
    out = {}
    for item in items:
        if "=" not in item:
            raise InputError(f"{option} {item}: expected NAME=VALUE with NAME one of {', '.join(names)}")
        name, value = (s.strip() for s in item.split("=", 1))
        if name not in names:
            raise InputError(f"{option} {name}: unknown name; known: {', '.join(names)}")
        if name in out:
            raise InputError(f"{option} {name} given twice")
        out[name] = value
    return out


def _fixes(items) -> dict:
    return {k: parse_number(f"--fix {k}", k, v) for k, v in _pairs("--fix", items, FIX_NAMES).items()}


def _bounds(items) -> dict:
    out = {}
    for k, v in _pairs("--bounds", items, BOUND_NAMES).items():
        parts = v.split(":")
        if len(parts) != 2:
            raise InputError(f"--bounds {k}={v}: expected NAME=LOWER:UPPER")
        out[k] = (parse_number(f"--bounds {k}", k, parts[0]), parse_number(f"--bounds {k}", k, parts[1]))
    return out


def _read(kind: str, path):
    from contactvib.fitting.data import load

    return checked_option(_DATA_OPTIONS[kind], load, kind, path) if path is not None else None


@click.command()
@click.option("--static", "static", default=None, metavar="FILE.csv",
              help="Static load-deflection curve: columns load_n,deflection_um (from first contact).")
@click.option("--decay", default=None, metavar="FILE.csv",
              help="Free decay (tap test): columns t_ms,y_um (about the static point) or t_ms,a_ms2; or a "
                   "universal file (.uff/.unv) dataset 58.")
@click.option("--frf", default=None, metavar="FILE.csv",
              help="Stepped-sine sweeps: columns fe_hz,force_amplitude_n,app_um,direction (up/down).")
@click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
              help="Given parameters (M always: --set M=...): " + ", ".join(f"{k} [{PARAMETER_UNITS[k]}]"
                                                                            for k in ("M", "g", "S")))
@click.option("--fix", multiple=True, metavar="NAME=VALUE",
              help="Hold a parameter at a known value: " + ", ".join(FIX_NAMES) + ".")
@click.option("--bounds", multiple=True, metavar="NAME=LO:HI",
              help="Bounds of the search: " + ", ".join(BOUND_NAMES) + " (f_n0_hz and zeta bound S_c_n, S_h_n).")
@click.option("--starts", default="8", show_default=True, help="Random starts added to the estimated ones.")
@click.option("--seed", default="0", show_default=True, help="Random seed of the starts.")
@click.option("--save-model", default=None, metavar="FILE.json",
              help="Write the fitted model (ContactModel parameters) for --model of other commands.")
@click.option("--out", default=None, type=click.Path(file_okay=False),
              help="Folder for fit.json, the fitted model and the figures (data, model, residuals).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--no-progress", is_flag=True, help="No progress bar on stderr.")
def fit(static, decay, frf, settings, fix, bounds, starts, seed, save_model, out, as_json, no_progress):
    """Fit the contact parameters (S c_n, m2, S h_n, l) to measurements by least squares."""
    from contactvib.errors import ComputationError
    from contactvib.fitting.solver import fit as fit_data

    if static is None and decay is None and frf is None:
        raise InputError("fit: give at least one of --static, --decay, --frf")
    if not any(s.split("=", 1)[0].strip() == "M" for s in settings):
        raise InputError("--set M=...: the slider mass M [kg] must be given (it is never fitted)")
    model = parse_model(settings)
    fixes, box = _fixes(fix), _bounds(bounds)
    n_starts = parse_int("--starts", starts, 0, 1000)
    n_seed = parse_int("--seed", seed, 0)
    if out is not None:
        out = checked_output_folder(out)
    if save_model is not None:
        _save_model_folder(save_model)
    data = {k: _read(k, p) for k, p in (("static", static), ("decay", decay), ("frf", frf))}
    options = {**_DATA_OPTIONS, **{k: f"--fix {k}" for k in FIX_NAMES}, **{k: f"--bounds {k}" for k in BOUND_NAMES}}
    code = 0
    try:
        with ctrl_c():
            result = fit_data(**data, model=model, fix=fixes, bounds=box, n_starts=n_starts, seed=n_seed,
                              progress=not no_progress and not as_json)
    except ParameterError as e:
        raise option_error(options.get(e.symbol, e.symbol), e, options) from None
    except ComputationError as e:
        click.echo(f"contactvib: error: {e}", err=True)
        result, code = e.result, 1
    if as_json:
        echo_json(result.to_dict())
    else:
        click.echo(result.table())
    if save_model is not None:
        _write_model(save_model, result)
    if out is not None:
        _write_outputs(out, result, as_json)
    if code:
        click.get_current_context().exit(code)


def _save_model_folder(path) -> None:
    """The folder of ``--save-model`` exists or is created, and can be written (before fitting)."""
    from pathlib import Path

    try:
        folder = Path(path).parent
    except (TypeError, ValueError):
        raise InputError(f"--save-model = {path}: not a file name") from None
    if "\0" in str(path) or Path(path).is_dir():
        raise InputError(f"--save-model = {path}: not a file name (a folder, or a NUL character)")
    checked_output_folder(folder, "--save-model", file=path)


def _write_model(path, result) -> None:
    with open(path, "w") as fh:
        json.dump(result.model.parameters(), fh, indent=1)


def _write_outputs(out, result, quiet: bool) -> None:
    from contactvib.fitting.curves import model_curves
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.fit import fit_figures

    (out / "fit.json").write_text(json.dumps(result.to_dict(), indent=1, allow_nan=False))
    _write_model(out / "fitted_model.json", result)
    written = [out / "fit.json", out / "fitted_model.json"]
    for name, fig in fit_figures(result, model_curves(result)).items():
        written.append(save_figure(fig, out / f"fit_{name}.png"))
    if not quiet:
        for p in written:
            click.echo(f"wrote {p}")
