"""The structure's flow map, stroboscopic map, step records and their sampling (compiled, pure).

Built on :func:`.system_flow.advance` (the scaled equation and its events are described there):

* :func:`flow_map` — the state at τ1 from τ0 and (optionally) the monodromy ∂y(τ1)/∂y(τ0);
* :func:`strobe_map` — k excitation periods T = 2π/r from phase 0, period by period;
* :func:`record_span` — a run with its step records (dense output per step), sampled by
  :func:`sample_records` (state and modes at given τ) and integrated by
  :func:`mean_element_forces` (∫ f_i dτ per element, Gauss–Legendre on each step: steps end on
  the switches, so each is smooth);
* :func:`element_forces` — f_i at sampled states (0 out of contact).

The settling of a start (the search's and the sweeps') is :mod:`.system_settle`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .dop853 import record_value
from .status import STATUS_OK
from .system_flow import GAUSS_W, GAUSS_X, MAX_STEPS_PER_PERIOD, advance, element_force, element_state, initial_modes


@njit(cache=True)
def _start(sa, z, nvar):
    """The state vector from z = (x, x'), with Φ = I when ``nvar``, and the element modes."""
    n2 = z.shape[0]
    N = n2 + n2 * n2 if nvar else n2
    y = np.zeros(N)
    for i in range(n2):
        y[i] = z[i]
    if nvar:
        for i in range(n2):
            y[n2 + i * n2 + i] = 1.0
    mode = np.zeros(sa.U.shape[0], dtype=np.bool_)
    initial_modes(sa, y, mode)
    return y, mode


@njit(cache=True)
def _unpack(y, out_z, out_phi):
    n2 = out_z.shape[0]
    for i in range(n2):
        out_z[i] = y[i]
    if out_phi.shape[0] == n2:
        for i in range(n2):
            for j in range(n2):
                out_phi[i, j] = y[n2 + i * n2 + j]


@njit(cache=True)
def flow_map(sa, z, t0, t1, rtol, atol, out_z, out_phi):
    """Integrate z = (x, x') from τ = ``t0`` to ``t1``; ``out_z`` ← the end state and, if
    ``out_phi`` is (2n, 2n) rather than (0, 0), ``out_phi`` ← the monodromy. Returns a status code."""
    nvar = out_phi.shape[0] == z.shape[0]
    y, mode = _start(sa, z, nvar)
    periods = abs(t1 - t0) * sa.r / (2.0 * math.pi) + 1.0
    _h, _i, _ns, _ne, st = advance(sa, y, t0, t1, mode, 0.01, rtol, atol, np.empty((0, 1)), np.int64(0),
                                   np.int64(periods * MAX_STEPS_PER_PERIOD))
    _unpack(y, out_z, out_phi)
    return st


@njit(cache=True)
def strobe_map(sa, z, k, rtol, atol, out_z, out_phi):
    """Advance z by ``k`` excitation periods from phase 0 (each period from τ = 0 to T); end state
    and monodromy (as :func:`flow_map`). Returns a status code."""
    nvar = out_phi.shape[0] == z.shape[0]
    y, mode = _start(sa, z, nvar)
    T = 2.0 * math.pi / sa.r
    h = 0.01
    for _ in range(k):
        h, _i, _ns, _ne, st = advance(sa, y, 0.0, T, mode, h, rtol, atol, np.empty((0, 1)), np.int64(0),
                                      np.int64(MAX_STEPS_PER_PERIOD))
        if st != STATUS_OK:
            return st
    _unpack(y, out_z, out_phi)
    return STATUS_OK


@njit(cache=True)
def record_span(sa, z, k, rtol, atol, rec, out_z):
    """Integrate ``k`` excitation periods from z at phase 0, recording every step in ``rec``.
    Returns (rows used, status); status ``STATUS_RECORD_FULL`` asks for a larger ``rec``."""
    y, mode = _start(sa, z, False)
    T = 2.0 * math.pi / sa.r
    h = 0.01
    irec = np.int64(0)
    st = STATUS_OK
    for j in range(k):
        h, irec, _ns, _ne, st = advance(sa, y, j * T, (j + 1) * T, mode, h, rtol, atol, rec, irec,
                                        np.int64(MAX_STEPS_PER_PERIOD))
        if st != STATUS_OK:
            break
    _unpack(y, out_z, np.empty((0, 0)))
    return irec, st


@njit(cache=True)
def sample_records(rec, nrec, m, tau, out_y, out_mode):
    """The state (x, x') [2n, len(tau)] and modes [m, len(tau)] at the sorted times ``tau``
    inside the recorded span."""
    n2 = out_y.shape[0]
    o = 2 + m
    row = 0
    for s in range(tau.shape[0]):
        ts = tau[s]
        while row < nrec - 1 and ts > rec[row, 0] + rec[row, 1]:
            row += 1
        h = rec[row, 1]
        theta = (ts - rec[row, 0]) / h if h > 0.0 else 0.0
        theta = min(1.0, max(0.0, theta))
        for c in range(n2):
            out_y[c, s] = record_value(rec, row, o, o + n2, n2, theta, c)
        for i in range(m):
            out_mode[i, s] = rec[row, 2 + i] > 0.5


@njit(cache=True)
def element_forces(sa, ys, modes, out):
    """f_i [units of W_i] at the sampled states ``ys`` [2n, T] with modes [m, T] (0 out of contact)."""
    for s in range(ys.shape[1]):
        y = ys[:, s].copy()
        for i in range(out.shape[0]):
            if modes[i, s]:
                xi, xv = element_state(sa, i, y)
                out[i, s] = element_force(sa, i, xi, xv)
            else:
                out[i, s] = 0.0


@njit(cache=True)
def mean_element_forces(sa, rec, nrec, out):
    """∫ f_i dτ [units of W_i τ] of each element over the recorded steps (Gauss–Legendre, 8 nodes
    per step), into ``out`` [m]."""
    m = out.shape[0]
    n2 = 2 * sa.Kx.shape[0]
    o = 2 + m
    y = np.empty(n2)
    for i in range(m):
        out[i] = 0.0
    for row in range(nrec):
        h = rec[row, 1]
        for g in range(GAUSS_X.shape[0]):
            for c in range(n2):
                y[c] = record_value(rec, row, o, o + n2, n2, GAUSS_X[g], c)
            for i in range(m):
                if rec[row, 2 + i] > 0.5:
                    xi, xv = element_state(sa, i, y)
                    out[i] += GAUSS_W[g] * h * element_force(sa, i, xi, xv)
