"""Newton's method on the tangential period map (compiled, pure): the loop of
:func:`contactvib.friction.newton.newton_steady` without the interpreter between its period maps.

The period map P over one normal period of the phase-0 state z = (w, w', f_t) is
:func:`.friction_period.run_period` from z with its quadratures zeroed. Newton steps
z ← z + (I − J)⁻¹ (P(z) − z) (a 3 × 3 system: :func:`.linalg.solve3`), J carried in (``has_jac``) or by
forward differences, improved by Broyden's update after each step and recomputed where a step
does not halve the relative distance of z and P(z).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .friction import N_STATE, SLIP
from .friction_period import S_WIDTH, run_period, state_distance
from .linalg import solve3
from .status import STATUS_OK

#: Outcomes of :func:`newton_period_map`.
NEWTON_CONVERGED, NEWTON_FAILED = 0, 1


@njit(cache=True)
def _map(rec, par, tpar, rtol, scale, z3, mode, sigma, out, times, wr):
    """``out`` = P(z3) with its quadratures; times and w range of the period. Returns
    (status, mode, σ at the period's end)."""
    out[:] = 0.0
    out[:3] = z3
    times[:] = 0.0
    wr[0] = math.inf
    wr[1] = -math.inf
    st, mode, sigma, _h = run_period(rec, 0.0, out, mode, sigma, 0.05, par, tpar, rtol, scale, times, wr,
                                     np.empty(0), np.empty((0, S_WIDTH)), np.zeros(1, np.int64))
    return st, mode, sigma


@njit(cache=True)
def fd_jacobian(rec, par, tpar, rtol, scale, z, mode, sigma, pz, fd_step, jac):
    """∂P/∂z at ``z`` into ``jac`` by forward differences (P(z) = ``pz``); returns the status."""
    zp = np.empty(3)
    out = np.empty(N_STATE)
    times = np.empty(4)
    wr = np.empty(2)
    for i in range(3):
        dz = fd_step * (scale[i] + abs(z[i]))
        zp[:] = z
        zp[i] += dz
        st, _m, _s = _map(rec, par, tpar, rtol, scale, zp, mode, sigma, out, times, wr)
        if st != STATUS_OK:
            return st
        for r in range(3):
            jac[r, i] = (out[r] - pz[r]) / dz
    return STATUS_OK


@njit(cache=True)
def newton_period_map(rec, par, tpar, rtol, scale, z0, mode, sigma, jac, has_jac, tol, max_steps, fd_step):
    """The fixed point of the period map from ``z0`` in ``mode`` (σ ``sigma``) to the relative
    distance ``tol`` of z and P(z), the phase-0 mode repeating; ``jac`` (3 × 3, used when
    ``has_jac``) is updated in place.

    Returns
    -------
    outcome, z, mode, sigma, has_jac, pz, m1, s1, times, wr, runs
        ``NEWTON_CONVERGED`` or ``NEWTON_FAILED``; the fixed point and its mode; whether ``jac``
        holds a Jacobian; the period from the fixed point (P(z) with its quadratures, the mode
        after it, times in each mode and switches, range of w); the period maps computed.
    """
    z = z0.copy()
    pz = np.empty(N_STATE)
    times = np.empty(4)
    wr = np.empty(2)
    last_z = np.empty(3)
    last_p = np.empty(3)
    have_last = False
    d_prev = math.inf
    runs = 0
    rhs = np.empty(3)
    step = np.empty(3)
    a = np.empty((3, 3))
    for _k in range(max_steps):
        st, m1, s1 = _map(rec, par, tpar, rtol, scale, z, mode, sigma, pz, times, wr)
        runs += 1
        if st != STATUS_OK:
            return NEWTON_FAILED, z, mode, sigma, has_jac, pz, m1, s1, times, wr, runs
        d = state_distance(pz, z, scale)
        if d <= tol and m1 == mode and (mode != SLIP or s1 == sigma):
            return NEWTON_CONVERGED, z, mode, sigma, has_jac, pz, m1, s1, times, wr, runs
        if has_jac and have_last:  # Broyden: the secant of the last step
            nz = 0.0
            for i in range(3):
                step[i] = z[i] - last_z[i]
                nz += step[i] * step[i]
            if nz > 0.0:
                for r in range(3):
                    acc = pz[r] - last_p[r]
                    for c in range(3):
                        acc -= jac[r, c] * step[c]
                    for c in range(3):
                        jac[r, c] += acc * step[c] / nz
        if not has_jac or d > 0.5 * d_prev:
            st = fd_jacobian(rec, par, tpar, rtol, scale, z, mode, sigma, pz, fd_step, jac)
            runs += 3
            if st != STATUS_OK:
                return NEWTON_FAILED, z, mode, sigma, False, pz, m1, s1, times, wr, runs
            has_jac = True
        d_prev = d
        for i in range(3):
            last_z[i] = z[i]
            last_p[i] = pz[i]
            rhs[i] = pz[i] - z[i]
            for c in range(3):
                a[i, c] = (1.0 if i == c else 0.0) - jac[i, c]
        have_last = True
        if not solve3(a, rhs, step):
            return NEWTON_FAILED, z, mode, sigma, has_jac, pz, m1, s1, times, wr, runs
        for i in range(3):
            z[i] += step[i]
        mode, sigma = m1, s1
    return NEWTON_FAILED, z, mode, sigma, has_jac, pz, mode, sigma, times, wr, runs


__all__ = ["NEWTON_CONVERGED", "NEWTON_FAILED", "newton_period_map", "fd_jacobian"]
