"""The registry of contact spring laws: the one list that the ``--law`` choices, the ``--set``
names, the explorer's fields, the command-line reference and the documentation's table of laws
are made from.

Laws come from two places, both found the first time the registry is read:

* every module of the package ``contactvib.model.laws`` (a law's class decorated with
  :func:`register_law`): a new built-in law is one file there;
* the entry-point group ``contactvib.laws`` of installed distributions (each entry a
  :class:`~contactvib.model.SpringLaw` subclass), the ecosystem's plug-in
  convention: ``[project.entry-points."contactvib.laws"] mylaw = "mypackage.module:MyLaw"``.
"""

from __future__ import annotations

import importlib
import pkgutil
import re
import threading
import warnings
from pathlib import Path

from contactvib.model.checks import ParameterError
from contactvib.model.laws.contract import SpringLaw

__all__ = ["register_law", "law_names", "law_class", "law_parameter_names", "ENTRY_POINT_GROUP",
           "RESERVED_NAMES"]

#: The entry-point group through which other packages provide laws.
ENTRY_POINT_GROUP = "contactvib.laws"
#: Names a law's parameter may not take: the model's own parameters and keywords.
RESERVED_NAMES = frozenset({"M", "g", "S", "c_n", "m2", "h_n", "l", "alpha", "preload", "law", "damping",
                            "table", "law_params"})
_NAME = re.compile(r"^[a-z][a-z0-9-]*$")
_PARAM = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")

_laws: dict[str, type[SpringLaw]] = {}
_lock = threading.RLock()
_loaded = False
#: Modules of this package that hold no law.
_NOT_LAWS = {"contract", "registry", "damping"}


def register_law(cls: type[SpringLaw]) -> type[SpringLaw]:
    """Add a law class to the registry (a decorator); checks the contract's declarations.

    Raises TypeError for a class that is no :class:`SpringLaw`, a name that is not lower-case
    letters, digits and dashes, a name taken by another class, parameter names that clash with
    the model's own, or kinks other than the engagement point."""
    if not (isinstance(cls, type) and issubclass(cls, SpringLaw)):
        raise TypeError(f"{cls!r} is not a SpringLaw subclass")
    name = cls.name
    if not isinstance(name, str) or not _NAME.match(name):
        raise TypeError(f"{cls.__name__}.name = {name!r}: must be lower-case letters, digits and dashes")
    names = [p.name for p in cls.parameters]
    reserved = RESERVED_NAMES - {"c_n", "m2"} if name == "power" else RESERVED_NAMES  # the model's own fields
    bad = [n for n in names if n in reserved or not _PARAM.match(n)]
    if bad or len(set(names)) != len(names):
        raise TypeError(f"the {name} law's parameters {names}: names must be unique identifiers and not one of "
                        f"{', '.join(sorted(RESERVED_NAMES))}")
    with _lock:
        other = _laws.get(name)
        if other is not None and other is not cls and other.__qualname__ != cls.__qualname__:
            raise TypeError(f"the law name {name!r} is taken by {other.__module__}.{other.__qualname__}")
        _laws[name] = cls
    return cls


def _load() -> None:
    """Import this package's law modules and the entry points, once."""
    global _loaded
    with _lock:
        if _loaded:
            return
        _loaded = True
        for info in pkgutil.iter_modules([str(Path(__file__).parent)]):  # this package's law modules
            if not info.name.startswith("_") and info.name not in _NOT_LAWS:
                importlib.import_module(f"{__package__}.{info.name}")
        from importlib.metadata import entry_points

        for ep in entry_points(group=ENTRY_POINT_GROUP):
            try:
                register_law(ep.load())
            except Exception as e:  # a broken plug-in must not take the package down with it
                warnings.warn(f"contactvib: the law plug-in {ep.name} = {ep.value} was not loaded: {e}",
                              RuntimeWarning, stacklevel=2)


def law_names() -> tuple[str, ...]:
    """Names of every registered law, the built-in ones first (power, exponential, table,
    clearance), then the plug-ins alphabetically."""
    _load()
    first = ("power", "exponential", "table", "clearance")
    return tuple(n for n in first if n in _laws) + tuple(sorted(n for n in _laws if n not in first))


def law_class(name: str) -> type[SpringLaw]:
    """The law class of ``name``; ParameterError (``law``) naming the known laws otherwise."""
    _load()
    cls = _laws.get(name) if isinstance(name, str) else None
    if cls is None:
        raise ParameterError("law", name, f"unknown law; known: {', '.join(law_names())}")
    return cls


def law_parameter_names() -> dict[str, tuple[str, ...]]:
    """Each law's parameter names (its ``--set`` names), by law name."""
    return {n: tuple(p.name for p in law_class(n).parameters) for n in law_names()}
