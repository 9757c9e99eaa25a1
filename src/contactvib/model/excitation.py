"""The periodic excitation of a contact oscillator: a harmonic force (the paper's), a
multi-harmonic force, or base (slideway) motion; its nondimensional kernel parameters."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from contactvib.model.checks import PA_MAX, PA_NOTE, R_RANGE, ParameterError, check_range, format_number

#: What an Excitation asks of its model (every :class:`ContactModel` has them)
_MODEL_MEMBERS = ("f_n0", "Q", "M", "spring_law", "require_paper_family")

__all__ = ["Excitation", "G_STANDARD", "HARMONIC_TERMS_MAX", "LEVEL_KINDS", "LEVEL_TAGS",
           "check_excitation", "excitation_at", "level_text"]

#: Standard gravity [m/s²]: the unit of a base acceleration given in g (``--base-g``).
G_STANDARD = 9.80665
#: Largest number of extra harmonics of a multi-harmonic force.
HARMONIC_TERMS_MAX = 64
#: What the level of a sweep holds, by excitation kind: (symbol, unit, long name). A sweep keeps
#: its level constant over f_e: the force amplitude P_a/Q, the base displacement U [µm] (the
#: inertial force M U (2π f_e)² grows with f_e²) or the base acceleration A [g].
LEVEL_KINDS = {
    "force": ("P_a/Q", "Q", "excitation amplitude P_a/(M g)"),
    "base-um": ("U", "um", "base displacement amplitude U"),
    "base-g": ("A", "g", "base acceleration amplitude A"),
}


def check_excitation(excitation, model: ExcitedModel | None = None) -> Excitation:
    """``excitation`` checked to be an :class:`~contactvib.Excitation` (of a model equal to ``model``, where
    given): the operating point of a verb at one point. Returns it."""
    if model is not None and not all(hasattr(type(model), a) for a in _MODEL_MEMBERS):
        raise ParameterError("model", model, "must be a ContactModel")
    if not isinstance(excitation, Excitation):
        raise ParameterError("excitation", excitation, "must be an Excitation (model.excitation(P_a/Q, f_e))")
    if model is not None and excitation.model != model:
        mine, theirs = model.parameters(), excitation.model.parameters()
        differ = ", ".join(k for k in mine if mine[k] != theirs.get(k))
        raise ParameterError("excitation", f"P_a/Q = {excitation.pa_over_q:g} at {excitation.f_e:g} Hz",
                             f"belongs to another model ({differ} differ): make it with "
                             f"model.excitation(P_a/Q, f_e)")
    return excitation


class ExcitedModel(Protocol):
    """What an :class:`Excitation` reads of its model: every :class:`contactvib.ContactModel` is
    one. The type is stated here, by what it offers, because the model's module
    (``model/oscillator.py``) imports this one and not the reverse."""

    M: float
    Q: float
    S: float
    W: float
    y0: float
    f_n0: float
    k_lin: float
    kappa: float
    m2: float
    l: float
    law: str
    damping: str
    preload: float
    damping_coefficient: float
    spring_law: object

    def require_paper_family(self, what: str, excitation: Excitation | None = None) -> None: ...


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

    model: ExcitedModel
    pa_over_q: float
    f_e: float
    harmonics: tuple = ()
    base_um: float | None = None
    base_g: float | None = None

    def __post_init__(self):
        # a ContactModel, known by what it offers (the model module imports this one, not back)
        if not all(hasattr(type(self.model), a) for a in _MODEL_MEMBERS):
            raise ParameterError("model", self.model, "must be a ContactModel")
        f_e = check_range("f_e", self.f_e, 0.0, False, "Hz")
        f_n0 = self.model.f_n0
        lo, hi = R_RANGE
        if not lo * f_n0 <= f_e <= hi * f_n0:
            raise ParameterError(
                "f_e", self.f_e,
                f"must lie in [{format_number(lo)} f_n0, {format_number(hi)} f_n0] = "
                f"[{format_number(lo * f_n0)}, {format_number(hi * f_n0)}] Hz, f_n0 = {format_number(f_n0)} Hz "
                f"(the range of r = f_e/f_n0 the integration takes)")
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
    def from_newtons(cls, model: ExcitedModel, P_a: float, f_e: float, harmonics=()) -> Excitation:
        """Excitation from an amplitude P_a in newtons."""
        P_a = check_range("P_a", P_a, 0.0, True, "N")
        P_a = check_range("P_a", P_a, None, unit=f"N (P_a/Q <= {format_number(PA_MAX)})",
                          upper=PA_MAX * model.Q)
        return cls(model, P_a / model.Q, f_e, harmonics=harmonics)

    @classmethod
    def base(cls, model: ExcitedModel, f_e: float, u_um: float | None = None,
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
    def level_kind(self) -> str:
        """The kind of :attr:`level` (:data:`~contactvib.model.LEVEL_KINDS`): "force", "base-um" or "base-g"."""
        return "base-um" if self.base_um is not None else ("base-g" if self.base_g is not None else "force")

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
    def base_amplitude_um(self) -> float | None:
        """Amplitude of the base displacement u(t) = U cos(2π f_e t) along y [µm]: U, or A g_n/ω²
        for a base acceleration A; None for a force. The slider's absolute displacement along y
        (from where it rests on the resting base) is s = y + u."""
        if self.base_um is not None:
            return self.base_um
        if self.base_g is not None:
            return self.base_g * G_STANDARD / (2.0 * math.pi * self.f_e) ** 2 * 1e6
        return None

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
        """Parameter vector of the nondimensional kernels (``contactvib._kernels.contact``):
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


#: Prefix of a level in file and branch names, by kind: ``pa0.65``, ``U0.05``, ``A0.3``.
LEVEL_TAGS = {"force": "pa", "base-um": "U", "base-g": "A"}


def check_level_kind(kind) -> str:
    """``kind`` if it is one of :data:`~contactvib.model.LEVEL_KINDS`, else a ParameterError naming the choices."""
    if kind not in LEVEL_KINDS:
        raise ParameterError("excitation", kind, "must be one of " + ", ".join(LEVEL_KINDS))
    return kind


def excitation_at(model: ExcitedModel, level: float, f_e: float, kind: str = "force") -> Excitation:
    """The excitation at f_e [Hz] of a sweep held at ``level``: P_a/Q (``kind`` "force"), U [µm]
    ("base-um") or A [g] ("base-g"); see :data:`~contactvib.model.LEVEL_KINDS`."""
    kind = check_level_kind(kind)
    if kind == "force":
        return Excitation(model, level, f_e)
    if kind == "base-um":
        return Excitation.base(model, f_e, u_um=level)
    return Excitation.base(model, f_e, a_g=level)


def level_text(level: float, kind: str = "force", digits: int = 4) -> str:
    """The level as a figure or table writes it: ``P_a = 0.65 Q``, ``U = 2 µm``, ``A = 0.5 g``."""
    sym, unit, _name = LEVEL_KINDS[check_level_kind(kind)]
    sym = "P_a" if sym == "P_a/Q" else sym
    unit = "µm" if unit == "um" else unit
    return f"{sym} = {level:.{digits}g} {unit}"
