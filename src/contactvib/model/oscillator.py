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

from contactvib.model.checks import ParameterError, check_range, format_number
from contactvib.model.contact_law import PowerLaw
from contactvib.model.excitation import Excitation
from contactvib.model.laws import (
    DAMPING_NAMES,
    DAMPING_PARAMETERS,
    HUNT_CROSSLEY_DEFAULT,
    PowerSpring,
    SpringLaw,
    TableLaw,
    law_class,
    law_parameter_names,
)
from contactvib.model.units import Units

__all__ = ["ContactModel", "Excitation", "PAPER_DEFAULTS", "PARAMETER_UNITS", "ZETA_MAX", "family_parameters"]

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



def family_parameters() -> dict[str, tuple[str, ...]]:
    """The model parameters a ``--set`` may name, by family: each registered law's (by its name)
    and each damping family's (``"damping power"``, ``"damping hunt-crossley"``); ``M``, ``g``,
    ``S`` belong to every law."""
    return {**law_parameter_names(), **{f"damping {k}": v for k, v in DAMPING_PARAMETERS.items()}}


#: Largest preload F_pre as a multiple of Q (guideways are preloaded by a few Q).
PRELOAD_MAX_Q = 1e3

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
    law : str or SpringLaw
        The spring law: a registered name (``contactvib.model.laws.law_names()``: power,
        exponential, table, clearance and any plug-in) or a law object.
    c_e, lam : float, optional
        The exponential law's parameters (also accepted in ``law_params``).
    table : TableLaw, optional
        The table law's curve.
    damping : str
        ``"power"`` (h_n, l) or ``"hunt-crossley"`` (alpha).
    alpha : float, optional
        Hunt–Crossley coefficient [s/m].
    preload : float
        Constant normal force F_pre [N] added to the weight.
    law_params : dict, optional
        The parameters of any other law by name, e.g. ``{"c_lin": 2e10, "gap_um": 1.0}`` for
        ``law="clearance"``; checked against the law's bounds.

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
    law_params: object = None
    _spring: object = field(default=None, init=False, repr=False, compare=False)

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
        """The law (by name from the registry, or a law object) and damping family, their
        parameters filled in and checked; the law object is kept for :attr:`spring_law`."""
        law = self.law
        params = dict(self.law_params or {}) if not isinstance(self.law_params, tuple) else dict(self.law_params)
        if isinstance(law, SpringLaw):
            if params:
                raise ParameterError("law_params", params, "give the law's parameters to the law object, not both")
            obj, law = law, law.name
        else:
            obj = None
            law_class(law)  # unknown names: ParameterError listing the known laws
        legacy = {k: getattr(self, k) for k in ("c_e", "lam") if getattr(self, k) is not None}
        if law == "exponential":
            params = {**params, **legacy}
        elif legacy:
            name, value = next(iter(legacy.items()))
            raise ParameterError(name, value, f"is a parameter of the exponential law, not of the {law} law "
                                              "(--law exponential)")
        if law == "table":
            t = obj if obj is not None else self.table
            if isinstance(t, dict):
                t = TableLaw.from_dict(t)
            if not isinstance(t, TableLaw):
                raise ParameterError("law_file", t, "the table law needs a table (TableLaw, --law-file FILE.csv)")
            obj = t
        elif self.table is not None:
            raise ParameterError("law_file", getattr(self.table, "source", self.table),
                                 f"a table belongs to the table law, not to the {law} law (--law table)")
        if law in ("power", "table") and params:
            name, value = next(iter(params.items()))
            known = "c_n, m2 (the model's own)" if law == "power" else "none (--law-file)"
            raise ParameterError(name, value, f"unknown parameter of the {law} law; known: {known}")
        if obj is None and law not in ("power", "table"):
            obj = law_class(law)(**params)
        if obj is not None and tuple(obj.kinks()) != (0.0,):
            raise ParameterError("law", law, f"has kinks at deflections {tuple(obj.kinks())} m: the integrators locate "
                                             "only the engagement point (0,)")
        if law == "exponential":
            object.__setattr__(self, "c_e", obj.c_e)
            object.__setattr__(self, "lam", obj.lam)
        object.__setattr__(self, "table", obj if law == "table" else None)
        object.__setattr__(self, "law", law)
        own = law not in ("power", "exponential", "table")
        object.__setattr__(self, "law_params", tuple(obj.values().items()) if own else None)
        object.__setattr__(self, "_spring", obj)
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
            except ParameterError:  # a law's own refusal (a table that does not reach W) says why
                raise
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
        parameters (``c_e``, ``lam``; ``table`` with its rows and content hash; any other law's
        as ``law_params``, a dict by the names of its ``--set``), Hunt–Crossley
        damping ``damping`` and ``alpha``, a preload ``preload`` [N]."""
        p = {name: getattr(self, name) for name in PAPER_DEFAULTS}
        if self.law != "power":
            del p["c_n"], p["m2"]
            p["law"] = self.law
            if self.law_params is not None:
                p["law_params"] = dict(self.law_params)
            else:
                p.update(self.spring_law.values())
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
               f"{self.law} law ({fmt(self.spring_law.values())})")
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
    def spring_law(self) -> SpringLaw:
        """The spring law as an object of the registry (``contactvib.model.laws``)."""
        if self._spring is None:  # the power law: its parameters are the model's own c_n, m2
            object.__setattr__(self, "_spring", PowerSpring(self.c_n, self.m2))
        return self._spring

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
        """Factors from the kernels' x = δ/y0, x' and τ = ω_n0 t to µm, mm/s and ms (with the
        law's engagement point as the offset of positions: y = y_e + x y0)."""
        return Units.of(self.y0, self.omega_n0, self.spring_law.engagement_m)

    def superharmonic_frequencies(self, m_max: int = 6) -> np.ndarray:
        """Estimates f_n0/m [Hz] of the 1/m resonances, m = 1..m_max (Eq. 2.6).

        >>> ContactModel().superharmonic_frequencies(4).round(1).tolist()
        [1485.0, 742.5, 495.0, 371.3]
        """
        m = np.arange(1, int(m_max) + 1)
        return self.f_n0 / m

    # ----------------------------------------------------------------- forces
    @property
    def power_law(self) -> PowerLaw:
        """The nondimensional power law ``f(x, v) = x^m2 + c x^l v`` of this model's m2 and l
        (:class:`~contactvib.model.PowerLaw`; the contact law when ``law == "power"`` and ``damping == "power"``)."""
        return PowerLaw(self.m2, self.l)

    def spring_force(self, y):
        """Spring force F_s(y) = −S c_n y^m2 for y > 0, else 0 [N] (Eq. 2.3; the spring law's
        F_s(y − y_e) for the other laws, y_e its engagement point); y in m.

        Evaluated by the compiled contact law: ``F_s = −W f_s((y − y_e)/y0)`` since ``F_s(y0) = W``.
        """
        y = np.asarray(y, dtype=float)
        from contactvib._kernels.contact import contact_force_array

        x = np.ascontiguousarray((y - self.spring_law.engagement_m) / self.y0, dtype=float).ravel()
        f, fx, fv = np.empty_like(x), np.empty_like(x), np.empty_like(x)
        par = self.excitation(0.0, self.f_n0).kernel_parameters()
        par[2] = 0.0  # no damping
        contact_force_array(x, np.zeros_like(x), par, f, fx, fv)
        return -self.W * f.reshape(y.shape)

    def contact_force(self, y, ydot):
        """Contact force F_c(y, ẏ) = S c_n y^m2 + S h_n y^l ẏ for y > 0, else 0 [N] (Eq. 2.3: the
        force the contact exerts on the slider is −F_c; the spring and damping laws' F_s + F_d of
        the deflection δ = y − y_e for the other laws, y_e their engagement point); y in m, ẏ in
        m/s, arrays of one shape.

        Evaluated by the compiled contact law, as the kernels integrate it: ``F_c = W f(x, x')``
        with x = (y − y_e)/y0, x' = ẏ/(y0 ω_n0).
        """
        y, ydot = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(ydot, dtype=float))
        from contactvib._kernels.contact import contact_force_array

        x = np.ascontiguousarray((y - self.spring_law.engagement_m) / self.y0, dtype=float).ravel()
        v = np.ascontiguousarray(ydot / (self.y0 * self.omega_n0), dtype=float).ravel()
        f, fx, fv = np.empty_like(x), np.empty_like(x), np.empty_like(x)
        contact_force_array(x, v, self.excitation(0.0, self.f_n0).kernel_parameters(), f, fx, fv)
        return self.W * f.reshape(y.shape)

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
        """Refuse (ParameterError) a largest position ``y_max_um`` [µm] beyond the law's range of
        validity (a table law's last row, a tabulated law's extent)."""
        if self.law != "power":
            self.spring_law.check_motion(y_max_um * 1e-6 - self.spring_law.engagement_m, self.y0, what)

    # ----------------------------------------------------------------- kernel interface
    def excitation(self, pa_over_q: float, f_e: float, harmonics=()) -> Excitation:
        """A validated excitation P_a = ``pa_over_q`` Q at ``f_e`` Hz for this model (plus
        ``harmonics``, ``(k, P_k/Q, phase_deg)`` triples: a multi-harmonic force).

        >>> exc = ContactModel().excitation(0.65, 360.0)
        >>> round(exc.P_a, 4), round(exc.r, 4)  # P_a [N], f_e/f_n0
        (1.3429, 0.2424)
        """
        return Excitation(self, pa_over_q, f_e, harmonics=harmonics)
