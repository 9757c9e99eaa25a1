"""What a contact spring law provides: the contract every law of the registry fulfils.

A law is the static part of the contact force, ``F_s(δ)`` [N], as a function of the contact's
own deflection ``δ = y − y_e`` [m], where ``y_e`` (:attr:`SpringLaw.engagement_m`) is the position
at which the law engages (0 for a rough contact: it touches at y = 0; the gap for a clearance).
The force acts while ``δ > 0`` and is zero while ``δ ≤ 0`` (the contact is lost). The damping
law chosen beside it acts on the same δ (``S h_n δ^l δ̇`` or ``α F_s(δ) δ̇``).

A law declares, as class attributes:

* ``name`` — its ``--law`` name; ``formula`` — one line for ``--help`` and the docs table;
* ``parameters`` — a tuple of :class:`LawParameter` (name, unit, bounds, default): they become
  ``--set NAME=VALUE``, the explorer's fields, the keyword arguments of the class and of
  ``ContactModel(law=..., law_params={...})``, all checked against the bounds before any
  computation;
* ``taylor`` — whether its compiled form runs the Taylor-series flow (the fast path) rather than
  DOP853; ``fourier`` — whether harmonic balance takes it (through the alternating
  frequency–time scheme, which needs only the compiled force).

and implements, in SI units and vectorised over ``delta``:

* :meth:`SpringLaw.force` ``F_s(δ)`` [N] (0 for δ ≤ 0) and :meth:`SpringLaw.stiffness`
  ``dF_s/dδ`` [N/m];
* :meth:`SpringLaw.static_deflection` ``δ0`` with ``F_s(δ0) = W`` (default: bracketed root of
  :meth:`force`);
* :meth:`SpringLaw.kinks` — the deflections where the force or its slope jumps; the integrators
  locate the engagement point δ = 0 as an event, so a law's kinks must be ``(0.0,)``;
* :meth:`SpringLaw.kernel_spring` — its compiled form for the kernels (nondimensional, forces
  in units of W, deflections in units of δ0): one of the compiled families,
  :meth:`compiled_power`, :meth:`compiled_exponential` or :meth:`compiled_table`. A law that
  maps onto none of them keeps the default, its own :meth:`force` and :meth:`stiffness`
  tabulated on 801 knots and interpolated by cubic Hermite polynomials (:func:`tabulated_form`;
  relative error below 1e-9 from 1e-3 δ0 to 100 δ0 for a smooth force, see
  ``tests/model/test_law_registry.py``).

Register a law with :func:`contactvib.model.register_law`: a module dropped into the package
``contactvib.model.laws`` is found by itself; a law of another package is registered through the
entry-point group ``contactvib.laws`` (see the documentation page "Add a contact law").
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from contactvib.model.checks import ParameterError, check_range

__all__ = ["LawParameter", "SpringLaw", "tabulated_form", "COMPILED_POWER", "COMPILED_EXPONENTIAL",
           "COMPILED_TABLE"]

#: Codes of the compiled spring families (the same numbers as ``contactvib._kernels.contact``'s
#: ``SPRING_*``; tests/model/test_law_registry.py checks they agree). Kept here so that a law
#: module imports no numba.
COMPILED_POWER, COMPILED_EXPONENTIAL, COMPILED_TABLE = 0.0, 1.0, 2.0

#: Rows and extent of the tabulated compiled form of a law that provides none: PCHIP knots at
#: 0 and geometrically from 1e-4 δ0 to 1e4 δ0 (deflections beyond are refused as a table's).
TABULATED_ROWS = 801
TABULATED_SPAN = (1e-4, 1e4)


@dataclass(frozen=True)
class LawParameter:
    """One parameter of a law: its name (the ``--set`` name), unit, allowed range and default.

    ``lower``/``upper`` are the bounds (None: unbounded), ``lower_inclusive``/``upper_inclusive``
    whether the bound itself is allowed; ``description`` says what it is, for ``--help`` and the
    docs table."""

    name: str
    unit: str
    default: float
    description: str
    lower: float | None = 0.0
    lower_inclusive: bool = False
    upper: float | None = None
    upper_inclusive: bool = True

    def check(self, value) -> float:
        """``value`` as a float within the bounds; ParameterError naming the parameter and the
        bounds otherwise."""
        return check_range(self.name, value, self.lower, self.lower_inclusive, self.unit,
                           upper=self.upper, upper_inclusive=self.upper_inclusive)

    def bounds_text(self) -> str:
        """The allowed range in words, e.g. ``> 0 N/m^3`` or ``in [0, 1e+06] um``."""
        lo = None if self.lower is None else f"{self.lower:g}"
        hi = None if self.upper is None else f"{self.upper:g}"
        if lo is not None and hi is not None:
            return (f"in {'[' if self.lower_inclusive else '('}{lo}, {hi}{']' if self.upper_inclusive else ')'}"
                    f" {self.unit}")
        if lo is not None:
            return f"{'>=' if self.lower_inclusive else '>'} {lo} {self.unit}"
        if hi is not None:
            return f"{'<=' if self.upper_inclusive else '<'} {hi} {self.unit}"
        return f"any finite value [{self.unit}]"


class SpringLaw:
    """Base class of the contact spring laws: the contract (see the module's docstring).

    A subclass sets ``name``, ``formula``, ``parameters`` (and ``taylor``, ``fourier``) and
    implements :meth:`force` and :meth:`stiffness`; the constructor is shared: its values are
    the parameters, positionally in their order or by name, defaults filled in, each checked
    against its bounds (ParameterError naming it). Instances are immutable and compare by
    law and values."""

    name: ClassVar[str] = ""
    formula: ClassVar[str] = ""
    parameters: ClassVar[tuple[LawParameter, ...]] = ()
    taylor: ClassVar[bool] = False
    fourier: ClassVar[bool] = True

    def __init__(self, *args, **kwargs):
        names = [p.name for p in self.parameters]
        if len(args) > len(names):
            raise ParameterError("law", self.name, f"takes {len(names)} parameters ({', '.join(names)}), "
                                                   f"{len(args)} given")
        given = dict(zip(names, args))
        for k, v in kwargs.items():
            if k not in names:
                raise ParameterError(k, v, f"unknown parameter of the {self.name} law; known: "
                                           f"{', '.join(names) or 'none'}")
            if k in given:
                raise ParameterError(k, v, f"given twice to the {self.name} law")
            given[k] = v
        for p in self.parameters:
            value = given.get(p.name)
            object.__setattr__(self, p.name, p.check(p.default if value is None else value))

    def __setattr__(self, key, value):
        raise AttributeError(f"{type(self).__name__} is immutable")

    def values(self) -> dict[str, float]:
        """The parameters by name (SI or the unit each declares)."""
        return {p.name: getattr(self, p.name) for p in self.parameters}

    def __eq__(self, other):
        return type(other) is type(self) and other.values() == self.values()

    def __hash__(self):
        return hash((type(self).__name__, tuple(self.values().items())))

    def __repr__(self):
        return f"{type(self).__name__}({', '.join(f'{k}={v!r}' for k, v in self.values().items())})"

    # ------------------------------------------------------------------ the contract
    @property
    def engagement_m(self) -> float:
        """Position y [m] at which the law engages: δ = y − engagement_m (0: contact at y = 0)."""
        return 0.0

    def kinks(self) -> tuple[float, ...]:
        """Deflections δ [m] where the force or its derivative jumps (the integrators locate δ = 0)."""
        return (0.0,)

    def force(self, delta, S: float):
        """Spring force F_s(δ) [N] on the nominal area S [m²]; 0 for δ ≤ 0. Vectorised."""
        raise NotImplementedError(f"the {self.name} law does not define force()")

    def stiffness(self, delta, S: float):
        """dF_s/dδ [N/m]; 0 for δ ≤ 0. Vectorised."""
        raise NotImplementedError(f"the {self.name} law does not define stiffness()")

    def contact_force(self, delta, S: float):
        """F_s in contact continued smoothly a little below δ = 0 (where an integrator's last
        stage before a located exit samples it) [N]; scalar. Default: :meth:`force`."""
        return float(self.force(delta, S))

    def static_deflection(self, W: float, S: float) -> float:
        """δ0 [m] with F_s(δ0) = W [N] (default: a bracketed root of :meth:`force`)."""
        from scipy.optimize import brentq

        hi = 1e-9
        while float(self.force(hi, S)) < W:
            hi *= 2.0
            if hi > 1e3:
                raise ParameterError("law", self.name, f"its force does not reach the static load W = {W:g} N "
                                                       "below a deflection of 1 km")
        return float(brentq(lambda d: float(self.force(d, S)) - W, 0.0, hi, xtol=1e-15 * hi, rtol=1e-15))

    def kernel_spring(self, y0: float, W: float, S: float):
        """The compiled form ``(code, s1, s2, data)`` for deflections in units of ``y0`` = δ0 [m]
        and forces in units of W [N]. Default: ``tabulated_form`` of :meth:`force`."""
        return tabulated_form(self, y0, W, S)

    def check_motion(self, delta_max_m: float, y0: float, what: str = "the motion") -> None:
        """Refuse (ParameterError) a result whose largest deflection ``delta_max_m`` [m] leaves the
        law's range of validity (static deflection ``y0`` [m]): by default the range of the
        tabulated form, for a law that keeps it."""
        if type(self).kernel_spring is SpringLaw.kernel_spring:
            reach = TABULATED_SPAN[1] * y0
            if delta_max_m > reach:
                raise ParameterError("law", self.name, f"{what} reaches a deflection of {delta_max_m * 1e6:.4g} um, "
                                                       f"beyond its tabulated form ({reach * 1e6:.4g} um)")

    # ------------------------------------------------------------------ compiled forms
    @staticmethod
    def compiled_power(m2: float):
        """The compiled power spring x^m2 (forces in units of W, x = δ/δ0)."""
        return COMPILED_POWER, float(m2), 0.0, np.empty(0)

    @staticmethod
    def compiled_exponential(a: float, b: float):
        """The compiled exponential spring b (exp(a x) − 1)."""
        return COMPILED_EXPONENTIAL, float(a), float(b), np.empty(0)

    @staticmethod
    def compiled_table(x, f, d):
        """The compiled cubic Hermite table through knots x (from 0, increasing), values f and
        slopes d (nondimensional), linear beyond the last knot."""
        x = np.asarray(x, float)
        return COMPILED_TABLE, float(x.size), 0.0, np.concatenate([x, np.asarray(f, float), np.asarray(d, float)])


def tabulated_form(law: SpringLaw, y0: float, W: float, S: float):
    """A law's force and stiffness at ``TABULATED_ROWS`` knots (0, then geometric from 1e-4 δ0 to
    1e4 δ0), interpolated by the compiled table's cubic Hermite polynomials: the compiled form of
    a law that maps onto no compiled family (exact for a cubic force, O(h⁴) otherwise)."""
    lo, hi = TABULATED_SPAN
    d = np.concatenate([[0.0], np.geomspace(lo, hi, TABULATED_ROWS - 1)]) * y0
    F = np.asarray(law.force(d, S), dtype=float)
    k = np.asarray(law.stiffness(np.maximum(d, 1e-9 * d[1]), S), dtype=float)  # the right-hand slope at 0
    if not (np.all(np.isfinite(F)) and np.all(np.isfinite(k)) and np.all(np.diff(F) > 0.0) and np.all(k >= 0.0)):
        raise ParameterError("law", law.name, "its force must be finite and increase with the deflection from 0 to "
                                              f"{hi:g} static deflections")
    return law.compiled_table(d / y0, F / W, k * (y0 / W))
