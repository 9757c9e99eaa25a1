"""Input checks of the library, one place: :class:`~contactvib.ParameterError`, the checks, and the ranges.

Every public function and settings object checks its inputs with these functions, naming each
value by its paper symbol (``"f_e"``, ``"P_a/Q"``, ``"kmax"``); the command line calls the same
checks and only maps the symbols onto its option names (:mod:`contactvib.cli.common`). A check
returns the checked value (a ``float`` or an ``int``) or raises :class:`~contactvib.ParameterError` with the
allowed range in words, e.g. ``f_e = -5: must be > 0 Hz``.

The ranges that more than one caller enforces are the constants below (``*_MAX``, ``*_RANGE``).
"""

from __future__ import annotations

import math
import numbers
import re

from contactvib.errors import ContactvibError

__all__ = ["ParameterError", "check_finite", "check_range", "check_int", "check_choice",
           "check_frequency_range", "check_pa_level", "format_number", "PA_NOTE", "SHOOTING_RTOL_RANGE",
           "KMAX_SEARCH_MAX", "KMAX_SWEEP_MAX", "MULTISTART_PER_OCTAVE_MAX", "EVOLUTION_ORDER_MAX",
           "HARMONICS_MAX", "CAPTURE_TOL_MAX", "WORKERS_MAX", "PA_MAX", "R_RANGE", "MEMORY_MAX",
           "check_memory"]

#: How an amplitude P_a/Q is measured, appended to its allowed range in messages.
PA_NOTE = "(multiple of Q = M g)"
#: Integrator tolerance of the shooting and continuation of periodic orbits [1], inclusive.
SHOOTING_RTOL_RANGE = (1e-15, 1e-6)
#: Largest period [excitation periods] of the attractor search at one operating point.
KMAX_SEARCH_MAX = 64
#: Largest period [excitation periods] detected by the resonance sweeps.
KMAX_SWEEP_MAX = 16
#: Largest number of multi-start frequencies per octave of a sweep.
MULTISTART_PER_OCTAVE_MAX = 1000
#: Largest order m of the 1/m resonance whose evolution is continued in two parameters.
EVOLUTION_ORDER_MAX = 8
#: Largest number of harmonics of the harmonic balance.
HARMONICS_MAX = 1024
#: Largest number of worker processes of a resonance sweep.
WORKERS_MAX = 256
#: Largest relative capture distance of the attractor search's second wave.
CAPTURE_TOL_MAX = 0.1
#: Largest excitation amplitude P_a/Q [1] (the paper's levels are below 1.3).
PA_MAX = 1e3
#: Frequency ratios r = f_e / f_n0 [1] the integration is feasible for, inclusive (below, one
#: excitation period holds more than 1e4 natural periods; above, the force averages out).
R_RANGE = (1e-4, 1e3)
#: Largest memory [bytes] the arrays of one computation may take (checked before computing).
MEMORY_MAX = 2 * 1024**3


class ParameterError(ContactvibError, ValueError):
    """A parameter is outside its allowed range.

    Attributes
    ----------
    symbol : str
        The paper's symbol of the parameter (``"m2"``, ``"f_e"``, ...).
    value : object
        The value that was given.
    allowed : str
        The allowed range in words, with units (``"must be > 0 Hz"``).
    bounds : tuple of str
        Names of other parameters that the range refers to (``("f_min",)`` in
        ``"must be > f_min = 300 Hz"``), so that a caller can rename them (the command line
        writes its option names).
    """

    def __init__(self, symbol: str, value, allowed: str, bounds: tuple[str, ...] = ()):
        self.symbol = symbol
        self.value = value
        self.allowed = allowed
        self.bounds = tuple(bounds)
        super().__init__(f"{symbol} = {_fmt(value)}: {allowed}")

    def allowed_with(self, names: dict[str, str]) -> str:
        """``allowed`` with the names in ``bounds`` replaced by ``names[name]``."""
        text = self.allowed
        for b in self.bounds:
            if b in names:
                text = re.sub(rf"(?<![\w-]){re.escape(b)}(?!\w)", names[b], text)
        return text


def _fmt(value) -> str:
    try:
        return format_number(to_float(value))
    except (TypeError, ValueError, OverflowError):
        return repr(value)


def format_number(x: float) -> str:
    """``x`` as ``%g`` without the exponent's leading zero (1e-6, not 1e-06)."""
    return re.sub(r"e([+-])0(\d)", r"e\1\2", f"{x:g}")


def _suffix(unit: str) -> str:
    return f" {unit}" if unit and unit != "1" else ""


#: A number written as text: plain ASCII decimal or scientific notation (``float()`` also takes
#: other scripts' digits, ``3_60``, ``inf`` and ``nan``, which are refused).
_NUMBER_TEXT = re.compile(r"\s*[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?\s*", re.ASCII)


def to_float(value) -> float:
    """``float(value)``; text must be plain ASCII decimal or scientific notation (ValueError)."""
    if isinstance(value, (str, bytes)):
        text = value.decode("ascii", "replace") if isinstance(value, bytes) else value
        if not _NUMBER_TEXT.fullmatch(text):
            raise ValueError(value)
        return float(text)
    return float(value)


def check_finite(symbol: str, value) -> float:
    """Return ``value`` as a float; raise :class:`~contactvib.ParameterError` for non-numbers, NaN and ±inf.

    Text must be plain ASCII decimal or scientific notation (``"1.5e-3"``); ``-0.0`` is returned
    as ``0.0``."""
    if isinstance(value, bool):
        raise ParameterError(symbol, value, "must be a finite number")
    try:
        v = to_float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(symbol, value, "must be a finite number") from None
    if not math.isfinite(v):
        raise ParameterError(symbol, value, "must be a finite number")
    return v + 0.0  # -0.0 -> 0.0


def _range_text(lower, inclusive, upper, upper_inclusive, unit, lower_name, upper_name) -> str:
    suffix = _suffix(unit)
    if upper is None:
        at = f"{lower_name} = " if lower_name else ""
        return f"must be {'>=' if inclusive else '>'} {at}{format_number(lower)}{suffix}"
    if lower is None:
        at = f"{upper_name} = " if upper_name else ""
        return f"must be {'<=' if upper_inclusive else '<'} {at}{format_number(upper)}{suffix}"
    lb, ub = "[" if inclusive else "(", "]" if upper_inclusive else ")"
    interval = f"{lb}{format_number(lower)}, {format_number(upper)}{ub}"
    if lower_name or upper_name:
        names = f"{lb}{lower_name or format_number(lower)}, {upper_name or format_number(upper)}{ub}"
        return f"must lie in {names} = {interval}{suffix}"
    return f"must be in {interval}{suffix}"


def check_range(symbol: str, value, lower: float | None = None, inclusive: bool = True,
                unit: str = "", *, upper: float | None = None, upper_inclusive: bool = True,
                lower_name: str | None = None, upper_name: str | None = None) -> float:
    """Check that ``value`` is finite and within ``lower`` .. ``upper``; return it as a float.

    Parameters
    ----------
    symbol : str
        Paper symbol of the value, for the message.
    value : object
        Anything ``float()`` accepts.
    lower, upper : float or None
        Bounds (None: unbounded on that side).
    inclusive, upper_inclusive : bool
        Whether ``value == lower`` (``== upper``) is allowed.
    unit : str
        Unit of the value and the bounds, for the message ("1": none).
    lower_name, upper_name : str or None
        Names of the parameters that set the bounds, if any (``"must be > f_min = 300 Hz"``);
        they are listed in ``ParameterError.bounds``.
    """
    v = check_finite(symbol, value)
    ok = True
    if lower is not None:
        ok = v >= lower if inclusive else v > lower
    if ok and upper is not None:
        ok = v <= upper if upper_inclusive else v < upper
    if not ok:
        text = _range_text(lower, inclusive, upper, upper_inclusive, unit, lower_name, upper_name)
        names = tuple(n for n in (lower_name, upper_name) if n)
        raise ParameterError(symbol, value, text, names)
    return v


def check_int(symbol: str, value, lower: int | None = None, upper: int | None = None) -> int:
    """Check that ``value`` is an integer in ``lower`` .. ``upper`` (inclusive); return an ``int``.

    Integral floats and numeric strings (``16.0``, ``"16"``, ``"1e3"``) are accepted; anything
    else (``16.7``, ``"abc"``, NaN, ``True``) is refused, never truncated.
    """
    if lower is not None and upper is not None:
        allowed = f"must be an integer in {lower}..{upper}"
    elif lower is not None:
        allowed = f"must be an integer >= {lower}"
    elif upper is not None:
        allowed = f"must be an integer <= {upper}"
    else:
        allowed = "must be an integer"
    if isinstance(value, bool):
        raise ParameterError(symbol, value, allowed)
    if isinstance(value, numbers.Integral):
        n = int(value)
    else:
        try:
            v = to_float(value)
        except (TypeError, ValueError, OverflowError):
            raise ParameterError(symbol, value, allowed) from None
        if not math.isfinite(v) or v != math.floor(v):
            raise ParameterError(symbol, value, allowed)
        n = int(v)
    if (lower is not None and n < lower) or (upper is not None and n > upper):
        raise ParameterError(symbol, value, allowed)
    return n


def check_choice(symbol: str, value, choices):
    """Check that ``value`` is one of ``choices``; return it."""
    choices = tuple(choices)
    if value not in choices:
        raise ParameterError(symbol, value, "must be one of " + ", ".join(repr(c) for c in choices))
    return value


def check_frequency_range(fmin, fmax, symbols: tuple[str, str] = ("f_min", "f_max")) -> tuple[float, float]:
    """A frequency range [Hz]: ``0 < f_min < f_max``; return ``(f_min, f_max)`` as floats."""
    lo = check_range(symbols[0], fmin, 0.0, False, "Hz")
    hi = check_range(symbols[1], fmax, lo, False, "Hz", lower_name=symbols[0])
    return lo, hi


def check_pa_level(value, symbol: str = "P_a/Q") -> float:
    """An excitation level P_a/Q [1] that must be > 0 (a sweep or a continuation level)."""
    return check_range(symbol, check_range(symbol, value, 0.0, False, PA_NOTE), None, unit=PA_NOTE,
                       upper=PA_MAX)


def check_memory(symbol: str, value, nbytes: float, largest: int) -> None:
    """Refuse a size ``value`` of ``symbol`` whose arrays would take ``nbytes`` > :data:`MEMORY_MAX`;
    ``largest`` is the largest value allowed (the other sizes kept), named in the message."""
    if not nbytes <= MEMORY_MAX:
        raise ParameterError(symbol, value, f"must be <= {largest} (it would need about "
                                            f"{nbytes / 1e9:.3g} GB of memory; at most "
                                            f"{MEMORY_MAX / 1e9:.3g} GB)")
