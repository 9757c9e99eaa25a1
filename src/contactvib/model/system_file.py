"""A structure with contact elements read from a TOML file (SI units): :func:`load_system`.

The format (``docs/formats.md``; ``examples/two_dof_stop.toml``)::

    [system]
    coordinates = ["q1", "q2"]               # names; optional units = ["m", "rad"] (default m)
    mass = [[1.0, 0.0], [0.0, 1.0]]          # kg (kg m² for rotations)
    stiffness = [[1.0, -1.0], [-1.0, 2.0]]   # optional, N/m
    damping = [[0.03, -0.03], [-0.03, 0.06]] # optional, N s/m
    static_load = [0.0, 0.0]                 # optional, N
    force_shape = [0.0, 1.0]                 # b: the force is b P_a cos(2π f_e t)
    [[contact]]
    name = "stop"
    direction = [1.0, 0.0]                   # δ = direction · q − (the law's engagement)
    area = 1.0                               # m² (default 1)
    law = "clearance"                        # a registered law; its parameters by name, in the
    c_lin = 100.0                            # units of --set
    gap_um = 1.0e6
    # optional: damping = "power" (h_n, l) or "hunt-crossley" (alpha)

It describes ``M q̈ + C q̇ + K q = f0 + b P(t) − Σ_i w_i F_i(δ_i, δ̇_i)``
(:class:`~contactvib.model.system.System`). Every error is a
:class:`~contactvib.model.ParameterError` whose symbol is the key path (``system.mass``,
``contact[0].direction``, ``contact[1].c_lin``) and whose text says what is wrong.
"""

from __future__ import annotations

import sys

from contactvib.model.checks import ParameterError
from contactvib.model.laws import law_class, law_names
from contactvib.model.system import ContactElement, System

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

__all__ = ["load_system", "SYSTEM_KEYS", "CONTACT_KEYS"]

#: The keys of ``[system]``: the System field each fills, and whether it is required.
SYSTEM_KEYS = {"coordinates": ("coordinates", True), "units": ("units", False), "mass": ("M", True),
               "stiffness": ("K", False), "damping": ("C", False), "static_load": ("f0", False),
               "force_shape": ("b", True)}
#: The keys of a ``[[contact]]`` besides the law's parameters: the ContactElement field each fills.
CONTACT_KEYS = {"name": "name", "direction": "direction", "area": "S", "law": "law", "damping": "damping",
                "h_n": "h_n", "l": "l", "alpha": "alpha"}
_REQUIRED_CONTACT = ("name", "direction", "law")


def _read(path) -> dict:
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except OSError as e:
        raise ParameterError("file", str(path), f"cannot be read ({e.strerror or e})") from None
    except tomllib.TOMLDecodeError as e:
        raise ParameterError("file", str(path), f"is not valid TOML ({e})") from None


def _contact(i: int, table) -> ContactElement:
    where = f"contact[{i}]"
    if not isinstance(table, dict):
        raise ParameterError(where, table, "must be a table ([[contact]])")
    for key in _REQUIRED_CONTACT:
        if key not in table:
            raise ParameterError(f"{where}.{key}", None, "is missing")
    name = table["law"]
    if not isinstance(name, str) or name not in law_names():
        raise ParameterError(f"{where}.law", name, f"must be a registered law: {', '.join(law_names())}")
    cls = law_class(name)
    own = {p.name for p in cls.parameters}
    for key in table:
        if key not in CONTACT_KEYS and key not in own:
            known = ", ".join([*CONTACT_KEYS, *sorted(own)])
            raise ParameterError(f"{where}.{key}", table[key], f"unknown key (law {name} takes: {known})")
    params = {k: v for k, v in table.items() if k in own}
    for k, v in params.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise ParameterError(f"{where}.{k}", v, "must be a number")
    try:
        law = cls(**params)
    except ParameterError as e:
        raise ParameterError(f"{where}.{e.symbol}" if e.symbol in own else f"{where}.law", e.value, e.allowed) \
            from None
    fields = {CONTACT_KEYS[k]: v for k, v in table.items() if k in CONTACT_KEYS and k != "law"}
    return ContactElement(law=law, **{"S": 1.0, **fields})


def _key_path(symbol: str) -> str:
    """A System's symbol (``M``, ``contacts[0].S``) as the file's key (``system.mass``, ``contact[0].area``)."""
    by_field = {f: f"system.{k}" for k, (f, _) in SYSTEM_KEYS.items()}
    if symbol in by_field:
        return by_field[symbol]
    if symbol.startswith("contacts["):
        head, _, field = symbol.partition("].")
        keys = {v: k for k, v in CONTACT_KEYS.items()}
        return f"contact[{head[len('contacts['):]}]" + (f".{keys.get(field, field)}" if field else "")
    return "contact" if symbol == "contacts" else symbol


def load_system(path) -> System:
    """The :class:`~contactvib.model.system.System` of a TOML file (the module's format).

    Raises
    ------
    ParameterError
        The file cannot be read or parsed, a key is missing or unknown, or a value is invalid
        (a matrix of the wrong shape, a mass matrix that is not symmetric positive definite, an
        unknown law or law parameter, a zero direction, NaN); its symbol is the key path.
    """
    data = _read(path)
    for key in data:
        if key not in ("system", "contact"):
            raise ParameterError(key, data[key], "unknown table (expected [system] and [[contact]])")
    sysd = data.get("system")
    if not isinstance(sysd, dict):
        raise ParameterError("system", sysd, "is missing (a [system] table)")
    for key in sysd:
        if key not in SYSTEM_KEYS:
            raise ParameterError(f"system.{key}", sysd[key], f"unknown key (known: {', '.join(SYSTEM_KEYS)})")
    for key, (_f, required) in SYSTEM_KEYS.items():
        if required and key not in sysd:
            raise ParameterError(f"system.{key}", None, "is missing")
    contacts = data.get("contact", [])
    if not isinstance(contacts, list):
        raise ParameterError("contact", contacts, "must be an array of tables ([[contact]])")
    try:
        elements = [_contact(i, c) for i, c in enumerate(contacts)]
        return System(contacts=elements, **{f: sysd[k] for k, (f, _) in SYSTEM_KEYS.items() if k in sysd})
    except ParameterError as e:
        if e.symbol.startswith("contact[") or e.symbol in ("system", "file"):
            raise
        raise ParameterError(_key_path(e.symbol), e.value, e.allowed) from None
