"""Pseudo-arclength corrector for periodic orbits of the stroboscopic map (compiled, pure).

Unknowns ``u = (x, x', q)``: the orbit point at phase 0 (nondimensional, :mod:`.flow`) and one
parameter ``q = par[ip]`` (``ip = 4``: the frequency ratio ``r = f_e/f_n0``; ``ip = 3``: the
amplitude ``p = P_a/Q``). Equations::

    G(u) = P^k(z; q) − z = 0                                   (2 equations)
    N(u) = τ · W (u − u_prev) − Δs = 0                          (pseudo-arclength, 1 equation)

with ``W = diag(w)`` the scaling of the unknowns (``1/max(1,|x|,|x'|)`` for the state,
``1/|q|`` for the parameter: arclength measures relative change) and ``τ`` the unit tangent in
scaled coordinates. The Jacobian of ``G`` is ``[M − I | ∂P^k/∂q]``: the monodromy ``M`` from the
variational equations (:func:`.shooting.strobe_map`, saltation at the contact events) and the
parameter column by central differences of the map. The excitation period ``T = 2π/r`` depends on
``r``; the finite difference of the whole map ``P(z; r) = φ(2π/r; z, r)`` includes that.

The null vector of the 2×3 Jacobian (the branch tangent) is the cross product of its rows; its
``q``-component is ``det(M − I)`` (times the scaling): it changes sign at a fold.

References
----------
H. B. Keller, *Lectures on Numerical Methods in Bifurcation Problems*, Springer (1987), Ch. 4.
E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*, SIAM (2003), Ch. 2.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .flow import STATUS_OK, STATUS_RECORD_FULL
from .orbit import RECORD_CAP_MAX, measure_orbit, record_steps
from .shooting import state_scale, strobe_map

STATUS_SINGULAR = 20
STATUS_DIVERGED = 21
STATUS_MAXITER = 22

#: relative step of the central difference in the parameter (floor 1e-3 absolute)
FD_REL = 1e-5


@njit(cache=True)
def fd_step(q):
    """Central-difference step for parameter value ``q``."""
    return FD_REL * max(abs(q), 1e-3)


@njit(cache=True)
def residual_jacobian(u, k, par, ip, rtol, out_G, out_J, out_M):
    """G(u) and its 2×3 Jacobian ``[M − I | ∂P^k/∂q]`` at ``u = (x, x', q)``.

    ``par`` is used as scratch (``par[ip]`` is set to ``u[2]``). Returns a :mod:`.flow` status.
    """
    z = np.empty(2)
    z[0] = u[0]
    z[1] = u[1]
    pz = np.empty(2)
    par[ip] = u[2]
    st = strobe_map(z, k, par, rtol, rtol, pz, out_M)
    if st != STATUS_OK:
        return st
    out_G[0] = pz[0] - z[0]
    out_G[1] = pz[1] - z[1]
    out_J[0, 0] = out_M[0, 0] - 1.0
    out_J[0, 1] = out_M[0, 1]
    out_J[1, 0] = out_M[1, 0]
    out_J[1, 1] = out_M[1, 1] - 1.0
    h = fd_step(u[2])
    none = np.empty((0, 0))
    pp = np.empty(2)
    pm = np.empty(2)
    par[ip] = u[2] + h
    st = strobe_map(z, k, par, rtol, rtol, pp, none)
    if st != STATUS_OK:
        par[ip] = u[2]
        return st
    par[ip] = u[2] - h
    st = strobe_map(z, k, par, rtol, rtol, pm, none)
    par[ip] = u[2]
    if st != STATUS_OK:
        return st
    out_J[0, 2] = (pp[0] - pm[0]) / (2.0 * h)
    out_J[1, 2] = (pp[1] - pm[1]) / (2.0 * h)
    return STATUS_OK


@njit(cache=True)
def tangent(J, w, out_t):
    """Unit null vector of ``J W⁻¹`` (scaled coordinates) into ``out_t``; returns its norm."""
    a0 = J[0, 0] / w[0]
    a1 = J[0, 1] / w[1]
    a2 = J[0, 2] / w[2]
    b0 = J[1, 0] / w[0]
    b1 = J[1, 1] / w[1]
    b2 = J[1, 2] / w[2]
    t0 = a1 * b2 - a2 * b1
    t1 = a2 * b0 - a0 * b2
    t2 = a0 * b1 - a1 * b0
    nrm = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    if nrm == 0.0 or not math.isfinite(nrm):
        return 0.0
    out_t[0] = t0 / nrm
    out_t[1] = t1 / nrm
    out_t[2] = t2 / nrm
    return nrm


@njit(cache=True)
def solve3(A, b, out):
    """Solve a 3×3 system by Gaussian elimination with partial pivoting; False if singular."""
    M = A.copy()
    y = b.copy()
    for c in range(3):
        p = c
        for i in range(c + 1, 3):
            if abs(M[i, c]) > abs(M[p, c]):
                p = i
        if M[p, c] == 0.0 or not math.isfinite(M[p, c]):
            return False
        if p != c:
            for j in range(3):
                tmp = M[c, j]
                M[c, j] = M[p, j]
                M[p, j] = tmp
            tmp = y[c]
            y[c] = y[p]
            y[p] = tmp
        for i in range(c + 1, 3):
            f = M[i, c] / M[c, c]
            for j in range(c, 3):
                M[i, j] -= f * M[c, j]
            y[i] -= f * y[c]
    for i in range(2, -1, -1):
        acc = y[i]
        for j in range(i + 1, 3):
            acc -= M[i, j] * out[j]
        out[i] = acc / M[i, i]
    return True


@njit(cache=True)
def correct(u_pred, u_prev, tau, w, ds, k, par, ip, rtol, tol, max_iter, out_u, out_J, out_M):
    """Newton corrector onto the branch on the hyperplane ``τ·W(u − u_prev) = ds``.

    ``ds = 0`` with ``τ = (0, 0, 1)`` and ``u_prev = u_pred`` fixes ``q`` (natural parameter).
    Converged when ``|G|∞ ≤ tol · max(1, |z|∞)`` and the last scaled Newton step ≤ 1e-3 ... on
    return ``out_u``, ``out_J`` and ``out_M`` hold the last iterate, its Jacobian and monodromy.

    Returns
    -------
    status : int
        ``STATUS_OK`` or a flow / ``STATUS_*`` code.
    iterations : int
        Jacobian evaluations used.
    """
    u = u_pred.copy()
    G = np.empty(2)
    A = np.empty((3, 3))
    b = np.empty(3)
    d = np.empty(3)
    for it in range(max_iter + 1):
        st = residual_jacobian(u, k, par, ip, rtol, G, out_J, out_M)
        if st != STATUS_OK:
            return st, it + 1
        for i in range(3):
            out_u[i] = u[i]
        sc = state_scale(u[0], u[1])
        res = max(abs(G[0]), abs(G[1])) / sc
        cons = 0.0
        for i in range(3):
            cons += tau[i] * w[i] * (u[i] - u_prev[i])
        cons -= ds
        if res <= tol and abs(cons) <= 1e-9:
            return STATUS_OK, it + 1
        if it == max_iter:
            break
        for i in range(2):
            for j in range(3):
                A[i, j] = out_J[i, j]
            b[i] = -G[i]
        for j in range(3):
            A[2, j] = tau[j] * w[j]
        b[2] = -cons
        if not solve3(A, b, d):
            return STATUS_SINGULAR, it + 1
        step = 0.0
        for i in range(3):
            step = max(step, abs(d[i] * w[i]))
        if not math.isfinite(step) or step > 1.0:
            return STATUS_DIVERGED, it + 1
        for i in range(3):
            u[i] += d[i]
        if u[2] <= 0.0 and ip == 4:
            return STATUS_DIVERGED, it + 1
    return STATUS_MAXITER, max_iter + 1


@njit(cache=True)
def orbit_range(z, k, par, rtol):
    """Extrema of ``x`` over the period-``k`` orbit through ``z`` (:func:`.orbit.measure_orbit`).

    Returns
    -------
    xmin, xmax : float
        Smallest and largest x over the orbit [y0].
    flight : float
        Fraction of the period with x ≤ 0.
    n_min : int
        Local minima over the orbit.
    status : int
    """
    rec, _ze, tf, _ne, st = record_steps(z, 0.0, k, par, rtol, 256 * k, RECORD_CAP_MAX)
    if st != STATUS_OK:
        return math.nan, math.nan, math.nan, 0, st
    xmin, xmax, flight, n_min, _t, _x, _m = measure_orbit(rec, tf, k, par[4])
    return xmin, xmax, flight, n_min, STATUS_OK
