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
branch is followed in f_e by pseudo-arclength continuation (tangent predictor, bordered Newton
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

import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib.model import ContactModel, Excitation, ParameterError, check_range
from contactvib.model.contact_law import PowerLaw

__all__ = ["HBSolution", "HBBranch", "hb_solve", "hb_continuation", "coefficients_from_orbit", "HBError"]


class HBError(RuntimeError):
    """Harmonic-balance Newton did not converge."""


class _AFT:
    """AFT on n_time samples of θ ∈ [0, 2π) for H harmonics, FFT only (no dense products).

    The Jacobian of the projected product ``P(g · basis_k)`` is assembled from the Fourier
    coefficients G_m of g (|m| ≤ 2H) by index arithmetic: cos kθ and sin kθ map onto
    G_{j−k} ± G_{j+k}. (Dense synthesis/projection matrices would need BLAS products with an
    n_time-long inner dimension, which collapse when the machine's cores are oversubscribed.)
    """

    def __init__(self, H: int, n_time: int):
        self.H = H
        self.n = n_time
        k = np.arange(1, H + 1)
        d2 = np.zeros(2 * H + 1)
        d2[1::2] = -(k ** 2)
        d2[2::2] = -(k ** 2)
        self.d2 = d2
        self.k = k
        j = np.arange(0, H + 1)[:, None]
        kk = np.arange(1, H + 1)[None, :]
        self.jm = j - kk   # indices j − k, in −H..H−1
        self.jp = j + kk   # indices j + k, in 2..2H
        self.j = np.arange(0, H + 1)

    def synth(self, X):
        """Samples of x and x_θ from [a0, a1, b1, ...]."""
        H, n = self.H, self.n
        C = np.zeros(n // 2 + 1, complex)
        C[0] = X[0]
        C[1:H + 1] = 0.5 * (X[1::2] - 1j * X[2::2])
        x = np.fft.irfft(C * n, n)
        xt = np.fft.irfft(1j * np.arange(n // 2 + 1) * C * n, n)
        return x, xt

    def project(self, f):
        """[a0, a1, b1, ...] of the samples f (harmonics ≤ H)."""
        F = np.fft.rfft(f) / self.n
        out = np.empty(2 * self.H + 1)
        out[0] = F[0].real
        out[1::2] = 2.0 * F[1:self.H + 1].real
        out[2::2] = -2.0 * F[1:self.H + 1].imag
        return out

    def product_matrix(self, g):
        """Matrix of X ↦ P(g · x) on the real coefficient vector."""
        H = self.H
        F = np.fft.rfft(g) / self.n

        def G(m):
            v = F[np.abs(m)]
            return np.where(m < 0, np.conj(v), v)

        Gm, Gp = G(self.jm), G(self.jp)  # shape (H+1, H)
        S, D = Gm + Gp, Gm - Gp
        T = np.empty((2 * H + 1, 2 * H + 1))
        G0 = F[: H + 1]
        T[0, 0] = G0[0].real
        T[1::2, 0] = 2.0 * G0[1:].real
        T[2::2, 0] = -2.0 * G0[1:].imag
        # columns of cos kθ
        T[0, 1::2] = S[0].real / 2.0
        T[1::2, 1::2] = S[1:].real
        T[2::2, 1::2] = -S[1:].imag
        # columns of sin kθ
        T[0, 2::2] = D[0].imag / 2.0
        T[1::2, 2::2] = D[1:].imag
        T[2::2, 2::2] = D[1:].real
        return T

    def times_derivative(self, T):
        """T @ D_θ, with D_θ the derivative on the coefficient vector (a_k' = k b_k, b_k' = −k a_k)."""
        out = np.zeros_like(T)
        out[:, 1::2] = -self.k * T[:, 2::2]
        out[:, 2::2] = self.k * T[:, 1::2]
        return out


def _residual(X, r, par, aft: _AFT, jac: bool = True):
    """HB residual (2H+1,), its Jacobian in X and its derivative in r."""
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


@dataclass(frozen=True)
class HBSolution:
    """One harmonic-balance periodic solution.

    Attributes
    ----------
    fe_hz, pa_over_q : float
        Excitation frequency [Hz] and amplitude [Q].
    harmonics : int
        Number of harmonics H.
    app_um, ymin_um, ymax_um : float
        Peak-to-peak amplitude and extrema of y [µm] (from the series sampled on 64 H points
        and refined by Newton on x_θ).
    loses_contact : bool
        y_min < 0.
    top_energy_fraction : float
        Share of the AC energy Σ_{k≥1}(a_k²+b_k²) held by the harmonics k > 3H/4 [1].
    residual : float
        Max-norm of the HB residual at the solution [1, units of Q].
    floquet_multipliers : ndarray of complex
        Eigenvalues of the one-period monodromy from the HB orbit point (empty if not computed).
    closure : float
        Relative closure |P(z) − z|∞ / max(1, |z|∞) of one shooting period from the HB point.
    coefficients : ndarray (2H+1,)
        [a0, a1, b1, ..., aH, bH] of x = y/y0.
    """

    fe_hz: float
    pa_over_q: float
    harmonics: int
    app_um: float
    ymin_um: float
    ymax_um: float
    loses_contact: bool
    top_energy_fraction: float
    residual: float
    floquet_multipliers: np.ndarray
    closure: float
    y0_um: float
    coefficients: np.ndarray = field(repr=False)

    @property
    def stable(self) -> bool | None:
        """All |multipliers| < 1 (None if not computed)."""
        if self.floquet_multipliers.size == 0:
            return None
        return bool(np.max(np.abs(self.floquet_multipliers)) < 1.0)

    @property
    def harmonics_um(self) -> np.ndarray:
        """One-sided amplitudes of the k·f_e components of y [µm]; k = 0: mean shift ⟨y⟩ − y0."""
        X = self.coefficients
        a = np.hypot(X[1::2], X[2::2]) * self.y0_um
        return np.concatenate([[(X[0] - 1.0) * self.y0_um], a])


def _eval(X, th, deriv=0):
    H = (X.size - 1) // 2
    k = np.arange(1, H + 1)
    a, b = X[1::2], X[2::2]
    ang = np.outer(np.atleast_1d(th), k)
    if deriv == 0:
        return X[0] + np.cos(ang) @ a + np.sin(ang) @ b
    if deriv == 1:
        return np.cos(ang) @ (k * b) - np.sin(ang) @ (k * a)
    return -(np.cos(ang) @ (k * k * a) + np.sin(ang) @ (k * k * b))


def _extrema(X):
    """(x_min, x_max) of the series: samples on 64 H points (zero-padded inverse FFT), then
    Newton on x_θ = 0 inside the sampling bracket."""
    H = (X.size - 1) // 2
    n = max(1024, 64 * H)
    C = np.zeros(n // 2 + 1, complex)
    C[0] = X[0]
    C[1:H + 1] = 0.5 * (X[1::2] - 1j * X[2::2])
    s = np.fft.irfft(C * n, n)
    out = []
    for i in (int(np.argmin(s)), int(np.argmax(s))):
        t = 2.0 * math.pi * i / n
        for _ in range(20):
            d2 = _eval(X, t, 2)[0]
            if d2 == 0.0:
                break
            step = _eval(X, t, 1)[0] / d2
            if abs(step) > 2.0 * math.pi / n:  # stay in the bracket (corner of a contact orbit)
                break
            t -= step
            if abs(step) < 1e-14:
                break
        out.append(float(_eval(X, t)[0]))
    lo, hi = min(out[0], float(s.min())), max(out[1], float(s.max()))
    return lo, hi


def _top_fraction(X):
    H = (X.size - 1) // 2
    e = X[1::2] ** 2 + X[2::2] ** 2
    tot = e.sum()
    if tot == 0.0:
        return 0.0
    return float(e[int(math.floor(0.75 * H)):].sum() / tot)


def _check_harmonics(harmonics, n_time):
    try:
        h = float(harmonics)
    except (TypeError, ValueError):
        raise ParameterError("harmonics", harmonics, "must be an integer in 1..1024") from None
    if not math.isfinite(h) or h != int(h) or not 1 <= h <= 1024:
        raise ParameterError("harmonics", harmonics, "must be an integer in 1..1024")
    H = int(h)
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
    raise HBError(f"harmonic-balance Newton did not converge (residual {res:.2e} after {it} "
                  "iterations); start closer, e.g. from a neighbouring solution")


def _solution(model, exc_pa, fe, X, par, aft, res, stability, y0_um):
    lo, hi = _extrema(X)
    mult = np.empty(0, complex)
    closure = math.nan
    if stability:
        from contactvib._kernels.flow import STATUS_OK
        from contactvib._kernels.shooting import state_scale, strobe_map

        r = fe / model.f_n0
        z = np.array([_eval(X, 0.0)[0], r * _eval(X, 0.0, 1)[0]])
        kpar = np.array([par[0], par[1], par[2], par[3], r])
        out_z, out_M = np.empty(2), np.empty((2, 2))
        st = strobe_map(z, 1, kpar, 1e-12, 1e-12, out_z, out_M)
        if st == STATUS_OK:
            mult = np.linalg.eigvals(out_M).astype(complex)
            closure = float(np.max(np.abs(out_z - z)) / state_scale(z[0], z[1]))
    return HBSolution(fe_hz=fe, pa_over_q=exc_pa, harmonics=aft.H, app_um=(hi - lo) * y0_um,
                      ymin_um=lo * y0_um, ymax_um=hi * y0_um, loses_contact=bool(lo < 0.0),
                      top_energy_fraction=_top_fraction(X), residual=res,
                      floquet_multipliers=mult, closure=closure, y0_um=y0_um,
                      coefficients=X.copy())


def _initial_guess(model: ContactModel, exc: Excitation, H: int) -> np.ndarray:
    """Linear response about x = 1 (order 1 of the perturbation series)."""
    X = np.zeros(2 * H + 1)
    X[0] = 1.0
    r = exc.r
    A = (exc.pa_over_q / model.m2) / (1.0 - r * r + 2j * model.zeta * r)
    X[1], X[2] = A.real, -A.imag  # A e^{iθ}: cos part Re A, sin part −Im A
    return X


def hb_solve(model: ContactModel, excitation: Excitation, harmonics: int = 32,
             start=None, n_time: int | None = None, tol: float = 1e-12, max_iter: int = 60,
             stability: bool = True) -> HBSolution:
    """Harmonic-balance periodic solution at one operating point.

    Parameters
    ----------
    model, excitation
        The oscillator and the force.
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
    HBError
        If Newton does not converge.
    """
    H, n_time = _check_harmonics(harmonics, n_time)
    aft = _AFT(H, n_time)
    if start is None:
        X = _initial_guess(model, excitation, H)
    else:
        s = start.coefficients if isinstance(start, HBSolution) else np.asarray(start, float)
        X = np.zeros(2 * H + 1)
        n = min(s.size, X.size)
        X[:n] = s[:n]
    par = (model.m2, model.l, model.damping_coefficient, excitation.pa_over_q)
    X, res, _ = _newton(X, excitation.r, par, aft, tol, max_iter)
    return _solution(model, excitation.pa_over_q, excitation.f_e, X, par, aft, res, stability,
                     model.y0 * 1e6)


@dataclass(frozen=True)
class HBBranch:
    """A branch of HB solutions continued in f_e, stored column by column.

    Attributes
    ----------
    fe_hz, app_um, ymin_um, ymax_um : ndarray
        Excitation frequency [Hz], peak-to-peak amplitude and extrema of y [µm] per point.
    floquet_abs_max : ndarray
        Largest |Floquet multiplier| per point [1] (NaN if not computed).
    stable : ndarray of bool
    loses_contact : ndarray of bool
    top_energy_fraction : ndarray
        Energy share of the top quarter of the harmonics [1].
    pa_over_q : float
    harmonics : int
    stop_reason : str
        Why the continuation ended.
    solutions : list of HBSolution
    """

    fe_hz: np.ndarray
    app_um: np.ndarray
    ymin_um: np.ndarray
    ymax_um: np.ndarray
    floquet_abs_max: np.ndarray
    stable: np.ndarray
    loses_contact: np.ndarray
    top_energy_fraction: np.ndarray
    pa_over_q: float
    harmonics: int
    stop_reason: str
    solutions: list = field(repr=False)

    def __len__(self):
        return self.fe_hz.size

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib hbm --json``."""
        return {
            "pa_over_q": float(self.pa_over_q),
            "harmonics": int(self.harmonics),
            "stop_reason": self.stop_reason,
            "units": {"fe_hz": "Hz", "app_um": "um", "ymin_um": "um", "ymax_um": "um"},
            "points": [
                {"fe_hz": float(f), "app_um": float(a), "ymin_um": float(lo), "ymax_um": float(hi),
                 "stable": bool(s), "floquet_abs_max": float(mu) if np.isfinite(mu) else None,
                 "loses_contact": bool(g), "top_energy_fraction": float(e)}
                for f, a, lo, hi, s, mu, g, e in zip(
                    self.fe_hz, self.app_um, self.ymin_um, self.ymax_um, self.stable,
                    self.floquet_abs_max, self.loses_contact, self.top_energy_fraction)
            ],
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), **kwargs)


def hb_continuation(model: ContactModel, pa_over_q: float, fmin: float, fmax: float,
                    harmonics: int = 32, n_time: int | None = None, ds: float = 0.02,
                    ds_min: float = 1e-6, ds_max: float = 0.5, df_max: float = 5.0,
                    max_points: int = 5000,
                    energy_tol: float = 1e-8, tol: float = 1e-11, stability: bool = True,
                    start=None, from_fmax: bool = False, f_start: float | None = None) -> HBBranch:
    """Follow a periodic branch from ``fmin`` to ``fmax`` by pseudo-arclength continuation.

    Parameters
    ----------
    model : ContactModel
    pa_over_q : float
        Excitation amplitude [Q], ≥ 0.
    fmin, fmax : float
        Frequency range [Hz], 0 < fmin < fmax. The branch starts at ``fmin`` (``fmax`` with
        ``from_fmax``), from ``start`` or the linear response, and ends when it leaves
        [fmin, fmax]; folds are passed (pseudo-arclength), so it may leave through either end.
    harmonics : int
        Number of harmonics H.
    ds, ds_min, ds_max : float
        Initial, smallest and largest arclength step (in the scaled unknowns: coefficients in
        y0, r = f_e/f_n0).
    df_max : float
        Largest frequency step [Hz] (resolves narrow superharmonic peaks).
    max_points : int
        Largest number of points.
    energy_tol : float
        Stop when the top quarter of the harmonics holds more than this share of the AC energy
        (the truncation no longer resolves the orbit: long flights, impacts). The default 1e-8
        corresponds to an A_pp truncation error of about 1e-4 in the measured cases.
    tol : float
        Newton tolerance on the residual.
    stability : bool
        Floquet multipliers by one shooting period per point.
    start : ndarray or HBSolution, optional
        Initial coefficients at the first frequency.
    from_fmax : bool
        Start at ``fmax`` and continue towards lower frequencies.
    f_start : float, optional
        Start at this frequency [Hz] inside the range instead (direction still set by
        ``from_fmax``: decreasing f_e if True).

    Returns
    -------
    HBBranch
    """
    pa_over_q = check_range("P_a/Q", pa_over_q, 0.0, True)
    fmin = check_range("fmin", fmin, 0.0, False, "Hz")
    fmax = check_range("fmax", fmax, 0.0, False, "Hz")
    if not fmin < fmax:
        raise ParameterError("fmax", fmax, f"must be > fmin = {fmin:g} Hz")
    ds = check_range("ds", ds, 0.0, False)
    ds_min = check_range("ds_min", ds_min, 0.0, False)
    ds_max = check_range("ds_max", ds_max, ds_min, True)
    energy_tol = check_range("energy_tol", energy_tol, 0.0, False)
    max_points = int(check_range("max_points", max_points, 2, True))
    dr_max = check_range("df_max", df_max, 0.0, False, "Hz") / model.f_n0
    H, n_time = _check_harmonics(harmonics, n_time)
    aft = _AFT(H, n_time)
    fn0 = model.f_n0
    par = (model.m2, model.l, model.damping_coefficient, pa_over_q)
    y0_um = model.y0 * 1e6
    f0 = fmax if from_fmax else fmin
    if f_start is not None:
        f0 = check_range("f_start", f_start, 0.0, False, "Hz")
        if not fmin <= f0 <= fmax:
            raise ParameterError("f_start", f_start, f"must be in [{fmin:g}, {fmax:g}] Hz")
    first = hb_solve(model, model.excitation(pa_over_q, f0), H, start=start, n_time=n_time,
                     tol=tol, stability=False)
    X = first.coefficients.copy()
    r = f0 / fn0
    rmin, rmax = fmin / fn0, fmax / fn0
    n = 2 * H + 2
    # initial tangent: into the range
    _, J, dr = _residual(X, r, par, aft)
    t = np.append(np.linalg.solve(J, -dr), 1.0) * (-1.0 if from_fmax else 1.0)
    t /= np.linalg.norm(t)
    sols = [_solution(model, pa_over_q, f0, X, par, aft, first.residual, stability, y0_um)]
    reason = ""
    while True:
        if len(sols) >= max_points:
            reason = f"stopped after max_points = {max_points} points"
            break
        if sols[-1].top_energy_fraction > energy_tol:
            s = sols[-1]
            reason = (f"stopped at {s.fe_hz:.1f} Hz: the top quarter of the {H} harmonics holds "
                      f"{s.top_energy_fraction:.1e} of the energy (> {energy_tol:g}); the orbit "
                      f"{'loses contact' if s.loses_contact else 'is too sharp'} and needs more "
                      "harmonics")
            break
        Y = np.append(X, r)
        accepted = False
        ds = min(ds, dr_max / max(abs(t[-1]), 1e-300))
        while ds >= ds_min:
            Yp = Y + ds * t
            Z = Yp.copy()
            ok = False
            for it in range(12):
                R, J, dr = _residual(Z[:-1], Z[-1], par, aft)
                res = float(np.max(np.abs(R)))
                if res <= tol and it > 0:
                    ok = True
                    break
                if not np.isfinite(res):
                    break
                A = np.empty((n, n))
                A[:-1, :-1] = J
                A[:-1, -1] = dr
                A[-1] = t
                rhs = np.append(-R, -(t @ (Z - Yp)))
                try:
                    dZ = np.linalg.solve(A, rhs)
                except np.linalg.LinAlgError:
                    break
                Z = Z + dZ
            if ok:
                accepted = True
                break
            ds *= 0.5
        if not accepted:
            reason = (f"stopped at {r * fn0:.1f} Hz: the corrector failed at the smallest step "
                      f"ds_min = {ds_min:g}")
            break
        # new tangent, oriented along the old one
        _, J, dr = _residual(Z[:-1], Z[-1], par, aft)
        A = np.empty((n, n))
        A[:-1, :-1] = J
        A[:-1, -1] = dr
        A[-1] = t
        tn = np.linalg.solve(A, np.append(np.zeros(n - 1), 1.0))
        tn /= np.linalg.norm(tn)
        if tn @ t < 0:
            tn = -tn
        X, r, t = Z[:-1], Z[-1], tn
        if it <= 3:
            ds = min(ds * 1.5, ds_max)
        if r > rmax or r < rmin:
            reason = f"left the range at {fmax if r > rmax else fmin:g} Hz"
            break
        sols.append(_solution(model, pa_over_q, r * fn0, X, par, aft, res, stability, y0_um))
    mu = np.array([np.max(np.abs(s.floquet_multipliers)) if s.floquet_multipliers.size else np.nan
                   for s in sols])
    return HBBranch(
        fe_hz=np.array([s.fe_hz for s in sols]), app_um=np.array([s.app_um for s in sols]),
        ymin_um=np.array([s.ymin_um for s in sols]), ymax_um=np.array([s.ymax_um for s in sols]),
        floquet_abs_max=mu, stable=mu < 1.0,
        loses_contact=np.array([s.loses_contact for s in sols]),
        top_energy_fraction=np.array([s.top_energy_fraction for s in sols]),
        pa_over_q=pa_over_q, harmonics=H, stop_reason=reason, solutions=sols)


def coefficients_from_orbit(excitation: Excitation, z, harmonics: int) -> np.ndarray:
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
