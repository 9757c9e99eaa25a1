"""Perturbation solution: the regular series in the excitation amplitude, to any order.

Equation
--------
With ``y = y0 (1 + u)``, ``τ = ω_n0 t`` and the kernels' form of Eq. (2.5)
(``x = 1 + u``, ``c = 2 m2 ζ``), motion in contact obeys::

    u'' + 2ζ (1 + u)^l u' + [(1 + u)^m2 − 1] / m2 = ε cos(r τ) / m2,     ε = P_a / Q

(for the paper's law m2 = 2, l = 1: ``u'' + 2ζ(1+u)u' + u + u²/2 = (P_a/2Q) cos rτ``).

Method
------
The regular expansion ``u = Σ_{n≥1} εⁿ uₙ(θ)``, ``θ = r τ``, gives at every order the linear
damped oscillator::

    uₙ'' + 2ζ uₙ' + uₙ = δ_{n1} cos(θ)/m2 − Rₙ/m2 − 2ζ Σ_{k=1}^{n−1} Dₖ u'_{n−k}

where ``W = (1+u)^m2 = Σ Wₙ εⁿ``, ``Rₙ = Wₙ − m2 uₙ`` and ``D = (1+u)^l = Σ Dₙ εⁿ``. The
power-series coefficients of ``W`` and ``D`` come from J. C. P. Miller's recurrence for
``v^α`` (``v = 1 + u``)::

    wₙ = (1/n) Σ_{k=1}^{n} [(α+1) k − n] uₖ w_{n−k},    w₀ = 1

whose ``k = n`` term is ``α uₙ``: the non-linear remainder ``Rₙ`` involves only lower orders,
so the recursion is explicit, exact for any real m2 ≥ 1 and l ≥ 0. Each ``uₙ`` is a
trigonometric polynomial of degree ``n`` in θ (order n carries the 1/n superharmonic resonance
near f_n0/n); products are formed on ``M > 2N`` equispaced samples (exact, no aliasing) and each
linear problem is solved harmonic by harmonic, ``U_j = F_j / (1 − (j r)² + 2iζ j r)``.

Validity
--------
The series describes the orbit only while contact is kept (``y_min > 0``) and while it converges
in N; ``valid`` means ``y_min > 0`` and an estimated A_pp error ≤ 1e-3 A_pp.

Summation
---------
The plain partial sum converges slowly near the 1/m resonances (oscillating at 360 Hz, 0.65 Q:
complex singularities in ε close to the circle |ε| = P_a/Q) and is only asymptotic at 50 Hz,
0.90 Q (the terms of harmonic ≈ f_n0/f_e grow beyond N ≈ 45). Summing each harmonic's series in
ε² by its diagonal Padé approximant converges in all three paper cases (measured tables in
docs/tutorials/perturbation.md), so it is the default; ``summation="plain"`` keeps the partial sum.

References
----------
A. H. Nayfeh, D. T. Mook, *Nonlinear Oscillations*, Wiley (1995), Ch. 4 (straightforward
expansions, superharmonic resonances). D. E. Knuth, *The Art of Computer Programming* vol. 2,
Sec. 4.7 (powers of power series, Miller's recurrence). R. Kostek, J. Theor. Appl. Mech. 51 (2013)
(the perturbation solution of the contact oscillator).
"""

from __future__ import annotations

import functools
import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib.call_forms import old_form
from contactvib.model import ContactModel, Excitation, ParameterError, check_excitation, check_range
from contactvib.model.contact_law import PowerLaw
from contactvib.steady.results import TimeHistory

__all__ = ["PerturbationResult", "perturbation_series", "series_state", "perturbation_curve", "linear_response",
           "steady_counterpart", "described_attractor", "convergence_table", "VALID_RTOL", "MAX_TERMS", "SUMMATIONS"]

#: ``valid`` requires an estimated A_pp truncation error at most this fraction of A_pp.
VALID_RTOL = 1e-3
#: Largest number of terms N accepted (the recursion is O(N²) vector operations; beyond ~200 round-off of
#: the growing terms dominates anyway).
MAX_TERMS = 400


@functools.lru_cache(maxsize=512)
def _series_terms(m2: float, l: float, zeta: float, r: float, terms: int):
    """Two-sided harmonic amplitudes ``C[n, j]`` of ``uₙ`` (n = 0..terms, j = 0..terms).

    ``uₙ(θ) = C[n,0] + 2 Re Σ_{j≥1} C[n,j] e^{ijθ}``; row 0 is zero (u₀ = 0). The powers
    ``(1+u)^m2`` and ``(1+u)^l`` come from the contact law (:meth:`PowerLaw.series_about_one`).
    The terms do not depend on P_a (the series is in powers of P_a/Q), so they are kept per
    (law, ζ, r, terms) and shared by every level of a sweep run in this process; the array is
    read-only.
    """
    law = PowerLaw(m2, l)
    N = terms
    M = 1 << int(math.ceil(math.log2(2 * N + 4)))  # samples: degree ≤ N needs M > 2N
    M = max(M, 16)
    theta = 2.0 * math.pi * np.arange(M) / M
    j = np.arange(M // 2 + 1)
    lin = 1.0 - (j * r) ** 2 + 2j * zeta * (j * r)  # linear operator per harmonic
    C = np.zeros((N + 1, N + 1), complex)
    u = np.zeros((N + 1, M))    # uₙ(θ) samples
    du = np.zeros((N + 1, M))   # duₙ/dτ samples
    W = np.zeros((N + 1, M))    # coefficients of (1+u)^m2
    D = np.zeros((N + 1, M))    # coefficients of (1+u)^l
    W[0] = 1.0
    D[0] = 1.0
    for n in range(1, N + 1):
        # the law's series without their uₙ terms (Miller's recurrence: R, S involve orders < n)
        R, S = law.series_about_one(u, W, D, n)
        if n > 1:
            damp = (D[1:n] * du[n - 1:0:-1]).sum(axis=0)
            rhs = -R / m2 - 2.0 * zeta * damp
        else:
            rhs = np.zeros(M)
        if n == 1:
            rhs = rhs + np.cos(theta) / m2
        F = np.fft.rfft(rhs) / M
        U = F / lin
        U[n + 1:] = 0.0  # degree n exactly (drops round-off only)
        if n % 2 == 1:  # parity: odd orders hold odd harmonics, even orders even ones
            U[0::2] = 0.0
        else:
            U[1::2] = 0.0
        u[n] = np.fft.irfft(U * M, M)
        du[n] = np.fft.irfft(1j * j * r * U * M, M)
        W[n] = m2 * u[n] + R
        D[n] = l * u[n] + S
        C[n] = U[: N + 1]
    C.setflags(write=False)
    return C


def _trig_eval(c: np.ndarray, theta, deriv: int = 0) -> np.ndarray:
    """Evaluate d^deriv/dθ^deriv of ``c0 + 2 Re Σ c_j e^{ijθ}`` at ``theta``."""
    theta = np.atleast_1d(np.asarray(theta, float))
    j = np.arange(c.size)
    e = np.exp(1j * np.outer(theta, j)) * (1j * j) ** deriv
    return 2.0 * (e[:, 1:] @ c[1:]).real + (c[0].real if deriv == 0 else 0.0)


def _extrema(c: np.ndarray):
    """(θ_min, u_min, θ_max, u_max) of the trigonometric polynomial with coefficients ``c``."""
    n = c.size - 1
    Mf = max(4096, 64 * n)
    spec = np.zeros(Mf // 2 + 1, complex)
    spec[: n + 1] = c * Mf
    s = np.fft.irfft(spec, Mf)
    out = []
    for i in (int(np.argmin(s)), int(np.argmax(s))):
        th = 2.0 * math.pi * i / Mf
        for _ in range(30):  # Newton on u'(θ) = 0
            d1 = _trig_eval(c, th, 1)[0]
            d2 = _trig_eval(c, th, 2)[0]
            if d2 == 0.0:
                break
            step = d1 / d2
            th -= step
            if abs(step) < 1e-15:
                break
        out.extend([th, float(_trig_eval(c, th)[0])])
    return tuple(out)


@dataclass(frozen=True)
class PerturbationResult:
    """Series solution of N terms at one operating point.

    Attributes
    ----------
    fe_hz, pa_over_q : float
        Excitation frequency [Hz] and amplitude [Q].
    terms : int
        Number of terms N of the series in ε = P_a/Q.
    app_um, ymin_um, ymax_um : float
        Peak-to-peak amplitude and extrema of y [µm] of the N-term sum.
    error_estimate_um : float
        Estimated truncation error of A_pp [µm] (inf when the terms do not decrease).
    valid : bool
        ``ymin_um > 0`` (contact kept) and ``error_estimate_um ≤ 1e-3 app_um``.
    reason : str
        Why the series is invalid ("" when valid).
    harmonics_um : ndarray (terms+1,)
        One-sided amplitude of the k·f_e component of y [µm]; k = 0 is the mean shift
        ⟨y⟩ − y0 (signed).
    phases_rad : ndarray (terms+1,)
        Phase φ_k of each component, y = y0 + Σ A_k cos(k 2π f_e t + φ_k) [rad].
    term_norms_um : ndarray (terms,)
        max_t ``|εⁿ uₙ|`` y0 for n = 1..N [µm]: the size of each term.
    y0_um, fn0_hz : float
        Static deflection [µm] and linear natural frequency [Hz] of the model.
    summation : str
        ``"pade"`` (diagonal Padé in ε² of every harmonic's series) or ``"plain"`` (partial sum).
    coefficients : ndarray (terms+1, terms+1), complex
        Two-sided harmonic amplitudes C[n, j] of the unscaled terms uₙ (units of y0, per εⁿ).
    sum_coefficients : ndarray (terms+1,), complex
        Two-sided harmonic amplitudes of the summed u (units of y0):
        ``u(θ) = c0 + 2 Re Σ c_j e^{ijθ}``.
    """

    fe_hz: float
    pa_over_q: float
    terms: int
    app_um: float
    ymin_um: float
    ymax_um: float
    error_estimate_um: float
    valid: bool
    reason: str
    harmonics_um: np.ndarray
    phases_rad: np.ndarray
    term_norms_um: np.ndarray
    y0_um: float
    fn0_hz: float
    summation: str
    coefficients: np.ndarray = field(repr=False)
    sum_coefficients: np.ndarray = field(repr=False)

    # ------------------------------------------------------------------ evaluation
    def _summed(self, terms: int | None = None) -> np.ndarray:
        if terms is None or int(terms) == self.terms:
            return self.sum_coefficients
        return _sum(self.coefficients, self.pa_over_q, int(terms), self.summation)

    @property
    def state(self) -> np.ndarray:
        """Nondimensional orbit point (x, x') at phase 0 (for shooting from the series)."""
        return _phase_zero_state(self._summed(), self.fe_hz / self.fn0_hz)

    def history(self, n_periods: int = 2, samples_per_period: int = 400,
                terms: int | None = None) -> TimeHistory:
        """Time history of the series (N terms, or fewer ``terms``) from phase 0.

        Returns a :class:`contactvib.TimeHistory` (t [ms], y [µm], ẏ [mm/s]); plot it
        only after checking ``valid``.
        """
        n_periods = int(check_range("n_periods", n_periods, 1, True))
        samples_per_period = int(check_range("samples_per_period", samples_per_period, 2, True))
        c = self._summed(terms)
        theta = np.linspace(0.0, 2.0 * math.pi * n_periods, n_periods * samples_per_period + 1)
        wf = 2.0 * math.pi * self.fe_hz  # dθ/dt [rad/s]
        y = self.y0_um * (1.0 + _trig_eval(c, theta))
        ydot = self.y0_um * _trig_eval(c, theta, 1) * wf * 1e-3  # µm/s → mm/s
        return TimeHistory(t_ms=theta / wf * 1e3, y_um=y, ydot_mm_s=ydot, in_contact=y > 0.0,
                           y0_um=self.y0_um, fe_hz=self.fe_hz, pa_over_q=self.pa_over_q)

    def app_of_terms(self, terms: int) -> float:
        """A_pp [µm] of the sum of the first ``terms`` terms (1 ≤ terms ≤ N)."""
        if not 1 <= int(terms) <= self.terms:
            raise ParameterError("terms", terms, f"must be an integer in 1..{self.terms}")
        _, lo, _, hi = _extrema(self._summed(int(terms)))
        return (hi - lo) * self.y0_um

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib perturbation --json``.

        Keys: app_um, ymin_um, ymax_um [µm], valid, terms (N), error_estimate [µm, estimated A_pp
        truncation error; null if the terms do not decrease], fe_hz, pa_over_q, harmonics_um
        [µm, k = 0 the mean shift], plus reason ("" when valid) and summation.
        """
        err = float(self.error_estimate_um)
        return {
            "app_um": float(self.app_um),
            "ymin_um": float(self.ymin_um),
            "ymax_um": float(self.ymax_um),
            "valid": bool(self.valid),
            "terms": int(self.terms),
            "error_estimate": err if math.isfinite(err) else None,
            "fe_hz": float(self.fe_hz),
            "pa_over_q": float(self.pa_over_q),
            "harmonics_um": [float(a) for a in self.harmonics_um],
            "reason": self.reason,
            "summation": self.summation,
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), **kwargs)


def _tail_estimate(norms: np.ndarray) -> float:
    """Estimated sup-norm of the remainder of a plain series from the envelope of its last terms.

    Root test over two windows of ``w = max(2, N//5)`` terms: ρ = (max of the last window / max
    of the window before)^(1/w); the geometric tail is ``max(last window) ρ/(1−ρ)``; inf when
    ρ ≥ 1 (the terms do not decrease).
    """
    N = norms.size
    w = max(2, N // 5)
    if N < 2 * w:
        return math.inf
    last = float(norms[N - w:].max())
    prev = float(norms[N - 2 * w:N - w].max())
    if last == 0.0:
        return 0.0
    if prev == 0.0:
        return math.inf
    rho = (last / prev) ** (1.0 / w)
    return last * rho / (1.0 - rho) if rho < 1.0 else math.inf


def _pade_at_one(a: np.ndarray) -> complex:
    """Value at t = 1 of the Padé approximant [K−M / M] (M = K − K//2) of Σ a_k t^k.

    The denominator's linear system is solved in the least-squares sense (minimum norm), which
    keeps the approximant defined when the Toeplitz matrix is rank-deficient (a lower-degree
    approximant would do); see Gonnet, Güttel, Trefethen, SIAM Rev. 55 (2013).
    """
    K = a.size - 1
    if K < 2:
        return complex(a.sum())
    L = K // 2  # numerator degree
    M = K - L   # denominator degree
    scale = np.abs(a).max()
    if scale == 0.0:
        return 0j
    b = a / scale
    # rows k = L+1..K: Σ_{i=1}^{M} q_i b_{k−i} = −b_k
    A = np.array([[b[k - i] if k - i >= 0 else 0.0 for i in range(1, M + 1)]
                  for k in range(L + 1, K + 1)], dtype=complex)
    q, *_ = np.linalg.lstsq(A, -b[L + 1:K + 1], rcond=1e-13)
    q = np.concatenate([[1.0], q])
    p = np.array([sum(q[i] * b[k - i] for i in range(0, min(k, M) + 1)) for k in range(L + 1)])
    den = q.sum()
    if den == 0.0 or not np.isfinite(den):
        return complex(np.nan)
    return complex(p.sum() / den * scale)


def _sum(C: np.ndarray, eps: float, terms: int, summation: str) -> np.ndarray:
    """Two-sided harmonics of u summed over ``terms`` terms, plainly or by Padé per harmonic.

    Harmonic j of u is ε^j g_j(ε²) (parity), so its Padé approximant is taken in t = (ε'/ε)²
    at t = 1, using the coefficients C[n, j] εⁿ, n = j, j+2, ..., terms.
    """
    N = int(terms)
    powers = eps ** np.arange(N + 1)
    if summation == "plain":
        return powers @ C[: N + 1, : N + 1]
    c = np.zeros(N + 1, complex)
    for j in range(N + 1):
        n0 = j if j > 0 else 2
        a = C[n0:N + 1:2, j] * powers[n0:N + 1:2]
        if a.size:
            c[j] = _pade_at_one(a)
    return c


def _sup_bound(c: np.ndarray) -> float:
    """Upper bound of max_θ |c0 + 2 Re Σ c_j e^{ijθ}|."""
    return float(abs(c[0]) + 2.0 * np.abs(c[1:]).sum())


SUMMATIONS = ("pade", "plain")


def _check_terms(terms, summation) -> int:
    """The number of terms N as an int, after checking it and the summation."""
    try:
        o = float(terms)
    except (TypeError, ValueError):
        raise ParameterError("terms", terms, f"must be an integer in 1..{MAX_TERMS}") from None
    if not math.isfinite(o) or o != int(o) or not 1 <= o <= MAX_TERMS:
        raise ParameterError("terms", terms, f"must be an integer in 1..{MAX_TERMS}")
    if summation not in SUMMATIONS:
        raise ParameterError("summation", summation, f"must be one of {', '.join(SUMMATIONS)}")
    return int(o)


def _phase_zero_state(c: np.ndarray, r: float) -> np.ndarray:
    """(x, x') at phase 0 of the summed harmonics ``c`` (r = f_e/f_n0)."""
    return np.array([1.0 + _trig_eval(c, 0.0)[0], r * _trig_eval(c, 0.0, 1)[0]])


def series_state(model: ContactModel, excitation: Excitation, terms: int = 40,
                 summation: str = "pade") -> np.ndarray:
    """The nondimensional orbit point (x, x') at phase 0 of :func:`perturbation_series` (the same
    numbers as its ``.state``) without its error estimate, term sizes and extrema: a third of
    the work, for a Newton start (the sweep's small-amplitude seeds)."""
    model.require_paper_family("the perturbation series", excitation)
    N = _check_terms(terms, summation)
    c = _sum(_series_terms(model.m2, model.l, model.zeta, excitation.r, N), excitation.pa_over_q, N,
             summation)
    if not np.all(np.isfinite(c)):
        c = np.nan_to_num(c)
    return _phase_zero_state(c, excitation.f_e / model.f_n0)


@old_form("model", "excitation", "terms", "summation")
def perturbation_series(excitation: Excitation, *, terms: int = 40, summation: str = "pade") -> PerturbationResult:
    """The regular perturbation series of the steady state, summed over ``terms`` terms.

    Parameters
    ----------
    excitation : Excitation
        P_a/Q is the expansion parameter ε; f_e > 0. Its model (``excitation.model``): any power
        law (m2 ≥ 1, l ≥ 0).
    terms : int
        Number of terms N (1 ≤ N ≤ 400). N = 1 is the linear response.
    summation : {"pade", "plain"}
        ``"plain"``: the partial sum Σ_{n≤N} εⁿ uₙ; its error is estimated from the geometric
        envelope of the last terms. ``"pade"``: each harmonic's series in ε² summed by its
        diagonal Padé approximant (converges where the plain series converges slowly or not at
        all: near the 1/m resonances and at 50 Hz, 0.90 Q, where the plain series is only
        asymptotic); its error is estimated as the change from the sums of N−2 and N−4 terms.

    Returns
    -------
    PerturbationResult
    """
    model = check_excitation(excitation).model
    model.require_paper_family("the perturbation series", excitation)
    N = _check_terms(terms, summation)
    eps = excitation.pa_over_q
    r = excitation.r
    C = _series_terms(model.m2, model.l, model.zeta, r, N)
    y0_um = model.units.y_um
    # term sizes: max over θ of |εⁿ uₙ| (sampled finely enough for degree n)
    Mf = 1 << int(math.ceil(math.log2(16 * (N + 1))))
    spec = np.zeros((N + 1, Mf // 2 + 1), complex)
    spec[:, : N + 1] = C * Mf
    sampled = np.fft.irfft(spec, Mf, axis=1) * (eps ** np.arange(N + 1))[:, None]
    norms = np.abs(sampled[1:]).max(axis=1) * y0_um
    c = _sum(C, eps, N, summation)
    if summation == "plain":
        tail = _tail_estimate(norms)
    elif N <= 4:
        tail = math.inf
    else:
        diffs = []
        for k in (2, 4):
            ck = np.zeros(N + 1, complex)
            ck[: N + 1 - k] = _sum(C, eps, N - k, summation)
            diffs.append(_sup_bound(c - ck) * y0_um)
        tail = max(diffs)
    if not np.all(np.isfinite(c)):
        tail = math.inf
        c = np.nan_to_num(c)
    err = 2.0 * tail  # A_pp = max − min moves by at most twice the sup-norm of the remainder
    _, lo, _, hi = _extrema(c)
    app = (hi - lo) * y0_um
    ymin, ymax = (1.0 + lo) * y0_um, (1.0 + hi) * y0_um
    harm = 2.0 * np.abs(c) * y0_um
    harm[0] = c[0].real * y0_um
    phases = np.angle(c)
    reasons = []
    if ymin <= 0.0:
        reasons.append(f"the series predicts loss of contact (y_min = {ymin:.4g} um <= 0)")
    if not err <= VALID_RTOL * app:
        reasons.append("the series has not converged (estimated A_pp error "
                       f"{err:.3g} um > {VALID_RTOL:g} A_pp): raise the number of terms, or it diverges")
    return PerturbationResult(
        fe_hz=excitation.f_e, pa_over_q=eps, terms=N, app_um=app, ymin_um=ymin, ymax_um=ymax,
        error_estimate_um=err, valid=not reasons, reason="; ".join(reasons), harmonics_um=harm,
        phases_rad=phases, term_norms_um=norms, y0_um=y0_um, fn0_hz=model.f_n0,
        summation=summation, coefficients=C, sum_coefficients=c)


@old_form("model", "pa_over_q", "fe_hz", "terms")
def perturbation_curve(model: ContactModel, *, pa_over_q: float, fe_hz, terms: int = 24):
    """The series' A_pp along frequencies (for the resonance graphs' small-amplitude parts).

    Returns ``(fe_hz, app_um, valid)`` arrays [Hz, µm, bool]; ``valid`` as
    ``PerturbationResult.valid`` (contact kept and converged to 1e-3 of A_pp with ``terms`` terms).
    """
    model.require_paper_family("the perturbation series")
    fe = np.asarray(fe_hz, float)
    out = [perturbation_series(model.excitation(pa_over_q, float(f)), terms=terms) for f in fe]
    return fe, np.array([r.app_um for r in out]), np.array([r.valid for r in out], bool)


def linear_response(model: ContactModel, excitation: Excitation) -> tuple[float, float]:
    """Analytic linear steady state: (one-sided amplitude [µm], phase [rad]) of y − y0.

    ``y − y0 = A cos(2π f_e t + φ)`` with ``A e^{iφ} = (P_a / k) / (1 − r² + 2iζ r)``,
    ``k = m2 Q / y0`` the linearised contact stiffness.
    """
    r = excitation.r
    H = (excitation.P_a / model.k_lin) / (1.0 - r * r + 2j * model.zeta * r)
    return abs(H) * 1e6, float(np.angle(H))


def steady_counterpart(model: ContactModel, excitation: Excitation, result: PerturbationResult):
    """The numerical steady state the series describes (an :class:`~contactvib.Attractor`).

    Newton shooting is started from the series' orbit point; if that fails or lands on an orbit
    that loses contact, the multi-start search is used and the period-1 attractor without loss of
    contact closest in A_pp is taken (else the closest one).
    """
    from contactvib.errors import ComputationError
    from contactvib.steady.attractors import find_attractors
    from contactvib.steady.orbits import describe_orbit, refine_orbit

    try:
        z, M, res = refine_orbit(excitation, result.state, 1)
        att = describe_orbit(excitation, z, 1, monodromy=M, closure=res)
        if not att.loses_contact or not result.valid:
            if abs(att.app_um - result.app_um) <= 0.5 * max(result.app_um, 1e-12) or not result.valid:
                return att
    except ComputationError:
        pass
    found = find_attractors(excitation)
    if len(found) == 0:
        raise ComputationError("no steady state found at this operating point", stage="settle")
    return found[described_attractor(found, result)]


def described_attractor(attractors, result: PerturbationResult) -> int:
    """Index of the attractor the series describes among ``attractors`` (non-empty): the
    period-1 orbit without loss of contact closest to the series in A_pp, else the closest
    attractor of all."""
    pool = [i for i, a in enumerate(attractors) if a.period == 1 and not a.loses_contact]
    pool = pool or list(range(len(attractors)))
    return min(pool, key=lambda i: abs(attractors[i].app_um - result.app_um))


def convergence_table(model: ContactModel, excitation: Excitation, terms, reference_app_um: float,
                      summation: str = "pade"):
    """Rows ``(N, A_pp [µm], |A_pp − reference| / reference, error estimate [µm], valid)``, one
    per number of terms N in ``terms`` (a sequence)."""
    rows = []
    for n in terms:
        res = perturbation_series(excitation, terms=n, summation=summation)
        rows.append((int(n), res.app_um, abs(res.app_um - reference_app_um) / reference_app_um,
                     res.error_estimate_um, res.valid))
    return rows
