"""The contact oscillator of Kostek (2013), Eqs. (2.1)–(2.5), and its derived quantities.

A slider of mass ``M`` rests on a rough planar contact of nominal area ``S``::

    M ÿ = M g − S c_n y^m2 [y > 0] − S h_n y^l ẏ [y > 0] + P_a cos(2π f_e t)      (2.5)

``y`` [m] points downwards and is the contact deflection while ``y > 0``; ``y ≤ 0`` is a gap
(loss of contact). Eq. (2.3) of the paper prints the damping condition as ``y < 0``; that is a
typo: damping acts only in contact.

The compiled kernels integrate the nondimensional form obtained with ``x = y / y0`` and
``τ = ω_n0 t`` (``y0`` the static deflection, ``ω_n0 = 2π f_n0``)::

    x'' = [1 − x^m2 − c x^l x' + p cos(r τ)] / m2      while x > 0
    x'' = [1 + p cos(r τ)] / m2                        while x ≤ 0

with ``p = P_a / Q``, ``r = f_e / f_n0`` and ``c = 2 m2 ζ``, ``ζ`` the linear damping ratio.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

from contactvib.model.checks import PA_MAX, PA_NOTE, R_RANGE, ParameterError, check_range, format_number
from contactvib.model.contact_law import PowerLaw
from contactvib.model.units import Units

__all__ = ["ContactModel", "Excitation", "PAPER_DEFAULTS", "PARAMETER_UNITS", "ZETA_MAX"]

#: The paper's parameters (Section 2): SI units.
PAPER_DEFAULTS = {
    "M": 0.2106,  # kg
    "g": 9.81,  # m/s²
    "S": 0.0009,  # m²
    "c_n": 4.52e16,  # N/m^(2+m2) (N/m⁴ for m2 = 2)
    "m2": 2.0,  # 1
    "h_n": 3.5e11,  # N s/m^(3+l) (N s/m⁴ for l = 1)
    "l": 1.0,  # 1
}

#: Units of every model parameter, for messages and result attributes.
PARAMETER_UNITS = {
    "M": "kg",
    "g": "m/s^2",
    "S": "m^2",
    "c_n": "N/m^(2+m2)",
    "m2": "1",
    "h_n": "N s/m^(3+l)",
    "l": "1",
}

#: Largest exponents m2 and l of the contact law accepted (x^m2, x^l overflow in a transient
#: far beyond; the paper's are 2 and 1).
EXPONENT_MAX = 10.0

# (lower bound, inclusive?, upper bound or None) for each parameter; the allowed ranges.
_BOUNDS = {
    "M": (0.0, False, None),
    "g": (0.0, False, None),
    "S": (0.0, False, None),
    "c_n": (0.0, False, None),
    "m2": (1.0, True, EXPONENT_MAX),
    "h_n": (0.0, True, None),
    "l": (0.0, True, EXPONENT_MAX),
}

#: Range [1] of the derived scales Q [N], y0 [m] and f_n0 [Hz] (finite, with room for the unit
#: conversions and the kernels' products).
DERIVED_RANGE = (1e-100, 1e100)


#: Largest linear damping ratio accepted (the paper's is 0.018; above this the contact is stiff).
ZETA_MAX = 100.0


@dataclass(frozen=True)
class ContactModel:
    """Slider on a power-law rough contact (Kostek 2013, Eqs. 2.1–2.5); SI units.

    Parameters
    ----------
    M : float
        Slider mass [kg], > 0.
    g : float
        Gravity [m/s²], > 0.
    S : float
        Nominal contact area [m²], > 0.
    c_n : float
        Contact stiffness coefficient [N/m^(2+m2)], > 0.
    m2 : float
        Stiffness exponent [1], ≥ 1 (2 for the paper, 1.5 Hertz-like).
    h_n : float
        Contact damping coefficient [N s/m^(3+l)], ≥ 0.
    l : float
        Damping exponent [1], ≥ 0.

    Examples
    --------
    >>> m = ContactModel()
    >>> round(m.units.y_um, 4), round(m.f_n0, 1)
    (0.2254, 1485.0)
    """

    M: float = PAPER_DEFAULTS["M"]
    g: float = PAPER_DEFAULTS["g"]
    S: float = PAPER_DEFAULTS["S"]
    c_n: float = PAPER_DEFAULTS["c_n"]
    m2: float = PAPER_DEFAULTS["m2"]
    h_n: float = PAPER_DEFAULTS["h_n"]
    l: float = PAPER_DEFAULTS["l"]  # noqa: E741 (the paper's symbol)
    _checked: bool = field(default=False, repr=False, compare=False)

    def __post_init__(self):
        for name, (lower, inclusive, upper) in _BOUNDS.items():
            check_range(name, getattr(self, name), lower, inclusive, PARAMETER_UNITS[name])
            if upper is not None:
                check_range(name, getattr(self, name), None, unit=PARAMETER_UNITS[name], upper=upper)
            object.__setattr__(self, name, float(getattr(self, name)))
        self._check_scales()
        if not self.zeta <= ZETA_MAX:
            # ζ is proportional to h_n: name the largest h_n allowed with this l
            h_max = self.h_n * ZETA_MAX / self.zeta
            raise ParameterError(
                "h_n", self.h_n,
                f"gives the damping ratio zeta = {self.zeta:.3g} with l = {self.l:g}: must give "
                f"zeta <= {ZETA_MAX:g}, i.e. h_n <= {h_max:.3g} N s/m^(3+l) (a contact this "
                f"overdamped is stiff: explicit integration would take ~zeta steps per natural "
                f"period; h_n scales as y0^(1-l), about {PAPER_DEFAULTS['h_n'] * self.y0 ** (1.0 - self.l):.3g} "
                f"for the paper's zeta = 0.018 at this l)")

    def _check_scales(self) -> None:
        """The derived scales Q, y0, f_n0 and ζ must be finite (no overflow of the parameters'
        combination); ParameterError names the scale, its formula and the parameters."""
        lo, hi = DERIVED_RANGE
        given = ", ".join(f"{k} = {format_number(v)}" for k, v in self.parameters().items())
        for symbol, formula, unit, scale in (
                ("Q", "M g", "N", lambda: self.Q),
                ("y0", "(M g / (S c_n))^(1/m2)", "m", lambda: self.y0),
                ("f_n0", "sqrt(m2 M g / y0 / M) / (2 pi)", "Hz", lambda: self.f_n0),
                ("zeta", "S h_n y0^l / (2 sqrt(m2 M g M / y0))", "1", lambda: self.zeta)):
            try:
                v = scale()
            except (OverflowError, ZeroDivisionError, ValueError):
                v = math.inf
            ok = math.isfinite(v) and (lo <= v <= hi if symbol != "zeta" else v >= 0.0)
            if not ok:
                where = "finite and >= 0" if symbol == "zeta" else \
                    f"in [{format_number(lo)}, {format_number(hi)}] {unit}"
                raise ParameterError(symbol, v, f"must be {where} ({symbol} = {formula} of the "
                                                f"model's {given})")

    # ----------------------------------------------------------------- construction
    @classmethod
    def from_overrides(cls, overrides: dict[str, float] | None = None) -> ContactModel:
        """Paper defaults with some parameters replaced; unknown names raise ParameterError."""
        overrides = dict(overrides or {})
        for name in overrides:
            if name not in PAPER_DEFAULTS:
                raise ParameterError(
                    name, overrides[name], f"unknown parameter; known: {', '.join(PAPER_DEFAULTS)}"
                )
        return cls(**overrides)

    def replace(self, **changes) -> ContactModel:
        """A copy with some parameters changed (validated again)."""
        return replace(self, **changes)

    def parameters(self) -> dict[str, float]:
        """The seven model parameters, SI units, by paper symbol."""
        return {f.name: getattr(self, f.name) for f in fields(self) if not f.name.startswith("_")}

    # ----------------------------------------------------------------- derived quantities
    @property
    def Q(self) -> float:
        """Weight of the slider Q = M g [N] (Eq. 2.1)."""
        return self.M * self.g

    @property
    def y0(self) -> float:
        """Static deflection y0 [m]: S c_n y0^m2 = Q."""
        return (self.Q / (self.S * self.c_n)) ** (1.0 / self.m2)

    @property
    def k_lin(self) -> float:
        """Linearised contact stiffness at y0, k = m2 S c_n y0^(m2−1) = m2 Q / y0 [N/m]."""
        return self.m2 * self.Q / self.y0

    @property
    def c_lin(self) -> float:
        """Linearised contact damping at y0, S h_n y0^l [N s/m]."""
        return self.S * self.h_n * self.y0**self.l

    @property
    def omega_n0(self) -> float:
        """Linear natural angular frequency ω_n0 = sqrt(k/M) [rad/s]."""
        return math.sqrt(self.k_lin / self.M)

    @property
    def f_n0(self) -> float:
        """Linear natural frequency f_n0 [Hz] (1485.0 Hz for the paper's parameters)."""
        return self.omega_n0 / (2.0 * math.pi)

    @property
    def zeta(self) -> float:
        """Linear damping ratio ζ = c / (2 sqrt(k M)) [1] (≈ 0.018 for the paper)."""
        return self.c_lin / (2.0 * math.sqrt(self.k_lin * self.M))

    @property
    def damping_coefficient(self) -> float:
        """Nondimensional damping coefficient c = 2 m2 ζ of the kernel equation [1]."""
        return 2.0 * self.m2 * self.zeta

    @property
    def units(self) -> Units:
        """Factors from the kernels' x = y/y0, x' and τ = ω_n0 t to µm, mm/s and ms."""
        return Units.of(self.y0, self.omega_n0)

    def superharmonic_frequencies(self, m_max: int = 6) -> np.ndarray:
        """Estimates f_n0/m [Hz] of the 1/m resonances, m = 1..m_max (Eq. 2.6)."""
        m = np.arange(1, int(m_max) + 1)
        return self.f_n0 / m

    # ----------------------------------------------------------------- forces
    @property
    def law(self) -> PowerLaw:
        """The contact law ``f(x, v) = x^m2 + c x^l v`` of this model (:class:`PowerLaw`)."""
        return PowerLaw(self.m2, self.l)

    def spring_force(self, y):
        """Spring force F_s(y) = −S c_n y^m2 for y > 0, else 0 [N] (Eq. 2.3); y in m.

        Evaluated by the contact law: ``F_s = −Q f(y/y0, 0)`` since ``S c_n y0^m2 = Q``.
        """
        y = np.asarray(y, dtype=float)
        f, _, _ = self.law.force(y / self.y0, 0.0, 0.0)
        return -self.Q * f

    def conservative_force(self, y):
        """Conservative force F_k = F_s + Q [N] (Eq. 2.4); y in m."""
        return self.spring_force(y) + self.Q

    # ----------------------------------------------------------------- kernel interface
    def excitation(self, pa_over_q: float, f_e: float) -> Excitation:
        """A validated excitation P_a = ``pa_over_q`` Q at ``f_e`` Hz for this model."""
        return Excitation(self, pa_over_q, f_e)


@dataclass(frozen=True)
class Excitation:
    """Harmonic force P_a cos(2π f_e t) applied to a :class:`ContactModel`.

    Parameters
    ----------
    model : ContactModel
    pa_over_q : float
        Amplitude as a multiple of Q = M g [1], ≥ 0.
    f_e : float
        Excitation frequency [Hz], > 0.
    """

    model: ContactModel
    pa_over_q: float
    f_e: float

    def __post_init__(self):
        if not isinstance(self.model, ContactModel):
            raise ParameterError("model", self.model, "must be a ContactModel")
        p = check_range("P_a/Q", self.pa_over_q, 0.0, True, PA_NOTE)
        object.__setattr__(self, "pa_over_q", check_range("P_a/Q", p, None, unit=PA_NOTE, upper=PA_MAX))
        f_e = check_range("f_e", self.f_e, 0.0, False, "Hz")
        f_n0 = self.model.f_n0
        lo, hi = R_RANGE
        if not lo * f_n0 <= f_e <= hi * f_n0:
            raise ParameterError(
                "f_e", self.f_e,
                f"must lie in [{format_number(lo)} f_n0, {format_number(hi)} f_n0] = "
                f"[{format_number(lo * f_n0)}, {format_number(hi * f_n0)}] Hz with the model's "
                f"f_n0 = {format_number(f_n0)} Hz (the frequency ratio r = f_e/f_n0 must be in "
                f"[{format_number(lo)}, {format_number(hi)}] for the integration)")
        object.__setattr__(self, "f_e", f_e)

    @classmethod
    def from_newtons(cls, model: ContactModel, P_a: float, f_e: float) -> Excitation:
        """Excitation from an amplitude P_a in newtons."""
        P_a = check_range("P_a", P_a, 0.0, True, "N")
        P_a = check_range("P_a", P_a, None, unit=f"N (P_a/Q <= {format_number(PA_MAX)})",
                          upper=PA_MAX * model.Q)
        return cls(model, P_a / model.Q, f_e)

    @property
    def P_a(self) -> float:
        """Force amplitude [N]."""
        return self.pa_over_q * self.model.Q

    @property
    def r(self) -> float:
        """Frequency ratio f_e / f_n0 [1]."""
        return self.f_e / self.model.f_n0

    @property
    def period(self) -> float:
        """Excitation period 1/f_e [s]."""
        return 1.0 / self.f_e

    @property
    def tau_period(self) -> float:
        """Excitation period in nondimensional time τ = ω_n0 t: 2π / r [1]."""
        return 2.0 * math.pi / self.r

    def kernel_parameters(self) -> np.ndarray:
        """Parameter vector ``[m2, l, c, p, r]`` of the nondimensional kernels."""
        m = self.model
        return np.array([m.m2, m.l, m.damping_coefficient, self.pa_over_q, self.r], dtype=np.float64)
