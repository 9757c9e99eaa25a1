"""Shared argument parsing of the command line: one-line input errors, numbers, the model and the
operating point, option groups.

The checks and their ranges are the library's (:mod:`contactvib.model.checks`, and the settings
objects that use them); this module only maps option names onto the library's symbols and turns
a :class:`~contactvib.model.ParameterError` into one line,
``contactvib: error: --fe (f_e) = -5: must be > 0 Hz``. A new option is checked by calling the
library check with the library's symbol (``checked_option``), or by building the library object and
naming the option of each symbol (``mapped_options``); never by comparing numbers here.
"""

from __future__ import annotations

import contextvars
import functools
import json
import math

import click

from contactvib.cli.errors import (  # noqa: F401 (the commands import them from here)
    InputError,
    RunInterrupted,
    checked_option,
    ctrl_c,
    mapped_options,
    one_line,
    option_error,
    parse_int,
    parse_number,
    show_value,
)
from contactvib.model import (
    KMAX_SEARCH_MAX,
    LEVEL_KINDS,
    PAPER_DEFAULTS,
    PARAMETER_UNITS,
    ContactModel,
    Excitation,
    ParameterError,
    check_frequency_range,
    check_pa_level,
    check_range,
)
from contactvib.model.checks import format_number

#: The law options of the command being run (``law_options``): read by ``parse_model``.
LAW_OPTIONS: contextvars.ContextVar = contextvars.ContextVar("contactvib_law", default=None)
#: The excitation options of the command being run (``_excitation_family_options``).
_EXC: contextvars.ContextVar = contextvars.ContextVar("contactvib_excitation", default=None)


def _set_units() -> dict[str, str]:
    """Every name ``--set`` accepts, with its unit: the paper's, the Hunt–Crossley ``alpha``, and
    every registered law's parameters (the registry's, plug-ins included)."""
    from contactvib.model.laws import law_class, law_names

    units = {**{k: PARAMETER_UNITS[k] for k in PAPER_DEFAULTS}, "c_e": PARAMETER_UNITS["c_e"],
             "lam": PARAMETER_UNITS["lam"], "alpha": PARAMETER_UNITS["alpha"]}
    for law in law_names():
        for p in law_class(law).parameters:
            units.setdefault(p.name, p.unit)
    return units


#: Every name ``--set`` accepts, with its unit (``SET_NAMES``: the names in that order).
SET_UNITS = _set_units()
SET_NAMES = tuple(SET_UNITS)
_LAW_OPTION_NAMES = {"law": "--law", **{k: f"--set {k}" for k in SET_NAMES if k not in PAPER_DEFAULTS},
                     "damping": "--damping", "F_pre": "--preload", "law_file": "--law-file",
                     "law_params": "--set"}
#: Laws whose parameters are model fields of their own (the rest go into ``law_params``).
_FIELD_LAWS = ("power", "exponential", "table")


def _law_family(overrides: dict) -> dict:
    """The ContactModel keywords of the law options (--law, --law-file, --damping, --preload),
    each --set checked to belong to the chosen families; the --set values of a law without model
    fields of its own are taken out of ``overrides`` into ``law_params``."""
    from contactvib.model.laws import TableLaw
    from contactvib.model.oscillator import family_parameters

    opts = LAW_OPTIONS.get() or {}
    law = opts.get("law") or "power"
    damping = opts.get("damping") or "power"
    kw: dict = {}
    if law != "power":
        kw["law"] = law
    if damping != "power":
        kw["damping"] = damping
    law_file = opts.get("law_file")
    if law_file is not None and law != "table":
        raise InputError(f"--law-file = {law_file}: a table file belongs to --law table, not to --law {law}")
    if law == "table":
        if law_file is None:
            raise InputError("--law table: needs --law-file FILE.csv (columns deflection_um,load_n)")
        kw["table"] = checked_option("--law-file", TableLaw.from_csv, law_file)
    if opts.get("preload") is not None:
        kw["preload"] = checked_option("--preload", check_range, "F_pre", opts["preload"], 0.0, True, "N")
    families = family_parameters()
    own = families.get(law, ())
    for name in overrides:
        if name in own or name in families.get(f"damping {damping}", ()):
            continue
        for family, names in families.items():
            if name in names:
                flag = "--damping " + family.split()[1] if family.startswith("damping") else "--law " + family
                now = f"--damping {damping}" if family.startswith("damping") else f"--law {law}"
                raise InputError(f"--set {name}: a parameter of {flag}, not of {now}")
    if law not in _FIELD_LAWS:
        kw["law_params"] = {name: overrides.pop(name) for name in own if name in overrides}
    return kw


def read_model_file(path) -> dict:
    """The parameters of a model file (``--model``: ``contactvib fit --save-model``, the JSON of
    :meth:`ContactModel.parameters`, or any JSON object with such a ``model`` entry)."""
    try:
        with open(path, encoding="utf-8") as fh:
            p = json.load(fh)
        p = p.get("model", p) if isinstance(p, dict) else p
        if not isinstance(p, dict):
            raise ValueError("not a JSON object")
        ContactModel(**p)
    except ParameterError as e:
        raise option_error("--model", e) from None
    except (OSError, ValueError, TypeError) as e:
        raise InputError(f"--model = {path}: not a model file ({getattr(e, 'strerror', None) or e})") from None
    return p


def parse_model(settings: tuple[str, ...]) -> ContactModel:
    opts = LAW_OPTIONS.get() or {}
    base = read_model_file(opts["model_file"]) if opts.get("model_file") is not None else {}
    overrides = {}
    for item in settings:
        if "=" not in item:
            raise InputError(f"--set {item}: expected NAME=VALUE with NAME one of {', '.join(SET_NAMES)}")
        name, value = (s.strip() for s in item.split("=", 1))
        if name not in SET_NAMES:
            raise InputError(f"--set {name} ({name}) = {value}: unknown parameter; known: "
                             f"{', '.join(SET_NAMES)}")
        if name in overrides:
            raise InputError(f"--set {name} given twice")
        overrides[name] = parse_number(f"--set {name}", name, value)
    family = _law_family(overrides)
    if "law_params" in family:
        family["law_params"] = {**(base.get("law_params") or {}), **family["law_params"]}
        for name, value in family["law_params"].items():  # each value against its law's own bounds
            try:
                ContactModel(**{**base, **family, "law_params": {name: value}})
            except ParameterError as e:
                if e.symbol == name:
                    raise option_error(f"--set {name}", e) from None
    for name, value in overrides.items():
        try:
            ContactModel(**{**base, **family, name: value})
        except ParameterError as e:
            if e.symbol == name:  # the parameter's own range; combinations are checked below
                raise option_error(f"--set {name}", e) from None
    # a combination out of range (the damping ratio) names every --set the user gave
    given = " ".join(f"--set {k}={show_value(v)}" for k, v in {**overrides, **family.get("law_params", {})}.items()) \
        or "the paper's parameters"
    try:
        return ContactModel(**{**base, **family, **overrides})
    except ParameterError as e:
        if e.symbol in _LAW_OPTION_NAMES:
            raise option_error(_LAW_OPTION_NAMES[e.symbol], e) from None
        raise option_error(given, e) from None


def _set_changes(model: ContactModel) -> dict[str, float]:
    """The model's numeric parameters that differ from the paper's (what --set changed)."""
    return {k: v for k, v in model.parameters().items()
            if isinstance(v, float) and k in SET_NAMES and v != PAPER_DEFAULTS.get(k)}


def _boundary(model: ContactModel, name: str, accepts) -> float | None:
    """The value of parameter ``name`` between the model's and the paper's at which ``accepts``
    (a test of a model) turns true, by bisection (in log scale for positive values); None if
    the paper's value is not accepted either or the model cannot be rebuilt."""
    a, b = getattr(model, name), PAPER_DEFAULTS[name]

    def ok(x):
        try:
            return bool(accepts(model.replace(**{name: x})))
        except ParameterError:
            return False

    if not ok(b):
        return None
    log = a > 0.0 and b > 0.0
    lo, hi = (math.log(a), math.log(b)) if log else (a, b)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(math.exp(mid) if log else mid) else (mid, hi)
    return math.exp(hi) if log else hi


def model_blamed(model: ContactModel, e: ParameterError, accepts, option: str = "--fe") -> InputError | None:
    """An f_e refusal that the --set parameters cause (the frequency ratio r = f_e/f_n0 or the
    work of a search out of reach), as one line naming them: when the paper's parameters accept
    this f_e (``accepts(ContactModel())``), the --set values that moved f_n0 (and ζ) are to
    blame, with the range of each one alone that this f_e allows. None otherwise (``option``,
    the option that gave f_e, is named)."""
    changed = _set_changes(model)
    if e.symbol != "f_e" or not changed:
        return None
    paper = ContactModel()
    try:
        if not accepts(paper):
            return None
    except ParameterError:
        return None
    label = " ".join(f"--set {k} = {format_number(v)}" for k, v in changed.items())
    ranges = []
    for name, value in changed.items():
        edge = _boundary(model, name, accepts)
        if edge is not None:
            ranges.append(f"{name} {'>=' if edge > value else '<='} {edge:.4g}")
    allowed = f"; this f_e needs {' or '.join(ranges)} (each alone)" if ranges else ""
    return InputError(f"{label}: gives f_n0 = {model.f_n0:.6g} Hz, zeta = {model.zeta:.3g}; {option} (f_e) = "
                      f"{show_value(e.value)}: {e.allowed}{allowed}")


def scoped_options(var: contextvars.ContextVar, names: tuple[str, ...], f):
    """``f`` with the keyword arguments ``names`` taken out and kept in ``var`` while it runs."""
    @functools.wraps(f)
    def wrapper(*args, **kwargs):
        token = var.set({k: kwargs.pop(k, None) for k in names})
        try:
            return f(*args, **kwargs)
        finally:
            var.reset(token)
    return wrapper


def law_options(f):
    """--law, --law-file, --damping, --preload: the contact-law family of ``parse_model``."""
    from contactvib.model.laws import DAMPING_NAMES, law_class, law_names

    f = scoped_options(LAW_OPTIONS, ("law", "law_file", "damping", "preload", "model_file"), f)
    f = click.option("--model", "model_file", default=None, metavar="FILE.json",
                     help="Start from a saved model (contactvib fit --save-model); --set overrides it.")(f)
    f = click.option("--preload", default=None, metavar="N",
                     help="Constant normal force F_pre [N] pressing the slider down (y0, f_n0 from Q + F_pre).")(f)
    f = click.option("--damping", default="power", show_default=True, type=click.Choice(DAMPING_NAMES),
                     help="Contact damping: power S h_n y^l ydot (--set h_n, l) or hunt-crossley alpha F_s(y) ydot "
                          "(--set alpha [s/m]).")(f)
    f = click.option("--law-file", default=None, metavar="FILE.csv",
                     help="Load-deflection table of --law table: columns deflection_um,load_n from (0, 0).")(f)
    laws = "; ".join(f"{n}: {law_class(n).formula}"
                     + (f" (--set {', '.join(p.name for p in law_class(n).parameters)})" if law_class(n).parameters
                        else "") for n in law_names())
    f = click.option("--law", default="power", show_default=True, type=click.Choice(law_names()),
                     help=f"Contact spring law: {laws}.")(f)
    return f


def _excitation_family_options(f):
    """--base-um, --base-g, --harmonic: base motion or a multi-harmonic force for ``parse_excitation``."""
    f = scoped_options(_EXC, ("base_um", "base_g", "harmonic"), f)
    f = click.option("--harmonic", multiple=True, metavar="K:AMP:PHASE",
                     help="A further harmonic of the force: K f_e, amplitude AMP [Q], phase [deg] (repeatable).")(f)
    f = click.option("--base-g", default=None, metavar="A",
                     help="Base (slideway) motion of acceleration amplitude A [g = 9.80665 m/s^2], not a force.")(f)
    f = click.option("--base-um", default=None, metavar="U",
                     help="Base (slideway) motion u = U cos(2 pi f_e t), U [um], instead of a force.")(f)
    return f


def _harmonics(items) -> tuple:
    out = []
    for item in items:
        parts = item.split(":")
        if len(parts) != 3:
            raise InputError(f"--harmonic {item}: expected K:AMP:PHASE (e.g. 2:0.1:90)")
        out.append((parse_number("--harmonic", "k", parts[0]), parse_number("--harmonic", "P_k/Q", parts[1]),
                    parse_number("--harmonic", "phase", parts[2])))
    return tuple(out)


#: Options of the operating point, by the library's symbol.
_EXCITATION_OPTIONS = {"f_e": "--fe", "P_a/Q": "--pa", "P_a": "--pa-newton"}


def parse_excitation(model: ContactModel, pa: str | None, pa_newton: str | None, fe: str) -> Excitation:
    """The excitation of --pa or --pa-newton (or --base-um / --base-g), --harmonic and --fe,
    checked by :class:`Excitation`."""
    if pa is not None and pa_newton is not None:
        raise InputError("--pa and --pa-newton: give one of them, not both")
    fam = _EXC.get() or {}
    base = [(o, fam.get(k)) for o, k in (("--base-um", "base_um"), ("--base-g", "base_g")) if fam.get(k) is not None]
    names = {**_EXCITATION_OPTIONS, "U": "--base-um", "A": "--base-g", "k": "--harmonic", "P_k/Q": "--harmonic",
             "phase": "--harmonic", "harmonics": "--harmonic"}
    if base:
        given = [o for o, v in (("--pa", pa), ("--pa-newton", pa_newton)) if v is not None] + [o for o, _ in base]
        if len(given) > 1:
            raise InputError(f"{' and '.join(given)}: give one excitation (a force or a base motion), not both")
        if fam.get("harmonic"):
            raise InputError("--harmonic: harmonics belong to a force excitation, not to a base motion")
        (option, value), = base
        u = parse_number(option, "U" if option == "--base-um" else "A", value)
        kw = {"u_um": u} if option == "--base-um" else {"a_g": u}
        return mapped_options(names, Excitation.base, model, fe, **kw)
    harmonics = _harmonics(fam.get("harmonic") or ())
    try:
        if pa_newton is not None:
            return mapped_options(names, Excitation.from_newtons, model, pa_newton, fe, harmonics=harmonics)
        return mapped_options(names, Excitation, model, "0.65" if pa is None else pa, fe, harmonics=harmonics)
    except InputError as refused:
        try:
            f_e = float(fe)
        except ValueError:
            raise refused from None
        ratio = _frequency_ratio_error(model, f_e)
        blamed = ratio and model_blamed(model, ratio, lambda m: _frequency_ratio_error(m, f_e) is None)
        raise (blamed or refused) from None


def _frequency_ratio_error(model: ContactModel, f_e: float) -> ParameterError | None:
    """The refusal of ``f_e`` for ``model`` by the range of r = f_e/f_n0, or None."""
    try:
        Excitation(model, 0.0, f_e)
    except ParameterError as e:
        return e
    return None


def parse_frequency_range(fmin: str, fmax: str) -> tuple[float, float]:
    """--fmin/--fmax [Hz], checked by :func:`contactvib.model.check_frequency_range`."""
    return mapped_options({"f_min": "--fmin", "f_max": "--fmax"}, check_frequency_range, fmin, fmax)


def parse_pa_level(text: str, option: str = "--pa") -> float:
    """A P_a level [Q] > 0, checked by :func:`contactvib.model.check_pa_level`."""
    return checked_option(option, check_pa_level, text)


def parse_positive(option: str, symbol: str, text: str, unit: str = "") -> float:
    """A number > 0 [unit]."""
    return checked_option(option, check_range, symbol, text, 0.0, False, unit)


def _is_level(token: str) -> bool:
    """Whether ``token`` after ``--pa`` is one more level (a negative number is a level, refused
    by the level's range check); an option (``--fe``, ``-h``) or ``--`` ends the levels."""
    if token.startswith("--"):
        return False
    return not token.startswith("-") or token[1:2].isdigit() or token[1:2] == "."


class LevelsCommand(click.Command):
    """A command whose ``--pa`` takes one or more levels, ``--pa 0.5 0.6 0.65``: the values right
    after ``--pa`` (up to the next option) are its levels; a value anywhere else is refused.

    The command declares ``--pa`` with ``multiple=True``; ``--pa A B`` is read as
    ``--pa A --pa B``. A subclass names its own option and its values in ``multi``."""

    allow_extra_args = True  # collected here, to be refused with their value named
    #: (the option that takes one or more values, what its values are)
    multi = ("--pa", "levels P_a [Q]")

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        out: list[str] = []
        i = 0
        while i < len(args):
            token = args[i]
            if token == "--":
                out.extend(args[i:])
                break
            inline = token.startswith(self.multi[0] + "=")  # --pa=0.5 0.6: 0.6 is a level too
            if (token != self.multi[0] and not inline) or ctx.resilient_parsing:
                out.append(token)
                i += 1
                continue
            i += 1
            levels = [token.split("=", 1)[1]] if inline else []
            token = self.multi[0]
            while i < len(args) and _is_level(args[i]):
                levels.append(args[i])
                i += 1
            if not levels:
                raise InputError(f"{token}: expected one or more {self.multi[1]} after it")
            for level in levels:
                out.extend([token, level])
        rest = super().parse_args(ctx, out)
        if ctx.args and not ctx.resilient_parsing:
            raise InputError(f"{ctx.args[0]}: unexpected value (only the values right after {self.multi[0]} "
                             f"are {self.multi[1].split()[0]}; see contactvib {ctx.info_name} --help)")
        return rest


def parse_levels(levels: tuple[str, ...], kind: str = "force") -> list[float]:
    """The levels of a LevelsCommand's ``--pa``, each > 0: P_a [Q], or U [µm] / A [g] for
    ``--excitation base-um`` / ``base-g`` (:func:`level_kind_option`)."""
    if kind == "force":
        return [parse_pa_level(t) for t in levels]
    sym, unit, _name = LEVEL_KINDS[kind]
    return [parse_positive("--pa", sym, t, unit) for t in levels]


def level_kind_option(f):
    """``--excitation force|base-um|base-g``: what the levels of a sweep or a continuation in f_e
    hold (the command receives ``level_kind``)."""
    return click.option(
        "--excitation", "level_kind", type=click.Choice(list(LEVEL_KINDS)), default="force",
        show_default=True,
        help="What each level (--pa) holds: the force amplitude P_a [Q], or base (slideway) motion of "
             "displacement amplitude U [µm] (base-um: the inertial force grows with f_e²) or "
             "acceleration amplitude A [g] (base-g).")(f)


def _finite_or_none(obj):
    """``obj`` with every non-finite float (NaN, ±inf) replaced by None, for strict JSON."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite_or_none(v) for v in obj]
    return obj


def open_dataset_argument(dataset, option: str = "DATASET", load: bool = False):
    """The resonance dataset a command was given (a file, or a folder holding atlas.nc, paper.nc
    or resonance.nc) as a :class:`contactvib.sweeps.stored.ResonanceData`, opened by
    :func:`contactvib.sweeps.stored.open_resonance` (lazily; into memory with ``load``); its
    refusal is the one-line InputError ``<option> = <why>``."""
    from contactvib.sweeps.stored import DatasetError, open_resonance

    try:
        return open_resonance(dataset, load=load)
    except DatasetError as e:
        raise InputError(f"{option} = {e}") from None


def echo_json(payload) -> None:
    """Print ``payload`` (an object, or the JSON text of a ``to_json()``) as strict JSON: a
    non-finite number is written as ``null``, never as a bare ``NaN`` / ``Infinity`` token."""
    obj = json.loads(payload) if isinstance(payload, str) else payload
    click.echo(json.dumps(_finite_or_none(obj), allow_nan=False))


def operating_point_options(f):
    f = _excitation_family_options(law_options(f))
    f = click.option("--set", "settings", multiple=True, metavar="NAME=VALUE",
                     help="Override a model parameter by its symbol: "
                          + ", ".join(f"{k} [{u}]" for k, u in SET_UNITS.items()))(f)
    f = click.option("--fe", default="360", show_default=True, metavar="HZ",
                     help="Excitation frequency f_e [Hz], > 0.")(f)
    f = click.option("--pa-newton", default=None, metavar="N",
                     help="Excitation amplitude P_a in newtons (instead of --pa).")(f)
    f = click.option("--pa", default=None, metavar="Q",
                     help="Excitation amplitude P_a as a multiple of Q = M g (default 0.65).")(f)
    return f


def parse_max_periods(text: str) -> float | None:
    """``--max-periods``: None for ``auto`` (the library derives it from the damping), else its
    number (checked by the library)."""
    return None if text.strip().lower() == "auto" else parse_number("--max-periods", "max_periods", text)


def search_options(f):
    f = click.option("--no-seeds", is_flag=True, help="Skip the ballistic seeds (box starts only).")(f)
    f = click.option("--max-periods", default="auto", show_default=True,
                     help="Transient limit per start [excitation periods]; auto: twice the linear "
                          "decay time in contact, at least 400.")(f)
    f = click.option("--kmax", default="8", show_default=True,
                     help=f"Largest period searched (1..{KMAX_SEARCH_MAX}).")(f)
    f = click.option("--seed", default="0", show_default=True, help="Random seed of the start box.")(f)
    f = click.option("--starts", default="512", show_default=True, help="Random starts in the box.")(f)
    return f




def checked_output_folder(path, option: str = "--out", file: str | None = None):
    """The output folder ``path`` as a :class:`~pathlib.Path`, created and checked writable
    (a probe file is created and removed) before any computation; an InputError otherwise.
    ``file``: the option's value when it names a file in that folder (a film), named in the
    messages instead of the folder."""
    import os
    import tempfile
    from pathlib import Path

    p = Path(path)
    shown, which = (path, "the folder") if file is None else (file, "its folder")
    try:
        if p.exists() and not p.is_dir():
            if file is None:
                raise InputError(f"{option} = {path}: exists and is not a folder")
            raise NotADirectoryError(20, "Not a directory")
        p.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".contactvib-probe-", dir=p)
        os.close(fd)
        os.remove(probe)
    except OSError as e:
        raise InputError(f"{option} = {shown}: cannot create or write {which} "
                         f"({e.strerror or type(e).__name__})") from None
    return p


def feasible_frequencies(model: ContactModel, fmin: float, fmax: float,
                          options: tuple[str, str] = ("--fmin", "--fmax")) -> None:
    """Both ends of a frequency range are excitation frequencies the model can be integrated at
    (checked by :class:`Excitation`, whose f_e range follows from the model's f_n0)."""
    for option, f in zip(options, (fmin, fmax)):
        refused = _frequency_ratio_error(model, f)
        if refused is not None:
            blamed = model_blamed(model, refused, lambda m, f=f: _frequency_ratio_error(m, f) is None, option)
            raise blamed or option_error(option, refused)
