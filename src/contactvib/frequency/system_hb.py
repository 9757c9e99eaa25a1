"""Harmonic balance of a :class:`~contactvib.model.system.System` (n coordinates, contact
elements) with alternating frequency–time, and its continuation in f_e.

Equation
--------
In the excitation phase θ = ω t (ω = 2π f_e), with q(θ) the coordinates [SI]::

    R(θ) = ω² M q_θθ + ω C q_θ + K q − f0 − b P_a cos θ + Σ_i w_i F_i(δ_i, ω δ_i,θ) = 0
    δ_i = w_i · q − e_i,    F_i = F_s,i(δ_i) + c_i(δ_i) δ̇_i  for δ_i > 0, else 0

(:mod:`contactvib.model.system`). Each coordinate is written about the static state q_s in its
scale L_j (:attr:`System.scales`): ``q_j = q_s,j + L_j x_j(θ)``, ``x_j = a0 + Σ_{k≤H} (a_k cos kθ
+ b_k sin kθ)``, and the residual is divided by the reference force (:attr:`System.reference_force`).

Method
------
The contact forces, non-smooth at δ = 0, are sampled on ``n_time`` equispaced phases and
projected back on the harmonics (AFT, :class:`contactvib.frequency.aft.AFT`). Newton's method uses
the exact AFT Jacobian: the linear part ``K − ω² k² M`` and ``ω k C`` per harmonic, and per contact
``w_i w_iᵀ (T[∂F_i/∂δ] + ω T[∂F_i/∂δ̇] D_θ)`` (T[g] the projected product by g). The branch is
followed in f_e by the one pseudo-arclength engine (:mod:`contactvib.continuation.engine`).
Stability: the 2n Floquet multipliers of one shooting period from the HB orbit point
(:func:`contactvib.steady.system_orbits.period_map`). The mean of each contact force over the
period is its harmonic a0 (for an exact periodic orbit Σ w_i ⟨F_i⟩ = f0 − K ⟨q⟩).

References
----------
T. M. Cameron, J. H. Griffin, J. Appl. Mech. 56 (1989) 149–154 (AFT). M. Krack, J. Gross,
*Harmonic Balance for Nonlinear Vibration Problems*, Springer (2019) (NLvib: its 2-DOF oscillator
with a unilateral spring).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels.shooting import is_stable
from contactvib.continuation.engine import Bound, CorrectorSettings, Point, StepControl, continue_branch
from contactvib.errors import ComputationError
from contactvib.frequency.aft import AFT
from contactvib.frequency.hb_results import series_extrema
from contactvib.model import HARMONICS_MAX, ParameterError, check_int, check_range
from contactvib.model.system import System, check_excitation
from contactvib.steady.results import dofs_and_contacts

__all__ = ["SystemHBSolution", "SystemHBBranch", "system_hb_solve", "system_hb_continuation", "SystemHBProblem"]

#: Newton: relative residual max|R| / F_ref at convergence, and the largest number of iterations.
HB_TOL = 1e-10
HB_MAX_ITER = 30
#: Default AFT samples per period, per harmonic (128 H: the 2-DOF stop's branch passes its grazing
#: and its folds at H = 32 with 4096 samples and turns back at grazing with 512).
N_TIME_PER_HARMONIC = 128


def _display(unit: str) -> tuple[str, float]:
    from contactvib.steady.system_orbits import DISPLAY_UNITS

    return DISPLAY_UNITS[unit][0], DISPLAY_UNITS[unit][1]


def _derivative_matrix(H: int) -> np.ndarray:
    """D_θ on [a0, a1, b1, ...]: (a_k cos kθ + b_k sin kθ)' = k b_k cos kθ − k a_k sin kθ."""
    D = np.zeros((2 * H + 1, 2 * H + 1))
    for k in range(1, H + 1):
        D[2 * k - 1, 2 * k] = k
        D[2 * k, 2 * k - 1] = -k
    return D


def _contact_samples(c, d, dd):
    """F, ∂F/∂δ, ∂F/∂δ̇ of contact ``c`` at the samples δ = ``d``, δ̇ = ``dd`` [SI], zero where δ ≤ 0."""
    on = d > 0.0
    dp = np.where(on, d, 0.0)
    Fs = np.where(on, np.asarray(c.law.force(dp, c.S), float), 0.0)
    ks = np.where(on, np.asarray(c.law.stiffness(dp, c.S), float), 0.0)
    if c.damping == "hunt-crossley":
        cd, dcd = c.alpha * Fs, c.alpha * ks
    else:
        cd = np.where(on, c.S * c.h_n * dp ** c.l, 0.0)
        dcd = (np.where(on, c.S * c.h_n * c.l * np.where(on, dp, 1.0) ** (c.l - 1.0), 0.0)
               if c.l != 0.0 else np.zeros_like(d))
    return Fs + cd * dd, ks + dcd * dd, cd


class _Form:
    """The scaled residual of one system at one force level (unknowns: n × (2H+1) coefficients)."""

    def __init__(self, system: System, pa_newton: float, aft: AFT):
        self.s, self.pa, self.aft = system, float(pa_newton), aft
        self.H, self.n = aft.H, system.n
        self.m = 2 * aft.H + 1
        self.L = np.array(system.scales.length, float)
        self.qs = system.static_state()
        self.F = float(system.reference_force)
        self.D = _derivative_matrix(aft.H)
        self.D2 = self.D @ self.D
        self.W = system.directions
        self.e = np.array([c.engagement for c in system.contacts])
        self.static = system.K @ self.qs - system.f0  # the linear part's constant (harmonic 0)

    def q_samples(self, X):
        """q(θ) − q_s and q_θ per coordinate [SI], shape (n, n_time)."""
        xs = [self.aft.synth(X[j]) for j in range(self.n)]
        return (np.array([x for x, _ in xs]) * self.L[:, None], np.array([t for _, t in xs]) * self.L[:, None])

    def residual(self, u, jac: bool = True):
        """R (n m,), ∂R/∂X (n m × n m) and ∂R/∂ω·ω_ref... in units of F_ref; ``u = (X, f_e)``."""
        n, m, s = self.n, self.m, self.s
        X = u[:-1].reshape(n, m)
        w = 2.0 * math.pi * u[-1]
        Xs = X * self.L[:, None]  # SI coefficients of q − q_s
        R = (s.K @ Xs + w * (s.C @ Xs) @ self.D.T + w * w * (s.M @ Xs) @ self.D2.T)
        R[:, 0] += self.static
        R[:, 1] -= s.b * self.pa
        J = dR = None
        if jac:
            J = np.zeros((n * m, n * m))
            for j in range(n):
                for k in range(n):
                    blk = (s.K[j, k] * np.eye(m) + w * s.C[j, k] * self.D + w * w * s.M[j, k] * self.D2) * self.L[k]
                    J[j * m:(j + 1) * m, k * m:(k + 1) * m] = blk
            dR = (s.C @ Xs) @ self.D.T + 2.0 * w * (s.M @ Xs) @ self.D2.T
        if s.contacts:
            dq, dq_t = self.q_samples(X)
            for i, c in enumerate(s.contacts):
                wi = self.W[i]
                d = wi @ (self.qs[:, None] + dq) - self.e[i]
                d_t = wi @ dq_t
                F, Fd, Fv = _contact_samples(c, d, w * d_t)
                R += np.outer(wi, self.aft.project(F))
                if jac:
                    T = self.aft.product_matrix(Fd) + w * self.aft.times_derivative(self.aft.product_matrix(Fv))
                    for j in range(n):
                        for k in range(n):
                            if wi[j] != 0.0 and wi[k] != 0.0:
                                J[j * m:(j + 1) * m, k * m:(k + 1) * m] += wi[j] * wi[k] * self.L[k] * T
                    dR += np.outer(wi, self.aft.project(Fv * d_t))
        R = R.reshape(-1) / self.F
        if not jac:
            return R, None, None
        return R, J / self.F, dR.reshape(-1) * (2.0 * math.pi) / self.F  # ∂R/∂f_e

    def initial(self, fe_hz: float) -> np.ndarray:
        """The linear response about q_s: (K_t − ω² M + iω C_t) A = b P_a, C_t with the contacts'
        damping rates at the static state."""
        s, n, m = self.s, self.n, self.m
        w = 2.0 * math.pi * fe_hz
        Kt = s.tangent_stiffness(self.qs)
        Ct = np.array(s.C, float)
        for c in s.contacts:
            Ct = Ct + c.damping_rate(c.deflection(self.qs)) * np.outer(c.w, c.w)
        A = np.linalg.solve(Kt - w * w * s.M + 1j * w * Ct, s.b * self.pa)
        X = np.zeros((n, m))
        X[:, 1] = A.real / self.L
        X[:, 2] = -A.imag / self.L
        return X.reshape(-1)


@dataclass(frozen=True, eq=False)
class SystemHBSolution:
    """A harmonic-balance solution of a system at one (P_a, f_e).

    Attributes
    ----------
    fe_hz, pa_newton : float
        f_e [Hz] and P_a [N].
    harmonics : int
        H.
    coefficients : ndarray (n, 2H+1)
        [a0, a1, b1, ...] of each coordinate q_j(θ) [SI: m or rad], a0 including the static state.
    q_min, q_max, q_app, q_h1 : ndarray (n,)
        Each coordinate's extremes, peak-to-peak and first-harmonic amplitude √(a1² + b1²), in its
        display unit (``units``).
    units : tuple of str
        Display units (µm, µrad).
    loses_contact : ndarray of bool (m,)
        Whether each contact opens (δ ≤ 0 at some sample).
    contact_loss_fraction : ndarray (m,)
        Share of the period each contact is open [1].
    mean_force_n : ndarray (m,)
        ⟨F_i⟩ over the period [N] (the a0 of the sampled force).
    residual : float
        max |R| / F_ref at the solution [1].
    top_energy_fraction : float
        Largest, over the coordinates, share of the AC energy in the top quarter of the harmonics.
    floquet_multipliers : ndarray of complex (2n,)
        From one shooting period started at the HB orbit point (empty if not computed).
    """

    fe_hz: float
    pa_newton: float
    harmonics: int
    coefficients: np.ndarray
    q_min: np.ndarray
    q_max: np.ndarray
    q_app: np.ndarray
    q_h1: np.ndarray
    units: tuple
    coordinates: tuple
    contact_names: tuple
    loses_contact: np.ndarray
    contact_loss_fraction: np.ndarray
    mean_force_n: np.ndarray
    residual: float
    top_energy_fraction: float
    floquet_multipliers: np.ndarray = field(default_factory=lambda: np.empty(0, complex))

    @property
    def floquet_abs_max(self) -> float:
        """max |μ| [1] (NaN if not computed)."""
        return float(np.max(np.abs(self.floquet_multipliers))) if self.floquet_multipliers.size else math.nan

    @property
    def stable(self) -> bool | None:
        """The package's stability rule on the multipliers (None if not computed)."""
        return bool(is_stable(self.floquet_abs_max)) if self.floquet_multipliers.size else None

    def to_dict(self) -> dict:
        """The JSON form: ``fe_hz``, ``pa_newton``, ``harmonics``, ``stable``, ``floquet_abs_max``,
        ``floquet_multipliers``, ``residual``, ``top_energy_fraction``, and ``dofs``/``contacts``."""
        d = {"fe_hz": float(self.fe_hz), "pa_newton": float(self.pa_newton), "harmonics": int(self.harmonics),
             "stable": self.stable,
             "floquet_abs_max": None if math.isnan(self.floquet_abs_max) else self.floquet_abs_max,
             "floquet_multipliers": [[float(z.real), float(z.imag)] for z in self.floquet_multipliers],
             "residual": float(self.residual), "top_energy_fraction": float(self.top_energy_fraction)}
        d.update(dofs_and_contacts(
            dof_name=list(self.coordinates), dof_unit=list(self.units), dof_min=list(self.q_min),
            dof_max=list(self.q_max), dof_app=list(self.q_app), dof_h1=list(self.q_h1),
            contact_name=list(self.contact_names), contact_loses_contact=list(self.loses_contact),
            contact_loss_frac=list(self.contact_loss_fraction), contact_mean_force_n=list(self.mean_force_n)))
        return d


def _top_fraction(X: np.ndarray) -> float:
    """Share of the AC energy Σ (a_k² + b_k²) in the top quarter of the harmonics."""
    H = (X.size - 1) // 2
    e = X[1::2] ** 2 + X[2::2] ** 2
    tot = float(e.sum())
    return float(e[H - max(1, H // 4):].sum() / tot) if tot > 0.0 else 0.0


def _solution(form: _Form, u, residual: float, stability: bool) -> SystemHBSolution:
    s, n, m, aft = form.s, form.n, form.m, form.aft
    X = u[:-1].reshape(n, m)
    fe = float(u[-1])
    dq, dq_t = form.q_samples(X)
    q = form.qs[:, None] + dq
    coef = X * form.L[:, None]
    coef[:, 0] += form.qs
    units, factors = zip(*(_display(unit) for unit in s.units))
    f = np.array(factors)
    lo, hi = np.array([series_extrema(coef[j]) for j in range(n)]).T
    h1 = np.hypot(coef[:, 1], coef[:, 2])
    w = 2.0 * math.pi * fe
    loses, frac, mean = [], [], []
    for i, c in enumerate(s.contacts):
        d = form.W[i] @ q - form.e[i]
        F, _, _ = _contact_samples(c, d, w * (form.W[i] @ dq_t))
        loses.append(bool(np.any(d <= 0.0)))
        frac.append(float(np.mean(d <= 0.0)))
        mean.append(float(np.mean(F)))
    mult = np.empty(0, complex)
    if stability:
        from contactvib.steady.system_orbits import period_map

        z = np.concatenate([q[:, 0], w * dq_t[:, 0]])
        try:
            pm = period_map(s, form.pa, fe, z, 1)
            mult = np.linalg.eigvals(pm.monodromy).astype(complex)
            mult = mult[np.argsort(-np.abs(mult), kind="stable")]
        except ComputationError:
            pass
    return SystemHBSolution(
        fe_hz=fe, pa_newton=form.pa, harmonics=aft.H, coefficients=coef, q_min=lo * f, q_max=hi * f,
        q_app=(hi - lo) * f, q_h1=h1 * f, units=tuple(units), coordinates=tuple(s.coordinates),
        contact_names=tuple(c.name for c in s.contacts), loses_contact=np.array(loses, bool),
        contact_loss_fraction=np.array(frac), mean_force_n=np.array(mean), residual=float(residual),
        top_energy_fraction=max(_top_fraction(X[j]) for j in range(n)), floquet_multipliers=mult)


def _check(system, pa_newton, fe_hz, harmonics, n_time):
    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a System (contactvib.model.System, load_system, "
                                               "rocking_system)")
    pa, fe = check_excitation(pa_newton, fe_hz)
    H = check_int("harmonics", harmonics, 1, HARMONICS_MAX)
    if n_time is None:  # a contact closed for a small part of the period needs many samples
        n_time = N_TIME_PER_HARMONIC * H
    n_time = int(check_range("n_time", n_time, 4 * H + 2, True))
    return pa, fe, H, n_time


def _newton(form: _Form, u, tol: float, max_iter: int):
    res = math.inf
    for it in range(max_iter + 1):
        R, J, _ = form.residual(u)
        res = float(np.max(np.abs(R)))
        if res <= tol:
            return u, res
        if it == max_iter or not math.isfinite(res):
            break
        u = u.copy()
        u[:-1] += np.linalg.solve(J, -R)
    raise ComputationError(f"harmonic-balance Newton did not converge (relative residual {res:.2e}); start "
                           "closer, e.g. from a neighbouring solution or with more harmonics",
                           stage="harmonic-balance")


def system_hb_solve(system: System, pa_newton: float, fe_hz: float, *, harmonics: int = 16, start=None,
                    n_time: int | None = None, tol: float = HB_TOL, stability: bool = True) -> SystemHBSolution:
    """The harmonic-balance solution of ``system`` at P_a = ``pa_newton`` [N], f_e = ``fe_hz`` [Hz]
    with ``harmonics`` harmonics per coordinate, by Newton from ``start`` (a
    :class:`SystemHBSolution`) or from the linear response about the static state."""
    pa, fe, H, n_time = _check(system, pa_newton, fe_hz, harmonics, n_time)
    form = _Form(system, pa, AFT(H, n_time))
    X0 = form.initial(fe) if start is None else _coefficients_from(form, start)
    u, res = _newton(form, np.append(X0, fe), check_range("tol", tol, 0.0, False), HB_MAX_ITER)
    return _solution(form, u, res, stability)


def _coefficients_from(form: _Form, start) -> np.ndarray:
    if not isinstance(start, SystemHBSolution):
        raise ParameterError("start", start, "must be a SystemHBSolution")
    C = np.zeros((form.n, form.m))
    k = min(form.m, start.coefficients.shape[1])
    C[:, :k] = start.coefficients[:, :k]
    C[:, 0] -= form.qs
    return (C / form.L[:, None]).reshape(-1)


@dataclass(frozen=True, eq=False)
class SystemHBBranch:
    """A branch of harmonic-balance solutions in f_e (see :class:`SystemHBSolution`).

    Attributes
    ----------
    solutions : list of SystemHBSolution
        Along the branch (folds passed).
    stop_reason : str
        Why it ended.
    """

    pa_newton: float
    harmonics: int
    solutions: list
    stop_reason: str

    @property
    def fe_hz(self) -> np.ndarray:
        return np.array([s.fe_hz for s in self.solutions])

    def app(self, coordinate: int = 0) -> np.ndarray:
        """Peak-to-peak of one coordinate along the branch [display unit]."""
        return np.array([s.q_app[coordinate] for s in self.solutions])

    def h1(self, coordinate: int = 0) -> np.ndarray:
        """First-harmonic amplitude of one coordinate along the branch [display unit]."""
        return np.array([s.q_h1[coordinate] for s in self.solutions])

    @property
    def stable(self) -> np.ndarray:
        return np.array([bool(s.stable) for s in self.solutions])

    def to_dict(self) -> dict:
        return {"pa_newton": float(self.pa_newton), "harmonics": int(self.harmonics),
                "stop_reason": self.stop_reason, "points": [s.to_dict() for s in self.solutions]}


class SystemHBProblem:
    """Harmonic balance of a system in f_e as a continuation problem (the engine's protocol):
    unknowns ``u = (X, f_e)``, residual :meth:`_Form.residual`, weights 1 on X and 1/f_max on
    f_e, stop when the top quarter of the harmonics holds more than ``energy_tol`` of the energy."""

    test_names = ()
    fold_tests = ()

    def __init__(self, form: _Form, f_range, energy_tol: float, stability: bool):
        self.form, self.energy_tol, self.stability = form, energy_tol, stability
        n = form.n * form.m + 1
        self.w = np.ones(n)
        self.w[-1] = 1.0 / f_range[1]  # f_e in units of the range's top: comparable with the scaled X
        self.bounds = (Bound(n - 1, f_range[0], f_range[1], "f_e"),)

    def residual_jacobian(self, u):
        R, J, df = self.form.residual(u)
        Jf = np.empty((R.size, u.size))
        Jf[:, :-1] = J
        Jf[:, -1] = df
        return 0, R, Jf, None

    def residual_norm(self, u, F):
        return float(np.max(np.abs(F)))

    def weights(self, u):
        return self.w

    def admissible(self, u):
        return True

    def measure(self, u, J, data, residual) -> SystemHBSolution:
        return _solution(self.form, u, residual, self.stability)

    def tests(self, pt):
        return {}

    def check(self, pt):
        s = pt.record
        if s.top_energy_fraction <= self.energy_tol:
            return None
        return (f"stopped at {s.fe_hz:.4g} Hz: the top quarter of the {s.harmonics} harmonics holds "
                f"{s.top_energy_fraction:.1e} of the energy (> {self.energy_tol:g}); raise --harmonics")

    def check_step(self, a, b):
        return None


def system_hb_continuation(system: System, pa_newton: float, *, fmin_hz: float, fmax_hz: float,
                           harmonics: int = 16, from_fmax: bool = False, n_time: int | None = None,
                           ds: float = 0.05, df_max_hz: float | None = None, max_points: int = 2000,
                           energy_tol: float = 1e-6, stability: bool = True) -> SystemHBBranch:
    """Follow the HB branch of ``system`` at P_a = ``pa_newton`` [N] from ``fmin_hz`` (``fmax_hz``
    with ``from_fmax``) across [fmin_hz, fmax_hz] [Hz] by pseudo-arclength continuation (folds
    passed), started from the linear response. ``df_max_hz`` caps the f_e step (default 1/200 of
    the range); ``ds`` is the first arclength step in the unknowns' scale; Newton converges to a
    relative residual ``HB_TOL``."""
    pa, fmin, H, n_time = _check(system, pa_newton, fmin_hz, harmonics, n_time)
    fmax = check_range("fmax_hz", fmax_hz, 0.0, False, "Hz")
    if not fmin < fmax:
        raise ParameterError("fmax_hz", fmax, f"must be > fmin_hz = {fmin:g} Hz")
    max_points = check_int("max_points", max_points, 2, 1_000_000)
    df_max = (fmax - fmin) / 200.0 if df_max_hz is None else check_range("df_max_hz", df_max_hz, 0.0, False, "Hz")
    form = _Form(system, pa, AFT(H, n_time))
    f0 = fmax if from_fmax else fmin
    u0, res = _newton(form, np.append(form.initial(f0), f0), HB_TOL, HB_MAX_ITER)
    prob = SystemHBProblem(form, (fmin, fmax), check_range("energy_tol", energy_tol, 0.0, False), stability)
    _st, _F, J, data = prob.residual_jacobian(u0)
    cs = CorrectorSettings(tol=HB_TOL, max_iter=12, min_iter=1, cons_tol=math.inf, max_step=math.inf)
    sc = StepControl(ds=ds, ds_min=1e-8, ds_max=50.0 * ds, growth=((4, 1.5),), shrink=1.0,
                     dq_max=df_max, max_points=max_points, bound_action="drop")
    e_f = np.zeros(u0.size)
    e_f[-1] = -1.0 if from_fmax else 1.0
    run = continue_branch(prob, Point(u0, J, data, res), e_f, cs, sc)
    sols = [p.record for p in run.points]
    stop = run.stop
    if stop.code == "max_points":
        reason = f"stopped after max_points = {max_points} points"
    elif stop.code == "bound":
        reason = f"left the range at {fmax if stop.detail[1] == 'upper' else fmin:g} Hz"
    elif stop.code == "problem":
        reason = stop.detail
    else:
        reason = f"stopped at {sols[-1].fe_hz:.4g} Hz: the corrector failed at the smallest step"
    return SystemHBBranch(pa_newton=pa, harmonics=H, solutions=sols, stop_reason=reason)
