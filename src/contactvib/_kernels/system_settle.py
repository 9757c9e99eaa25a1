"""Settling of a structure's starts onto their attractors, period by period (compiled, pure).

Each start is advanced one excitation period at a time by :func:`.system_map.strobe_map`'s
arithmetic (the modes taken afresh from the state and the step proposal reset at each period's
start, so the stroboscopic points are bit-for-bit those of one ``strobe_map`` call per period).
After each period, in this order:

* captured: the newest point x_n is within ``capture_tol · max(1, |x_n|∞)`` (∞-norm) of a row of
  ``cap_pts`` (the first such row in order): the outcome is that row's ``cap_id``;
* periodic: for the least k ≤ kmax with at least 2k + 1 points so far, every one of the last k
  points repeats the one k periods before: ``|x_{n−j} − x_{n−j−k}|∞ ≤ tol · max(1, |x_{n−j}|∞)``,
  j = 0..k−1;

else, after ``max_periods`` periods, unsettled. An integration that fails is ``SETTLE_FAILED``; a
start whose ``stop[0]`` is set (Ctrl-C, :mod:`contactvib.interrupts`) ends after the period it is
in with ``SETTLE_INTERRUPTED``. The kernels release the GIL.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .status import (
    SETTLE_CAPTURED,
    SETTLE_FAILED,
    SETTLE_INTERRUPTED,
    SETTLE_NONPERIODIC,
    SETTLE_PERIODIC,
    STATUS_OK,
)
from .system_flow import MAX_STEPS_PER_PERIOD, advance, initial_modes


@njit(cache=True)
def _inf_norm(x):
    s = 0.0
    for i in range(x.shape[0]):
        a = abs(x[i])
        if a > s:
            s = a
    return s


@njit(cache=True)
def one_period(sa, y, mode, T, rtol):
    """y ← the state one period T [τ] on from phase 0 (as ``strobe_map(sa, y, 1, rtol, rtol)``).
    Returns the status code."""
    initial_modes(sa, y, mode)
    _h, _i, _ns, _ne, st = advance(sa, y, 0.0, T, mode, 0.01, rtol, rtol, np.empty((0, 1)), np.int64(0),
                                   np.int64(MAX_STEPS_PER_PERIOD))
    return st


@njit(cache=True)
def _repeats(hist, c, L, k, tol):
    """Whether the last k of the c points in the ring ``hist`` (L rows) each repeat the one k
    before (module docstring)."""
    if c < 2 * k + 1:
        return False
    n2 = hist.shape[1]
    for j in range(k):
        a = (c - 1 - j) % L
        b = (c - 1 - j - k) % L
        d = 0.0
        s = 0.0
        for i in range(n2):
            d = max(d, abs(hist[a, i] - hist[b, i]))
            s = max(s, abs(hist[a, i]))
        if not d <= tol * max(1.0, s):
            return False
    return True


@njit(cache=True, nogil=True)
def settle_start(sa, x0, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop, out_x):
    """Settle the scaled start ``x0`` (2n); ``out_x`` ← the last stroboscopic point.

    Returns (outcome, k, periods): ``SETTLE_PERIODIC`` with its period k, ``SETTLE_CAPTURED``
    with the ``cap_id`` of the row it came near, ``SETTLE_NONPERIODIC`` (unsettled) or
    ``SETTLE_FAILED`` or ``SETTLE_INTERRUPTED`` (k = 0); periods integrated."""
    n2 = x0.shape[0]
    L = 2 * kmax + 1
    hist = np.empty((L, n2))
    y = np.empty(n2)
    mode = np.zeros(sa.U.shape[0], dtype=np.bool_)
    for i in range(n2):
        hist[0, i] = x0[i]
        y[i] = x0[i]
        out_x[i] = x0[i]
    c = 1
    T = 2.0 * math.pi / sa.r
    for n in range(max_periods):
        if one_period(sa, y, mode, T, rtol) != STATUS_OK:
            return SETTLE_FAILED, 0, n + 1
        if stop[0] != 0:
            return SETTLE_INTERRUPTED, 0, n + 1
        a = c % L
        for i in range(n2):
            hist[a, i] = y[i]
            out_x[i] = y[i]
        c += 1
        lim = capture_tol * max(1.0, _inf_norm(y))
        for r in range(cap_pts.shape[0]):
            d = 0.0
            for i in range(n2):
                d = max(d, abs(cap_pts[r, i] - y[i]))
            if d <= lim:
                return SETTLE_CAPTURED, cap_id[r], n + 1
        for k in range(1, kmax + 1):
            if _repeats(hist, c, L, k, tol):
                return SETTLE_PERIODIC, k, n + 1
    return SETTLE_NONPERIODIC, 0, max_periods


@njit(cache=True, inline="always")
def _settle_one(q, sa, X, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop, how, kk, xs, nper):
    o = np.empty(X.shape[1])
    h, k, n = settle_start(sa, X[q], kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop, o)
    how[q] = h
    kk[q] = k
    nper[q] = n
    for i in range(o.shape[0]):
        xs[q, i] = o[i]


@njit(cache=True, parallel=True, nogil=True)
def _settle_threads(sa, X, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop):
    N = X.shape[0]
    how = np.empty(N, np.int64)
    kk = np.empty(N, np.int64)
    nper = np.empty(N, np.int64)
    xs = np.empty((N, X.shape[1]))
    for q in prange(N):
        _settle_one(q, sa, X, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop, how, kk, xs, nper)
    return how, kk, xs, nper


@njit(cache=True, nogil=True)
def _settle_serial(sa, X, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop):
    N = X.shape[0]
    how = np.empty(N, np.int64)
    kk = np.empty(N, np.int64)
    nper = np.empty(N, np.int64)
    xs = np.empty((N, X.shape[1]))
    for q in range(N):
        _settle_one(q, sa, X, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop, how, kk, xs, nper)
    return how, kk, xs, nper


def settle_starts(sa, X, kmax, max_periods, tol, cap_pts, cap_id, capture_tol, rtol, stop):
    """:func:`settle_start` for every row of ``X`` (N, 2n), independently; with more than one
    numba thread on the threads (a ``parallel=True`` kernel), else in a plain loop (the same
    results). Returns outcome, k, periods (int64[N]) and the last points (N, 2n), as
    (outcome, k, last points, periods)."""
    from numba import get_num_threads

    kernel = _settle_threads if get_num_threads() > 1 and X.shape[0] > 1 else _settle_serial
    return kernel(sa, np.ascontiguousarray(X, dtype=np.float64), np.int64(kmax), np.int64(max_periods),
                  float(tol), np.ascontiguousarray(cap_pts, dtype=np.float64),
                  np.ascontiguousarray(cap_id, dtype=np.int64), float(capture_tol), float(rtol), stop)
