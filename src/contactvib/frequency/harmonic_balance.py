"""Harmonic balance (HB) with alternating frequency–time (AFT) and continuation in f_e.

Equation
--------
The kernels' nondimensional form of Eq. (2.5) in the excitation phase θ = r τ::

    R(θ) = m2 r² x_θθ + f(x, r x_θ) − 1 − p cos θ = 0
    f(x, x') = x^m2 + c x^l x'   for x > 0,   0 for x ≤ 0 (loss of contact)

with ``x = y/y0``, ``p = P_a/Q``, ``r = f_e/f_n0``, ``c = 2 m2 ζ``.

Method
------
``x(θ) = a0 + Σ_{k=1}^{H} (a_k cos kθ + b_k sin kθ)``; the contact force, non-smooth at x = 0,
is evaluated on ``n_time`` equispaced samples and projected back on the 2H+1 harmonics
(AFT, numpy FFT). Newton's method uses the exact AFT Jacobian
``∂R̂/∂X = m2 r² D² + T[f_x] + r T[f_x'] D_θ``, where T[g] is the matrix of multiplication by g
projected on the harmonics, built from g's Fourier coefficients (G_{j−k} ± G_{j+k}), and the
branch is followed in f_e by the pseudo-arclength engine of
:mod:`contactvib.continuation.engine` (``HBProblem``; tangent predictor, bordered Newton
corrector, step-size control). Stability: the monodromy matrix of one shooting period from the
HB orbit point (x(0), x'(0)) (:func:`contactvib._kernels.shooting.strobe_map`), its largest
|multiplier| < 1.

The series of a smooth orbit (contact kept) converges geometrically in H; at a loss of contact
the force has a corner (a kink at touch-down), its harmonics decay algebraically and the
solution's only like a power of k, so A_pp converges algebraically (Gibbs-limited). A branch
stops, with the reason, when the top quarter of the harmonics carries more than
``energy_tol`` of the displacement's AC energy.

References
----------
T. M. Cameron, J. H. Griffin, J. Appl. Mech. 56 (1989) 149–154 (AFT). M. Krack, J. Gross,
*Harmonic Balance for Nonlinear Vibration Problems*, Springer (2019) (HB, continuation, NLvib).
E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*, SIAM (2003).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib._kernels.shooting import is_stable
from contactvib.call_forms import old_form, renamed_fields
from contactvib.continuation.engine import Bound, CorrectorSettings, Point, StepControl, continue_branch
from contactvib.continuation.settings import check_newton, check_steps
from contactvib.errors import ComputationError
from contactvib.frequency.aft import AFT as _AFT
from contactvib.frequency.hb_results import HBBranch, HBSolution, series_extrema, series_value, top_fraction
from contactvib.model import (
    HARMONICS_MAX,
    LEVEL_KINDS,
    ContactModel,
    Excitation,
    ParameterError,
    check_excitation,
    check_int,
    check_level_kind,
    check_range,
    excitation_at,
)
from contactvib.model.contact_law import PowerLaw

__all__ = ["HBSettings", "HBSolution", "HBBranch", "hb_solve", "hb_continuation", "coefficients_from_orbit",
           "HBProblem"]


def _hb_par(model: ContactModel, exc: Excitation):
    """The residual's parameters: ``(m2, l, c, p)`` for the paper's law under one harmonic force
    (its original path), else the kernels' full parameter vector
    (:meth:`Excitation.kernel_parameters`: any law, base motion, a multi-harmonic force)."""
    if model.is_paper_family and exc.kind == "force":
        return (model.m2, model.l, model.damping_coefficient, exc.pa_over_q)
    return exc.kernel_parameters()


def _excitation_coefficients(kpar, r, H):
    """Fourier coefficients [a0, a1, b1, …] of the right-hand side 1 + e(θ) [units of W] of the
    full parameter vector, and their derivative in r (base motion: p r² cos θ)."""
    from contactvib._kernels import contact as kc

    E, dE = np.zeros(2 * H + 1), np.zeros(2 * H + 1)
    E[0] = 1.0
    p = kpar[3]
    if kpar[kc.P_EXCITATION] == kc.EXCITATION_BASE:
        E[1], dE[1] = p * r * r, 2.0 * p * r
    else:
        E[1] = p
    o = int(kpar[kc.P_OEXC])
    for j in range(int(kpar[kc.P_NEXC])):  # a cos(kθ + φ) = a cos φ cos kθ − a sin φ sin kθ
        k, a, ph = int(kpar[o + 3 * j]), kpar[o + 3 * j + 1], kpar[o + 3 * j + 2]
        E[2 * k - 1] += a * math.cos(ph)
        E[2 * k] -= a * math.sin(ph)
    return E, dE


def _residual_general(X, r, kpar, aft: _AFT, jac: bool = True):
    """:func:`_residual` for any law and excitation (:mod:`contactvib._kernels.contact`):
    κ r² x_θθ + f(x, r x_θ) − 1 − e(θ), κ = k y0/W, forces in units of W = Q + F_pre."""
    from contactvib._kernels.contact import contact_force_array

    x, xt = aft.synth(X)
    v = r * xt
    f, fx, fv = np.empty_like(x), np.empty_like(x), np.empty_like(x)
    contact_force_array(x, v, kpar, f, fx, fv)
    kap = kpar[0]
    E, dE = _excitation_coefficients(kpar, r, aft.H)
    R = kap * r * r * aft.d2 * X + aft.project(f) - E
    if not jac:
        return R, None, None
    J = aft.product_matrix(fx) + r * aft.times_derivative(aft.product_matrix(fv))
    J[np.diag_indices_from(J)] += kap * r * r * aft.d2
    dr = 2.0 * kap * r * aft.d2 * X + aft.project(fv * xt) - dE
    return R, J, dr


def _residual(X, r, par, aft: _AFT, jac: bool = True):
    """HB residual (2H+1,), its Jacobian in X and its derivative in r."""
    if isinstance(par, np.ndarray):
        return _residual_general(X, r, par, aft, jac)
    m2, l, c, p = par
    x, xt = aft.synth(X)
    f, fx, fv = PowerLaw(m2, l).force(x, r * xt, c)  # the contact law, 0 in flight
    R = m2 * r * r * aft.d2 * X + aft.project(f)
    R[0] -= 1.0
    R[1] -= p
    if not jac:
        return R, None, None
    J = aft.product_matrix(fx) + r * aft.times_derivative(aft.product_matrix(fv))
    J[np.diag_indices_from(J)] += m2 * r * r * aft.d2
    dr = 2.0 * m2 * r * aft.d2 * X + aft.project(fv * xt)
    return R, J, dr


def _check_harmonics(harmonics, n_time):
    H = check_int("harmonics", harmonics, 1, HARMONICS_MAX)
    if n_time is None:
        n_time = max(64, 1 << int(math.ceil(math.log2(8 * H + 1))))
    n_time = int(check_range("n_time", n_time, 4 * H + 2, True))
    return H, n_time


def _newton(X, r, par, aft, tol, max_iter):
    for it in range(max_iter + 1):
        R, J, _ = _residual(X, r, par, aft)
        res = float(np.max(np.abs(R)))
        if res <= tol:
            return X, res, it
        if it == max_iter or not np.isfinite(res):
            break
        dX = np.linalg.solve(J, -R)
        X = X + dX
    raise ComputationError(f"harmonic-balance Newton did not converge (residual {res:.2e} after {it} "
                           "iterations); start closer, e.g. from a neighbouring solution", stage="harmonic-balance")


def _solution(model, exc_pa, fe, X, par, aft, res, stability, y0_um):
    lo, hi = series_extrema(X)
    mult = np.empty(0, complex)
    closure = math.nan
    if stability:
        from contactvib._kernels.shooting import state_scale, strobe_map
        from contactvib._kernels.status import STATUS_OK

        r = fe / model.f_n0
        z = np.array([series_value(X, 0.0)[0], r * series_value(X, 0.0, 1)[0]])
        if isinstance(par, np.ndarray):
            kpar = par.copy()
            kpar[4] = r
        else:
            kpar = np.array([par[0], par[1], par[2], par[3], r])
        out_z, out_M = np.empty(2), np.empty((2, 2))
        st = strobe_map(z, 1, kpar, 1e-12, 1e-12, out_z, out_M)
        if st == STATUS_OK:
            mult = np.linalg.eigvals(out_M).astype(complex)
            closure = float(np.max(np.abs(out_z - z)) / state_scale(z[0], z[1]))
    return HBSolution(fe_hz=fe, pa_over_q=exc_pa, harmonics=aft.H, app_um=(hi - lo) * y0_um,
                      ymin_um=model.units.position_um(lo), ymax_um=model.units.position_um(hi),
                      loses_contact=bool(lo < 0.0),
                      top_energy_fraction=top_fraction(X), residual=res,
                      floquet_multipliers=mult, closure=closure, y0_um=y0_um,
                      coefficients=X.copy())


def _initial_guess(model: ContactModel, exc: Excitation, H: int, par=None) -> np.ndarray:
    """Linear response about x = 1 (the first term of the perturbation series): κ (1 − r² + 2iζr) A = F
    with F the fundamental's amplitude [units of W] (the paper's law: κ = m2, F = P_a/Q)."""
    X = np.zeros(2 * H + 1)
    X[0] = 1.0
    r = exc.r
    if isinstance(par, np.ndarray):
        E, _dE = _excitation_coefficients(par, r, H)
        A = (E[1] / par[0]) / (1.0 - r * r + 2j * model.zeta * r)
    else:
        A = (exc.pa_over_q / model.m2) / (1.0 - r * r + 2j * model.zeta * r)
    X[1], X[2] = A.real, -A.imag  # A e^{iθ}: cos part Re A, sin part −Im A
    return X


def _check_force_harmonics(excitation: Excitation, H: int) -> None:
    """A multi-harmonic force needs every harmonic k <= H in the truncated series."""
    if excitation.harmonics and max(k for k, _a, _p in excitation.harmonics) > H:
        k = max(k for k, _a, _p in excitation.harmonics)
        raise ParameterError("harmonics", H, f"must be >= {k}: the force has a harmonic {k} f_e")


@old_form("model", "excitation", "harmonics", "start", "n_time", "tol", "max_iter", "stability")
def hb_solve(excitation: Excitation, *, harmonics: int = 32, start=None, n_time: int | None = None,
             tol: float = 1e-12, max_iter: int = 60, stability: bool = True) -> HBSolution:
    """Harmonic-balance periodic solution at one operating point.

    Parameters
    ----------
    excitation : Excitation
        The operating point (with its model, ``excitation.model``).
    harmonics : int
        Number of harmonics H (1..1024).
    start : ndarray (2H'+1,) or HBSolution, optional
        Initial coefficients (padded or truncated to H); default the linear response.
    n_time : int, optional
        AFT samples per period (≥ 4H+2, so that the Jacobian's products are alias-free;
        default the power of two ≥ 8H, at least 64).
    tol : float
        Newton tolerance on the max-norm of the residual [units of Q].
    stability : bool
        Compute the Floquet multipliers by one shooting period from the HB orbit point.

    Raises
    ------
    ComputationError
        If Newton does not converge (``stage`` "harmonic-balance").
    """
    model = check_excitation(excitation).model
    H, n_time = _check_harmonics(harmonics, n_time)
    _check_force_harmonics(excitation, H)
    tol, max_iter = check_range("tol", tol, 0.0, False), check_int("max_iter", max_iter, 1)
    aft = _AFT(H, n_time)
    par = _hb_par(model, excitation)
    if start is None:
        X = _initial_guess(model, excitation, H, par)
    else:
        try:
            s = start.coefficients if isinstance(start, HBSolution) else np.asarray(start, float).reshape(-1)
        except (TypeError, ValueError):
            s = np.array([np.nan])
        if s.size == 0 or not np.all(np.isfinite(s)):
            raise ParameterError("start", start, "must be an HBSolution or finite harmonic coefficients")
        X = np.zeros(2 * H + 1)
        n = min(s.size, X.size)
        X[:n] = s[:n]
    X, res, _ = _newton(X, excitation.r, par, aft, tol, max_iter)
    sol = _solution(model, excitation.pa_over_q, excitation.f_e, X, par, aft, res, stability, model.units.y_um)
    model.check_motion(sol.ymax_um, "the harmonic-balance orbit")  # a table law: within its rows
    return sol


@renamed_fields(df_max="df_max_hz")
@dataclass(frozen=True)
class HBSettings:
    """Knobs of a harmonic-balance continuation (:func:`hb_continuation`).

    Attributes
    ----------
    n_time : int or None
        AFT samples per period (default: the power of two ≥ 8H, at least 64).
    ds, ds_min, ds_max : float
        Initial, smallest and largest arclength step (in the scaled unknowns: coefficients in
        y0, r = f_e/f_n0); ``0 < ds_min ≤ ds ≤ ds_max``.
    df_max_hz : float
        Largest frequency step [Hz] (resolves narrow superharmonic peaks; ``df_max`` before
        0.2.0, still accepted with a DeprecationWarning).
    max_points : int
        Largest number of points.
    energy_tol : float
        Stop when the top quarter of the harmonics holds more than this share of the AC energy
        (the truncation no longer resolves the orbit: long flights, impacts). The default 1e-8
        corresponds to an A_pp truncation error of about 1e-4 in the measured cases.
    tol : float
        Newton tolerance on the residual [units of Q].
    max_iter : int
        Newton iterations per correction.
    stability : bool
        Floquet multipliers by one shooting period per point.
    """

    n_time: int | None = None
    ds: float = 0.02
    ds_min: float = 1e-6
    ds_max: float = 0.5
    df_max_hz: float = 5.0
    max_points: int = 5000
    energy_tol: float = 1e-8
    tol: float = 1e-11
    max_iter: int = 11
    stability: bool = True

    def __post_init__(self):
        # stored as checked (a number given as text is a float, a count an int)
        # the steps and the Newton corrector by the rules of every continuation's settings
        v = check_steps(self.ds, self.ds_min, self.ds_max)
        v["energy_tol"] = check_range("energy_tol", self.energy_tol, 0.0, False)
        v["max_points"] = check_int("max_points", self.max_points, 2)
        v["df_max_hz"] = check_range("df_max_hz", self.df_max_hz, 0.0, False, "Hz")
        v.update(check_newton(self.tol, self.max_iter))
        for name, value in v.items():
            object.__setattr__(self, name, value)


@old_form("model", "pa_over_q", "fmin_hz", "fmax_hz", renamed={"level_kind": "excitation"})
def hb_continuation(model: ContactModel, *, pa_over_q: float, fmin_hz: float, fmax_hz: float,
                    harmonics: int = 32, settings: HBSettings | None = None, start=None,
                    from_fmax: bool = False, f_start: float | None = None, excitation: str = "force",
                    force_harmonics=()) -> HBBranch:
    """Follow a periodic branch from ``fmin`` to ``fmax`` by pseudo-arclength continuation.

    Parameters
    ----------
    model : ContactModel
    pa_over_q : float
        Excitation amplitude [Q], ≥ 0.
    fmin_hz, fmax_hz : float
        Frequency range [Hz], 0 < fmin_hz < fmax_hz. The branch starts at ``fmin`` (``fmax`` with
        ``from_fmax``), from ``start`` or the linear response, and ends when it leaves
        [fmin, fmax]; folds are passed (pseudo-arclength), so it may leave through either end.
    harmonics : int
        Number of harmonics H.
    settings : HBSettings, optional
        Steps, tolerances, the energy criterion and stability (default :class:`HBSettings`).
    start : ndarray or HBSolution, optional
        Initial coefficients at the first frequency.
    from_fmax : bool
        Start at ``fmax`` and continue towards lower frequencies.
    f_start : float, optional
        Start at this frequency [Hz] inside the range instead (direction still set by
        ``from_fmax``: decreasing f_e if True).
    excitation : str
        What ``pa_over_q`` holds (:data:`contactvib.model.LEVEL_KINDS`): "force" (P_a/Q), or
        base motion "base-um" (U [µm], the inertial force growing with f_e²) / "base-g" (A [g]).
    force_harmonics : tuple of (k, P_k/Q, phase [deg])
        Further harmonics of a force (:class:`Excitation`), each k <= ``harmonics``.

    Returns
    -------
    HBBranch

    Notes
    -----
    ``contactvib.continuation.engine.continue_branch`` on ``HBProblem``: Newton with at
    least one step and at most 12 Jacobians, step ×1.5 after ≤ 4 Jacobians, halved after a
    failure, capped so that f_e moves at most ``df_max_hz``.
    """
    kind = check_level_kind(excitation)
    if kind != "force" and force_harmonics:
        raise ParameterError("force_harmonics", force_harmonics, "belong to a force level, not to base motion")
    pa_over_q = check_range(LEVEL_KINDS[kind][0], pa_over_q, 0.0, True)
    fmin = check_range("fmin_hz", fmin_hz, 0.0, False, "Hz")
    fmax = check_range("fmax_hz", fmax_hz, 0.0, False, "Hz")
    if not fmin < fmax:
        raise ParameterError("fmax_hz", fmax, f"must be > fmin_hz = {fmin:g} Hz")
    s = settings or HBSettings()
    if not isinstance(s, HBSettings):
        raise ParameterError("settings", settings, "must be an HBSettings")
    dr_max = s.df_max_hz / model.f_n0
    H, n_time = _check_harmonics(harmonics, s.n_time)
    aft = _AFT(H, n_time)
    fn0 = model.f_n0
    f0 = fmax if from_fmax else fmin
    if f_start is not None:
        f0 = check_range("f_start", f_start, 0.0, False, "Hz")
        if not fmin <= f0 <= fmax:
            raise ParameterError("f_start", f_start, f"must be in [{fmin:g}, {fmax:g}] Hz")
    exc0 = (model.excitation(pa_over_q, f0, harmonics=force_harmonics) if kind == "force"
            else excitation_at(model, pa_over_q, f0, kind))
    first = hb_solve(exc0, harmonics=H, start=start, n_time=n_time, tol=s.tol, stability=False)
    prob = HBProblem(model, pa_over_q, aft, (fmin, fmax), s.energy_tol, s.stability, _hb_par(model, exc0))
    u0 = np.append(first.coefficients, f0 / fn0)
    prob.f_exact = (u0[-1], f0)  # the first point's f_e as given, not r f_n0
    st, F, J, data = prob.residual_jacobian(u0)
    start_pt = Point(u0, J, data, first.residual)
    cs = CorrectorSettings(tol=s.tol, max_iter=s.max_iter, min_iter=1, cons_tol=math.inf, max_step=math.inf)
    sc = StepControl(ds=s.ds, ds_min=s.ds_min, ds_max=s.ds_max, growth=((4, 1.5),), shrink=1.0,
                     dq_max=dr_max, max_points=s.max_points, bound_action="drop")
    e_r = np.zeros(u0.size)
    e_r[-1] = -1.0 if from_fmax else 1.0  # initial tangent: into the range
    run = continue_branch(prob, start_pt, e_r, cs, sc)
    sols = [p.record for p in run.points]
    stop = run.stop
    if stop.code == "max_points":
        reason = f"stopped after max_points = {s.max_points} points"
    elif stop.code == "bound":
        reason = f"left the range at {fmax if stop.detail[1] == 'upper' else fmin:g} Hz"
    elif stop.code == "problem":
        reason = stop.detail
    else:
        reason = (f"stopped at {sols[-1].fe_hz:.1f} Hz: the corrector failed at the smallest step "
                  f"ds_min = {s.ds_min:g}")
    mu = np.array([np.max(np.abs(s.floquet_multipliers)) if s.floquet_multipliers.size else np.nan
                   for s in sols])
    return HBBranch(
        fe_hz=np.array([s.fe_hz for s in sols]), app_um=np.array([s.app_um for s in sols]),
        ymin_um=np.array([s.ymin_um for s in sols]), ymax_um=np.array([s.ymax_um for s in sols]),
        floquet_abs_max=mu, stable=is_stable(mu),
        loses_contact=np.array([s.loses_contact for s in sols]),
        top_energy_fraction=np.array([s.top_energy_fraction for s in sols]),
        pa_over_q=pa_over_q, harmonics=H, stop_reason=reason, solutions=sols)


class HBProblem:
    """Harmonic balance in f_e as a continuation problem (:mod:`contactvib.continuation.engine`).

    Unknowns ``u = (X, r)``: the 2H+1 coefficients of x = y/y0 and r = f_e/f_n0; residual the HB
    residual R(X, r) of :func:`_residual` (units of Q), Jacobian ``[∂R/∂X | ∂R/∂r]``; unscaled
    (weights 1); residual norm max |R|; measurements an :class:`HBSolution`; stop when the top
    quarter of the harmonics holds more than ``energy_tol`` of the AC energy; f_e bound
    ``[fmin, fmax]`` (the point outside is dropped).
    """

    test_names = ()
    fold_tests = ()

    def __init__(self, model, pa_over_q, aft, f_range, energy_tol, stability, par=None):
        self.model, self.pa, self.aft = model, pa_over_q, aft
        self.par = (model.m2, model.l, model.damping_coefficient, pa_over_q) if par is None else par
        self.fn0 = model.f_n0
        self.y0_um = model.units.y_um
        self.energy_tol, self.stability = energy_tol, stability
        n = 2 * aft.H + 2
        self.w = np.ones(n)
        self.f_exact = (math.nan, math.nan)
        self.bounds = (Bound(n - 1, f_range[0] / self.fn0, f_range[1] / self.fn0, "f_e"),)

    def residual_jacobian(self, u):
        R, J, dr = _residual(u[:-1], u[-1], self.par, self.aft)
        Jf = np.empty((R.size, u.size))
        Jf[:, :-1] = J
        Jf[:, -1] = dr
        return 0, R, Jf, None

    def residual_norm(self, u, F):
        return float(np.max(np.abs(F)))

    def weights(self, u):
        return self.w

    def admissible(self, u):
        return True

    def measure(self, u, J, data, residual) -> HBSolution:
        fe = self.f_exact[1] if u[-1] == self.f_exact[0] else u[-1] * self.fn0
        return _solution(self.model, self.pa, fe, u[:-1].copy(), self.par, self.aft,
                         residual, self.stability, self.y0_um)

    def tests(self, pt):
        return {}

    def check(self, pt):
        s = pt.record
        if self.model.law == "table" and s.ymax_um * 1e-6 > self.model.table.deflection_m[-1]:
            return (f"stopped at {s.fe_hz:.1f} Hz: the orbit reaches {s.ymax_um:.4g} um, beyond the table's "
                    f"last row ({self.model.table.deflection_m[-1] * 1e6:.4g} um)")
        if s.top_energy_fraction <= self.energy_tol:
            return None
        return (f"stopped at {s.fe_hz:.1f} Hz: the top quarter of the {s.harmonics} harmonics holds "
                f"{s.top_energy_fraction:.1e} of the energy (> {self.energy_tol:g}); the orbit "
                f"{'loses contact' if s.loses_contact else 'is too sharp'} and needs more "
                "harmonics")

    def check_step(self, a, b):
        return None


@old_form("excitation", "z", "harmonics")
def coefficients_from_orbit(excitation: Excitation, z, *, harmonics: int) -> np.ndarray:
    """HB coefficients [a0, a1, b1, ...] of the period-1 orbit through the nondimensional state
    ``z`` at phase 0 (one tight-tolerance period sampled from the dense output, then FFT)."""
    from contactvib._kernels.orbit import sample_records
    from contactvib.steady.orbits import record

    H, n_time = _check_harmonics(harmonics, None)
    n = max(4096, 8 * n_time)
    rec, _z, _tf = record(excitation, z, 1)
    tau = excitation.tau_period * np.arange(n) / n
    x, _v, _c = sample_records(rec, tau)
    F = np.fft.rfft(x) / n
    X = np.empty(2 * H + 1)
    X[0] = F[0].real
    X[1::2] = 2.0 * F[1:H + 1].real
    X[2::2] = -2.0 * F[1:H + 1].imag
    return X
