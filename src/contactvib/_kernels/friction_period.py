"""The tangential motion over normal periods: mode consistency and switches, one normal step,
one normal period, settling to a periodic steady state, and samples (compiled, pure).

The equations, modes and events are those of :mod:`.friction`. A run goes through the normal
orbit's step records (one normal period K, from phase 0) period after period; its state at
phase 0 (w, w', f_t and the mode) is compared with the states of the last ``jmax`` periods: the
steady state is reached when one of them repeats to ``tol`` (scaled by the tangential scales),
and its tangential period j (in normal periods) is the smallest such lag.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .dop853 import dense_value, landing_step, next_step, step_factor
from .flow import REC_F, REC_H, REC_MODE, REC_T, REC_X, dense_root
from .friction import (
    FREE,
    MAX_EVENTS_PER_STEP,
    N_STATE,
    Q_DRIVE,
    SLIP,
    STICK,
    T_KD,
    T_VD,
    Z_F,
    Z_V,
    Z_W,
    dense,
    find_event,
    limit,
    normal_at,
    rhs,
    rk_step,
)
from .status import STATUS_INTERRUPTED, STATUS_NONFINITE, STATUS_OK, STATUS_STEP_TOO_SMALL, STATUS_TOO_MANY_EVENTS

#: Columns of a sample: w, w', f_t, slip velocity s', r, mode.
S_W, S_V, S_F, S_SLIP, S_R, S_MODE = range(6)
S_WIDTH = 6


@njit(cache=True)
def consistent(mode, sigma, z, r, dr, kt, tpar):
    """The mode at a step's start made consistent with the normal force: free where r ≤ 0; stick
    (f_t = 0) where a free contact is compressed again; a stick force beyond the limit put on it
    (slip if it would leave); a slip whose velocity has reversed sticks. Returns (mode, σ)."""
    if r <= 0.0:
        z[Z_F] = 0.0
        return FREE, sigma
    lr, dl = limit(r, dr, tpar)
    du = z[Z_V] + tpar[T_VD]
    if mode == FREE:
        z[Z_F] = 0.0
        return STICK, sigma
    if mode == STICK:
        if abs(z[Z_F]) > lr:
            s = 1.0 if z[Z_F] > 0.0 else -1.0
            z[Z_F] = s * lr
            if s * kt * du - dl > 0.0:
                return SLIP, s
        return STICK, sigma
    z[Z_F] = sigma * lr
    if sigma * kt * du - dl <= 0.0:
        return STICK, sigma
    return SLIP, sigma


@njit(cache=True)
def switch(mode, sigma, which, z, r, dr, kt, tpar):
    """The mode after event ``which`` of ``mode`` (see :func:`.friction._event_g`); f_t is put
    on its new value. Returns (mode, σ)."""
    if r <= 0.0:  # the limit reached zero with the force
        z[Z_F] = 0.0
        return FREE, sigma
    lr, dl = limit(r, dr, tpar)
    if mode == STICK:
        s = 1.0 if which == 0 else -1.0
        z[Z_F] = s * lr
        if s * kt * (z[Z_V] + tpar[T_VD]) - dl > 0.0:
            return SLIP, s
        return STICK, sigma  # a grazing touch of the limit: the contact sticks on
    if mode == SLIP:
        if which == 0:
            z[Z_F] = sigma * lr
            return STICK, sigma
        z[Z_F] = 0.0
        return FREE, sigma
    z[Z_F] = 0.0
    return STICK, sigma


@njit(cache=True)
def _account(mode, sigma, t, z, h, F, nstep, par, tpar, times, wr, ts, so, jpos):
    """Time in ``mode``, the range of w (at five points of the step and at the extrema of w
    between them: the roots of w' on the interpolant) and the samples inside [t, t + h) of a
    finished step with interpolant F."""
    times[mode] += h
    v_prev = 0.0
    for s in range(5):
        th = s / 4.0
        v = dense_value(F, z, th, Z_V)
        w = dense_value(F, z, th, Z_W)
        wr[0] = min(wr[0], w)
        wr[1] = max(wr[1], w)
        if s > 0 and (v_prev < 0.0) != (v < 0.0):  # an extremum of w in between
            w = dense_value(F, z, dense_root(F, z, Z_V, 0.0, th - 0.25, th), Z_W)
            wr[0] = min(wr[0], w)
            wr[1] = max(wr[1], w)
        v_prev = v
    j = jpos[0]
    Fn, yn, t0, hn, contact = nstep
    while j < ts.shape[0] and ts[j] < t + h:
        th = (ts[j] - t) / h if h > 0.0 else 0.0
        r, dr, kt = normal_at(Fn, yn, t0, hn, contact, ts[j], par, tpar)
        lr, dl = limit(r, dr, tpar)
        v = dense_value(F, z, th, Z_V)
        so[j, S_W] = dense_value(F, z, th, Z_W)
        so[j, S_V] = v
        so[j, S_R] = r
        so[j, S_MODE] = mode
        if mode == STICK:
            so[j, S_F] = dense_value(F, z, th, Z_F)
            so[j, S_SLIP] = 0.0
        elif mode == SLIP:
            so[j, S_F] = sigma * lr
            so[j, S_SLIP] = v + tpar[T_VD] - sigma * dl / kt
        else:
            so[j, S_F] = 0.0
            so[j, S_SLIP] = v + tpar[T_VD]
        j += 1
    jpos[0] = j


@njit(cache=True)
def through_step(rec, i, off, z, mode, sigma, h, par, tpar, rtol, times, wr, ts, so, jpos, work):
    """Integrate the tangential state ``z`` across normal step ``i`` (shifted by ``off`` [τ]);
    ``work``: the arrays of :func:`_work` (no allocation per step). The DOP853 steps, their
    controller and landing on the normal step's end are :mod:`.dop853`'s; an event re-takes the
    step to end on it and switches the mode (:func:`switch`).

    Returns (status, mode, σ, h) with h the step size proposed for the next step."""
    K, znew, F, f0, Fn, yn, G, E, atol = work
    for q in range(7):
        Fn[q, 0] = rec[i, REC_F + 2 * q]
        Fn[q, 1] = rec[i, REC_F + 2 * q + 1]
    yn[0] = rec[i, REC_X]
    yn[1] = rec[i, REC_X + 1]
    t0 = rec[i, REC_T] + off
    hn = rec[i, REC_H]
    nstep = (Fn, yn, t0, hn, rec[i, REC_MODE] > 0.5)
    t = t0
    t_end = t0 + hn
    tc = math.nan  # the instant of the normal values E[3:] (a step's end: the next one's start)
    fresh = False
    rejected = False
    n_events = 0
    while t < t_end:
        if t == tc:
            r, dr, kt = E[3], E[4], E[5]
        else:
            r, dr, kt = normal_at(Fn, yn, t0, hn, nstep[4], t, par, tpar)
        E[0], E[1], E[2] = r, dr, kt
        if not fresh:
            mode, sigma = consistent(mode, sigma, z, r, dr, kt, tpar)
        fresh = False
        rhs(mode, sigma, z, r, dr, kt, tpar, f0)
        hh, last = landing_step(h, t_end - t)
        K[0, :] = f0
        err, E[3], E[4], E[5] = rk_step(mode, sigma, t, z, hh, nstep, par, tpar, rtol, atol, K, znew)
        tc = t + hh
        if not math.isfinite(err):
            return STATUS_NONFINITE, mode, sigma, h
        if not (err < 1.0):
            h = hh * step_factor(err, rejected)
            rejected = True
            if h < 1e-13 * (1.0 + abs(t)):
                return STATUS_STEP_TOO_SMALL, mode, sigma, h
            continue
        h_next = hh * step_factor(err, rejected)
        rejected = False
        dense(mode, sigma, t, z, znew, hh, nstep, par, tpar, K, F)
        which, th = find_event(mode, sigma, F, z, t, hh, nstep, par, tpar, G, E)
        if which >= 0:
            n_events += 1
            times[3] += 1.0  # switches of the period
            if n_events > MAX_EVENTS_PER_STEP:
                return STATUS_TOO_MANY_EVENTS, mode, sigma, h
            he = th * hh
            if he > 0.0:  # re-take the step to end on the event
                K[0, :] = f0
                _e, E[3], E[4], E[5] = rk_step(mode, sigma, t, z, he, nstep, par, tpar, rtol, atol, K, znew)
                tc = t + he
                dense(mode, sigma, t, z, znew, he, nstep, par, tpar, K, F)
                _account(mode, sigma, t, z, he, F, nstep, par, tpar, times, wr, ts, so, jpos)
                z[:] = znew
                t += he
            if t == tc:
                r, dr, kt = E[3], E[4], E[5]
            else:
                r, dr, kt = normal_at(Fn, yn, t0, hn, nstep[4], t, par, tpar)
            mode, sigma = switch(mode, sigma, which, z, r, dr, kt, tpar)
            fresh = True
            continue
        _account(mode, sigma, t, z, hh, F, nstep, par, tpar, times, wr, ts, so, jpos)
        z[:] = znew
        t = t_end if last else t + hh
        h = next_step(h, h_next, last)
    return STATUS_OK, mode, sigma, h


@njit(cache=True)
def _work(rtol, scale):
    """Work arrays of :func:`through_step`, made once a period: the stages K (16 and a work
    row), the new state, the tangential interpolant, f at the step's start and the normal
    step's interpolant and start (Fn, yn), the event functions' samples (G), the normal
    values at a step's start and end (E), and the absolute tolerances of w, w', f_t
    (``rtol`` times their scales)."""
    atol = np.empty(3)
    for i in range(3):
        atol[i] = rtol * scale[i]
    return (np.empty((17, N_STATE)), np.empty(N_STATE), np.empty((7, 3)), np.empty(N_STATE), np.empty((7, 2)),
            np.empty(2), np.empty((2, 5)), np.empty(6), atol)


@njit(cache=True)
def run_period(rec, off, z, mode, sigma, h, par, tpar, rtol, scale, times, wr, ts, so, jpos):
    """One normal period of the record, starting at ``off`` [τ]; the local error of w, w', f_t
    is held to ``rtol`` (their ``scale`` + magnitude). Returns (status, mode, σ, h)."""
    work = _work(rtol, scale)
    for i in range(rec.shape[0]):
        st, mode, sigma, h = through_step(rec, i, off, z, mode, sigma, h, par, tpar, rtol,
                                          times, wr, ts, so, jpos, work)
        if st != STATUS_OK:
            return st, mode, sigma, h
    return STATUS_OK, mode, sigma, h


@njit(cache=True)
def state_distance(a, b, scale):
    """max_i |a_i − b_i| / (scale_i + |a_i|) over the tangential phase state (w, w', F_t)."""
    d = 0.0
    for i in range(3):
        d = max(d, abs(a[i] - b[i]) / (scale[i] + abs(a[i])))
    return d


@njit(cache=True, nogil=True)
def settle(rec, period, par, tpar, z0, mode, sigma, rtol, scale, max_periods, jmax, tol, tol_fine, patience,
           stop):
    """Normal periods from the state ``z0`` (w, w', f_t) in ``mode`` until the phase-0 state
    repeats after j ≤ ``jmax`` periods to ``tol`` (distance relative to the state plus its
    scale); then on, with that j, until the distance is below ``tol_fine`` or has stopped
    halved for ``patience`` periods (the integrator's noise floor); the period reported is the
    smallest lag at which the last state repeats to 4 times that distance (a transient that
    spirals in can match at a longer lag first). Returns ``STATUS_INTERRUPTED`` at the start of
    the first period after ``stop[0]`` is set (int64[1]; Ctrl-C through
    :func:`contactvib.interrupts.run_interruptible`, which this kernel allows: it releases the
    GIL).

    Returns
    -------
    status : int
        Flow status (``STATUS_OK`` also when unsettled: then ``j`` = 0).
    n : int
        Periods integrated.
    j : int
        Tangential period [normal periods] (0: not settled within ``max_periods``).
    distance : float
        The last relative distance of the phase-0 states j periods apart.
    quad : float64[max_periods, 4]
        Per period: ∫ f_drive, damper, slip and spring works [W y0] (per unit τ integrated).
    times : float64[max_periods, 4]
        Per period: time [τ] in stick, slip, free, and the number of located switches.
    wr : float64[max_periods, 2]
        Per period: min and max of w [y0].
    states : float64[max_periods + 1, 3]
        The phase-0 states.
    modes : int64[max_periods + 1, 2]
        Their mode and σ.
    """
    quad = np.zeros((max_periods, 4))
    times = np.zeros((max_periods, 4))
    wr = np.zeros((max_periods, 2))
    states = np.zeros((max_periods + 1, 3))
    modes = np.zeros((max_periods + 1, 2), np.int64)
    z = np.zeros(N_STATE)
    z[:3] = z0
    states[0, :] = z0
    modes[0, 0] = mode
    modes[0, 1] = int(sigma)
    ts = np.empty(0)
    so = np.empty((0, 6))
    jpos = np.zeros(1, np.int64)
    found = 0
    best = math.inf
    stall = 0
    d = math.inf
    for n in range(max_periods):
        if stop[0] != 0:
            return STATUS_INTERRUPTED, n, 0, d, quad, times, wr, states, modes
        z[3:] = 0.0
        wr[n, 0] = math.inf
        wr[n, 1] = -math.inf
        h = 0.05  # the same step sequence every period: the period map is a fixed function
        st, mode, sigma, h = run_period(rec, 0.0, z, mode, sigma, h, par, tpar, rtol, scale,
                                        times[n], wr[n], ts, so, jpos)
        if st != STATUS_OK:
            return st, n, 0, d, quad, times, wr, states, modes
        quad[n, :] = z[Q_DRIVE:]
        states[n + 1, :] = z[:3]
        modes[n + 1, 0] = mode
        modes[n + 1, 1] = int(sigma)
        if found == 0:
            found = _repeats(states, modes, n + 1, jmax, scale, tol)
            if found > 0:
                best = state_distance(states[n + 1], states[n + 1 - found], scale)
            continue
        d = state_distance(states[n + 1], states[n + 1 - found], scale)
        if d <= tol_fine:
            found = _repeats(states, modes, n + 1, found, scale, max(4.0 * d, tol_fine))
            return STATUS_OK, n + 1, found, d, quad, times, wr, states, modes
        if d < 0.5 * best:
            best = d
            stall = 0
        else:
            stall += 1
            if stall >= patience:
                found = _repeats(states, modes, n + 1, found, scale, max(4.0 * d, tol_fine))
                return STATUS_OK, n + 1, found, d, quad, times, wr, states, modes
    return STATUS_OK, max_periods, found, d, quad, times, wr, states, modes


@njit(cache=True)
def _repeats(states, modes, m, jmax, scale, tol):
    """The smallest lag j ≤ jmax at which phase-0 state ``m`` repeats to ``tol`` (0: none)."""
    for j in range(1, min(jmax, m) + 1):
        same = modes[m, 0] == modes[m - j, 0] and (modes[m, 0] != SLIP or modes[m, 1] == modes[m - j, 1])
        if same and state_distance(states[m], states[m - j], scale) <= tol:
            return j
    return 0


@njit(cache=True)
def samples(rec, period, par, tpar, z0, mode, sigma, rtol, scale, n_periods, ts):
    """The tangential motion at sorted instants ``ts`` [τ] in [0, n_periods · period) from the
    phase-0 state ``z0``: rows of (w, w', f_t, s', r, mode) (:data:`S_WIDTH` columns).
    Returns (status, samples)."""
    so = np.full((ts.shape[0], S_WIDTH), np.nan)
    z = np.zeros(N_STATE)
    z[:3] = z0
    jpos = np.zeros(1, np.int64)
    times = np.zeros(4)
    wr = np.zeros(2)
    h = 0.05
    for n in range(n_periods):
        st, mode, sigma, h = run_period(rec, n * period, z, mode, sigma, h, par, tpar, rtol, scale,
                                        times, wr, ts, so, jpos)
        if st != STATUS_OK:
            return st, so
    return STATUS_OK, so


__all__ = ["FREE", "SLIP", "STICK", "T_KD", "consistent", "settle", "samples", "switch"]
