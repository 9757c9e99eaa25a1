"""A structure of n degrees of freedom with contact elements: the model of the system core (SI).

Equation (q [m or rad] the coordinates, P(t) = P_a cos(2π f_e t) [N] the excitation)::

    M q̈ + C q̇ + K q = f0 + b P(t) − Σ_i w_i F_i(δ_i, δ̇_i),      δ_i = w_i · q − e_i

Each contact element i has a direction ``w_i`` (its deflection δ_i [m] is positive into the
contact; w_i in m/m for a translation, m/rad for a rotation), an engagement point
``e_i = gap + law.engagement_m`` [m], a nominal area ``S_i`` [m²], a spring law of the registry
(``contactvib.model.laws``, ``F_s(δ)`` [N]) and a damping law, and acts only while δ_i > 0:
``F_i = F_s(δ_i) + S h_n δ_i^l δ̇_i`` (power damping) or ``F_s(δ_i) (1 + α δ̇_i)`` (Hunt–Crossley).
Its generalised force ``−w_i F_i`` pushes the structure out of the contact.

:meth:`System.single_dof` is the paper's slider (Kostek 2013, Eq. 2.5) as the n = 1 system. The
scaled form the compiled integrator runs (``contactvib._kernels.system_flow``) is
:meth:`System.kernel_form` (:mod:`contactvib.model.system_kernel`).

References
----------
R. I. Leine, N. van de Wouw, *Stability and Convergence of Mechanical Systems with Unilateral
Constraints*, Springer (2008), Ch. 2 (multibody systems with unilateral contacts).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from contactvib.model.checks import ParameterError, check_range
from contactvib.model.laws import DAMPING_NAMES, HUNT_CROSSLEY_DEFAULT, SpringLaw, law_class

__all__ = ["ContactElement", "System", "COORDINATE_UNITS", "STATIC_RTOL"]

#: Units of a coordinate: a translation [m] or a rotation [rad].
COORDINATE_UNITS = ("m", "rad")
#: Relative residual of the static equilibrium (:meth:`System.static_state`).
STATIC_RTOL = 1e-13
#: Largest exponent l of the power damping (as ContactModel's).
DAMPING_EXPONENT_MAX = 10.0


def _vector(symbol: str, value, n: int | None = None) -> np.ndarray:
    """``value`` as a finite float vector (of length ``n`` if given), read-only."""
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(symbol, value, "must be a vector of finite numbers") from None
    if a.ndim != 1 or (n is not None and a.shape[0] != n):
        raise ParameterError(symbol, value, f"must be a vector of {n if n is not None else 'n'} numbers; "
                                            f"got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ParameterError(symbol, value, "must be finite (no NaN or inf)")
    a.setflags(write=False)
    return a


def _matrix(symbol: str, value, n: int) -> np.ndarray:
    """``value`` as a finite n×n float matrix, read-only."""
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(symbol, value, f"must be an {n}x{n} matrix of finite numbers") from None
    if a.shape != (n, n):
        raise ParameterError(symbol, value, f"must be an {n}x{n} matrix (n = {n} coordinates); got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ParameterError(symbol, value, "must be finite (no NaN or inf)")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class ContactElement:
    """One contact of a :class:`System`; SI units.

    Parameters
    ----------
    name : str
        Its name (results are labelled by it).
    direction : sequence of float
        ``w`` [m/m or m/rad]: the deflection is ``δ = w · q − e`` [m], positive into the contact;
        not all zero. Its length is the system's n (checked by the system).
    S : float
        Nominal area [m²] of the law (> 0).
    law : SpringLaw or str
        The spring law: an object of ``contactvib.model.laws`` (``PowerSpring(c_n, m2)``,
        ``ClearanceLaw(c_lin, gap_um)``, ...) or a registered name (default parameters).
    damping : str
        ``"power"`` (``S h_n δ^l δ̇``) or ``"hunt-crossley"`` (``α F_s(δ) δ̇``).
    h_n : float
        Power damping coefficient [N s/m^(3+l)], ≥ 0.
    l : float
        Power damping exponent [1], in [0, 10] (l = 0: the damping force jumps at δ = 0).
    alpha : float or None
        Hunt–Crossley coefficient [s/m], ≥ 0 (default 34.4 s/m with ``damping="hunt-crossley"``).
    gap : float
        Clearance [m] ≥ 0 added to the law's own engagement point: ``e = gap + law.engagement_m``.

    The fields are checked when a :class:`System` is built (:meth:`check`), where an error names
    the element by its place: ``contacts[0].S``.
    """

    name: str
    direction: tuple
    S: float
    law: object
    damping: str = "power"
    h_n: float = 0.0
    l: float = 1.0  # noqa: E741 (the paper's symbol)
    alpha: float | None = None
    gap: float = 0.0

    def check(self, where: str, n: int) -> None:
        """Validate in place for a system of ``n`` coordinates; errors name ``where.field``
        (e.g. ``contacts[0].S``)."""
        if not isinstance(self.name, str) or not self.name:
            raise ParameterError(f"{where}.name", self.name, "must be a non-empty string")
        w = _vector(f"{where}.direction", self.direction, n)
        if not np.any(w != 0.0):
            raise ParameterError(f"{where}.direction", self.direction, "must not be zero (it gives the deflection "
                                                                       "delta = w . q - gap)")
        object.__setattr__(self, "direction", tuple(float(v) for v in w))
        object.__setattr__(self, "S", check_range(f"{where}.S", self.S, 0.0, False, "m^2"))
        law = self.law
        if isinstance(law, str):
            try:
                law = law_class(law)()
            except ParameterError as e:
                raise ParameterError(f"{where}.law", self.law, e.allowed) from None
        if not isinstance(law, SpringLaw):
            raise ParameterError(f"{where}.law", self.law, "must be a law of contactvib.model.laws (a SpringLaw "
                                                           "such as PowerSpring(c_n, m2)) or a registered law name")
        if tuple(law.kinks()) != (0.0,):
            raise ParameterError(f"{where}.law", law.name, f"has kinks at deflections {tuple(law.kinks())} m: the "
                                                           "integrator locates only the engagement point (0,)")
        object.__setattr__(self, "law", law)
        if self.damping not in DAMPING_NAMES:
            raise ParameterError(f"{where}.damping", self.damping, f"must be one of {', '.join(DAMPING_NAMES)}")
        object.__setattr__(self, "h_n", check_range(f"{where}.h_n", self.h_n, 0.0, True, "N s/m^(3+l)"))
        object.__setattr__(self, "l", check_range(f"{where}.l", self.l, 0.0, True, "1", upper=DAMPING_EXPONENT_MAX))
        if self.damping == "hunt-crossley":
            a = HUNT_CROSSLEY_DEFAULT if self.alpha is None else self.alpha
            object.__setattr__(self, "alpha", check_range(f"{where}.alpha", a, 0.0, True, "s/m"))
        elif self.alpha is not None:
            raise ParameterError(f"{where}.alpha", self.alpha, "is a parameter of the Hunt-Crossley damping "
                                                               "(damping='hunt-crossley'), not of the power damping")
        object.__setattr__(self, "gap", check_range(f"{where}.gap", self.gap, 0.0, True, "m"))

    @property
    def w(self) -> np.ndarray:
        """The direction as an array [m/m or m/rad]."""
        return np.array(self.direction)

    @property
    def engagement(self) -> float:
        """e [m]: the value of w · q at which the contact engages (gap + the law's own)."""
        return self.gap + self.law.engagement_m

    def deflection(self, q) -> float:
        """δ = w · q − e [m] at the coordinates ``q`` [SI]."""
        return float(np.dot(self.w, q)) - self.engagement

    def spring_force(self, delta) -> float:
        """F_s(δ) [N] (0 for δ ≤ 0)."""
        return float(self.law.force(delta, self.S))

    def stiffness(self, delta) -> float:
        """dF_s/dδ [N/m] (0 for δ ≤ 0)."""
        return float(self.law.stiffness(delta, self.S))

    def damping_rate(self, delta) -> float:
        """∂F/∂δ̇ [N s/m] at δ > 0: S h_n δ^l (power) or α F_s(δ) (Hunt–Crossley); 0 for δ ≤ 0."""
        if delta <= 0.0:
            return 0.0
        if self.damping == "hunt-crossley":
            return self.alpha * self.spring_force(delta)
        return self.S * self.h_n * delta**self.l

    def force(self, delta, delta_dot) -> float:
        """F = F_s(δ) + ∂F/∂δ̇ · δ̇ [N] while δ > 0, else 0 (SI, the law's own formula)."""
        if delta <= 0.0:
            return 0.0
        return self.spring_force(delta) + self.damping_rate(delta) * delta_dot


@dataclass(frozen=True, eq=False)
class System:
    """A structure of n coordinates with contact elements (SI units); see the module docstring.

    Parameters
    ----------
    M : array_like (n, n)
        Mass matrix [kg, kg m, kg m²], symmetric positive definite.
    K, C : array_like (n, n), optional
        Stiffness [N/m, ...] and damping [N s/m, ...] matrices (default 0).
    f0 : array_like (n,), optional
        Static load [N or N m] (gravity, preload); default 0.
    b : array_like (n,), optional
        Shape of the excitation: the force is b P(t), P(t) = P_a cos(2π f_e t) [N]; default 0.
    contacts : sequence of ContactElement
        The contact elements.
    coordinates : sequence of str, optional
        Names of the coordinates (default q1..qn).
    units : sequence of str, optional
        ``"m"`` or ``"rad"`` per coordinate (default all ``"m"``).

    Examples
    --------
    >>> from contactvib.model.laws import ClearanceLaw
    >>> s = System(M=np.eye(2), K=[[1, -1], [-1, 2]], b=[0, 1],
    ...            contacts=[ContactElement("stop", (1, 0), 1.0, ClearanceLaw(c_lin=100, gap_um=1e6))])
    >>> s.static_state().tolist(), s.linear_modes().round(4).tolist()
    ([0.0, 0.0], [0.0984, 0.2575])
    """

    M: np.ndarray
    K: np.ndarray | None = None
    C: np.ndarray | None = None
    f0: np.ndarray | None = None
    b: np.ndarray | None = None
    contacts: tuple = ()
    coordinates: tuple | None = None
    units: tuple | None = None
    _cache: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self):
        try:
            n = np.shape(np.asarray(self.M, dtype=float))[0]
        except (TypeError, ValueError, IndexError):
            raise ParameterError("M", self.M, "must be an n x n matrix of finite numbers") from None
        if n < 1:
            raise ParameterError("M", self.M, "must be an n x n matrix with n >= 1")
        M = _matrix("M", self.M, n)
        if not np.allclose(M, M.T, rtol=1e-12, atol=1e-14 * np.max(np.abs(M))):
            raise ParameterError("M", self.M, "must be symmetric")
        try:
            np.linalg.cholesky(M)
        except np.linalg.LinAlgError:
            raise ParameterError("M", self.M, "must be positive definite") from None
        object.__setattr__(self, "M", M)
        for name in ("K", "C"):
            v = getattr(self, name)
            object.__setattr__(self, name, _matrix(name, np.zeros((n, n)) if v is None else v, n))
        for name in ("f0", "b"):
            v = getattr(self, name)
            object.__setattr__(self, name, _vector(name, np.zeros(n) if v is None else v, n))
        self._check_names(n)
        contacts = self.contacts if self.contacts is not None else ()
        contacts = (contacts,) if isinstance(contacts, ContactElement) else tuple(contacts)
        for i, c in enumerate(contacts):
            if not isinstance(c, ContactElement):
                raise ParameterError(f"contacts[{i}]", c, "must be a ContactElement")
            c.check(f"contacts[{i}]", n)
        names = [c.name for c in contacts]
        if len(set(names)) != len(names):
            raise ParameterError("contacts", names, "must have distinct names")
        object.__setattr__(self, "contacts", contacts)

    def _check_names(self, n: int) -> None:
        coords = tuple(f"q{j + 1}" for j in range(n)) if self.coordinates is None else tuple(self.coordinates)
        if len(coords) != n or not all(isinstance(c, str) and c for c in coords) or len(set(coords)) != n:
            raise ParameterError("coordinates", self.coordinates, f"must be {n} distinct non-empty names")
        units = ("m",) * n if self.units is None else tuple(self.units)
        if len(units) != n or any(u not in COORDINATE_UNITS for u in units):
            raise ParameterError("units", self.units, f"must be {n} units, each one of {', '.join(COORDINATE_UNITS)}")
        object.__setattr__(self, "coordinates", coords)
        object.__setattr__(self, "units", units)

    # ------------------------------------------------------------------ construction
    @classmethod
    def single_dof(cls, model) -> System:
        """The paper's slider (a :class:`~contactvib.ContactModel`) as the n = 1 system: the
        coordinate ``y`` [m], one contact ``"contact"`` with the model's law, area and damping,
        ``f0 = [M g + F_pre]``, ``b = [1]``."""
        if not all(hasattr(model, a) for a in ("spring_law", "M", "W", "S", "damping")):
            raise ParameterError("model", model, "must be a ContactModel")
        if model.damping == "hunt-crossley":
            damping = {"damping": "hunt-crossley", "alpha": model.alpha}
        else:
            damping = {"damping": "power", "h_n": model.h_n, "l": model.l}
        contact = ContactElement("contact", (1.0,), model.S, model.spring_law, **damping)
        return cls(M=[[model.M]], f0=[model.W], b=[1.0], contacts=(contact,), coordinates=("y",), units=("m",))

    # ------------------------------------------------------------------ sizes and forces
    @property
    def n(self) -> int:
        """Number of coordinates."""
        return self.M.shape[0]

    @property
    def directions(self) -> np.ndarray:
        """The contacts' directions as rows, shape (m, n)."""
        return np.array([c.direction for c in self.contacts], dtype=float).reshape(len(self.contacts), self.n)

    def contact_forces(self, q, qdot) -> np.ndarray:
        """Each contact's force F_i ≥ 0 [N] at the state (q, q̇) [SI] (the laws' SI formulas)."""
        q, qdot = np.asarray(q, float), np.asarray(qdot, float)
        return np.array([c.force(c.deflection(q), float(np.dot(c.w, qdot))) for c in self.contacts])

    def static_residual(self, q) -> np.ndarray:
        """K q + Σ w_i F_s,i(δ_i) − f0 [N or N m]: zero at the static equilibrium."""
        q = np.asarray(q, float)
        r = self.K @ q - self.f0
        for c in self.contacts:
            r = r + c.w * c.spring_force(c.deflection(q))
        return r

    def tangent_stiffness(self, q) -> np.ndarray:
        """K + Σ k_i w_i w_iᵀ with k_i = dF_s/dδ at q (0 for a contact out of contact)."""
        q = np.asarray(q, float)
        J = np.array(self.K)
        for c in self.contacts:
            J += c.stiffness(c.deflection(q)) * np.outer(c.w, c.w)
        return J

    @property
    def reference_force(self) -> float:
        """A force scale [N]: the largest absolute component of f0, or 1 N without a static load."""
        f = float(np.max(np.abs(self.f0)))
        return f if f > 0.0 else 1.0

    def reference_stiffness(self) -> np.ndarray:
        """k_ref,i [N/m]: each contact's stiffness at the deflection where its spring carries the
        reference force (the scale of a contact that the static state leaves open)."""
        W = self.reference_force
        return np.array([c.stiffness(c.law.static_deflection(W, c.S)) for c in self.contacts])

    # ------------------------------------------------------------------ static state, modes
    def static_state(self) -> np.ndarray:
        """The static equilibrium q_s [SI]: K q + Σ w_i F_s,i(δ_i) = f0 (q = 0 if that holds there,
        e.g. no load and no contact engaged).

        Newton's method from q = 0 with a backtracking line search on the residual; where the
        tangent stiffness is singular (a contact at δ ≤ 0 holding an otherwise free coordinate)
        a contact contributes its reference stiffness instead (:meth:`reference_stiffness`).
        ParameterError (``f0``) if no equilibrium is found (a load no contact or stiffness holds)."""
        if "static" not in self._cache:
            q = self._solve_static()
            q.setflags(write=False)
            self._cache["static"] = q
        return self._cache["static"].copy()

    def _solve_static(self) -> np.ndarray:
        q = np.zeros(self.n)
        k_ref = self.reference_stiffness()

        def size(r, q):
            forces = sum(abs(c.spring_force(c.deflection(q))) * np.abs(c.w) for c in self.contacts)
            scale = np.abs(self.f0) + np.abs(self.K @ q) + forces
            return float(np.max(np.abs(r) / np.maximum(scale, 1e-300))) if np.any(r) else 0.0

        r = self.static_residual(q)
        err = size(r, q)
        for _ in range(200):
            if err <= STATIC_RTOL:
                return q
            J = self.tangent_stiffness(q)
            s = np.linalg.svd(J, compute_uv=False)
            r_model, search = r, True
            if s[-1] <= 1e-10 * max(s[0], 1e-300):
                # no stiffness along some direction: a contact without stiffness there becomes a
                # linear spring of its reference stiffness, engaged from where it is (the gap
                # closed), and the full step is taken (the residual is flat along it)
                search = False
                for c, kr in zip(self.contacts, k_ref):
                    d = c.deflection(q)
                    if c.stiffness(d) <= 1e-10 * kr:
                        J = J + kr * np.outer(c.w, c.w)
                        r_model = r_model + c.w * kr * min(d, 0.0)
            try:
                dq = np.linalg.solve(J, -r_model)
            except np.linalg.LinAlgError:
                break
            lam, norm = 1.0, float(np.max(np.abs(r)))
            while True:
                q_new = q + lam * dq
                r_new = self.static_residual(q_new)
                if not search or float(np.max(np.abs(r_new))) < (1.0 - 1e-4 * lam) * norm or lam < 1e-10:
                    break
                lam *= 0.5
            q, r = q_new, r_new
            err = size(r, q)
            if not np.all(np.isfinite(q)):
                break
        if err <= STATIC_RTOL:
            return q
        raise ParameterError("f0", self.f0.tolist(), "has no static equilibrium with these stiffnesses and contacts "
                                                     f"(Newton's method ended at a relative residual {err:.3g})")

    def linear_modes(self) -> np.ndarray:
        """Natural frequencies [Hz] (ascending) of the system linearised about the static state,
        each contact in contact contributing its stiffness dF_s/dδ (damping ignored)."""
        from scipy.linalg import eigvals

        lam = eigvals(self.tangent_stiffness(self.static_state()), self.M)
        w2 = np.sort(np.maximum(np.real(lam), 0.0))
        return np.sqrt(w2) / (2.0 * math.pi)

    def in_contact(self, q) -> np.ndarray:
        """Whether each contact is engaged (δ_i > 0) at q [SI]."""
        return np.array([c.deflection(q) > 0.0 for c in self.contacts], dtype=bool)

    @cached_property
    def scales(self):
        """The scales of the compiled form (``contactvib.model.system_kernel.SystemScales``)."""
        from contactvib.model.system_kernel import system_scales

        return system_scales(self)

    def kernel_form(self, pa_newton: float, fe_hz: float):
        """The scaled form the compiled integrator runs at P_a = ``pa_newton`` [N], f_e = ``fe_hz``
        [Hz] (``contactvib.model.system_kernel.KernelForm``)."""
        from contactvib.model.system_kernel import kernel_form, unit_form

        if "unit_form" not in self._cache:
            self._cache["unit_form"] = unit_form(self)
        return kernel_form(self, pa_newton, fe_hz, self._cache["unit_form"])


def check_state(system: System, z, symbol: str = "z0") -> np.ndarray:
    """A state (q, q̇) of 2n finite numbers [SI] as a float array."""
    return np.array(_vector(symbol, z, 2 * system.n))


def check_excitation(pa_newton, fe_hz) -> tuple[float, float]:
    """The excitation amplitude P_a [N] (≥ 0) and frequency f_e [Hz] (> 0), checked."""
    return check_range("P_a", pa_newton, 0.0, True, "N"), check_range("f_e", fe_hz, 0.0, False, "Hz")


__all__ += ["check_state", "check_excitation"]
