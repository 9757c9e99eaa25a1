"""Lyapunov spectra of the stroboscopic map by Benettin's QR method (compiled, pure).

For a trajectory z_{j+1} = P(z_j) of the period map with Jacobians M_j = ∂P/∂z (the monodromy of
one excitation period, saltation at every contact switch included: :mod:`.flow`,
:mod:`.system_flow`), an orthonormal frame Q_j is carried along: M_j Q_j = Q_{j+1} R_j
(Gram–Schmidt), and the exponents are λ_i = (1/N) Σ_j ln R_j[i, i] per excitation period
(Benettin et al. 1980). Each period starts the variational equation from Φ = I, so M_j is one
period's monodromy, and the N periods run in one compiled loop in batches: the sums of
ln R_ii per batch are returned, from which the caller forms the mean and the standard error of
the batch means.

Along the same run the Liouville trace ∫ tr J dτ (``tr J = ∂ẍ/∂ẋ``: minus the contact's damping
rate, 0 in flight) is integrated by 5-point Gauss–Legendre quadrature on every step's dense
output (steps end on the switches, so each is smooth): an estimate of λ1 + λ2 independent of the
variational equation (Σ ln R_ii = ln |det M_j|, and det M_j = exp ∫ tr J dτ because every
saltation matrix S = I + (f⁺ − f⁻) eₓᵀ / v has det S = 1).

Units: nondimensional as in :mod:`.flow` (x = y/y0, τ = ω_n0 t, T = 2π/r); the caller converts
per period into per second (× f_e).

References
----------
G. Benettin, L. Galgani, A. Giorgilli, J.-M. Strelcyn, Meccanica 15 (1980) 9–20, 21–30.
"""

from __future__ import annotations

import math

import numpy as np
from numba import get_num_threads, njit, parallel_chunksize, prange

from .dop853 import record_value
from .flow import REC_F, REC_H, REC_MODE, REC_WIDTH, REC_X, advance, initial_mode, jacobian_row
from .shooting import MAX_STEPS_PER_PERIOD
from .status import STATUS_INTERRUPTED, STATUS_NONFINITE, STATUS_OK, STATUS_RECORD_FULL
from .system_flow import advance as system_advance
from .system_flow import element_state, initial_modes, law_partials

#: 5-point Gauss–Legendre nodes and weights on [0, 1].
_GL_X = np.array([0.04691007703066800, 0.23076534494715845, 0.5, 0.76923465505284155,
                  0.95308992296933200])
_GL_W = np.array([0.11846344252809454, 0.23931433524968324, 0.28444444444444444, 0.23931433524968324,
                  0.11846344252809454])
#: Step records per period kept for the trace quadrature (more: the quadrature is skipped, NaN).
REC_ROWS = 8192

@njit(cache=True)
def trace_integral(rec, n_rows, par):
    """∫ tr J dτ over the first ``n_rows`` step records: Gauss–Legendre on each step's dense output
    of ∂ẍ/∂ẋ (the contact's damping rate with a minus sign; 0 in flight)."""
    acc = 0.0
    for row in range(n_rows):
        if rec[row, REC_MODE] == 0.0:
            continue
        h = rec[row, REC_H]
        s = 0.0
        for q in range(5):
            x = record_value(rec, row, REC_X, REC_F, 2, _GL_X[q], 0)
            v = record_value(rec, row, REC_X, REC_F, 2, _GL_X[q], 1)
            _j21, j22 = jacobian_row(True, x, v, par)
            s += _GL_W[q] * j22
        acc += h * s
    return acc


@njit(cache=True, inline="always")
def gram_schmidt(A, Q, logr):
    """Q R = A by modified Gram–Schmidt, applied twice (orthogonal to rounding); ln R_ii added to
    ``logr``. A and Q are (m, m); returns False where a column vanishes."""
    m = A.shape[0]
    for j in range(m):
        for i in range(m):
            Q[i, j] = A[i, j]
        r_jj = 0.0
        for _ in range(2):
            for p in range(j):
                d = 0.0
                for i in range(m):
                    d += Q[i, p] * Q[i, j]
                for i in range(m):
                    Q[i, j] -= d * Q[i, p]
        for i in range(m):
            r_jj += Q[i, j] * Q[i, j]
        r_jj = math.sqrt(r_jj)
        if not (r_jj > 0.0 and math.isfinite(r_jj)):
            return False
        for i in range(m):
            Q[i, j] /= r_jj
        logr[j] += math.log(r_jj)
    return True


@njit(cache=True, nogil=True)
def spectrum_map(z, par, rtol, n_transient, n_batches, per_batch, with_trace, out_log, out_trace,
                 out_z, out_strobe, stop):
    """Benettin's spectrum of the 1-DOF period map from ``z`` (phase 0).

    ``n_transient`` periods without the variational equation, then ``n_batches × per_batch``
    periods, each integrated with Φ(0) = I (its monodromy M_j), the frame advanced by
    :func:`gram_schmidt` of M_j Q_j. ``stop`` (int64[1]) is read every period.

    Outputs: ``out_log[b, i]`` Σ ln R_ii over batch b [1]; ``out_trace[b]`` ∫ tr J dτ over batch b
    (:func:`trace_integral`; NaN when not ``with_trace`` or a period took more than
    :data:`REC_ROWS` steps); ``out_z`` the end state; ``out_z[2]`` the fraction of the
    batches' time in contact; ``out_strobe`` (m, 2) the last m stroboscopic points of the run
    (m ≤ the periods averaged; m = 0 for none).

    Returns a :mod:`.flow` status (``STATUS_INTERRUPTED`` when stopped, ``STATUS_NONFINITE`` when a
    frame vector vanishes or overflows).
    """
    T = 2.0 * math.pi / par[4]
    y2 = np.empty(2)
    y2[0] = z[0]
    y2[1] = z[1]
    contact = initial_mode(y2[0], y2[1])
    h = 0.01
    no_rec = np.empty((0, REC_WIDTH))
    for _ in range(n_transient):
        contact, h, _i, _ns, _tf, _ne, st = advance(y2, 0.0, T, contact, h, par, rtol, rtol, no_rec,
                                                    np.int64(0), np.int64(MAX_STEPS_PER_PERIOD))
        if st != STATUS_OK:
            return st
        if stop[0] != 0:
            return STATUS_INTERRUPTED
    rec = np.empty((REC_ROWS if with_trace else 0, REC_WIDTH))
    y = np.zeros(6)
    y[0] = y2[0]
    y[1] = y2[1]
    Q = np.eye(2)
    A = np.empty((2, 2))
    t_flight = 0.0
    first_kept = n_batches * per_batch - out_strobe.shape[0]
    for b in range(n_batches):
        logr = np.zeros(2)
        tr = 0.0
        for q in range(per_batch):
            y[2] = 1.0
            y[3] = 0.0
            y[4] = 0.0
            y[5] = 1.0
            contact, h, irec, _ns, tf, _ne, st = advance(y, 0.0, T, contact, h, par, rtol, rtol, rec,
                                                         np.int64(0), np.int64(MAX_STEPS_PER_PERIOD))
            if st == STATUS_RECORD_FULL:
                tr = math.nan
            elif st != STATUS_OK:
                return st
            elif with_trace:
                tr += trace_integral(rec, irec, par)
            t_flight += tf
            kept = b * per_batch + q - first_kept
            if kept >= 0:
                out_strobe[kept, 0] = y[0]
                out_strobe[kept, 1] = y[1]
            for i in range(2):
                for j in range(2):
                    A[i, j] = y[2 + 2 * i] * Q[0, j] + y[3 + 2 * i] * Q[1, j]
            if not gram_schmidt(A, Q, logr):
                return STATUS_NONFINITE
            if stop[0] != 0:
                return STATUS_INTERRUPTED
        out_log[b, 0] = logr[0]
        out_log[b, 1] = logr[1]
        out_trace[b] = tr if with_trace else math.nan
    out_z[0] = y[0]
    out_z[1] = y[1]
    out_z[2] = 1.0 - t_flight / (n_batches * per_batch * T)
    return STATUS_OK


@njit(cache=True)
def system_trace_integral(sa, rec, n_rows, out_contact):
    """∫ tr J dτ over the first ``n_rows`` n-DOF step records (:mod:`.system_flow`): Gauss–Legendre
    (5 nodes) on each step's dense output of tr ∂x''/∂x' = −tr C_x − Σ_i mode_i (∂f_i/∂ξ_i')
    (A_i · U_i); ``out_contact[i]`` += the τ each element spends in contact."""
    n = sa.Kx.shape[0]
    n2 = 2 * n
    m = sa.U.shape[0]
    o = 2 + m
    tr_c = 0.0
    for k in range(n):
        tr_c += sa.Cx[k, k]
    y = np.empty(n2)
    acc = 0.0
    for row in range(n_rows):
        h = rec[row, 1]
        acc -= h * tr_c
        for i in range(m):
            if rec[row, 2 + i] < 0.5:
                continue
            out_contact[i] += h
            au = 0.0
            for k in range(n):
                au += sa.Aw[i, k] * sa.U[i, k]
            s = 0.0
            for q in range(5):
                for c in range(n2):
                    y[c] = record_value(rec, row, o, o + n2, n2, _GL_X[q], c)
                xi, xv = element_state(sa, i, y)
                _fx, fv = law_partials(False, sa, i, xi, xv)
                s += _GL_W[q] * fv
            acc -= h * au * s
    return acc


@njit(cache=True, inline="always")
def _spectrum_row(q, Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status, stop):
    """Row ``q`` of :func:`spectrum_map_rows`: :func:`spectrum_map` from ``Z[q]`` with ``PAR[q]``."""
    status[q] = spectrum_map(Z[q], PAR[q], rtol, 0, n_batches, per_batch, False, out_log[q], out_trace[q],
                             out_z[q], out_strobe[q], stop)


@njit(cache=True, parallel=True, nogil=True)
def _spectrum_rows_threads(Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status,
                           stop):
    for q in prange(Z.shape[0]):
        _spectrum_row(q, Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status, stop)


@njit(cache=True, nogil=True)
def _spectrum_rows_serial(Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status,
                          stop):
    for q in range(Z.shape[0]):
        _spectrum_row(q, Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status, stop)


def spectrum_map_rows(Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status, stop):
    """:func:`spectrum_map` (no transient, no trace quadrature) from every row of ``Z`` (N, 2) with
    the parameter vector ``PAR[q]`` (N, P), independently, in one compiled call: with more than one
    numba thread on the threads (a ``parallel=True`` kernel, rows handed out one at a time), else in
    a plain loop. Row q fills ``out_log[q]`` (N, n_batches, 2), ``out_trace[q]`` (NaN),
    ``out_z[q]`` (N, 3), ``out_strobe[q]`` (N, m, 2) and ``status[q]`` (int64[N]), exactly as one
    :func:`spectrum_map` call would (the same compiled arithmetic, whatever the thread)."""
    args = (Z, PAR, rtol, n_batches, per_batch, out_log, out_trace, out_z, out_strobe, status, stop)
    if get_num_threads() > 1 and Z.shape[0] > 1:
        with parallel_chunksize(1):  # rows differ in cost: handed out one at a time (this thread's setting)
            _spectrum_rows_threads(*args)
    else:
        _spectrum_rows_serial(*args)


@njit(cache=True)
def nearest_candidates(p, counts, js):
    """For each point i of ``p`` (n, 2), the points j ≠ i whose squared distance
    dx² + dy² is within a relative 1e-12 (plus 1e-300) of the smallest: its nearest neighbour
    under any rounding of the distance (a correctly rounded √ or hypot moves a distance by less
    than 1e-15 relative) is among them. ``counts[i]`` gets their number; ``js`` their indices,
    point after point, as far as it holds them. Returns the total (larger than ``js``: call again
    with room for it)."""
    n = p.shape[0]
    m = 0
    for i in range(n):
        best = np.inf
        for j in range(n):
            if j != i:
                dx = p[i, 0] - p[j, 0]
                dy = p[i, 1] - p[j, 1]
                s = dx * dx + dy * dy
                if s < best:
                    best = s
        lim = best * (1.0 + 1e-12) + 1e-300
        c = 0
        for j in range(n):
            if j != i:
                dx = p[i, 0] - p[j, 0]
                dy = p[i, 1] - p[j, 1]
                if dx * dx + dy * dy <= lim:
                    if m < js.shape[0]:
                        js[m] = j
                    m += 1
                    c += 1
        counts[i] = c
    return m


@njit(cache=True, nogil=True)
def system_spectrum_map(sa, z, rtol, n_transient, n_batches, per_batch, with_trace, out_log, out_trace, out_z,
                        out_contact, out_strobe, stop):
    """Benettin's spectrum of an n-DOF period map (:mod:`.system_flow`) from ``z`` (scaled, phase 0):
    as :func:`spectrum_map` with the 2n × 2n monodromy of each period.

    Outputs: ``out_log[b, i]`` Σ ln R_ii over batch b (i < 2n); ``out_trace[b]`` ∫ tr J dτ over
    batch b (:func:`system_trace_integral`; NaN when not ``with_trace`` or a period took more than
    :data:`REC_ROWS` steps); ``out_z`` the end state; ``out_contact[i]`` the fraction of the
    batches' time element i is in contact (NaN when not ``with_trace``); ``out_strobe`` (m, 2n) the
    last m stroboscopic points of the run (m ≤ the periods averaged; m = 0 for none). The step
    records of ``with_trace`` leave the steps, hence the exponents, unchanged."""
    n2 = z.shape[0]
    m = sa.U.shape[0]
    T = 2.0 * math.pi / sa.r
    mode = np.zeros(m, dtype=np.bool_)
    y2 = z.copy()
    initial_modes(sa, y2, mode)
    h = 0.01
    no_rec = np.empty((0, 1))
    for _ in range(n_transient):
        h, _i, _ns, _ne, st = system_advance(sa, y2, 0.0, T, mode, h, rtol, rtol, no_rec, np.int64(0),
                                             np.int64(MAX_STEPS_PER_PERIOD))
        if st != STATUS_OK:
            return st
        if stop[0] != 0:
            return STATUS_INTERRUPTED
    rec = np.empty((REC_ROWS, 2 + m + 8 * n2)) if with_trace else no_rec
    contact = np.zeros(m)
    y = np.zeros(n2 + n2 * n2)
    for i in range(n2):
        y[i] = y2[i]
    Q = np.eye(n2)
    A = np.empty((n2, n2))
    first_kept = n_batches * per_batch - out_strobe.shape[0]
    for b in range(n_batches):
        logr = np.zeros(n2)
        tr = 0.0
        for q in range(per_batch):
            for i in range(n2 * n2):
                y[n2 + i] = 0.0
            for i in range(n2):
                y[n2 + i * n2 + i] = 1.0
            h, irec, _ns, _ne, st = system_advance(sa, y, 0.0, T, mode, h, rtol, rtol, rec, np.int64(0),
                                                   np.int64(MAX_STEPS_PER_PERIOD))
            if st == STATUS_RECORD_FULL:
                tr = math.nan
            elif st != STATUS_OK:
                return st
            elif with_trace:
                tr += system_trace_integral(sa, rec, irec, contact)
            kept = b * per_batch + q - first_kept
            if kept >= 0:
                for i in range(n2):
                    out_strobe[kept, i] = y[i]
            for i in range(n2):
                for j in range(n2):
                    s = 0.0
                    for p in range(n2):
                        s += y[n2 + i * n2 + p] * Q[p, j]
                    A[i, j] = s
            if not gram_schmidt(A, Q, logr):
                return STATUS_NONFINITE
            if stop[0] != 0:
                return STATUS_INTERRUPTED
        for i in range(n2):
            out_log[b, i] = logr[i]
        out_trace[b] = tr if with_trace else math.nan
    for i in range(n2):
        out_z[i] = y[i]
    for i in range(m):
        out_contact[i] = contact[i] / (n_batches * per_batch * T) if with_trace else math.nan
    return STATUS_OK
