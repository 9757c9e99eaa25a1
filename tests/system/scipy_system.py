"""An independent reference for the system core: ``solve_ivp`` (DOP853) on the SI equation

    M q̈ + C q̇ + K q = f0 + b P_a cos(2π f_e t) − Σ_i [δ_i > 0] w_i F_i(δ_i, δ̇_i)

mode by mode, with a terminal event on every contact's δ_i = w_i·q − e_i (direction: leaving a
contact in contact, entering one out of it), restarting in the new mode. Only the system's SI
fields are read: the power spring's formula is written here (S c_n δ^m2, continued oddly), any
other law through its own SI ``contact_force`` (never the compiled kernels); damping S h_n δ^l δ̇
or α F_s δ̇. A last state component integrates trace(M⁻¹ C(t)), C(t) = C + Σ_i c_d,i w_i w_iᵀ
over the contacts in contact (Liouville's formula)."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from contactvib.model.laws import PowerSpring


def _odd_power(x, a):
    if a == 0.0:
        return 1.0
    return math.copysign(abs(x) ** a, x)


def _element(c):
    """(spring(δ), rate(δ)) of a contact in contact, SI, continued below δ = 0."""
    law, S = c.law, c.S
    if isinstance(law, PowerSpring):
        Sc, m2 = S * law.c_n, law.m2

        def spring(d):
            return Sc * _odd_power(d, m2)
    else:
        def spring(d):
            return law.contact_force(d, S)
    if c.damping == "hunt-crossley":
        alpha = c.alpha

        def rate(d):
            return alpha * spring(d)
    else:
        Sh, l = S * c.h_n, c.l

        def rate(d):
            return Sh * _odd_power(d, l)
    return spring, rate


def integrate_system(system, pa_newton, fe_hz, z0, t1, rtol=1e-11, atol_q=None, max_switches=10_000, t0=0.0):
    """Integrate from z0 = (q, q̇) [SI] at t = ``t0`` (default 0) to ``t1`` [s].

    Returns
    -------
    z : ndarray (2n,)
        End state.
    liouville : float
        ∫ trace(M⁻¹ C(t)) dt [1].
    n_switches : int
        Contact switches located.
    """
    n = system.n
    Minv = np.linalg.inv(np.asarray(system.M))
    K, C, f0, b = (np.asarray(a, float) for a in (system.K, system.C, system.f0, system.b))
    W = [np.asarray(c.direction, float) for c in system.contacts]
    e = [c.gap + c.law.engagement_m for c in system.contacts]
    laws = [_element(c) for c in system.contacts]
    om = 2.0 * math.pi * fe_hz

    def make_rhs(mode):
        def rhs(t, s):
            q, v = s[:n], s[n:2 * n]
            f = f0 + b * pa_newton * math.cos(om * t) - C @ v - K @ q
            Ceff = np.array(C)
            for i, on in enumerate(mode):
                if on:
                    d, dd = W[i] @ q - e[i], W[i] @ v
                    spring, rate = laws[i]
                    cd = rate(d)
                    f = f - W[i] * (spring(d) + cd * dd)
                    Ceff = Ceff + cd * np.outer(W[i], W[i])
            return np.concatenate([v, Minv @ f, [np.trace(Minv @ Ceff)]])
        return rhs

    def make_events(mode):
        evs = []
        for i, on in enumerate(mode):
            def ev(t, s, i=i):
                return W[i] @ s[:n] - e[i]
            ev.terminal, ev.direction = True, (-1.0 if on else 1.0)
            evs.append(ev)
        return evs

    z0 = np.asarray(z0, float)
    s = np.concatenate([z0, [0.0]])
    mode = [bool(w @ z0[:n] - ei > 0.0 or (w @ z0[:n] - ei == 0.0 and w @ z0[n:] > 0.0)) for w, ei in zip(W, e)]
    scale_q = np.full(n, 1e-12) if atol_q is None else np.asarray(atol_q, float)
    atol = np.concatenate([scale_q, scale_q * om, [1e-14]])
    t, switches = float(t0), 0
    while t < t1:
        sol = solve_ivp(make_rhs(mode), (t, t1), s, method="DOP853", rtol=rtol, atol=atol,
                        events=make_events(mode))
        assert sol.status >= 0, sol.message
        t, s = float(sol.t[-1]), sol.y[:, -1].copy()
        if sol.status == 1:
            hit = [i for i, te in enumerate(sol.t_events) if len(te)]
            assert len(hit) == 1, f"simultaneous switches at t = {t}"
            mode[hit[0]] = not mode[hit[0]]
            switches += 1
            assert switches < max_switches, "chattering"
    return s[:2 * n], float(s[2 * n]), switches
