"""Stroboscopic map, monodromy and Newton shooting for period-k orbits (compiled, pure).

The stroboscopic map ``P`` advances a state ``z = (x, x')`` by one excitation period
``T = 2π/r`` (nondimensional time, phase 0 where the force ``p cos(rτ)`` is largest). A period-k
orbit solves ``G(z) = P^k(z) − z = 0``; Newton's method uses ``G'(z) = M − I`` with the monodromy
matrix ``M = ∂P^k/∂z`` from the variational equation integrated through the contact events
(:mod:`.flow`). The eigenvalues of ``M`` are the Floquet multipliers of the orbit.

Defined here once, for every periodic orbit of the normal motion: the residual of the period map
(:func:`map_residual`), the Newton step (:func:`newton_step`, the 2×2 solve of
:func:`.linalg.solve2`), Newton's method with its callers' options (:func:`newton_map`;
:func:`newton_orbit`), the stability rule (:data:`STABILITY_TOL`, :func:`stable_multipliers`,
:func:`stable_monodromy`, :func:`is_stable`) and the minimal-period tolerance
(:data:`MINIMAL_PERIOD_TOL`).

References
----------
T. S. Parker, L. O. Chua, *Practical Numerical Algorithms for Chaotic Systems*, Springer (1989),
Ch. 5 (shooting).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .flow import REC_WIDTH, advance, initial_mode, rhs
from .linalg import solve2
from .status import (
    STATUS_NEWTON_DIVERGED,
    STATUS_NEWTON_MAXITER,
    STATUS_NEWTON_QUICK,
    STATUS_NEWTON_SINGULAR,
    STATUS_OK,
)

#: Stability rule of every periodic orbit: stable when max |Floquet multiplier| ≤ 1 + STABILITY_TOL
#: (the tolerance absorbs the error of the monodromy at a fold or a period doubling).
STABILITY_TOL = 1e-6

#: A period-k orbit has the smaller period d (a proper divisor of k) when P^d returns within this
#: relative distance (:func:`.settle.refine_stable_orbit`, :func:`.trace.continue_orbit`).
MINIMAL_PERIOD_TOL = 1e-6


MAX_STEPS_PER_PERIOD = 2_000_000


@njit(cache=True)
def state_scale(x, v):
    """Scale for relative distances between states [y0 and y0 ω_n0 units]: max(1, |x|, |v|)."""
    return max(1.0, abs(x), abs(v))


@njit(cache=True)
def advance_periods(y, k, par, rtol, atol):
    """Advance ``y`` in place by ``k`` excitation periods ``T = 2π/r`` from phase 0 (:func:`.flow.advance`,
    the mode and step proposal carried from one period to the next): the state (n = 2), with the
    monodromy (n = 6), and with the sensitivity to r (n = 8), which each period also gains
    ``f(T) dT/dr`` (``dT/dr = −2π/r²``: the period's end moves with r). Returns a :mod:`.flow`
    status code."""
    T = 2.0 * math.pi / par[4]
    contact = initial_mode(y[0], y[1])
    h = 0.01
    f = np.empty(8 if y.shape[0] == 8 else 0)  # the vector field at T, for the sensitivity only
    for _ in range(k):
        contact, h, _i, _ns, _tf, _ne, st = advance(
            y, 0.0, T, contact, h, par, rtol, atol, np.empty((0, REC_WIDTH)), np.int64(0),
            np.int64(MAX_STEPS_PER_PERIOD)
        )
        if st != STATUS_OK:
            return st
        if y.shape[0] == 8:
            rhs(contact, T, y, par, f)
            dT = -T / par[4]
            y[6] += f[0] * dT
            y[7] += f[1] * dT
    return STATUS_OK


@njit(cache=True, inline="always")
def _write_end(y, out_z, out_M):
    """The state of ``y`` into ``out_z`` and, if it has 4 entries, the monodromy into ``out_M``."""
    out_z[0] = y[0]
    out_z[1] = y[1]
    if out_M.shape[0] == 2:
        out_M[0, 0] = y[2]
        out_M[0, 1] = y[3]
        out_M[1, 0] = y[4]
        out_M[1, 1] = y[5]


@njit(cache=True)
def strobe_map(z, k, par, rtol, atol, out_z, out_M):
    """Advance ``z`` by ``k`` periods; write the end state and (if out_M has 4 entries) ``∂P^k/∂z``.

    Returns a :mod:`.flow` status code.
    """
    with_jac = out_M.shape[0] == 2
    y = np.zeros(6 if with_jac else 2)
    y[0] = z[0]
    y[1] = z[1]
    if with_jac:
        y[2] = 1.0
        y[5] = 1.0
    st = advance_periods(y, k, par, rtol, atol)
    if st == STATUS_OK:
        _write_end(y, out_z, out_M)
    return st


@njit(cache=True)
def strobe_map_dr(z, k, par, rtol, atol, out_z, out_M, out_dr):
    """:func:`strobe_map` with the monodromy (``out_M``) and the derivative ``∂P^k/∂r`` of the
    map with respect to the frequency ratio r (``out_dr``).

    Per period ``P(z; r) = φ(T(r); z, r)`` with ``T = 2π/r``, so ``∂P/∂r = s(T) + f(T) dT/dr``:
    the sensitivity ``s`` of the flow (:mod:`.flow`, n = 8) plus the vector field at the period's
    end times ``dT/dr = −2π/r²``; over k periods the chain rule carries ``s`` from one period to
    the next (``∂P^k/∂r = M ∂P^{k−1}/∂r + ∂P/∂r``; :func:`advance_periods`). Returns a
    :mod:`.flow` status code.
    """
    y = np.zeros(8)
    y[0] = z[0]
    y[1] = z[1]
    y[2] = 1.0
    y[5] = 1.0
    st = advance_periods(y, k, par, rtol, atol)
    if st == STATUS_OK:
        _write_end(y, out_z, out_M)
        out_dr[0] = y[6]
        out_dr[1] = y[7]
    return st


@njit(cache=True, inline='always')
def map_residual(z, k, par, rtol, atol, pz, M):
    """The residual ``g = P^k(z) − z`` of the period-k map and its Jacobian ``M − I`` (``M``,
    the monodromy, written into ``M``; ``P^k(z)`` into ``pz``).

    Returns
    -------
    status, g0, g1, scale, residual
        A :mod:`.flow` status; ``g``; the state scale :func:`state_scale` at ``z``; the relative
        closure ``|g|∞ / scale``.
    """
    st = strobe_map(z, k, par, rtol, atol, pz, M)
    if st != STATUS_OK:
        return st, 0.0, 0.0, 1.0, math.inf
    g0 = pz[0] - z[0]
    g1 = pz[1] - z[1]
    sc = state_scale(z[0], z[1])
    return STATUS_OK, g0, g1, sc, max(abs(g0), abs(g1)) / sc


@njit(cache=True)
def newton_step(M, g0, g1, sc):
    """Newton correction dz of the period-k map's fixed point: (M − I) dz = −g
    (:func:`.linalg.solve2`).

    ``M`` is the monodromy, ``g = P^k(z) − z`` and ``sc`` the state scale. Steps larger than 0.5
    (relative) are damped to 0.5; singular or diverging (> 10) steps fail.

    Returns
    -------
    status, dz0, dz1, step
        ``step`` is the relative size before damping.
    """
    ok, x0, x1 = solve2(M[0, 0] - 1.0, M[0, 1], M[1, 0], M[1, 1] - 1.0, g0, g1)
    if not ok:
        return STATUS_NEWTON_SINGULAR, 0.0, 0.0, math.inf
    dz0 = -x0
    dz1 = -x1
    step = max(abs(dz0), abs(dz1)) / sc
    if not math.isfinite(step) or step > 10.0:
        return STATUS_NEWTON_DIVERGED, 0.0, 0.0, step
    if step > 0.5:  # damped step far from the solution
        dz0 *= 0.5 / step
        dz1 *= 0.5 / step
    return STATUS_OK, dz0, dz1, step


@njit(cache=True, inline='always')
def newton_map(z0, k, par, rtol, atol, tol, max_evals, quick_step, out_z, out_M):
    """Newton's method on the period-k map: the one Newton iteration of every periodic orbit.

    Each evaluation integrates ``P^k`` with its monodromy (:func:`map_residual`); converged
    when ``|P^k(z) − z|∞ ≤ tol · max(1, |z|∞)``; otherwise the damped step of
    :func:`newton_step`. Options of the callers:

    ``max_evals``
        Largest number of map evaluations.
    ``quick_step``
        0: no step follows the last evaluation. > 0: a step follows every evaluation that has
        not converged, and a step of relative size ≤ ``quick_step`` ends the run with
        ``STATUS_NEWTON_QUICK`` (the closure after it is ~ step², which the caller checks on
        its own run without the variational equations).

    On return ``out_z`` holds the last evaluated iterate (after a quick step: the stepped
    point) and ``out_M`` the monodromy of the last evaluation.

    Returns
    -------
    status : int
        ``STATUS_OK`` (converged), ``STATUS_NEWTON_QUICK``, a Newton failure
        (``STATUS_NEWTON_SINGULAR``, ``_DIVERGED``, ``_MAXITER``) or a :mod:`.flow` status.
    residual : float
        The relative closure of the last completed evaluation (∞ before the first).
    n_evals : int
        Map evaluations done.
    """
    z = np.empty(2)
    z[0] = z0[0]
    z[1] = z0[1]
    pz = np.empty(2)
    M = np.empty((2, 2))
    residual = math.inf
    for it in range(max_evals):
        st, g0, g1, sc, res = map_residual(z, k, par, rtol, atol, pz, M)
        if st != STATUS_OK:
            return st, residual, it + 1
        residual = res
        out_z[0] = z[0]
        out_z[1] = z[1]
        for i in range(2):
            for j in range(2):
                out_M[i, j] = M[i, j]
        if residual <= tol:
            return STATUS_OK, residual, it + 1
        if it == max_evals - 1 and quick_step <= 0.0:
            break
        st, dz0, dz1, step = newton_step(M, g0, g1, sc)
        if st != STATUS_OK:
            return st, residual, it + 1
        z[0] += dz0
        z[1] += dz1
        if quick_step > 0.0 and step <= quick_step:
            out_z[0] = z[0]
            out_z[1] = z[1]
            return STATUS_NEWTON_QUICK, residual, it + 1
    return STATUS_NEWTON_MAXITER, residual, max_evals


@njit(cache=True)
def newton_orbit(z0, k, par, rtol, atol, tol, max_iter, out_z, out_M):
    """Newton shooting for a period-``k`` orbit started at ``z0``: :func:`newton_map` with
    ``max_iter`` steps (``max_iter + 1`` evaluations), no quick exit.

    Converged when ``|P^k(z) − z|∞ ≤ tol · max(1, |z|∞)``. On return ``out_z`` holds the last
    iterate and ``out_M`` its monodromy.

    Returns
    -------
    status : int
        ``STATUS_OK`` when converged.
    residual : float
        Relative closure ``|P^k(z) − z|∞ / max(1, |z|∞)`` at ``out_z``.
    """
    st, residual, _n = newton_map(z0, k, par, rtol, atol, tol, max_iter + 1, 0.0, out_z, out_M)
    return st, residual


@njit(cache=True, inline='always')
def stable_multipliers(mu_abs_max):
    """The stability rule (compiled): ``mu_abs_max ≤ 1 + STABILITY_TOL``; NaN is unstable."""
    return mu_abs_max <= 1.0 + STABILITY_TOL


@njit(cache=True, inline='always')
def stable_monodromy(M):
    """The stability rule on a 2×2 monodromy ``M``: :func:`stable_multipliers` of
    :func:`floquet_abs_max`."""
    return stable_multipliers(floquet_abs_max(M))


def is_stable(floquet_abs_max):
    """The stability rule: max |Floquet multiplier| ≤ 1 + :data:`STABILITY_TOL` [1], for Python
    callers (the compiled :func:`stable_multipliers` itself, element by element).

    ``floquet_abs_max`` is a number (returns a ``bool``) or an array (returns a bool array of its
    shape); NaN is unstable. Kernels call :func:`stable_multipliers` or :func:`stable_monodromy`.
    """
    mu = np.asarray(floquet_abs_max, dtype=float)
    if mu.ndim == 0:
        return bool(stable_multipliers(float(mu)))
    return stable_multipliers(np.ascontiguousarray(mu).reshape(-1)).reshape(mu.shape)


@njit(cache=True)
def floquet_abs_max(M):
    """Largest |eigenvalue| of a 2×2 matrix."""
    tr = M[0, 0] + M[1, 1]
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    disc = 0.25 * tr * tr - det
    if disc >= 0.0:
        s = math.sqrt(disc)
        return max(abs(0.5 * tr + s), abs(0.5 * tr - s))
    return math.sqrt(abs(det))
