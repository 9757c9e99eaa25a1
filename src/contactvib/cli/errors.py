"""The command line's one-line input errors: :class:`InputError`, :class:`RunInterrupted`, and
the mapping of a library :class:`~contactvib.model.ParameterError` onto the option that gave the
value (``checked_option``, ``mapped_options``), ``contactvib: error: --fe (f_e) = -5: must be > 0 Hz``."""

from __future__ import annotations

from contextlib import contextmanager

from contactvib.errors import ContactvibError
from contactvib.model import ParameterError, check_finite, check_int
from contactvib.model.checks import format_number, to_float

__all__ = ["InputError", "RunInterrupted", "one_line"]


def one_line(message: str) -> str:
    """``message`` with its control characters (e.g. a newline typed into an option value)
    escaped, so that an error is always one line."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in message)


class InputError(ContactvibError):
    """A user input error: printed as one line (control characters escaped), no traceback, no
    usage banner."""

    def __init__(self, message: str):
        super().__init__(one_line(str(message)))


class RunInterrupted(ContactvibError):
    """A command stopped by Ctrl-C (SIGINT): ``main`` prints ``contactvib: <message>`` as one
    line and exits 130 (not a KeyboardInterrupt, so that click adds nothing)."""


@contextmanager
def ctrl_c():
    """Within: Ctrl-C (the library stops its kernels within one period) becomes the one line
    ``contactvib: interrupted``, exit 130."""
    try:
        yield
    except KeyboardInterrupt:
        raise RunInterrupted("interrupted") from None


def option_error(option: str, e: ParameterError, names: dict[str, str] | None = None) -> InputError:
    """The one-line message ``--fe (f_e) = -5: must be > 0 Hz`` of a library ParameterError."""
    return InputError(f"{option} ({e.symbol}) = {show_value(e.value)}: {e.allowed_with(names or {})}")


def checked_option(option: str, check, *args, names: dict[str, str] | None = None, **kwargs):
    """``check(*args, **kwargs)``, a library check of the value of ``option``; a ParameterError
    becomes an InputError naming ``option`` (and ``names[bound]`` for the bounds it refers to)."""
    try:
        return check(*args, **kwargs)
    except ParameterError as e:
        raise option_error(option, e, names) from None


def mapped_options(options: dict[str, str], call, *args, **kwargs):
    """``call(*args, **kwargs)``, a library call that checks several values; a ParameterError
    becomes an InputError naming the option of its symbol (``options[symbol]``)."""
    try:
        return call(*args, **kwargs)
    except ParameterError as e:
        raise option_error(options.get(e.symbol, e.symbol), e, options) from None


def show_value(value) -> str:
    try:
        return format_number(to_float(value))
    except (TypeError, ValueError, OverflowError):
        return str(value)


def parse_number(option: str, symbol: str, text: str) -> float:
    """A finite number."""
    return checked_option(option, check_finite, symbol, text)


def parse_int(option: str, text: str, lower: int | None, upper: int | None = None,
         symbol: str | None = None) -> int:
    """An integer in ``lower..upper`` (the library's range); non-integers are refused."""
    return checked_option(option, check_int, symbol or option.lstrip("-"), text, lower, upper)
