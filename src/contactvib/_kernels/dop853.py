"""The DOP853 step's system-independent pieces (compiled, pure): the tableau, the stage state,
the 8th-order solution, the error norm, the step-size controller and the 7th-order dense output.

An integrator of ``y' = f(t, y)`` (``K``: float64[≥16, ≥n], stage ``s`` in row ``s``) takes
a step of size h from (t, y) as::

    K[0] = f(t, y)
    for s in 1..11:  K[s] = f(t + C[s] h, stage_state(K, y, h, s))   # y + h Σ_{j<s} A[s, j] K[j]
    ynew = solution(K, y, h)                                          # y + h Σ_{j<12} B[j] K[j]
    K[12] = f(t + h, ynew)
    err = error_norm(K, y, ynew, h, atol, rtol)                       # < 1: accept
    h_next = h · step_factor(err, rejected)

and, for dense output, K[13..15] = f at the extra stages (13..15) before :func:`interpolant`
fills the 7 coefficients that :func:`dense_value` evaluates. Only f, the events and what a
step carries besides y (modes, saltation, quadratures) belong to a system: the normal contact
flow (:mod:`.flow`, whose stages work on scalars for speed) and the tangential friction contact
(:mod:`.friction`) both step with these pieces.

References
----------
E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
Springer (1993), Sec. II.4 (step-size control), II.5 (DOP853), II.6 (dense output, CONTD8).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types
from numba.extending import overload

from . import _dop853_coefficients as _co

A = np.ascontiguousarray(_co.A)
B = np.ascontiguousarray(_co.B)
C = np.ascontiguousarray(_co.C)
E3 = np.ascontiguousarray(_co.E3)
E5 = np.ascontiguousarray(_co.E5)
D = np.ascontiguousarray(_co.D)

#: Step-size controller: safety factor, smallest and largest factor, exponent −1/(order + 1).
SAFETY = 0.9
MIN_FACTOR = 0.2
MAX_FACTOR = 10.0
ERR_EXP = -1.0 / 8.0


def component(a, i):
    """``a[i]`` for an array, ``a`` for a scalar: one tolerance for all components or one each."""
    return a[i] if isinstance(a, np.ndarray) else a


@overload(component, inline="always")
def _component(a, i):
    if isinstance(a, types.Array):
        return lambda a, i: a[i]
    return lambda a, i: a


@njit(cache=True, inline="always")
def stage_state(K, y, h, s, n, out):
    """out[:n] = y + h Σ_{j<s} A[s, j] K[j]: the state at which stage ``s`` evaluates f."""
    for i in range(n):
        acc = 0.0
        for j in range(s):
            acc += A[s, j] * K[j, i]
        out[i] = y[i] + h * acc


@njit(cache=True, inline="always")
def solution(K, y, h, n, ynew):
    """ynew[:n] = y + h Σ_{j<12} B[j] K[j]: the 8th-order solution at the step's end."""
    for i in range(n):
        acc = 0.0
        for j in range(12):
            acc += B[j] * K[j, i]
        ynew[i] = y[i] + h * acc


@njit(cache=True, inline="always")
def error_norm(K, y, ynew, h, n, atol, rtol):
    """DOP853's error norm of components 0..n − 1 (the 5th- and 3rd-order estimates combined,
    Hairer's ERR), each scaled by ``atol`` + ``rtol`` max(|y|, |ynew|); ``atol`` one number or
    one per component. K[12] must hold f(t + h, ynew). < 1: accept the step."""
    e5 = 0.0
    e3 = 0.0
    for i in range(n):
        a5 = 0.0
        a3 = 0.0
        for j in range(13):
            a5 += E5[j] * K[j, i]
            a3 += E3[j] * K[j, i]
        sc = component(atol, i) + rtol * max(abs(y[i]), abs(ynew[i]))
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)


@njit(cache=True)
def step_factor(err, rejected):
    """Step-size factor of the controller after a step with error norm ``err``: shrink after a
    rejected step (err ≥ 1, or not finite), grow at most by MAX_FACTOR after an accepted one
    (not at all right after a rejection)."""
    if not (err < 1.0):
        if not math.isfinite(err):
            return MIN_FACTOR
        return max(MIN_FACTOR, SAFETY * err**ERR_EXP)
    if err == 0.0:
        factor = MAX_FACTOR
    else:
        factor = min(MAX_FACTOR, SAFETY * err**ERR_EXP)
    if rejected:
        factor = min(1.0, factor)
    return factor


@njit(cache=True, inline="always")
def landing_step(h, remaining):
    """(h_try, landing): the proposal ``h``, or the ``remaining`` span when h reaches (to a
    relative 1e-12) the end of the interval, so that the step lands on it."""
    landing = h >= remaining * (1.0 - 1e-12)
    return (remaining if landing else h), landing


@njit(cache=True, inline="always")
def next_step(h, h_next, landing):
    """The proposal after an accepted step: the controller's ``h_next``, but not below the
    proposal ``h`` when the step was shortened to land on the interval's end (that says nothing
    against the longer proposal)."""
    return max(h_next, h) if landing else h_next


@njit(cache=True)
def interpolant(K, y, ynew, h, n, F):
    """F[0..6, :n]: the coefficients of DOP853's 7th-order dense output over the last step from
    ``y`` to ``ynew`` (Hairer's CONTD8), from its 16 stages ``K`` (the last three the extra ones)."""
    for i in range(n):
        dy = ynew[i] - y[i]
        F[0, i] = dy
        F[1, i] = h * K[0, i] - dy
        F[2, i] = 2.0 * dy - h * (K[12, i] + K[0, i])
        for q in range(4):
            acc = 0.0
            for j in range(16):
                acc += D[q, j] * K[j, i]
            F[3 + q, i] = h * acc


@njit(cache=True)
def record_value(rec, row, x0, f0, stride, theta, comp):
    """:func:`dense_value` of a step stored as a row of a record array: the step's start state at
    column ``x0 + comp`` and its interpolant's coefficient q of component ``comp`` at column
    ``f0 + q * stride + comp`` (the 1-DOF records: stride 2; the n-DOF records: stride 2n)."""
    acc = 0.0
    for q in range(6, -1, -1):
        acc += rec[row, f0 + q * stride + comp]
        if (6 - q) % 2 == 0:
            acc *= theta
        else:
            acc *= 1.0 - theta
    return rec[row, x0 + comp] + acc


@njit(cache=True)
def dense_value(F, y_old, theta, comp):
    """Interpolated component ``comp`` at fraction ``theta`` of a step (F from :func:`interpolant`)."""
    acc = 0.0
    for q in range(6, -1, -1):
        acc += F[q, comp]
        if (6 - q) % 2 == 0:
            acc *= theta
        else:
            acc *= 1.0 - theta
    return y_old[comp] + acc
