"""Independent references for the tests: scipy DOP853 on the contact-mode equation alone
(:func:`scipy_in_contact`, nondimensional power law), and any contact law under any forcing in SI
with located contact events (:class:`ContactODE`, :func:`integrate_contact`, :func:`model_ode`)."""
import math

import numpy as np


def scipy_in_contact(par, z0, t_end, rtol=1e-12):
    """End state of x'' = [1 − x^m2 − c x^l x' + p cos rτ]/m2 from ``z0`` at τ = 0 to ``t_end``,
    written here independently of the kernels; asserts that contact is kept (x > 0.1)."""
    from scipy.integrate import solve_ivp

    m2, l, c, p, r = (float(v) for v in par)

    def f(t, y):
        return [y[1], (1.0 - y[0] ** m2 - c * y[0] ** l * y[1] + p * math.cos(r * t)) / m2]

    sol = solve_ivp(f, (0.0, t_end), np.asarray(z0, float), method="DOP853", rtol=rtol, atol=rtol)
    assert sol.success and np.min(sol.y[0]) > 0.1  # contact is kept throughout
    return sol.y[:, -1]


# ------------------------------------------------------------------------------------------------
# Any contact law and any forcing, in SI, with located contact events (written independently of
# the package: only the model's parameters are read, never its kernels or derived scales).


class ContactODE:
    """``M ÿ = W + e(t) − F_c(y, ẏ) [y > 0]`` in SI units.

    Parameters
    ----------
    M : float
        Mass [kg].
    W : float
        Constant force along y [N] (weight plus preload), acting in contact and in flight.
    contact_force : callable (y, ydot) -> float
        F_c = F_s(y) + F_d(y, ẏ) [N], used only while y > 0.
    forcing : callable t -> float
        e(t) [N].
    damping_rate : callable y -> float, optional
        c_d(y) = ∂F_c/∂ẏ [N s/m] in contact (for the Liouville integral ∫ c_d dt).
    """

    def __init__(self, M, W, contact_force, forcing, damping_rate=None):
        self.M = float(M)
        self.W = float(W)
        self.contact_force = contact_force
        self.forcing = forcing
        self.damping_rate = damping_rate or (lambda y: 0.0)


class Trajectory:
    """The result of :func:`integrate_contact`.

    Attributes
    ----------
    y, ydot : float
        End state [m], [m/s].
    ymin, ymax : float
        Extrema of y over the span [m]: the turning points (ẏ = 0, located as events) and the ends.
    turns : list of (t, y, is_min)
        The turning points [s], [m], a minimum where ÿ > 0.
    impulse : float
        ∫ F_c dt over the span, contact only [N s].
    damping_integral : float
        ∫ c_d(y) dt over the span, contact only [kg]: divided by M, minus the logarithm of the
        determinant of the flow's Jacobian (Liouville's formula).
    contact_time : float
        Time spent with y > 0 [s].
    n_switches : int
        Contact/flight switches located.
    segments : list of (mode, (t_start, t_end), OdeSolution)
        Dense output of each smooth segment (mode True: contact).
    """

    def sample(self, t):
        """y(t) and ẏ(t) [SI] at sorted times ``t`` inside the span, from the dense outputs."""
        t = np.asarray(t, float)
        out = np.empty((2, t.size))
        for j, tj in enumerate(t):
            for _mode, (ta, tb), sol in self.segments:
                if ta <= tj <= tb:
                    out[:, j] = sol(tj)[:2]
                    break
            else:
                raise ValueError(f"t = {tj} outside the integrated span")
        return out


def integrate_contact(ode, y0, v0, t0, t1, rtol=1e-11, method="DOP853", y_scale=1e-7, v_scale=1e-3):
    """Integrate :class:`ContactODE` from (y0, v0) at ``t0`` to ``t1`` (SI), switching the
    right-hand side at every located crossing of y = 0 (terminal events of solve_ivp)."""
    from scipy.integrate import solve_ivp

    M, W = ode.M, ode.W
    F_scale = max(W, 1e-300)
    atol = rtol * np.array([y_scale, v_scale, F_scale * (t1 - t0), 1e-300 + M])

    def rhs_contact(t, s):
        fc = ode.contact_force(s[0], s[1])
        return [s[1], (W + ode.forcing(t) - fc) / M, fc, ode.damping_rate(s[0])]

    def rhs_flight(t, s):
        return [s[1], (W + ode.forcing(t)) / M, 0.0, 0.0]

    def hit(t, s):
        return s[0]

    def turn(t, s):
        return s[1]

    leave, land = (lambda t, s: hit(t, s)), (lambda t, s: hit(t, s))
    leave.terminal, leave.direction = True, -1.0
    land.terminal, land.direction = True, 1.0
    turn.terminal, turn.direction = False, 0.0

    tr = Trajectory()
    tr.segments, tr.turns, tr.n_switches, tr.contact_time = [], [], 0, 0.0
    s = np.array([y0, v0, 0.0, 0.0], float)
    ys = [float(y0)]
    contact = y0 > 0.0 or (y0 == 0.0 and v0 > 0.0)
    t = float(t0)
    while t < t1:
        fun, ev = (rhs_contact, leave) if contact else (rhs_flight, land)
        sol = solve_ivp(fun, (t, t1), s, method=method, rtol=rtol, atol=atol, events=(ev, turn),
                        dense_output=True)
        assert sol.status >= 0, sol.message
        for te, se in zip(sol.t_events[1], np.reshape(sol.y_events[1], (-1, 4))):
            ys.append(float(se[0]))
            tr.turns.append((float(te), float(se[0]), fun(te, se)[1] > 0.0))
        tr.segments.append((contact, (t, float(sol.t[-1])), sol.sol))
        if contact:
            tr.contact_time += float(sol.t[-1]) - t
        t = float(sol.t[-1])
        s = sol.y[:, -1].copy()
        ys.append(float(s[0]))
        if sol.status == 1 and t < t1:  # a contact event: switch the mode, exactly on y = 0
            s[0] = 0.0
            contact = not contact
            tr.n_switches += 1
    tr.y, tr.ydot, tr.impulse, tr.damping_integral = (float(v) for v in s)
    tr.ymin, tr.ymax = min(ys), max(ys)
    return tr


def _power(y, a):
    """y^a, continued analytically below 0 for an integer a, else oddly (−|y|^a)."""
    if a == int(a):
        return y ** int(a)
    return y**a if y >= 0.0 else -((-y) ** a)


def model_ode(model, excitation):
    """The :class:`ContactODE` of a ``contactvib`` model and excitation, built from their SI
    parameters alone (the law's formulas written here: power, exponential, table through scipy's
    own PCHIP; power or Hunt–Crossley damping; force, harmonics or base excitation).

    The contact mode's right-hand side is continued smoothly a little below y = 0, where the last
    step before a located exit samples it: analytically (integer powers, the exponential, the
    table's first cubic), oddly for other powers."""
    from scipy.interpolate import PchipInterpolator

    m = model
    W = m.M * m.g + m.preload
    if m.law == "power":
        Sc, m2 = m.S * m.c_n, m.m2

        def spring(y):
            return Sc * _power(y, m2)
    elif m.law == "exponential":
        Sc, lam = m.S * m.c_e, m.lam

        def spring(y):
            return Sc * math.expm1(y / lam)
    else:
        d, F = np.asarray(m.table.deflection_m, float), np.asarray(m.table.load_n, float)
        pchip = PchipInterpolator(d, F, extrapolate=True)  # the first cubic continued below 0
        slope_end = float(pchip.derivative()(d[-1]))

        def spring(y):
            return float(pchip(y)) if y <= d[-1] else F[-1] + slope_end * (y - d[-1])
    if m.damping == "power":
        Sh, l = m.S * m.h_n, m.l

        def rate(y):
            return Sh * _power(y, l)
    else:
        alpha = m.alpha

        def rate(y):
            return alpha * spring(y)
    w = 2.0 * math.pi * excitation.f_e
    if excitation.base_um is not None:
        amp, terms = m.M * excitation.base_um * 1e-6 * w * w, ()
    elif excitation.base_g is not None:
        amp, terms = m.M * excitation.base_g * 9.80665, ()
    else:
        Q = m.M * m.g
        amp = excitation.pa_over_q * Q
        terms = tuple((k * w, a * Q, math.radians(ph)) for k, a, ph in excitation.harmonics)

    def forcing(t):
        return amp * math.cos(w * t) + sum(a * math.cos(wk * t + ph) for wk, a, ph in terms)

    return ContactODE(m.M, W, lambda y, v: spring(y) + rate(y) * v, forcing, rate)
