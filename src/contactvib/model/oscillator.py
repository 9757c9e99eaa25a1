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
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from contactvib.model.checks import PA_MAX, PA_NOTE, R_RANGE, ParameterError, check_range, format_number
from contactvib.model.contact_law import PowerLaw
from contactvib.model.laws import (
    DAMPING_NAMES,
    EXPONENTIAL_DEFAULTS,
    HUNT_CROSSLEY_DEFAULT,
    LAW_NAMES,
    ExponentialLaw,
    PowerSpring,
    TableLaw,
)
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
    "c_e": "N/m^2",
    "lam": "m",
    "alpha": "s/m",
    "preload": "N",
}

#: The model parameters a ``--set`` may name, by family (``M``, ``g``, ``S`` belong to every law).
FAMILY_PARAMETERS = {"power": ("c_n", "m2"), "exponential": ("c_e", "lam"), "table": (),
                     "damping power": ("h_n", "l"), "damping hunt-crossley": ("alpha",)}
#: Largest preload F_pre as a multiple of Q (guideways are preloaded by a few Q).
PRELOAD_MAX_Q = 1e3
#: Standard gravity [m/s²]: the unit of a base acceleration given in g (``--base-g``).
G_STANDARD = 9.80665
#: Largest number of extra harmonics of a multi-harmonic force.
HARMONIC_TERMS_MAX = 64

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
    law: object = "power"
    c_e: float | None = None
    lam: float | None = None
    table: object = None
    damping: str = "power"
    alpha: float | None = None
    preload: float = 0.0
    _checked: bool = field(default=False, repr=False, compare=False)

    def __post_init__(self):
        self._normalise_family()
        for name, (lower, inclusive, upper) in _BOUNDS.items():
            check_range(name, getattr(self, name), lower, inclusive, PARAMETER_UNITS[name])
            if upper is not None:
                check_range(name, getattr(self, name), None, unit=PARAMETER_UNITS[name], upper=upper)
            object.__setattr__(self, name, float(getattr(self, name)))
        q = self.M * self.g
        if math.isfinite(q):
            check_range("F_pre", self.preload, None, upper=PRELOAD_MAX_Q * q,
                        unit=f"N (at most {PRELOAD_MAX_Q:g} Q = {PRELOAD_MAX_Q * q:.4g} N)")
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
                f"for the paper's zeta = 0.018 at this l)"
                if self.damping == "power" else
                f"gives the damping ratio zeta = {self.zeta:.3g}: must give zeta <= {ZETA_MAX:g}, i.e. "
                f"alpha <= {self.alpha * ZETA_MAX / self.zeta:.3g} s/m")

    def _normalise_family(self) -> None:
        """The law and damping families by name, their parameters filled in and checked."""
        law = self.law
        if isinstance(law, ExponentialLaw):
            object.__setattr__(self, "c_e", law.c_e)
            object.__setattr__(self, "lam", law.lam)
            law = "exponential"
        elif isinstance(law, TableLaw):
            object.__setattr__(self, "table", law)
            law = "table"
        if law not in LAW_NAMES:
            raise ParameterError("law", law, f"must be one of {', '.join(LAW_NAMES)} (or an ExponentialLaw, "
                                             "a TableLaw)")
        object.__setattr__(self, "law", law)
        if law == "exponential":
            for name in ("c_e", "lam"):
                v = EXPONENTIAL_DEFAULTS[name] if getattr(self, name) is None else getattr(self, name)
                object.__setattr__(self, name, check_range(name, v, 0.0, False, PARAMETER_UNITS[name]))
        else:
            for name in ("c_e", "lam"):
                if getattr(self, name) is not None:
                    raise ParameterError(name, getattr(self, name), f"is a parameter of the exponential law, "
                                                                    f"not of the {law} law (--law exponential)")
        if law == "table":
            t = self.table
            if isinstance(t, dict):
                t = TableLaw.from_dict(t)
            if not isinstance(t, TableLaw):
                raise ParameterError("law_file", t, "the table law needs a table (TableLaw, --law-file FILE.csv)")
            object.__setattr__(self, "table", t)
        elif self.table is not None:
            raise ParameterError("law_file", getattr(self.table, "source", self.table),
                                 f"a table belongs to the table law, not to the {law} law (--law table)")
        if self.damping not in DAMPING_NAMES:
            raise ParameterError("damping", self.damping, f"must be one of {', '.join(DAMPING_NAMES)}")
        if self.damping == "hunt-crossley":
            a = HUNT_CROSSLEY_DEFAULT if self.alpha is None else self.alpha
            object.__setattr__(self, "alpha", check_range("alpha", a, 0.0, True, "s/m"))
        elif self.alpha is not None:
            raise ParameterError("alpha", self.alpha, "is a parameter of the Hunt-Crossley damping, not of the "
                                                      "power damping (--damping hunt-crossley)")
        object.__setattr__(self, "preload", check_range("F_pre", self.preload, 0.0, True, "N"))

    def _check_scales(self) -> None:
        """The derived scales Q, y0, f_n0 and ζ must be finite (no overflow of the parameters'
        combination); ParameterError names the scale, its formula and the parameters."""
        lo, hi = DERIVED_RANGE
        given = ", ".join(f"{k} = {format_number(v)}" for k, v in self.parameters().items()
                          if isinstance(v, float))
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

    def parameters(self) -> dict:
        """The model's parameters, SI units, by symbol (JSON-able; ``ContactModel(**p)`` rebuilds it).

        The paper's family gives the seven paper symbols; another law adds ``law`` and its own
        parameters (``c_e``, ``lam``; ``table`` with its rows and content hash), Hunt–Crossley
        damping ``damping`` and ``alpha``, a preload ``preload`` [N]."""
        p = {name: getattr(self, name) for name in PAPER_DEFAULTS}
        if self.law != "power":
            del p["c_n"], p["m2"]
            p["law"] = self.law
            p.update(self.spring_law.parameters())
        if self.damping != "power":
            del p["h_n"], p["l"]
            p["damping"] = self.damping
            p["alpha"] = self.alpha
        if self.preload != 0.0:
            p["preload"] = self.preload
        return p

    def describe_law(self) -> str:
        """One line naming the law, damping and preload, e.g. ``power law (c_n = 4.52e16, m2 = 2)``."""
        def fmt(d):
            return ", ".join(f"{k} = {v:.4g}" if isinstance(v, float) else f"{k} = {v}" for k, v in d.items())
        law = (f"table law ({self.table.source}, {self.table.deflection_m.size} rows, sha256 "
               f"{self.table.sha256[:12]})" if self.law == "table" else
               f"{self.law} law ({fmt(self.spring_law.parameters())})")
        damp = (f"power damping (h_n = {self.h_n:.4g}, l = {self.l:g})" if self.damping == "power"
                else f"Hunt-Crossley damping (alpha = {self.alpha:.4g} s/m)")
        pre = f", preload {self.preload:.4g} N" if self.preload else ""
        return f"{law}, {damp}{pre}"

    # ----------------------------------------------------------------- derived quantities
    @property
    def Q(self) -> float:
        """Weight of the slider Q = M g [N] (Eq. 2.1)."""
        return self.M * self.g

    @property
    def W(self) -> float:
        """Static load W = Q + F_pre [N]: weight plus preload, the unit of force of the kernels."""
        return self.Q + self.preload

    @property
    def spring_law(self):
        """The spring family as an object (:mod:`contactvib.model.laws`)."""
        if self.law == "exponential":
            return ExponentialLaw(self.c_e, self.lam)
        if self.law == "table":
            return self.table
        return PowerSpring(self.c_n, self.m2)

    @cached_property
    def y0(self) -> float:
        """Static deflection y0 [m]: F_s(y0) = W (S c_n y0^m2 = Q for the paper)."""
        if self.law == "power":
            return (self.W / (self.S * self.c_n)) ** (1.0 / self.m2)
        return self.spring_law.static_deflection(self.W, self.S)

    @property
    def k_lin(self) -> float:
        """Linearised contact stiffness at y0, k = F_s'(y0) [N/m] (m2 W / y0 for the power law)."""
        if self.law == "power":
            return self.m2 * self.W / self.y0
        return float(self.spring_law.stiffness(self.y0, self.S))

    @property
    def kappa(self) -> float:
        """Nondimensional mass κ = k y0 / W of the kernel equation κ x'' = 1 + e(τ) − f [1] (m2 for
        the power law)."""
        if self.law == "power":
            return self.m2
        return self.k_lin * self.y0 / self.W

    @property
    def c_lin(self) -> float:
        """Linearised contact damping at y0 [N s/m]: S h_n y0^l (power), α W (Hunt–Crossley)."""
        if self.damping == "hunt-crossley":
            return self.alpha * self.W
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
        """Nondimensional damping coefficient c = 2 κ ζ of the kernel equation [1] (2 m2 ζ for the
        power law; α y0 ω_n0 for Hunt–Crossley damping)."""
        return 2.0 * self.kappa * self.zeta

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
    def power_law(self) -> PowerLaw:
        """The nondimensional power law ``f(x, v) = x^m2 + c x^l v`` of this model's m2 and l
        (:class:`PowerLaw`; the contact law when ``law == "power"`` and ``damping == "power"``)."""
        return PowerLaw(self.m2, self.l)

    def spring_force(self, y):
        """Spring force F_s(y) = −S c_n y^m2 for y > 0, else 0 [N] (Eq. 2.3; the spring family's
        F_s for the other laws); y in m.

        Evaluated by the compiled contact law: ``F_s = −W f_s(y/y0)`` since ``F_s(y0) = W``.
        """
        y = np.asarray(y, dtype=float)
        from contactvib._kernels.contact import contact_force_array

        x = np.ascontiguousarray(y / self.y0, dtype=float).ravel()
        f, fx, fv = np.empty_like(x), np.empty_like(x), np.empty_like(x)
        par = self.excitation(0.0, self.f_n0).kernel_parameters()
        par[2] = 0.0  # no damping
        contact_force_array(x, np.zeros_like(x), par, f, fx, fv)
        return -self.W * f.reshape(y.shape)

    def conservative_force(self, y):
        """Conservative force F_k = F_s + Q + F_pre [N] (Eq. 2.4 with the preload); y in m."""
        return self.spring_force(y) + self.W

    @property
    def is_paper_family(self) -> bool:
        """Power spring, power damping and no preload: the law of the perturbation series and of
        harmonic balance (whose forms are written for x^m2 + c x^l x' with p = P_a/Q)."""
        return self.law == "power" and self.damping == "power" and self.preload == 0.0

    def require_paper_family(self, what: str, excitation: Excitation | None = None) -> None:
        """ParameterError (``law``) unless the model is the power law without preload under a
        single harmonic force: ``what`` (e.g. "the perturbation series") is written for it."""
        if not self.is_paper_family:
            raise ParameterError("law", self.describe_law(),
                                 f"{what} is written for the power law with power damping and no preload; "
                                 "use attractors, continue or resonance for this law")
        if excitation is not None and excitation.kind != "force":
            raise ParameterError("excitation", excitation.kind,
                                 f"{what} is written for a single harmonic force; use attractors, continue or "
                                 "resonance for this excitation")

    def check_motion(self, y_max_um: float, what: str = "the motion") -> None:
        """Refuse (ParameterError ``law_file``) a deflection beyond a table law's last row."""
        if self.law == "table":
            self.table.check_deflection(y_max_um * 1e-6, what)

    # ----------------------------------------------------------------- kernel interface
    def excitation(self, pa_over_q: float, f_e: float, harmonics=()) -> Excitation:
        """A validated excitation P_a = ``pa_over_q`` Q at ``f_e`` Hz for this model (plus
        ``harmonics``, ``(k, P_k/Q, phase_deg)`` triples: a multi-harmonic force)."""
        return Excitation(self, pa_over_q, f_e, harmonics=harmonics)


@dataclass(frozen=True)
class Excitation:
    """Periodic excitation of a :class:`ContactModel` at f_e.

    * force (default): P_a cos(2π f_e t), plus optional harmonics Σ P_k cos(2π k f_e t + φ_k);
    * base motion of the slideway (:meth:`base`): u(t) = U cos(2π f_e t) along y; the contact acts
      on the relative coordinate y (slider − base), which feels the inertial force
      M U (2π f_e)² cos(2π f_e t) — given as U (``base_um``) or as the acceleration amplitude A
      (``base_g``, in standard g).

    Parameters
    ----------
    model : ContactModel
    pa_over_q : float
        Amplitude of the force at f_e as a multiple of Q = M g [1], ≥ 0 (for base motion the
        equivalent force amplitude M U (2π f_e)² / Q).
    f_e : float
        Excitation frequency [Hz], > 0.
    harmonics : tuple of (k, P_k/Q, phase [deg])
        Further harmonics of the force, k an integer ≥ 2.
    base_um, base_g : float or None
        Base displacement amplitude U [µm] or acceleration amplitude A [g] (set by :meth:`base`).
    """

    model: ContactModel
    pa_over_q: float
    f_e: float
    harmonics: tuple = ()
    base_um: float | None = None
    base_g: float | None = None

    def __post_init__(self):
        if not isinstance(self.model, ContactModel):
            raise ParameterError("model", self.model, "must be a ContactModel")
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
        if self.base_um is not None or self.base_g is not None:
            if self.base_um is not None and self.base_g is not None:
                raise ParameterError("base", (self.base_um, self.base_g), "give U (base_um) or A (base_g), not both")
            if self.harmonics:
                raise ParameterError("harmonics", self.harmonics, "belong to a force excitation, not to base motion")
            if self.base_um is not None:
                U = check_range("U", self.base_um, 0.0, True, "um")
                object.__setattr__(self, "base_um", U)
                pa = self.model.M * U * 1e-6 * (2.0 * math.pi * f_e) ** 2 / self.model.Q
            else:
                A = check_range("A", self.base_g, 0.0, True, "g")
                object.__setattr__(self, "base_g", A)
                pa = self.model.M * A * G_STANDARD / self.model.Q
            if not pa <= PA_MAX:
                sym, val, unit = self.level
                raise ParameterError(sym, val, f"gives an inertial force M U (2 pi f_e)^2 = {pa:.4g} Q at "
                                               f"{f_e:g} Hz: must be <= {PA_MAX:g} Q, i.e. {sym} <= "
                                               f"{val * PA_MAX / pa:.4g} {unit}")
            object.__setattr__(self, "pa_over_q", pa)
        p = check_range("P_a/Q", self.pa_over_q, 0.0, True, PA_NOTE)
        object.__setattr__(self, "pa_over_q", check_range("P_a/Q", p, None, unit=PA_NOTE, upper=PA_MAX))
        object.__setattr__(self, "harmonics", _check_harmonics(self.harmonics))

    @classmethod
    def from_newtons(cls, model: ContactModel, P_a: float, f_e: float, harmonics=()) -> Excitation:
        """Excitation from an amplitude P_a in newtons."""
        P_a = check_range("P_a", P_a, 0.0, True, "N")
        P_a = check_range("P_a", P_a, None, unit=f"N (P_a/Q <= {format_number(PA_MAX)})",
                          upper=PA_MAX * model.Q)
        return cls(model, P_a / model.Q, f_e, harmonics=harmonics)

    @classmethod
    def base(cls, model: ContactModel, f_e: float, u_um: float | None = None,
             a_g: float | None = None) -> Excitation:
        """Base (support) motion of amplitude U = ``u_um`` µm, or acceleration A = ``a_g`` g."""
        if (u_um is None) == (a_g is None):
            raise ParameterError("base", (u_um, a_g), "give exactly one of U (u_um) and A (a_g)")
        return cls(model, 0.0, f_e, base_um=u_um, base_g=a_g)

    @property
    def kind(self) -> str:
        """``"force"``, ``"harmonics"`` (a multi-harmonic force) or ``"base"``."""
        if self.base_um is not None or self.base_g is not None:
            return "base"
        return "harmonics" if self.harmonics else "force"

    @property
    def level(self) -> tuple[str, float, str]:
        """(symbol, value, unit) of the excitation level: P_a/Q, U [um] or A [g]."""
        if self.base_um is not None:
            return "U", self.base_um, "um"
        if self.base_g is not None:
            return "A", self.base_g, "g"
        return "P_a/Q", self.pa_over_q, "Q"

    def describe(self) -> dict:
        """The excitation as a JSON-able record (kind, level, f_e, harmonics)."""
        sym, val, unit = self.level
        d = {"kind": self.kind, "level_symbol": sym, "level": val, "level_unit": unit, "fe_hz": self.f_e,
             "pa_over_q": self.pa_over_q}
        if self.harmonics:
            d["harmonics"] = [list(h) for h in self.harmonics]
        return d

    @property
    def P_a(self) -> float:
        """Force amplitude at f_e [N] (for base motion the inertial force's)."""
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
        """Parameter vector of the nondimensional kernels (:mod:`contactvib._kernels.contact`):
        ``[m2, l, c, p, r]`` for the paper's law under a force, else the full layout
        ``[κ, l, c, p, r, spring, damping, excitation, s1, s2, n_exc, off_exc, data…]``."""
        m = self.model
        if (m.law == "power" and m.damping == "power" and m.preload == 0.0 and self.kind == "force"):
            return np.array([m.m2, m.l, m.damping_coefficient, self.pa_over_q, self.r], dtype=np.float64)
        from contactvib._kernels import contact as kc

        code, s1, s2, data = m.spring_law.kernel_spring(m.y0, m.W, m.S)
        q = m.Q / m.W  # forces in units of W
        if self.base_um is not None:
            exc, p = kc.EXCITATION_BASE, m.k_lin * self.base_um * 1e-6 / m.W  # × r² in the kernel
        else:
            exc, p = (kc.EXCITATION_HARMONICS if self.harmonics else kc.EXCITATION_FORCE), self.pa_over_q * q
        terms = [(float(k), a * q, math.radians(ph)) for k, a, ph in self.harmonics]
        damping = kc.DAMPING_HUNT_CROSSLEY if m.damping == "hunt-crossley" else kc.DAMPING_POWER
        l = m.l if m.damping == "power" else 0.0
        head = np.array([m.kappa, l, m.damping_coefficient, p, self.r, code, damping, exc, s1,
                         kc.HEADER if data.size else s2, len(terms), kc.HEADER + data.size], dtype=np.float64)
        return np.concatenate([head, data, np.array(terms, dtype=np.float64).ravel()])


def _check_harmonics(harmonics) -> tuple:
    """Harmonics as a tuple of (k, P_k/Q, phase_deg): k an integer 2..64, amplitude in [0, PA_MAX] Q."""
    out = []
    try:
        items = list(harmonics)
    except TypeError:
        raise ParameterError("harmonics", harmonics, "must be a sequence of (k, P_k/Q, phase_deg)") from None
    if len(items) > HARMONIC_TERMS_MAX:
        raise ParameterError("harmonics", len(items), f"at most {HARMONIC_TERMS_MAX} harmonics")
    for h in items:
        try:
            k, a, ph = h
        except (TypeError, ValueError):
            raise ParameterError("harmonics", h, "each harmonic is (k, P_k/Q, phase_deg)") from None
        kf = check_range("k", k, 2.0, True, "(an integer multiple of f_e)", upper=float(HARMONIC_TERMS_MAX))
        if kf != math.floor(kf):
            raise ParameterError("k", k, "must be an integer (a harmonic of f_e)")
        a = check_range("P_k/Q", a, 0.0, True, PA_NOTE, upper=PA_MAX)
        ph = check_range("phase", ph, -360.0, True, "deg", upper=360.0)
        out.append((int(kf), a, ph))
    return tuple(out)
