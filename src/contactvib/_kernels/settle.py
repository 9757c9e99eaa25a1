"""Convergence to an attractor with period detection and Newton refinement (compiled, pure).

One trajectory is integrated period by period at a loose tolerance (the Taylor-series flow of
:mod:`.taylor` for polynomial laws, DOP853 otherwise). After each period the
stroboscopic points are searched for the smallest ``k ≤ kmax`` with
``|P_n − P_{n−k}| < detect_tol · scale``; the candidate is then refined by Newton shooting
(:func:`.shooting.newton_orbit`) at a tight tolerance and accepted only if it closes
(``≤ tol``), is stable (:func:`.shooting.stable_monodromy`), and no
proper divisor of ``k`` closes too (the period reported is minimal). A refused candidate makes the detection ten times
stricter and the integration goes on. No candidate by ``max_periods`` means a non-periodic
attractor (or a period above ``kmax``).

This avoids the bias of a plain "successive strobe points agree" test, which for multipliers
``μ`` near 1 is off by up to ``1/(1 − |μ|)``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .flow import REC_WIDTH, advance, initial_mode
from .shooting import (
    MAX_STEPS_PER_PERIOD,
    MINIMAL_PERIOD_TOL,
    newton_orbit,
    stable_monodromy,
    state_scale,
)
from .status import (
    SETTLE_CAPTURED,
    SETTLE_FAILED,
    SETTLE_INTERRUPTED,
    SETTLE_NONPERIODIC,
    SETTLE_PERIODIC,
    STATUS_OK,
)
from .taylor import advance_state


@njit(cache=True)
def refine_stable_orbit(z, k, par, rtol, tol, out_z, out_M):
    """Newton at period k (:func:`.shooting.newton_orbit`, 12 steps), then reduce k to the minimal
    period: a proper divisor d of k whose map returns within ``MINIMAL_PERIOD_TOL`` is refined
    at period d. Accepted only if stable (:func:`.shooting.stable_monodromy`).
    Returns (ok, k, residual)."""
    st, res = newton_orbit(z, k, par, rtol, rtol, tol, np.int64(12), out_z, out_M)
    if st != STATUS_OK:
        return False, k, res
    if not stable_monodromy(out_M):
        return False, k, res
    sc = state_scale(out_z[0], out_z[1])
    # P^d(out_z) for the proper divisors d of k, smallest first, from one run period by period:
    # the same steps as strobe_map(out_z, d) for each d (its mode and step proposal carried on)
    d_last = 0
    for d in range(1, k):
        if k % d == 0:
            d_last = d
    T = 2.0 * math.pi / par[4]
    pz = np.zeros(2)
    pz[0] = out_z[0]
    pz[1] = out_z[1]
    contact = initial_mode(pz[0], pz[1])
    h = 0.01
    for d in range(1, d_last + 1):
        contact, h, _i, _ns, _tf, _ne, st = advance(pz, 0.0, T, contact, h, par, rtol, rtol,
                                                    np.empty((0, REC_WIDTH)), np.int64(0),
                                                    np.int64(MAX_STEPS_PER_PERIOD))
        if st != STATUS_OK:
            return False, k, res
        if k % d != 0:
            continue
        if max(abs(pz[0] - out_z[0]), abs(pz[1] - out_z[1])) / sc < MINIMAL_PERIOD_TOL:
            z2 = out_z.copy()
            st, res = newton_orbit(z2, d, par, rtol, rtol, tol, np.int64(12), out_z, out_M)
            if st != STATUS_OK or not stable_monodromy(out_M):
                return False, k, res
            return True, d, res
    return True, k, res


@njit(cache=True, nogil=True)
def settle_core(z_init, phase0, par, kmax, min_periods, max_periods, detect_tol, rtol_transient,
                rtol_refine, tol, cap_pts, cap_id, capture_tol, hist, out_z, out_M, stop):
    """Integrate from ``z_init`` at phase ``phase0`` (fraction of a period) to an attractor.

    ``stop`` (int64[1]) is read after every period: nonzero ends the run with
    ``SETTLE_INTERRUPTED`` (another thread sets it on Ctrl-C).

    After each period the stroboscopic point is first compared with the points ``cap_pts``
    (float64[m, 2], e.g. the strobe points of attractors already known here): within
    ``capture_tol`` (relative) of one, the run stops early with ``SETTLE_CAPTURED`` and that
    point's ``cap_id`` as ``k``. Then the period detection of :func:`settle` runs.

    Returns
    -------
    status : int
        ``SETTLE_PERIODIC``, ``SETTLE_NONPERIODIC``, ``SETTLE_FAILED``, ``SETTLE_CAPTURED`` or
        ``SETTLE_INTERRUPTED``.
    k : int
        Minimal period (periodic), or the captured ``cap_id``.
    n_periods : int
        Periods integrated in the transient (rows ``0..n_periods`` of ``hist`` are filled).
    residual : float
        Relative closure of the refined orbit.
    """
    T = 2.0 * math.pi / par[4]
    y = np.empty(2)
    y[0] = z_init[0]
    y[1] = z_init[1]
    contact = initial_mode(y[0], y[1])
    h = 0.01
    contact, h, _ns, _tf, _ne, st = advance_state(
        y, phase0 * T, T, contact, h, par, rtol_transient, MAX_STEPS_PER_PERIOD)
    if st != STATUS_OK:
        return SETTLE_FAILED, 0, 0, math.inf
    hist[0, 0] = y[0]
    hist[0, 1] = y[1]
    repeat_tol = detect_tol
    for n in range(1, max_periods + 1):
        contact, h, _ns, _tf, _ne, st = advance_state(
            y, 0.0, T, contact, h, par, rtol_transient, MAX_STEPS_PER_PERIOD)
        if st != STATUS_OK:
            return SETTLE_FAILED, 0, n, math.inf
        hist[n, 0] = y[0]
        hist[n, 1] = y[1]
        if stop[0] != 0:
            return SETTLE_INTERRUPTED, 0, n, math.inf
        sc = state_scale(y[0], y[1])
        for j in range(cap_pts.shape[0]):
            if max(abs(y[0] - cap_pts[j, 0]), abs(y[1] - cap_pts[j, 1])) <= capture_tol * sc:
                return SETTLE_CAPTURED, cap_id[j], n, math.inf
        if n < min_periods:
            continue
        for k in range(1, kmax + 1):
            if n - 2 * k < 0:
                break
            d1 = max(abs(hist[n, 0] - hist[n - k, 0]), abs(hist[n, 1] - hist[n - k, 1])) / sc
            if d1 < repeat_tol:
                ok, kk, res = refine_stable_orbit(y, k, par, rtol_refine, tol, out_z, out_M)
                if ok:
                    return SETTLE_PERIODIC, kk, n, res
                repeat_tol *= 0.1
                break
    return SETTLE_NONPERIODIC, 0, max_periods, math.inf


@njit(cache=True)
def settle(z_init, phase0, par, kmax, min_periods, max_periods, detect_tol, rtol_transient,
           rtol_refine, tol, hist, out_z, out_M):
    """Integrate from ``z_init`` at phase ``phase0`` (fraction of a period) to an attractor.

    Parameters
    ----------
    hist : float64[max_periods + 1, 2]
        Work array; on return rows ``0..n_periods`` hold the stroboscopic points.

    Returns
    -------
    status, k, n_periods, residual
        As :func:`settle_core` (never ``SETTLE_CAPTURED``).
    """
    return settle_core(z_init, phase0, par, kmax, min_periods, max_periods, detect_tol,
                       rtol_transient, rtol_refine, tol, np.empty((0, 2)),
                       np.empty(0, np.int64), 0.0, hist, out_z, out_M, np.zeros(1, np.int64))


@njit(cache=True)
def settle_many(Z, phases, par, kmax, min_periods, max_periods, detect_tol, rtol_transient,
                rtol_refine, tol, n_tail):
    """:func:`settle` for many starts at once (numba threads): :func:`settle_capture_many`
    with nothing to capture; the same outputs."""
    return settle_capture_many(Z, phases, par, kmax, min_periods, max_periods, detect_tol,
                               rtol_transient, rtol_refine, tol, n_tail, np.empty((0, 2)),
                               np.empty(0, np.int64), 0.0, np.zeros(1, np.int64))


@njit(cache=True, parallel=True, nogil=True)
def settle_capture_many(Z, phases, par, kmax, min_periods, max_periods, detect_tol, rtol_transient,
                        rtol_refine, tol, n_tail, cap_pts, cap_id, capture_tol, stop):
    """:func:`settle_core` for many starts at once, in parallel over the starts (numba threads).

    Releases the GIL, so that it can run in a helper thread while the main thread waits for
    Ctrl-C and then sets ``stop[0]`` (:func:`contactvib.interrupts.run_interruptible`).

    A start whose stroboscopic point comes within ``capture_tol`` (relative) of one of
    ``cap_pts`` stops there with ``SETTLE_CAPTURED`` and that point's ``cap_id`` as its period.

    Returns
    -------
    status, period, n_periods : int64[N]
    residual : float64[N]
    z_star : float64[N, 2]
        Refined orbit point (periodic) or last stroboscopic point.
    monodromy : float64[N, 2, 2]
    tail : float64[N, n_tail, 2]
        The last ``n_tail`` stroboscopic points of the transient (for non-periodic attractors).
    """
    N = Z.shape[0]
    status = np.empty(N, np.int64)
    period = np.zeros(N, np.int64)
    n_periods = np.zeros(N, np.int64)
    residual = np.empty(N)
    z_star = np.empty((N, 2))
    monodromy = np.zeros((N, 2, 2))
    tail = np.full((N, n_tail, 2), np.nan)
    for i in prange(N):
        hist = np.empty((max_periods + 1, 2))
        oz = np.empty(2)
        oM = np.zeros((2, 2))
        s, k, n, res = settle_core(Z[i], phases[i], par, kmax, min_periods, max_periods,
                                   detect_tol, rtol_transient, rtol_refine, tol, cap_pts,
                                   cap_id, capture_tol, hist, oz, oM, stop)
        status[i] = s
        period[i] = k
        n_periods[i] = n
        residual[i] = res
        if s == SETTLE_PERIODIC:
            z_star[i, 0] = oz[0]
            z_star[i, 1] = oz[1]
            monodromy[i] = oM
        else:
            z_star[i, 0] = hist[n, 0]
            z_star[i, 1] = hist[n, 1]
        first = max(0, n + 1 - n_tail)
        for j in range(first, n + 1):
            tail[i, j - first, 0] = hist[j, 0]
            tail[i, j - first, 1] = hist[j, 1]
    return status, period, n_periods, residual, z_star, monodromy, tail
