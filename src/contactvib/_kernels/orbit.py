"""Dense records of an orbit, its local extrema, its measurement and samples (compiled, pure).

:func:`record_orbit` integrates ``n_periods`` excitation periods at a tight tolerance and keeps
each accepted step's 7th-order interpolant (:data:`.flow.REC_WIDTH` columns);
:func:`record_steps` does so with a buffer grown until the record fits. The extrema of ``x`` are
the sign changes of ``x'`` located by root-finding on those interpolants (a minimum is a − to +
change); ``x'`` is continuous across contact events, so the count over a closed orbit is exact
and cyclic. :func:`measure_orbit` turns a record into the numbers every caller reports (x range,
A_pp = x_max − x_min, contact-loss fraction, minima count, extrema): the tracer
(:func:`.describe.describe_point`), the continuation (:func:`.continuation.orbit_range`) and
:func:`contactvib.steady.orbits.describe_orbit` all measure through it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .flow import (
    REC_F,
    REC_H,
    REC_MODE,
    REC_T,
    REC_WIDTH,
    REC_X,
    advance,
    dense_root,
    dense_value,
    initial_mode,
)
from .shooting import MAX_STEPS_PER_PERIOD
from .status import STATUS_OK, STATUS_RECORD_FULL

_N_SUB = 8  # sub-intervals per step searched for sign changes of x'

#: Largest step-record buffer the kernels grow to [records] (2**22 records ≈ 640 MB).
RECORD_CAP_MAX = 1 << 22


@njit(cache=True)
def _step_arrays(rec, i):
    F = np.empty((7, 2))
    for q in range(7):
        F[q, 0] = rec[i, REC_F + 2 * q]
        F[q, 1] = rec[i, REC_F + 2 * q + 1]
    y = np.empty(2)
    y[0] = rec[i, REC_X]
    y[1] = rec[i, REC_X + 1]
    return F, y


@njit(cache=True)
def record_orbit(z, phase0, n_periods, par, rtol, max_records):
    """Integrate ``n_periods`` periods from ``z`` at phase 0 and record every step.

    Returns
    -------
    rec : float64[n_rec, REC_WIDTH]
        Step records with global time τ ∈ [0, n_periods T].
    z_end : float64[2]
        State at the end.
    t_flight : float
        Total time in flight (x ≤ 0) [τ].
    n_events : int
        Number of switching instants.
    status : int
        :mod:`.flow` status (``STATUS_RECORD_FULL``: enlarge ``max_records``).
    """
    T = 2.0 * math.pi / par[4]
    rec = np.empty((max_records, REC_WIDTH))
    y = np.empty(2)
    y[0] = z[0]
    y[1] = z[1]
    contact = initial_mode(y[0], y[1])
    h = 0.01
    irec = np.int64(0)
    t_flight = 0.0
    n_events = 0
    start = phase0 * T
    for j in range(n_periods):
        i0 = irec
        contact, h, irec, _ns, tf, ne, st = advance(
            y, start, T, contact, h, par, rtol, rtol, rec, irec, np.int64(MAX_STEPS_PER_PERIOD))
        start = 0.0
        t_flight += tf
        n_events += ne
        if st != STATUS_OK:
            return rec[: min(irec, max_records)], y, t_flight, n_events, st
        for i in range(i0, irec):
            rec[i, REC_T] += j * T
    return rec[:irec], y, t_flight, n_events, STATUS_OK


@njit(cache=True, inline='always')
def record_steps(z, phase0, n_periods, par, rtol, cap, cap_max):
    """:func:`record_orbit` with a buffer grown until the record fits.

    Starts with ``cap`` records and, while the integration stops with ``STATUS_RECORD_FULL``
    and the buffer is below ``cap_max`` (``cap_max ≤ 0``: no bound), integrates again with
    four times the buffer. The record does not depend on the buffer size.

    Returns
    -------
    rec, z_end, t_flight, n_events, status
        As :func:`record_orbit` (``status`` is ``STATUS_RECORD_FULL`` past ``cap_max``).
    """
    while True:
        rec, z_end, t_flight, n_events, st = record_orbit(z, phase0, n_periods, par, rtol, cap)
        if st == STATUS_RECORD_FULL and (cap_max <= 0 or cap < cap_max):
            cap *= 4
            continue
        return rec, z_end, t_flight, n_events, st


@njit(cache=True, inline='always')
def measure_orbit(rec, t_flight, n_periods, r):
    """Range, contact loss and extrema of ``x`` over a record of ``n_periods`` periods.

    Parameters
    ----------
    rec : float64[n_rec, REC_WIDTH]
        Step records of :func:`record_orbit` (from phase 0).
    t_flight : float
        Time in flight over the record [τ].
    n_periods : int
        Excitation periods recorded; the span is ``n_periods · T``, ``T = 2π/r`` [τ].
    r : float
        Frequency ratio ``f_e/f_n0`` (``par[4]``).

    Returns
    -------
    xmin, xmax : float
        Smallest and largest x [y0]: over the extrema (:func:`find_extrema`) and the ends; the
        peak-to-peak amplitude is ``A_pp = xmax − xmin``.
    flight : float
        Fraction of the span with x ≤ 0: ``t_flight / (n_periods · 2π/r)``.
    n_min : int
        Local minima (x' from − to +).
    t_ext, x_ext : float64[n]
        Instants [τ] and values [y0] of the extrema, in order.
    is_min : bool[n]
        True for minima.

    Notes
    -----
    The range of a continuous x over the span is attained at an extremum or at an end of the
    span, so both ends (x at the first step's start and at the last step's end) are included.
    On a closed orbit the ends lie between the extrema and change nothing; on a record that is
    not an orbit (a transient, a chaotic piece, a flight longer than the record) they can hold
    the range.
    """
    t_e, x_e, m_e = find_extrema(rec)
    n_e = t_e.shape[0]
    n_rec = rec.shape[0]
    xmin = math.inf
    xmax = -math.inf
    n_min = 0
    for j in range(n_e):
        xmin = min(xmin, x_e[j])
        xmax = max(xmax, x_e[j])
        if m_e[j]:
            n_min += 1
    if n_rec > 0:
        F, y = _step_arrays(rec, n_rec - 1)
        x_start = rec[0, REC_X]
        x_end = dense_value(F, y, 1.0, 0)
        xmin = min(xmin, x_start, x_end)
        xmax = max(xmax, x_start, x_end)
    T = 2.0 * math.pi / r
    return xmin, xmax, t_flight / (n_periods * T), n_min, t_e, x_e, m_e


@njit(cache=True)
def find_extrema(rec):
    """Local extrema of x over the recorded steps.

    Returns
    -------
    t : float64[n]
        Instants [τ] of the extrema, in order.
    x : float64[n]
        Values [y0].
    is_min : bool[n]
        True for minima (x' changes from − to +).
    """
    n_rec = rec.shape[0]
    cap = 64
    t_out = np.empty(cap)
    x_out = np.empty(cap)
    m_out = np.empty(cap, np.bool_)
    n = 0
    for i in range(n_rec):
        F, y = _step_arrays(rec, i)
        t0 = rec[i, REC_T]
        h = rec[i, REC_H]
        va = dense_value(F, y, 0.0, 1)
        for s in range(1, _N_SUB + 1):
            a = (s - 1) / _N_SUB
            b = s / _N_SUB
            vb = dense_value(F, y, b, 1)
            if (va < 0.0) != (vb < 0.0):
                th = dense_root(F, y, 1, 0.0, a, b)
                if n == cap:
                    cap *= 2
                    t2 = np.empty(cap)
                    x2 = np.empty(cap)
                    m2 = np.empty(cap, np.bool_)
                    for q in range(n):  # a loop: a slice copy compiles numba's shape-error path
                        t2[q] = t_out[q]
                        x2[q] = x_out[q]
                        m2[q] = m_out[q]
                    t_out, x_out, m_out = t2, x2, m2
                t_out[n] = t0 + th * h
                x_out[n] = dense_value(F, y, th, 0)
                m_out[n] = va < 0.0
                n += 1
            va = vb
    return t_out[:n], x_out[:n], m_out[:n]


@njit(cache=True)
def sample_records(rec, times):
    """x, x' and contact flag at sorted instants ``times`` [τ] inside the recorded span."""
    m = times.shape[0]
    xs = np.empty(m)
    vs = np.empty(m)
    cs = np.empty(m, np.bool_)
    i = 0
    n_rec = rec.shape[0]
    F, y = _step_arrays(rec, np.int64(0))
    loaded = 0
    for j in range(m):
        t = times[j]
        while i < n_rec - 1 and rec[i, REC_T] + rec[i, REC_H] < t:
            i += 1
        if i != loaded:  # unpack a step's dense-output coefficients once
            F, y = _step_arrays(rec, i)
            loaded = i
        th = (t - rec[i, REC_T]) / rec[i, REC_H]
        th = min(max(th, 0.0), 1.0)
        xs[j] = dense_value(F, y, th, 0)
        vs[j] = dense_value(F, y, th, 1)
        cs[j] = rec[i, REC_MODE] > 0.5
    return xs, vs, cs
