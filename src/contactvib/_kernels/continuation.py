"""Residual and Jacobian of periodic orbits of the stroboscopic map, orbit extrema (compiled, pure).

Unknowns ``u = (x, x', q)``: the orbit point at phase 0 (nondimensional, :mod:`.flow`) and one
parameter ``q = par[ip]`` (``ip = 4``: the frequency ratio ``r = f_e/f_n0``; ``ip = 3``: the
amplitude ``p = P_a/Q``). Equations::

    G(u) = P^k(z; q) − z = 0                                   (2 equations)

(the pseudo-arclength equation, predictor, corrector and step control are those of the one
engine, :mod:`contactvib.continuation.engine`). The Jacobian of ``G`` is ``[M − I | ∂P^k/∂q]``:
the monodromy ``M`` from the variational equations (:func:`.shooting.strobe_map`, saltation at
the contact events) and the parameter column: for r from the sensitivity equation integrated
with them, the period ``T = 2π/r`` moving with r included (:func:`.shooting.strobe_map_dr`); for
the amplitude by central differences of the map.

The null vector of the 2×3 Jacobian (the branch tangent) has the ``q``-component
``det(M − I)`` (up to a factor): it changes sign at a fold.

Also here, for the engine's small problems (n + 1 ≤ 8 unknowns): the bordered Newton step and
the bordered null vector (:func:`bordered_newton_step`, :func:`null_vector`), solved by
:func:`.linalg.solve_dense`; larger ones (harmonic balance) use LAPACK.

References
----------
H. B. Keller, *Lectures on Numerical Methods in Bifurcation Problems*, Springer (1987), Ch. 4.
E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*, SIAM (2003), Ch. 2.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .linalg import solve_dense
from .orbit import RECORD_CAP_MAX, measure_orbit, record_steps
from .shooting import map_residual, strobe_map, strobe_map_dr
from .status import STATUS_OK

#: Index of the frequency ratio r in ``par``: its column of the Jacobian is exact (sensitivity).
IP_RATIO = 4
#: relative step of the central difference in the parameter (floor 1e-3 absolute)
FD_REL = 1e-5


@njit(cache=True)
def fd_step(q):
    """Central-difference step for parameter value ``q``."""
    return FD_REL * max(abs(q), 1e-3)


@njit(cache=True)
def residual_jacobian(u, k, par, ip, rtol, out_G, out_J, out_M):
    """G(u) and its 2×3 Jacobian ``[M − I | ∂P^k/∂q]`` at ``u = (x, x', q)``. For the frequency
    ratio (``ip`` = :data:`IP_RATIO`) G, M and ∂P^k/∂r come from one run of the flow with its
    sensitivity equation (:func:`.shooting.strobe_map_dr`); for the amplitude, G and M from
    :func:`.shooting.map_residual` and the column by central differences of the map.

    ``par`` is used as scratch (``par[ip]`` is set to ``u[2]``). Returns a :mod:`.flow` status.
    """
    z = np.empty(2)
    z[0] = u[0]
    z[1] = u[1]
    pz = np.empty(2)
    par[ip] = u[2]
    if ip == IP_RATIO:  # the parameter column from the sensitivity equation, in the same run
        dr = np.empty(2)
        st = strobe_map_dr(z, k, par, rtol, rtol, pz, out_M, dr)
        if st != STATUS_OK:
            return st
        out_G[0] = pz[0] - z[0]
        out_G[1] = pz[1] - z[1]
        out_J[0, 0] = out_M[0, 0] - 1.0
        out_J[0, 1] = out_M[0, 1]
        out_J[1, 0] = out_M[1, 0]
        out_J[1, 1] = out_M[1, 1] - 1.0
        out_J[0, 2] = dr[0]
        out_J[1, 2] = dr[1]
        return STATUS_OK
    st, g0, g1, _sc, _res = map_residual(z, k, par, rtol, rtol, pz, out_M)
    if st != STATUS_OK:
        return st
    out_G[0] = g0
    out_G[1] = g1
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
def residual_jacobian_step(u, k, par, ip, rtol, bord, u_prev, ds, w):
    """:func:`residual_jacobian` at ``u``, its relative residual ``max|G| / max(1, |x|, |x'|)``
    and the bordered Newton step from it (:func:`bordered_newton_step`) in one call: one
    crossing of the Python–numba boundary per corrector iteration of a shooting problem.

    Returns ``(status, residual, N, step, G, J, M, u_new)``.
    """
    G = np.empty(2)
    J = np.empty((2, 3))
    M = np.empty((2, 2))
    u_new = np.empty(3)
    st = residual_jacobian(u, k, par, ip, rtol, G, J, M)
    if st != STATUS_OK:
        return st, math.inf, 0.0, math.nan, G, J, M, u_new
    res = max(abs(G[0]), abs(G[1])) / max(1.0, abs(u[0]), abs(u[1]))
    cons, step = bordered_newton_step(J, G, bord, u, u_prev, ds, w, u_new)
    return st, res, cons, step, G, J, M, u_new


@njit(cache=True)
def bordered_newton_step(J, F, bord, u, u_prev, ds, w, out_u):
    """Newton step of a pseudo-arclength corrector (small dense systems, any size n)::

        N = bord · (u − u_prev) − ds                  (bord = τ w: the hyperplane's normal)
        [ J    ] d = −[ F ]         J: (n, n+1) Jacobian, F: (n,) residual
        [ bordᵀ]      [ N ]

    ``out_u = u + d``. Returns ``(N, max |w_i d_i|)``; the step is NaN when the system is
    singular (``out_u`` undefined then).
    """
    n1 = J.shape[1]
    cons = 0.0
    for i in range(n1):
        cons += bord[i] * (u[i] - u_prev[i])
    cons -= ds
    A = np.empty((n1, n1))
    y = np.empty(n1)
    d = np.empty(n1)
    for i in range(n1 - 1):
        for j in range(n1):
            A[i, j] = J[i, j]
        y[i] = -F[i]
    for j in range(n1):
        A[n1 - 1, j] = bord[j]
    y[n1 - 1] = -cons
    if not solve_dense(A, y, d):
        return cons, math.nan
    step = 0.0
    for i in range(n1):
        step = max(step, abs(d[i] * w[i]))
        out_u[i] = u[i] + d[i]
    return cons, step


@njit(cache=True)
def null_vector(J, w, direction, out_t):
    """Unit null vector of ``J W⁻¹`` (J: (n, n+1)) with ``direction · t > 0``, from
    ``[J W⁻¹; directionᵀ] t = [0; 1]``; returns False if that system is singular."""
    n1 = J.shape[1]
    A = np.empty((n1, n1))
    y = np.zeros(n1)
    for i in range(n1 - 1):
        for j in range(n1):
            A[i, j] = J[i, j] / w[j]
    for j in range(n1):
        A[n1 - 1, j] = direction[j]
    y[n1 - 1] = 1.0
    if not solve_dense(A, y, out_t):
        return False
    nrm = 0.0
    for i in range(n1):
        nrm += out_t[i] * out_t[i]
    nrm = math.sqrt(nrm)
    if nrm == 0.0 or not math.isfinite(nrm):
        return False
    for i in range(n1):
        out_t[i] /= nrm
    return True


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
