"""The steady tangential motion by Newton's method on the period map: what makes the friction
columns of a resonance sweep cheap.

From a cold start the tangential transient decays with the slider's time on its drive,
2 M / c_d (≈ 0.2 s at the defaults: hundreds of normal periods). The steady state is a fixed
point z* = P(z*) of the map P over one normal period of the phase-0 state z = (w, w', f_t)
(:func:`contactvib._kernels.friction_period.run_period`). P is smooth between changes of its
sequence of stick, slip and free modes, so Newton's method with a finite-difference Jacobian
finds z* in a few periods; along a branch of a sweep the neighbouring point's z* and Jacobian
(improved by Broyden's update after each step, recomputed where a step does not halve
the residual) start it, and one
or two periods per point usually suffice.

A run that does not converge (a tangential period of several normal periods, quasi-periodic
stick–slip, a mode change right at phase 0) or converges to an unstable fixed point returns
None: the caller then settles the transient (:func:`contactvib.friction.friction_at`). Not used
under a force drive (u drifts: no fixed point of w).

Where the tangential motion is bistable (two stable stick–slip cycles under one normal orbit),
the continuation along a branch stays on the cycle it started on, which need not be the one the
transient from steady sliding (:func:`contactvib.friction.friction_at` without a warm start)
reaches.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels.shooting import is_stable
from contactvib._kernels.status import STATUS_OK

__all__ = ["WarmStart", "newton_steady"]

#: Relative distance of P(z) and z (scaled as the steady-state test) at which z is the fixed point.
NEWTON_TOL = 1e-11
#: Newton steps before giving up.
MAX_STEPS = 12
#: Finite-difference step, relative to the state's scale plus its magnitude.
FD_STEP = 1e-6


@dataclass
class WarmStart:
    """The steady phase-0 states of the previous points of a branch and the period map's
    Jacobian at the last one.

    Attributes
    ----------
    z : ndarray or None
        (w, w', f_t) [y0, y0 ω_n0, W] of the last point.
    mode : int
        Its mode (stick, slip, free).
    sigma : float
        Its slip direction.
    jac : ndarray or None
        ∂P/∂z (3 × 3) of the period map there.
    period : int
        The normal period [excitation periods] of that point (the Jacobian and the history are
        kept for the same period only).
    fe_hz : float
        Its excitation frequency [Hz].
    history : list of (float, ndarray)
        (f_e [Hz], z) of the last three points of this period (the predictor's).
    """

    z: np.ndarray | None = None
    mode: int = 0
    sigma: float = 1.0
    jac: np.ndarray | None = None
    period: int = 0
    fe_hz: float = math.nan
    history: list = field(default_factory=list)

    def push(self, z, mode: int, sigma: float, period: int, fe_hz: float) -> None:
        """Record the steady state of the point just computed."""
        if period != self.period:
            self.history = []
        self.history = [*self.history[-2:], (float(fe_hz), np.array(z[:3], float))]
        self.z, self.mode, self.sigma, self.period, self.fe_hz = self.history[-1][1], int(mode), \
            float(sigma), int(period), float(fe_hz)

    def predict(self, period: int, fe_hz: float):
        """The start of the point at ``fe_hz`` [Hz]: the last state, extrapolated by the
        polynomial through the last two or three states when they have this ``period`` and the
        step goes on in their direction by at most twice their last distance."""
        h = self.history
        if len(h) < 2 or period != self.period:
            return self.z
        last = h[-1][0] - h[-2][0]
        if last == 0.0 or not 0.0 < (fe_hz - h[-1][0]) / last <= 2.0:
            return self.z
        fs = np.array([f for f, _z in h])
        if np.unique(fs).size < fs.size:
            h, fs = h[-2:], fs[-2:]
        out = np.zeros(3)
        for a, (fa, za) in enumerate(h):  # Lagrange's form
            w = 1.0
            for b, fb in enumerate(fs):
                if b != a:
                    w *= (fe_hz - fb) / (fa - fb)
            out += w * za
        return out


def stable_fixed_point(jac) -> bool:
    """Whether the period map's fixed point with Jacobian ``jac`` (3 × 3) is stable by the
    package's one rule (:func:`contactvib._kernels.shooting.is_stable`: the largest |eigenvalue|,
    the tangential motion's Floquet multiplier, ≤ 1 + ``STABILITY_TOL``); a Jacobian with a
    non-finite entry is not. (One 3 × 3 eigenvalue call, ~10 µs, a point: nothing beside the
    period maps of its Newton steps.)"""
    jac = np.asarray(jac, dtype=float)
    if not np.all(np.isfinite(jac)):
        return False
    return is_stable(np.max(np.abs(np.linalg.eigvals(jac))))


def newton_steady(rec, par, tpar, rtol, scale, warm: WarmStart, z0, mode, sigma, tol: float = NEWTON_TOL):
    """The fixed point of the period map from ``z0`` in ``mode`` (σ ``sigma``), to the relative
    distance ``tol`` of z and P(z): Newton steps with ``warm``'s Jacobian (else one by finite
    differences), improved by Broyden's update after each step and recomputed where a step does
    not halve the residual (compiled: :func:`contactvib._kernels.friction_newton.newton_period_map`).

    A fixed point whose Jacobian (by finite differences where Broyden's estimate says so) fails
    the package's stability rule (:func:`stable_fixed_point`) is unstable, not a steady state:
    None.

    Returns
    -------
    None, or (z*, mode, σ, jac, run, runs)
        ``run`` = (P(z*) with its quadratures, mode and σ after it, times, w range) of the period
        from the fixed point (the steady period); ``runs`` the period maps computed.
    """
    from contactvib._kernels import friction_newton as kn

    has = warm.jac is not None
    jac = warm.jac.copy() if has else np.zeros((3, 3))
    out, z, mode, sigma, has, pz, m1, s1, times, wr, runs = kn.newton_period_map(
        rec, par, tpar, float(rtol), scale, np.asarray(z0, float), int(mode), float(sigma), jac, has, float(tol),
        MAX_STEPS, FD_STEP)
    if out != kn.NEWTON_CONVERGED:
        return None
    if not has or not stable_fixed_point(jac):  # unstable? Broyden's estimate is rough: recompute
        if kn.fd_jacobian(rec, par, tpar, float(rtol), scale, z, mode, sigma, pz, FD_STEP, jac) != STATUS_OK:
            return None
        runs += 3
        if not stable_fixed_point(jac):
            return None  # an unstable steady state: not what the slider does
    return z, mode, sigma, jac, (pz, m1, s1, times, wr), runs
