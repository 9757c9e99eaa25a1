"""An independent reference of the friction analysis: scipy's DOP853 on the normal and tangential
motion together, in SI, with the contact and the stick/slip switches located as terminal events.

Written from the model's equations alone (power-law spring and damping, preload, harmonic force;
the package's kernels, records and scalings are not used)::

    M ÿ = W + P_a cos ωt − R,   R = S c_n y^m2 + S h_n y^l ẏ  (y > 0), 0 in flight
    M ẅ = −k_d w − c_d ẇ − F_t,  w = u − v_d t
    stick: Ḟ_t = k_t (ẇ + v_d);  slip: F_t = σ L;  free (R ≤ 0): F_t = 0
    L = μ W (R⁺/W)^β,  k_t = kt_ratio dF_s/dy (y) (or at y0)

The slip ends where σ k_t (ẇ + v_d) − dL/dt falls to 0, dL/dt from dR/dt = ∂R/∂y ẏ + ∂R/∂ẏ ÿ;
a touchdown starts a stick with F_t = 0; R's own zeros inside the contact are events (of R/y
where R is rising, so that the separation's R → 0 is not one). Power laws with m2, l ≥ 1.
"""

import math

import numpy as np
from scipy.integrate import solve_ivp

STICK, SLIP, FREE = "stick", "slip", "free"


class FrictionODE:
    """The coupled system for a power-law ContactModel ``m`` (any preload), force P_a [N] at f_e
    [Hz], and tangential parameters (μ, kt_ratio, kt_law, k_d, c_d, v_d [m/s], β)."""

    def __init__(self, m, P_a, f_e, mu, kt_ratio, kt_law, kd, cd, vd, beta):
        self.M, self.W = m.M, m.M * m.g + m.preload
        self.Sc, self.m2, self.Sh, self.l = m.S * m.c_n, m.m2, m.S * m.h_n, m.l
        self.P, self.w = P_a, 2.0 * math.pi * f_e
        self.mu, self.ktr, self.kd, self.cd, self.vd, self.beta = mu, kt_ratio, kd, cd, vd, beta
        y0 = (self.W / self.Sc) ** (1.0 / self.m2)
        self.kt_const = kt_ratio * self.Sc * self.m2 * y0 ** (self.m2 - 1.0) if kt_law == "constant" else None

    def normal(self, t, y, v, contact):
        """(ÿ, R, dR/dt, k_t)."""
        f = self.W + self.P * math.cos(self.w * t)
        if not contact:
            return f / self.M, 0.0, 0.0, 0.0
        R = self.Sc * y ** self.m2 + self.Sh * y ** self.l * v
        a = (f - R) / self.M  # continued below y = 0 for the step that overshoots a separation
        if y <= 0.0:  # ... but no friction there: its root would hide a stick/slip event
            return a, 0.0, 0.0, 0.0
        dRdy = self.Sc * self.m2 * y ** (self.m2 - 1.0) + self.Sh * self.l * y ** (self.l - 1.0) * v
        dR = dRdy * v + self.Sh * y ** self.l * a
        kt = self.kt_const if self.kt_const is not None else self.ktr * self.Sc * self.m2 * y ** (self.m2 - 1.0)
        return a, R, dR, kt

    def limit(self, R, dR):
        if R <= 0.0:
            return 0.0, 0.0
        L = self.mu * self.W * (R / self.W) ** self.beta
        return L, self.beta * L / R * dR

    def rhs(self, t, s, contact, mode, sigma):
        y, v, w, wd, F = s[:5]
        a, R, dR, kt = self.normal(t, y, v, contact)
        L, _dL = self.limit(R, dR)
        ft = F if mode == STICK else (sigma * L if mode == SLIP else 0.0)
        fd = -self.kd * w - self.cd * wd
        dF = kt * (wd + self.vd) if mode == STICK else 0.0
        return [v, a, wd, (fd - ft) / self.M, dF, fd]

    def events(self, contact, mode, sigma, t_start):
        """Terminal events of the segment from ``t_start``. A stick or slip event function that
        starts the segment at 0 (F_t = L = 0 at a touchdown, or on the limit after a switch) is
        taken as just inside there, so that its root is the next crossing, not the start."""
        evs = []

        def gap(t, s):
            return s[0]
        gap.terminal, gap.direction = True, (-1.0 if contact else 1.0)
        evs.append(gap)
        if not contact:
            return evs

        def lim(t, s, sign):
            a, R, dR, kt = self.normal(t, s[0], s[1], True)
            L, dL = self.limit(R, dR)
            g = L - sign * s[4]
            return 1e-300 if (g == 0.0 and t == t_start) else g

        def stop(t, s):
            a, R, dR, kt = self.normal(t, s[0], s[1], True)
            L, dL = self.limit(R, dR)
            g = sigma * kt * (s[3] + self.vd) - dL
            return 1e-300 if (g <= 0.0 and t == t_start) else g

        def force(t, s):
            return self.normal(t, s[0], s[1], True)[1]

        def force_per_y(t, s):  # R/y: its zero is R's inside the contact, not the separation's y = 0
            return self.Sc * s[0] ** (self.m2 - 1.0) + self.Sh * s[0] ** (self.l - 1.0) * s[1]

        if mode == STICK:
            evs += [lambda t, s: lim(t, s, 1.0), lambda t, s: lim(t, s, -1.0)]
            for e in evs[1:]:
                e.terminal, e.direction = True, -1.0
        elif mode == SLIP:
            stop.terminal, stop.direction = True, -1.0
            force.terminal, force.direction = True, -1.0
            evs += [stop, force]
        else:
            force_per_y.terminal, force_per_y.direction = True, 1.0
            evs.append(force_per_y)
        return evs

    def consistent(self, t, s, contact, mode, sigma):
        """The package's documented rules, written again: free without compression, stick after
        one, a stick force beyond the limit put on it (slip if it leaves), a reversed slip sticks."""
        a, R, dR, kt = self.normal(t, s[0], s[1], contact)
        if R <= 0.0:
            s[4] = 0.0
            return FREE, sigma
        L, dL = self.limit(R, dR)
        if mode == FREE:
            s[4] = 0.0
            return STICK, sigma
        if mode == STICK:
            if abs(s[4]) > L:
                sg = 1.0 if s[4] > 0.0 else -1.0
                s[4] = sg * L
                if sg * kt * (s[3] + self.vd) - dL > 0.0:
                    return SLIP, sg
            return STICK, sigma
        s[4] = sigma * L
        return (SLIP, sigma) if sigma * kt * (s[3] + self.vd) - dL > 0.0 else (STICK, sigma)


def integrate_friction(ode, state, t1, rtol=1e-11, t_marks=()):
    """Integrate from ``state`` = (y, ẏ, w, ẇ) at t = 0 (slipping forward with F_t = L, as the
    package starts) to ``t1`` [s]; returns ∫ F_drive dt between the sorted ``t_marks`` (interpolated
    on the dense outputs) as a list, and the number of segments."""
    s = np.array([state[0], state[1], state[2], state[3], 0.0, 0.0], float)
    contact = s[0] > 0.0
    mode, sigma = (SLIP if contact else FREE), 1.0
    t = 0.0
    marks = list(t_marks)
    at_marks, n_seg, n_zero = [], 0, 0
    atol = rtol * np.array([1e-7, 1e-3, 1e-6, 1e-4, ode.W, ode.W * 1e-3])
    fresh = False  # right after a tangential switch its mode is trusted (the event's root has an error)
    while t < t1:
        if not contact:
            mode, s[4] = FREE, 0.0
        elif not fresh:
            mode, sigma = ode.consistent(t, s, contact, mode, sigma)
        fresh = False
        sol = solve_ivp(lambda tt, ss, c=contact, md=mode, sg=sigma: ode.rhs(tt, ss, c, md, sg), (t, t1), s,
                        method="DOP853",
                        rtol=rtol, atol=atol, events=ode.events(contact, mode, sigma, t), dense_output=True)
        assert sol.status >= 0, sol.message
        t_new = float(sol.t[-1])
        while marks and marks[0] <= t_new:
            at_marks.append(float(sol.sol(marks.pop(0))[5]))
        n_zero = n_zero + 1 if t_new == t else 0
        assert n_zero < 5, "no progress at a switch"
        t, s = t_new, sol.y[:, -1].copy()
        n_seg += 1
        if sol.status == 1:
            which = next(i for i, te in enumerate(sol.t_events) if len(te))
            if which == 0:  # the normal contact switches
                s[0] = 0.0
                contact = not contact
                mode, s[4], fresh = (STICK, 0.0, True) if contact else (FREE, 0.0, False)  # touchdown: F_t = 0
            else:
                mode, sigma = _switch(ode, t, s, mode, sigma, which)
                fresh = True
    return at_marks, n_seg


def _switch(ode, t, s, mode, sigma, which):
    a, R, dR, kt = ode.normal(t, s[0], s[1], True)
    L, dL = ode.limit(R, dR)
    if mode == STICK:
        sg = 1.0 if which == 1 else -1.0
        s[4] = sg * L
        return (SLIP, sg) if sg * kt * (s[3] + ode.vd) - dL > 0.0 else (STICK, sigma)
    if mode == SLIP:
        if which == 1:
            s[4] = sigma * L
            return STICK, sigma
        s[4] = 0.0
        return FREE, sigma
    s[4] = 0.0
    return STICK, sigma
