"""Forward models of :mod:`contactvib.fitting`: a stepped-sine sweep and a free decay (compiled, pure).

Stepped sine (:func:`stepped_sweep`). At step ``i`` the excitation is ``p[i] cos(r[i] τ)`` and the
state at phase 0 is the one the previous step ended on (the first step starts from the static
point x = 1, x' = 0): the trajectory is integrated to the attractor it reaches
(:func:`.settle.settle`: period detection, Newton refinement, stability), that orbit is recorded
over its period and measured (:func:`.orbit.measure_orbit`: A_pp = x_max − x_min), and the next
step starts from its phase-0 point. A laboratory stepped-sine sweep does the same, so up and down
sweeps jump where the experiment jumps (hysteresis at the folds). A start that settles on no
period ≤ ``kmax`` within ``max_periods`` (non-periodic) is measured over ``N_NONPERIODIC``
periods from where it ended; a failed integration gives NaN.

Free decay (:func:`decay_samples`): the unforced oscillator (p = 0) from ``z0`` at τ = 0, sampled
on the dense output at the instants ``times``.

:func:`sweeps_many` and :func:`decays_many` run many parameter vectors (a finite-difference
Jacobian's columns, the multi-start's candidates) and all sweeps in parallel (numba threads).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from .orbit import measure_orbit, record_steps, sample_records
from .settle import settle
from .status import SETTLE_NONPERIODIC, SETTLE_PERIODIC, STATUS_OK

#: Periods measured for a step that settles on no period ≤ kmax.
N_NONPERIODIC = 8


@njit(cache=True)
def stepped_sweep(par, r, p, z_start, warm, kmax, max_periods, detect_tol, rtol_transient, rtol, tol):
    """One stepped-sine sweep: A_pp [y0] at each step, following the attractor reached.

    With ``warm`` each step starts instead from ``z_start[i]`` (the phase-0 orbit point that a
    sweep at nearby parameters reached at that step): the same attractors, continued, in a few
    periods (the finite-difference Jacobian's columns).

    Parameters
    ----------
    par : float64[5]
        ``[m2, l, c, p, r]`` (``p`` and ``r`` replaced at every step).
    r, p : float64[n]
        Frequency ratio f_e/f_n0 and force P_a/Q of each step, in the order of the sweep.

    Returns
    -------
    app : float64[n]
        Peak-to-peak amplitude of the steady state [y0] (NaN where the integration failed).
    period : int64[n]
        Period of the attractor in excitation periods (0: non-periodic, −1: failed).
    z_out : float64[n, 2]
        The phase-0 point of each step's attractor (for a warm start).
    """
    n = r.shape[0]
    app = np.full(n, np.nan)
    period = np.full(n, -1, np.int64)
    z_out = np.empty((n, 2))
    q = par.copy()
    z = np.empty(2)
    z[0] = 1.0
    z[1] = 0.0
    hist = np.empty((max_periods + 1, 2))
    oz = np.empty(2)
    oM = np.empty((2, 2))
    for i in range(n):
        q[3] = p[i]
        q[4] = r[i]
        if warm:
            z[0] = z_start[i, 0]
            z[1] = z_start[i, 1]
        s, k, m, _res = settle(z, 0.0, q, kmax, 4, max_periods, detect_tol, rtol_transient, rtol,
                               tol, hist, oz, oM)
        if s == SETTLE_PERIODIC:
            z[0] = oz[0]
            z[1] = oz[1]
            nper = k
        elif s == SETTLE_NONPERIODIC:
            z[0] = hist[m, 0]
            z[1] = hist[m, 1]
            k = 0
            nper = N_NONPERIODIC
        else:
            z[0] = 1.0  # the next step starts again from the static point
            z[1] = 0.0
            z_out[i, 0] = 1.0
            z_out[i, 1] = 0.0
            continue
        z_out[i, 0] = z[0]
        z_out[i, 1] = z[1]
        rec, z_end, t_flight, _ne, st = record_steps(z, 0.0, nper, q, rtol, 256, 1 << 20)
        if st != STATUS_OK:
            continue
        xmin, xmax, _fl, _nm, _t, _x, _m = measure_orbit(rec, t_flight, nper, q[4])
        app[i] = xmax - xmin
        period[i] = k
        if k == 0:
            z[0] = z_end[0]
            z[1] = z_end[1]
    return app, period, z_out


@njit(cache=True, parallel=True)
def sweeps_many(pars, r, p, z_start, warm, seg_start, seg_len, kmax, max_periods, detect_tol, rtol_transient,
                rtol, tol):
    """:func:`stepped_sweep` for every parameter vector ``pars[j]`` (float64[K, 5]) and every sweep
    (steps ``seg_start[s] .. seg_start[s] + seg_len[s]`` of ``r[j]``, ``p``), in parallel.

    ``r`` is float64[K, n] (the frequency ratio depends on the parameters through f_n0),
    ``max_periods`` int64[K] the transient limit of each parameter vector; ``z_start``
    float64[n, 2] and ``warm`` as in :func:`stepped_sweep` (the same starts for every vector).
    Returns ``app`` float64[K, n] [y0], ``period`` int64[K, n] and ``z_out`` float64[K, n, 2]."""
    K = pars.shape[0]
    n_seg = seg_start.shape[0]
    n = p.shape[0]
    app = np.full((K, n), np.nan)
    period = np.full((K, n), -1, np.int64)
    z_out = np.empty((K, n, 2))
    for task in prange(K * n_seg):
        j = task // n_seg
        s = task % n_seg
        a = seg_start[s]
        b = a + seg_len[s]
        aj, kj, zj = stepped_sweep(pars[j], r[j, a:b], p[a:b], z_start[a:b], warm, kmax, max_periods[j],
                                   detect_tol, rtol_transient, rtol, tol)
        app[j, a:b] = aj
        period[j, a:b] = kj
        z_out[j, a:b] = zj
    return app, period, z_out


@njit(cache=True)
def decay_samples(par, z0, times, rtol):
    """The free oscillator (``par[3] = 0``) from ``z0`` at τ = 0 sampled at sorted ``times`` [τ]
    (``times[-1] ≤ 2π/par[4]``: one "period" spans the record). Returns x, x' (NaN on failure)."""
    m = times.shape[0]
    rec, _z, _tf, _ne, st = record_steps(z0, 0.0, 1, par, rtol, 1024, 1 << 22)
    if st != STATUS_OK or rec.shape[0] == 0:
        return np.full(m, np.nan), np.full(m, np.nan)
    xs, vs, _c = sample_records(rec, times)
    return xs, vs


@njit(cache=True, parallel=True)
def decays_many(pars, z0s, times, rtol):
    """:func:`decay_samples` for every ``pars[j]``, ``z0s[j]``, ``times[j]`` in parallel."""
    K = pars.shape[0]
    m = times.shape[1]
    xs = np.empty((K, m))
    vs = np.empty((K, m))
    for j in prange(K):
        x, v = decay_samples(pars[j], z0s[j], times[j], rtol)
        xs[j] = x
        vs[j] = v
    return xs, vs

