"""The table law's Taylor recurrence (compiled, pure): the PCHIP spring of
:func:`.contact.spring` is a cubic on each interval between rows, so the series of the contact
mode on one interval is exact (:func:`series_table`); the rows, where the curve is only C¹, are
events of the Taylor flow (:func:`.taylor.advance_taylor_table`).
"""

from __future__ import annotations

from numba import njit

from .contact import DAMPING_HUNT_CROSSLEY, INV, P_DAMPING, P_S1, P_S2, power_table_update, table_interval


@njit(cache=True)
def table_segment(x, par):
    """Segment of the table law holding x ≥ 0: i with x_i <= x < x_{i+1}, or n − 1 for the
    linear continuation beyond the last row (the segments of :func:`series_table`)."""
    n = int(par[P_S1])
    if x >= par[int(par[P_S2]) + n - 1]:
        return n - 1
    return table_interval(max(x, 0.0), par)


@njit(cache=True, inline="always")
def series_table(E, X, V, W, P, N, par, seg):
    """Taylor coefficients of the contact mode ``κ x'' = E(τ) − f_s(x) − f_d(x, x')`` of the
    table law on its segment ``seg``, where the PCHIP spring is the cubic
    ``f_s = c0 + c1 u + c2 u² + c3 u³`` in ``u = x − x_i`` (h = x_{i+1} − x_i)::

        c0 = f_i, c1 = d_i, c2 = (3 (f_{i+1} − f_i)/h − 2 d_i − d_{i+1})/h,
        c3 = (2 (f_i − f_{i+1})/h + d_i + d_{i+1})/h²

    (the Hermite form of :func:`_table_spring` expanded; c2 = c3 = 0 on the linear continuation
    beyond the last row, seg = n − 1), so its series is exact: the Cauchy products ``(u²)_k``
    (summed symmetrically), ``(u³)_k`` of ``u_0 = x_0 − x_i``, ``u_k = x_k``. Damping: power
    ``c x^l x'`` (integer l; ``x^l x' = (x^(l+1))'/(l+1)`` with ``(x²)_k = (u²)_k + 2 x_i u_k``
    for l = 1, else :func:`power_table_update`) or Hunt–Crossley ``c f_s x'`` (the Cauchy
    product with V).

    Parameters
    ----------
    E : float64[N]
        Taylor coefficients of the excitation side (1 + e(τ) about τ0).
    X, V : float64[N + 1]
        X[0], V[0] given (x on the segment, x' at τ0); X[1..N], V[1..N] written.
    W : float64[≥ l + 2, N + 1]
        Work array for the powers of x (power damping; rows 1..l+1 written).
    P : float64[4, N + 1]
        Work array: the series of u, u² and f_s (rows 0, 1, 3).
    N : int
        Order.
    par : float64[:]
        Kernel parameters (κ = par[0], l = par[1], c = par[2], the table from par[P_S2]).
    seg : int
        The segment (:func:`table_segment`).
    """
    n = int(par[P_S1])
    o = int(par[P_S2])
    kappa = par[0]
    c = par[2]
    il = int(par[1])
    hunt_crossley = par[P_DAMPING] == DAMPING_HUNT_CROSSLEY
    xl = par[o + seg]
    c0 = par[o + n + seg]
    c1 = par[o + 2 * n + seg]
    c2 = 0.0
    c3 = 0.0
    if seg < n - 1:
        h = par[o + seg + 1] - xl
        q = (par[o + n + seg + 1] - c0) / h
        d1 = par[o + 2 * n + seg + 1]
        c2 = (3.0 * q - 2.0 * c1 - d1) / h
        c3 = (c1 + d1 - 2.0 * q) / (h * h)
    inv_kappa = 1.0 / kappa
    U = P[0]
    U2 = P[1]
    F = P[3]
    U[0] = X[0] - xl
    U2[0] = U[0] * U[0]
    if not hunt_crossley and il != 1:
        W[1, 0] = X[0]
        for q in range(2, il + 2):
            W[q, 0] = W[q - 1, 0] * X[0]
    for k in range(N):
        s3 = 0.0  # (u³)_k
        for j in range(k + 1):
            s3 += U2[j] * U[k - j]
        f = c1 * U[k] + c2 * U2[k] + c3 * s3
        if k == 0:
            f += c0
        F[k] = f
        m = k + 1
        X[m] = V[k] * INV[m]
        U[m] = X[m]
        s2 = 0.0  # (u²)_m, the symmetric sum
        for j in range((m + 1) // 2):
            s2 += U[j] * U[m - j]
        s2 = 2.0 * s2
        if m % 2 == 0:
            s2 += U[m // 2] * U[m // 2]
        U2[m] = s2
        a = E[k] - f
        if hunt_crossley:
            d = 0.0
            for j in range(k + 1):
                d += F[j] * V[k - j]
            a -= c * d
        elif il == 1:  # (x²)_m = (u²)_m + 2 x_i u_m
            a -= c * m * 0.5 * (s2 + 2.0 * xl * U[m])
        elif c != 0.0:
            power_table_update(m, X, W, il + 1)
            a -= c * m / (il + 1) * W[il + 1, m]
        V[m] = a * inv_kappa * INV[m]
