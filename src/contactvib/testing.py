"""The public reference solver: the contact oscillator in scipy, independent of contactvib's
kernels (the package's ``numpy.testing``), for checking results against.

The contact oscillator integrated with :func:`scipy.integrate.solve_ivp` (DOP853), mode by mode,
switching the right-hand side at every located crossing of y = 0 (terminal events). Nothing
here imports the package's kernels or derived scales: only a model's parameters are read, so the
results are a reference written independently of the code under test. A public module of the
API (documented with it): contactvib's own tests, the scripts that made their stored reference
data (``tests/data/make_reference.py``, ``tests/data/make_fit_reference.py``) and the scipy rows
of ``benchmarks/`` use it, and so can a user who wants to check a result or a new contact law.

* :func:`integrate_modes`: any pair of right-hand sides (contact, flight) in any units, with
  extra events, dense output and counters — the one switching loop.
* :func:`power_law_rhs`, :func:`scipy_in_contact`: the paper's nondimensional equation.
* :class:`ContactODE`, :func:`model_ode`, :func:`integrate_contact`: any contact law under any
  forcing, in SI, with the turning points, the impulse and the Liouville integral.
* :func:`integrate_system`: a structure of n coordinates with m contacts (``contactvib.model.System``),
  in SI, mode by mode with an event on every contact.

A grazing switch (contact left or entered with ẏ ≈ 0) puts the root of the new mode's event at
its own start; the new mode is then started again a hair (``graze``) on its own side of y = 0,
so that its event finds the next crossing, not the start.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["ContactODE", "ModeTrajectory", "Trajectory", "benettin_reference", "initial_mode", "integrate_contact",
           "integrate_modes", "integrate_system", "model_ode", "power_law_rhs", "power_law_variational_rhs",
           "scipy_in_contact"]

#: consecutive zero-length segments after which :func:`integrate_modes` gives up (a trajectory
#: held on y = 0 by opposing fields, which two modes switched at y = 0 cannot represent)
MAX_GRAZING_RETRIES = 4
#: a run of more than MAX_SHORT_SEGMENTS consecutive switches, each after less than MIN_SEGMENT of
#: the time span, is chattering (a motion held on y = 0, or a Zeno sequence of impacts): refused
MAX_SHORT_SEGMENTS = 50
MIN_SEGMENT = 1e-7


def initial_mode(y, v) -> bool:
    """Contact for y > 0, or y = 0 moving into the contact (the kernels' convention)."""
    return bool(y > 0.0 or (y == 0.0 and v > 0.0))


def _crossing(direction):
    def event(t, s):
        return s[0]

    event.terminal, event.direction = True, direction
    return event


@dataclass
class ModeTrajectory:
    """The result of :func:`integrate_modes`.

    Attributes
    ----------
    y : ndarray
        End state.
    contact : bool
        Mode at the end.
    segments : list of (mode, (t_start, t_end), OdeSolution or None)
        The smooth segments (mode True: contact); the dense output with ``dense_output=True``.
    ends : list of ndarray
        The state at the end of each segment (before a switch puts it on y = 0).
    steps : list of ndarray
        The solver's step times in each segment.
    events : list of list of (t, state, mode)
        The roots of each extra event, in time order, with the mode they were found in.
    nfev, n_switches : int
        Right-hand side evaluations, contact/flight switches located.
    """

    y: np.ndarray
    contact: bool
    segments: list = field(default_factory=list)
    ends: list = field(default_factory=list)
    steps: list = field(default_factory=list)
    events: list = field(default_factory=list)
    nfev: int = 0
    n_switches: int = 0


def integrate_modes(f_contact, f_flight, y0, t0, t1, *, contact=None, rtol=1e-12, atol=1e-12, events=(),
                    dense_output=False, graze=1e-15, **options):
    """Integrate ``s' = f(t, s)`` from ``y0`` at ``t0`` to ``t1``, with ``f = f_contact`` while
    s[0] > 0 and ``f_flight`` while s[0] < 0, switching at every located crossing of s[0] = 0.

    Parameters
    ----------
    f_contact, f_flight : callable (t, s) -> sequence
        Right-hand sides; ``s[0]`` is the deflection, any further components are carried along.
    y0 : array_like
        Initial state.
    t0, t1 : float
        Time span.
    contact : bool, optional
        Initial mode; by default :func:`initial_mode` of ``y0[0], y0[1]``.
    rtol, atol : float or array_like
        solve_ivp tolerances.
    events : sequence of callable
        Extra non-terminal events, recorded in the ``events`` of the :class:`ModeTrajectory`.
    dense_output : bool
        Keep each segment's dense output.
    graze : float
        Offset of s[0] from 0 (on the mode's own side) with which a mode whose event fires at its
        own start is started again: a grazing switch.
    **options
        Further options of :func:`scipy.integrate.solve_ivp` (``method``, default ``"DOP853"``;
        ``max_step``, ...).

    Returns
    -------
    ModeTrajectory
    """
    from scipy.integrate import solve_ivp

    leave, land = _crossing(-1.0), _crossing(1.0)
    options.setdefault("method", "DOP853")
    s = np.array(y0, float)
    tr = ModeTrajectory(s, initial_mode(s[0], s[1]) if contact is None else bool(contact),
                        events=[[] for _ in events])
    t, stuck, short = float(t0), 0, 0
    tiny = MIN_SEGMENT * abs(t1 - t0)
    while t < t1:
        fun = f_contact if tr.contact else f_flight
        sol = solve_ivp(fun, (t, t1), s, rtol=rtol, atol=atol, events=(leave if tr.contact else land, *events),
                        dense_output=dense_output, **options)
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        tr.nfev += sol.nfev
        t_end = float(sol.t[-1])
        if sol.status == 1 and t_end <= t + 4.0 * np.finfo(float).eps * max(abs(t), 1.0):
            stuck += 1  # the event's root is the start itself: start again a hair inside the mode
            if stuck > MAX_GRAZING_RETRIES:
                raise RuntimeError(f"trajectory held on y = 0 at t = {t!r}: no mode can be followed")
            s[0] = graze * 10.0 ** (stuck - 1) * (1.0 if tr.contact else -1.0)
            continue
        stuck = 0
        short = short + 1 if (sol.status == 1 and t_end - t <= tiny) else 0
        if short > MAX_SHORT_SEGMENTS:  # chattering: switched back at once, again and again (Zeno)
            raise RuntimeError(f"trajectory held on y = 0 at t = {t_end!r}: {short} switches within "
                               f"{MIN_SEGMENT:g} of the span each")
        for rec, te, se in zip(tr.events, sol.t_events[1:], sol.y_events[1:]):
            se = np.reshape(se, (len(te), s.size))
            rec.extend((float(a), np.array(b, float), tr.contact) for a, b in zip(te, se))
        tr.segments.append((tr.contact, (t, t_end), sol.sol))
        tr.steps.append(sol.t.copy())
        t, s = t_end, sol.y[:, -1].copy()
        tr.ends.append(s.copy())
        if sol.status == 1 and t < t1:  # a contact event: switch the mode, exactly on y = 0
            s[0] = 0.0
            tr.contact = not tr.contact
            tr.n_switches += 1
    tr.y = s
    return tr


def _odd_power(x, a):
    """x^a, continued oddly below 0 (−|x|^a); x^0 = 1."""
    if a == 0.0:
        return 1.0
    return math.copysign(abs(x) ** a, x)


def power_law_rhs(par):
    """The paper's nondimensional right-hand sides (contact, flight) for ``par = (m2, l, c, p, r)``::

        x'' = [1 − x^m2 − c x^l x' + p cos(r τ)] / m2     contact (x > 0)
        x'' = [1 + p cos(r τ)] / m2                       flight  (x ≤ 0)

    The contact side is continued below x = 0 as sign(x)|x|^a (only the overshoot of a trial step
    before a located exit ever sees it)."""
    m2, l, c, p, r = (float(v) for v in par)

    def contact(t, y):
        x, v = y
        return [v, (1.0 - _odd_power(x, m2) - c * _odd_power(x, l) * v + p * math.cos(r * t)) / m2]

    def flight(t, y):
        return [y[1], (1.0 + p * math.cos(r * t)) / m2]

    return contact, flight


def scipy_in_contact(par, z0, t_end, rtol=1e-12):
    """End state of the paper's contact-mode equation (:func:`power_law_rhs`) from ``z0`` at τ = 0
    to ``t_end``; asserts that contact is kept (x > 0.1)."""
    from scipy.integrate import solve_ivp

    f, _ = power_law_rhs(par)
    sol = solve_ivp(f, (0.0, t_end), np.asarray(z0, float), method="DOP853", rtol=rtol, atol=rtol)
    assert sol.success and np.min(sol.y[0]) > 0.1  # contact is kept throughout
    return sol.y[:, -1]


# ------------------------------------------------------------------------------------------------
# Any contact law and any forcing, in SI (only the model's parameters are read).


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
    """Integrate :class:`ContactODE` from (y0, v0) at ``t0`` to ``t1`` (SI) with
    :func:`integrate_modes`; ``y_scale`` [m] and ``v_scale`` [m/s] set the absolute tolerances (and
    ``1e-8 y_scale`` the grazing offset)."""
    M, W = ode.M, ode.W
    F_scale = max(W, 1e-300)
    atol = rtol * np.array([y_scale, v_scale, F_scale * (t1 - t0), 1e-300 + M])

    def rhs_contact(t, s):
        fc = ode.contact_force(s[0], s[1])
        return [s[1], (W + ode.forcing(t) - fc) / M, fc, ode.damping_rate(s[0])]

    def rhs_flight(t, s):
        return [s[1], (W + ode.forcing(t)) / M, 0.0, 0.0]

    def turn(t, s):
        return s[1]

    turn.terminal, turn.direction = False, 0.0
    run = integrate_modes(rhs_contact, rhs_flight, [y0, v0, 0.0, 0.0], t0, t1,
                          contact=initial_mode(y0, v0), rtol=rtol, atol=atol, method=method, events=(turn,),
                          dense_output=True, graze=1e-8 * y_scale)
    tr = Trajectory()
    tr.segments, tr.n_switches = run.segments, run.n_switches
    tr.contact_time = sum(tb - ta for mode, (ta, tb), _ in run.segments if mode)
    ys = [float(y0)] + [float(e[0]) for e in run.ends]
    tr.turns = []
    for te, se, contact in run.events[0]:
        ys.append(float(se[0]))
        tr.turns.append((te, float(se[0]), (rhs_contact if contact else rhs_flight)(te, se)[1] > 0.0))
    tr.y, tr.ydot, tr.impulse, tr.damping_integral = (float(v) for v in run.y)
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
    own PCHIP; any other registered law through its own SI :meth:`SpringLaw.contact_force
    <contactvib.model.SpringLaw.contact_force>`, never the compiled kernels; power or
    Hunt–Crossley damping; force, harmonics or base excitation). Its coordinate is the contact's
    deflection δ = y − y_e (y_e the law's engagement point, 0 but for a clearance).

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
    elif m.law != "table":
        law, S = m.spring_law, m.S

        def spring(y):
            return law.contact_force(y, S)
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


def power_law_variational_rhs(par):
    """The paper's nondimensional right-hand sides (contact, flight) of the state (x, x'), the
    variational equation Φ' = J Φ (Φ row-major) and ∫ tr J dτ, ``par = (m2, l, c, p, r)``, l ≥ 1 (no
    saltation): J = [[0, 1], [−(m2 x^(m2−1) + c l x^(l−1) x')/m2, −c x^l/m2]] in contact, [[0, 1], [0, 0]]
    in flight."""
    m2, l, c, p, r = (float(v) for v in par)
    contact_state, flight_state = power_law_rhs(par)

    def contact(t, s):
        x, v = s[0], s[1]
        xp = max(x, 0.0)
        j21 = -(m2 * xp ** (m2 - 1.0) + c * l * xp ** (l - 1.0) * v) / m2
        j22 = -c * xp ** l / m2
        return [*contact_state(t, s[:2]), s[4], s[5], j21 * s[2] + j22 * s[4], j21 * s[3] + j22 * s[5], j22]

    def flight(t, s):
        return [*flight_state(t, s[:2]), s[4], s[5], 0.0, 0.0, 0.0]

    return contact, flight


def benettin_reference(par, z0, n_periods: int, rtol: float = 1e-10):
    """Benettin's QR method on the paper's period map with scipy (:func:`integrate_modes`, DOP853,
    located switches), the reference of ``contactvib.steady.lyapunov``: each period from Φ = I,
    the frame advanced by Gram–Schmidt of M_j Q_j. Returns ``(logr, trace, z)``: ln R_j[i, i] of
    each period (n_periods, 2) [1], ∫ tr J dτ over each period [1], the state after ``n_periods``.
    """
    f_contact, f_flight = power_law_variational_rhs(par)
    T = 2.0 * math.pi / float(par[4])
    z = np.array(z0, float)
    Q = np.eye(2)
    logr, trace = np.zeros((n_periods, 2)), np.zeros(n_periods)
    for j in range(n_periods):
        s = np.concatenate([z, [1.0, 0.0, 0.0, 1.0, 0.0]])
        tr = integrate_modes(f_contact, f_flight, s, 0.0, T, rtol=rtol, atol=rtol)
        z, M = tr.y[:2].copy(), tr.y[2:6].reshape(2, 2)
        Q, R = np.linalg.qr(M @ Q)
        sign = np.sign(np.diag(R))
        Q, R = Q * sign, (R.T * sign).T
        logr[j] = np.log(np.diag(R))
        trace[j] = tr.y[6]
    return logr, trace, z



# ------------------------------------------------------------------ structures of n coordinates
def _system_element(c):
    """(spring(δ), rate(δ)) of a contact in contact, SI, continued below δ = 0."""
    law, S = c.law, c.S
    if getattr(law, "name", None) == "power":
        Sc, m2 = S * law.c_n, law.m2

        def spring(d):
            return Sc * _power(d, m2)
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
            return Sh * _power(d, l)
    return spring, rate


def integrate_system(system, pa_newton, fe_hz, z0, t1, rtol=1e-11, atol_q=None, max_switches=10_000, t0=0.0,
                     liouville=True):
    """A structure (``contactvib.model.System``) under P_a cos(2π f_e t), integrated by
    ``solve_ivp`` (DOP853) mode by mode from z0 = (q, q̇) [SI] at t = ``t0`` to ``t1`` [s]:

        M q̈ + C q̇ + K q = f0 + b P_a cos(2π f_e t) − Σ_i [δ_i > 0] w_i F_i(δ_i, δ̇_i)

    with a terminal event on every contact's δ_i = w_i·q − e_i, restarting in the new mode. Only
    the system's SI fields are read: the power spring S c_n δ^m2 written here, any other law
    through its own SI ``contact_force``; damping S h_n δ^l δ̇ or α F_s δ̇ (Hunt–Crossley).
    ``rtol``: solve_ivp's; ``atol_q``: of q [m or rad] (default 1e-12), of q̇ times 2π f_e;
    ``liouville``: also integrate ∫ trace(M⁻¹ C(t)) dt, C(t) = C + Σ_i c_d,i w_i w_iᵀ over the
    contacts in contact (``ln |det Φ|`` = −that).

    Returns ``(z, liouville, n_switches)``: the end state (2n,), that integral [1] (nan without
    it) and the contact switches located.
    """
    from scipy.integrate import solve_ivp

    n = system.n
    Minv = np.linalg.inv(np.asarray(system.M))
    K, C, f0, b = (np.asarray(a, float) for a in (system.K, system.C, system.f0, system.b))
    W = [np.asarray(c.direction, float) for c in system.contacts]
    e = [c.gap + c.law.engagement_m for c in system.contacts]
    laws = [_system_element(c) for c in system.contacts]
    om = 2.0 * math.pi * fe_hz

    def make_rhs(mode):
        def rhs(t, s):
            q, v = s[:n], s[n:2 * n]
            f = f0 + b * pa_newton * math.cos(om * t) - C @ v - K @ q
            Ceff = np.array(C) if liouville else None
            for i, on in enumerate(mode):
                if on:
                    d, dd = W[i] @ q - e[i], W[i] @ v
                    spring, rate = laws[i]
                    cd = rate(d)
                    f = f - W[i] * (spring(d) + cd * dd)
                    if liouville:
                        Ceff = Ceff + cd * np.outer(W[i], W[i])
            if not liouville:
                return np.concatenate([v, Minv @ f])
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
    s = np.concatenate([z0, [0.0]]) if liouville else z0.copy()
    mode = [bool(w @ z0[:n] - ei > 0.0 or (w @ z0[:n] - ei == 0.0 and w @ z0[n:] > 0.0)) for w, ei in zip(W, e)]
    scale_q = np.full(n, 1e-12) if atol_q is None else np.broadcast_to(np.asarray(atol_q, float), (n,))
    atol = np.concatenate([scale_q, scale_q * om, [1e-14]] if liouville else [scale_q, scale_q * om])
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
    return s[:2 * n], (float(s[2 * n]) if liouville else math.nan), switches
