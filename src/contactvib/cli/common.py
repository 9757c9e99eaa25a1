"""Shared argument parsing of the command line: one-line input errors, numbers, the model and the
operating point, option groups. The checks themselves are the library's (``contactvib.model``):
this module maps option names onto them."""

from __future__ import annotations

import click

from contactvib.model import PAPER_DEFAULTS, PARAMETER_UNITS, ContactModel, Excitation, ParameterError


class InputError(Exception):
    """A user input error: printed as one line, no traceback, no usage banner."""


def _checked(option: str, func, *args):
    try:
        return func(*args)
    except ParameterError as e:
        raise InputError(f"{option} ({e.symbol}) = {_show(e.value)}: {e.allowed}") from None


def _show(value) -> str:
    try:
        return f"{float(value):g}"
    except (TypeError, ValueError):
        return str(value)


def _number(option: str, symbol: str, text: str) -> float:
    from contactvib.model import check_finite

    return _checked(option, check_finite, symbol, text)


def _model(settings: tuple[str, ...]) -> ContactModel:
    overrides = {}
    for item in settings:
        if "=" not in item:
            raise InputError(f"--set {item}: expected NAME=VALUE with NAME one of {', '.join(PAPER_DEFAULTS)}")
        name, value = (s.strip() for s in item.split("=", 1))
        if name not in PAPER_DEFAULTS:
            raise InputError(f"--set {name} ({name}) = {value}: unknown parameter; known: "
                             f"{', '.join(PAPER_DEFAULTS)}")
        overrides[name] = _number(f"--set {name}", name, value)
    for name, value in overrides.items():
        try:
            ContactModel(**{name: value})
        except ParameterError as e:
            if e.symbol == name:  # the parameter's own range; combinations are checked below
                raise InputError(f"--set {name} ({e.symbol}) = {_show(e.value)}: {e.allowed}") from None
    # a combination out of range (the damping ratio) names every --set the user gave
    given = " ".join(f"--set {k}={_show(v)}" for k, v in overrides.items()) or "the paper's parameters"
    return _checked(given, ContactModel.from_overrides, overrides)


def _excitation(model: ContactModel, pa: str | None, pa_newton: str | None, fe: str) -> Excitation:
    fe_v = _number("--fe", "f_e", fe)
    if pa is not None and pa_newton is not None:
        raise InputError("--pa and --pa-newton: give one of them, not both")
    if pa_newton is not None:
        p = _number("--pa-newton", "P_a", pa_newton)
        if p < 0:
            raise InputError(f"--pa-newton (P_a) = {_show(p)}: must be >= 0 N")
        pa_q = p / model.Q
    else:
        pa_q = _number("--pa", "P_a/Q", pa if pa is not None else "0.65")
        if pa_q < 0:
            raise InputError(f"--pa (P_a/Q) = {_show(pa_q)}: must be >= 0 (multiple of Q = M g)")
    if fe_v <= 0:
        raise InputError(f"--fe (f_e) = {_show(fe_v)}: must be > 0 Hz")
    return model.excitation(pa_q, fe_v)


def _frequency_range(fmin: str, fmax: str) -> tuple[float, float]:
    """--fmin/--fmax [Hz], checked: 0 < f_min < f_max."""
    lo = _number("--fmin", "f_min", fmin)
    hi = _number("--fmax", "f_max", fmax)
    if lo <= 0:
        raise InputError(f"--fmin (f_min) = {lo:g}: must be > 0 Hz")
    if hi <= lo:
        raise InputError(f"--fmax (f_max) = {hi:g}: must be > --fmin = {lo:g} Hz")
    return lo, hi


def _pa_level(text: str, option: str = "--pa") -> float:
    """A P_a level [Q] that must be > 0."""
    v = _number(option, "P_a/Q", text)
    if v <= 0:
        raise InputError(f"{option} (P_a/Q) = {v:g}: must be > 0 (multiple of Q = M g)")
    return v


def _int(option: str, text: str, lower: int, upper: int | None = None) -> int:
    v = _number(option, option.lstrip("-"), text)
    if v != int(v) or v < lower or (upper is not None and v > upper):
        rng = f">= {lower}" if upper is None else f"in {lower}..{upper}"
        raise InputError(f"{option} ({option.lstrip('-')}) = {_show(text)}: must be an integer {rng}")
    return int(v)


def _operating_point_options(f):
    f = click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
                     help="Override a model parameter by its paper symbol: "
                          + ", ".join(f"{k} [{PARAMETER_UNITS[k]}]" for k in PAPER_DEFAULTS))(f)
    f = click.option("--fe", default="360", show_default=True, metavar="HZ",
                     help="Excitation frequency f_e [Hz], > 0.")(f)
    f = click.option("--pa-newton", default=None, metavar="N",
                     help="Excitation amplitude P_a in newtons (instead of --pa).")(f)
    f = click.option("--pa", default=None, metavar="Q",
                     help="Excitation amplitude P_a as a multiple of Q = M g (default 0.65).")(f)
    return f


def _search_options(f):
    f = click.option("--no-seeds", is_flag=True, help="Skip the ballistic seeds (box starts only).")(f)
    f = click.option("--max-periods", default="400", show_default=True,
                     help="Transient limit per start [excitation periods].")(f)
    f = click.option("--kmax", default="8", show_default=True, help="Largest period searched (1..64).")(f)
    f = click.option("--seed", default="0", show_default=True, help="Random seed of the start box.")(f)
    f = click.option("--starts", default="512", show_default=True, help="Random starts in the box.")(f)
    return f


