"""Tangential (friction) motion of the slider under the normal contact force of a recorded orbit
(compiled, pure).

Nondimensional, in the normal problem's units (length y0, force W = Q + F_pre, time τ = ω_n0 t,
κ = k y0 / W the nondimensional mass, ``par[0]``), with w = (u − v_d t)/y0 the slider's
tangential displacement behind the drive's end moving at v_d::

    κ w'' = f_T − k_d w − c_d w' − f_t

(the velocity drive: f_T = 0; a constant tangential force f_T: k_d = v_d = 0, w = u/y0, the
damper c_d to the ground)

where f_t is the tangential force of the contact, a Jenkins element: a spring k_t(τ) in series
with a Coulomb slip element of limit l(τ) = μ (r⁺)^β, r = R/W the normal contact force of the
normal orbit (β = 1: Coulomb, μ r⁺; β < 1: Hess & Soom's real-area law)::

    stick (|f_t| ≤ l):  f_t' = k_t(τ) (w' + v_d)          (the slip point at rest; Mindlin's
                                                           incremental form dF = k_t dδ)
    slip  (σ = ±1):     f_t = σ l(τ)                       while σ k_t (w' + v_d) > l'
    free  (r ≤ 0):      f_t = 0                            (flight, or the damper pulling: the
                                                           spring relaxes, the slip point follows)

k_t = kt_ratio · df_s/dx (x(τ)) (following the normal contact) or kt_ratio · κ (constant). Modes
switch at located events: stick → slip where |f_t| reaches l (σ its sign), slip → stick where
σ k_t (w' + v_d) − l' falls to 0 (the slip velocity reverses), slip → free where r falls to 0,
free → stick (f_t = 0) where r rises above 0; the normal flight steps are free.

R(τ) comes from the normal orbit's step records (``_kernels/orbit.record_orbit``: each step's
7th-order interpolant, steps ending exactly on the contact events): the normal motion does not
depend on the tangential one, so one record of one normal period K serves every tangential
period, exactly periodic, and the tangential DOP853 steps never straddle a normal step (R is
smooth inside each). The step, its error norm, the step-size controller and the dense output are
the package's (:mod:`.dop853`, as the normal flow's); the right-hand side, its stages (R at each
stage point), the modes and the events are this module's. Events are located on the tangential
step's 7th-order dense output (sign changes at five points of the step, Illinois as the normal
flow's), and the step is re-taken to end on the event.

Quadratures per period (``q``): ∫ f_drive dτ, the damper's dissipation ∫ c_d w'² dτ, the slip
element's dissipation ∫ f_t s' dτ and the work into the tangential spring ∫ f_t (u' − s') dτ
(zero over a period for a constant k_t; with k_t following the normal contact it is the work the
neglected normal-tangential coupling would exchange).

References
----------
K. L. Johnson, *Contact Mechanics*, CUP (1985), Sec. 7.4 (Mindlin's incremental compliance).
B. D. Yang, C. H. Menq, "Characterization of contact kinematics and application to the design
of wedge dampers", J. Sound Vib. 217 (1998) (Jenkins element under a variable normal load).
D. P. Hess, A. Soom, "Normal vibrations and friction under harmonic loads", J. Tribol. 113 (1991).
"""

from __future__ import annotations

from numba import njit

from .contact import contact_force, contact_partials, spring
from .dop853 import C, dense_value, error_norm, interpolant, solution, stage_state
from .flow import acceleration
from .roots import illinois_trial, illinois_update

#: Slots of the tangential parameter vector ``tpar`` (T_FT: a constant drive force [W]).
T_MU, T_BETA, T_KT, T_KT_CONSTANT, T_KD, T_CD, T_VD, T_KAPPA, T_FT = range(9)
#: Modes of the contact.
STICK, SLIP, FREE = 0, 1, 2
#: Components of the state: w, w', f_t (dynamic) and the quadratures of the period.
Z_W, Z_V, Z_F, Q_DRIVE, Q_DAMP, Q_SLIP, Q_EL = range(7)
N_STATE = 7
_N_DYN = 3
_SAMPLES = 4  # sub-intervals of a step searched for events
MAX_EVENTS_PER_STEP = 64  # events within one normal step before the run is called chattering


@njit(cache=True)
def normal_at(Fn, yn, t0, h, contact, tau, par, tpar):
    """(r, r', k_t) at τ inside a normal step: the contact force [W], its rate and the tangential
    stiffness [W/y0]; (0, 0, 0) in a flight step."""
    if not contact:
        return 0.0, 0.0, 0.0
    th = min(max((tau - t0) / h, 0.0), 1.0)
    x = dense_value(Fn, yn, th, 0)
    v = dense_value(Fn, yn, th, 1)
    if x <= 0.0:  # at the surface (a contact step's ends, to round-off): no compression
        return 0.0, 0.0, 0.0
    r = contact_force(x, v, par)
    fx, fv = contact_partials(x, v, par)
    dr = fx * v + fv * acceleration(True, tau, x, v, par)
    if tpar[T_KT_CONSTANT] != 0.0:
        kt = tpar[T_KT] * tpar[T_KAPPA]
    else:
        kt = tpar[T_KT] * spring(x, par)[1]
    return r, dr, kt


@njit(cache=True)
def limit(r, dr, tpar):
    """Slip limit l = μ (r⁺)^β [W] and its rate l' (0 where r ≤ 0)."""
    if r <= 0.0:
        return 0.0, 0.0
    mu = tpar[T_MU]
    beta = tpar[T_BETA]
    if beta == 1.0:
        return mu * r, mu * dr
    lr = mu * r ** beta
    return lr, beta * lr / r * dr


@njit(cache=True)
def rhs(mode, sigma, z, r, dr, kt, tpar, out):
    """Right-hand side of the state (w, w', f_t) and the quadratures in ``mode``."""
    lr, dl = limit(r, dr, tpar)
    du = z[Z_V] + tpar[T_VD]  # u' = w' + v_d
    el = 0.0
    ds = 0.0
    out[Z_F] = 0.0
    if mode == STICK:
        ft = z[Z_F]
        out[Z_F] = kt * du
        el = ft * du
    elif mode == SLIP:
        ft = sigma * lr
        el = lr * dl / kt if kt > 0.0 else 0.0
        ds = sigma * lr * du - el
    else:
        ft = 0.0
    fd = tpar[T_FT] - tpar[T_KD] * z[Z_W] - tpar[T_CD] * z[Z_V]
    out[Z_W] = z[Z_V]
    out[Z_V] = (fd - ft) / tpar[T_KAPPA]
    out[Q_DRIVE] = fd
    out[Q_DAMP] = tpar[T_CD] * z[Z_V] * z[Z_V]
    out[Q_SLIP] = ds
    out[Q_EL] = el


@njit(cache=True)
def _stages(mode, sigma, t, z, h, nstep, par, tpar, K, s_first, s_last):
    """DOP853 stages s_first..s_last − 1 of a step from (t, z) of size h inside the normal step
    ``nstep`` = (Fn, yn, t0, hn, contact); K[16] is the stage state's work row (no allocation
    per step). Returns (r, r', k_t) at the last stage's point."""
    Fn, yn, t0, hn, contact = nstep
    zs = K[16]
    r = dr = kt = 0.0
    for s in range(s_first, s_last):
        stage_state(K, z, h, s, N_STATE, zs)
        ts = t + C[s] * h
        r, dr, kt = normal_at(Fn, yn, t0, hn, contact, ts, par, tpar)
        rhs(mode, sigma, zs, r, dr, kt, tpar, K[s])
    return r, dr, kt


@njit(cache=True)
def rk_step(mode, sigma, t, z, h, nstep, par, tpar, rtol, atol, K, znew):
    """One DOP853 step (:mod:`.dop853`; K[0] must hold f(t, z); K has 17 rows, the last a work
    row); fills K[0..12] and ``znew``; returns the error norm of the dynamic components w, w',
    f_t (absolute tolerances ``atol``: float64[3]; < 1: accept) and (r, r', k_t) at t + h
    (stage 11's: c₁₁ = 1)."""
    re, dre, kte = _stages(mode, sigma, t, z, h, nstep, par, tpar, K, 1, 12)
    solution(K, z, h, N_STATE, znew)
    rhs(mode, sigma, znew, re, dre, kte, tpar, K[12])
    return error_norm(K, z, znew, h, _N_DYN, atol, rtol), re, dre, kte


@njit(cache=True)
def dense(mode, sigma, t, z, znew, h, nstep, par, tpar, K, F):
    """F[7, 3]: the 7th-order interpolant of w, w', f_t over the last step (K from rk_step)."""
    _stages(mode, sigma, t, z, h, nstep, par, tpar, K, 13, 16)
    interpolant(K, z, znew, h, _N_DYN, F)


@njit(cache=True)
def _event_g(mode, sigma, which, w_v, f, r, dr, kt, tpar):
    """Event function ``which`` (0, 1) of ``mode``: an event where it passes from > 0 to ≤ 0
    (free: from ≥ 0 to < 0). stick: l − f, l + f; slip: σ k_t u' − l', r; free: −r."""
    lr, dl = limit(r, dr, tpar)
    if mode == STICK:
        return lr - f if which == 0 else lr + f
    if mode == SLIP:
        if which == 0:
            return sigma * kt * (w_v + tpar[T_VD]) - dl
        return r
    return -r


@njit(cache=True)
def _outside(mode, g):
    return g < 0.0 if mode == FREE else g <= 0.0


@njit(cache=True)
def _g_at(mode, sigma, which, F, z, th, t, h, nstep, par, tpar):
    Fn, yn, t0, hn, contact = nstep
    r, dr, kt = normal_at(Fn, yn, t0, hn, contact, t + th * h, par, tpar)
    return _event_g(mode, sigma, which, dense_value(F, z, th, Z_V), dense_value(F, z, th, Z_F),
                    r, dr, kt, tpar)


@njit(cache=True)
def find_event(mode, sigma, F, z, t, h, nstep, par, tpar, G, ends):
    """The first event inside the last step: (which, θ) or (−1, 1.0). The event functions are
    sampled at θ = 0, 1/4, …, 1 (``G``: float64[2, 5], work), the normal force and the
    interpolant evaluated once a point for both (``ends``: float64[6], (r, r', k_t) at t and at t + h, known);
    none in a flight step (r ≡ 0: no event)."""
    if not nstep[4]:
        return -1, 1.0
    n_ev = 1 if mode == FREE else 2
    Fn, yn, t0, hn, contact = nstep
    for s in range(_SAMPLES + 1):
        th = s / _SAMPLES
        if s == 0 or s == _SAMPLES:
            q = 0 if s == 0 else 3
            r, dr, kt = ends[q], ends[q + 1], ends[q + 2]
        else:
            r, dr, kt = normal_at(Fn, yn, t0, hn, contact, t + th * h, par, tpar)
        w_v = dense_value(F, z, th, Z_V)
        f = dense_value(F, z, th, Z_F)
        for which in range(n_ev):
            G[which, s] = _event_g(mode, sigma, which, w_v, f, r, dr, kt, tpar)
    best = 1.0
    found = -1
    for which in range(n_ev):
        ga = G[which, 0]
        a = 0.0
        for s in range(1, _SAMPLES + 1):
            b = s / _SAMPLES
            if a >= best:
                break
            gb = G[which, s]
            if not _outside(mode, ga) and _outside(mode, gb):
                th = _root(mode, sigma, which, F, z, a, b, ga, gb, t, h, nstep, par, tpar)
                if th < best or found < 0:
                    best = th
                    found = which
                break
            a = b
            ga = gb
    return found, best


@njit(cache=True)
def _root(mode, sigma, which, F, z, a, b, ga, gb, t, h, nstep, par, tpar):
    """Bisection-safeguarded secant (Illinois) root of the event function on [a, b]; returns
    the right end of the final bracket (the outside side), so that the event has happened."""
    side = 0
    for _ in range(200):
        if b - a < 1e-15:
            break
        c = illinois_trial(a, b, ga, gb)  # ga is inside, gb outside: never equal
        gc = _g_at(mode, sigma, which, F, z, c, t, h, nstep, par, tpar)
        if gc == 0.0:  # on the surface: outside or not as the mode says (free: not yet)
            if _outside(mode, gc):
                b = c
            break
        # a nonzero gc is outside exactly where it has gb's sign
        a, b, ga, gb, side = illinois_update(a, b, ga, gb, c, gc, side)
    return b
