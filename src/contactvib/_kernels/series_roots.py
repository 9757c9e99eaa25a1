"""Events on a Taylor step's polynomial (compiled, pure): where x(s) = Σ x_k s^k reaches a level.

:func:`crossing` finds the first arrival of x at the switching surface x = 0 of a mode on
[0, h] (cheap exclusion tests, then sub-interval sampling and the Illinois method of
:mod:`.roots`, :func:`poly_root`); :func:`segment_event` the first arrival at either end of a table law's
interval (the fast path for a monotone x: Newton's method in the bracket, :func:`_monotone_root`).
Used by the Taylor flows of :mod:`.taylor`.
"""

from __future__ import annotations

import math

from numba import njit

from .flow import crosses_contact
from .roots import illinois_root

N_SUB = 8  # sub-intervals of a step searched for a crossing of x = 0


@njit(cache=True)
def poly(C, N, s, shift):
    """Σ_{k≥shift} C[k] s^(k−shift) (Horner); shift = 1 gives x(s)/s when C[0] = 0."""
    acc = 0.0
    for k in range(N, shift - 1, -1):
        acc = acc * s + C[k]
    return acc


@njit(cache=True, inline='always')
def _poly_value(s, args):
    """:func:`poly` of ``args = (C, N, shift)`` at s."""
    return poly(args[0], args[1], s, args[2])


@njit(cache=True)
def poly_root(C, N, shift, a, b):
    """Root of the polynomial (:func:`poly`) on [a, b], a sign change assumed (Illinois,
    :func:`.roots.illinois_root`, to 4e-16 relative)."""
    fa = poly(C, N, a, shift)
    fb = poly(C, N, b, shift)
    if fb == 0.0:
        return b
    if fa == 0.0:
        return a
    return illinois_root(_poly_value, (C, N, shift), a, b, fa, fb, 4e-16, 200)


@njit(cache=True)
def crossing(contact, X, V, N, h, S):
    """First s ∈ (0, h] where x reaches the switching surface for this mode, or −1.

    A crossing is a sign change of x, or an interior extremum of x (a sign change of x'
    towards the surface) that lies on the far side. A step that starts on the surface
    (``X[0] = 0``, right after a switch) is searched on x(s)/s, so that s = 0 is not a root.
    ``S``: work array (2, N_SUB + 1).
    """
    # x = q(s) + R(s), q the quadratic part, |R| ≤ Σ_{k≥3} |x_k| h^k: no crossing if the extreme
    # of q on [0, h] clears that bound
    bound = 0.0
    hk = h * h
    for k in range(3, N + 1):
        hk *= h
        bound += abs(X[k]) * hk
    q0 = X[0]
    qh = X[0] + h * (X[1] + h * X[2])
    qe = min(q0, qh) if contact else max(q0, qh)
    if X[2] != 0.0:
        s_v = -X[1] / (2.0 * X[2])
        if 0.0 < s_v < h:
            q_v = X[0] + s_v * (X[1] + s_v * X[2])
            qe = min(qe, q_v) if contact else max(qe, q_v)
    bound *= 1.0 + 1e-12
    if (qe > bound) if contact else (qe < -bound):
        return -1.0  # the polynomial cannot reach x = 0 on [0, h]
    # x at the sub-interval ends, all points at once (independent Horner chains); between two
    # of them x stays within (dh²/8) max|x''| of the chord: no crossing if all clear that margin
    dh = h / N_SUB
    for j in range(N_SUB + 1):
        S[0, j] = X[N]
    for k in range(N - 1, -1, -1):
        for j in range(N_SUB + 1):
            S[0, j] = S[0, j] * (dh * j) + X[k]
    m2 = 0.0
    hk = 1.0
    for k in range(2, N + 1):
        m2 += k * (k - 1) * abs(X[k]) * hk
        hk *= h
    margin = 0.125 * dh * dh * m2
    clear = True
    for j in range(N_SUB + 1):
        if (S[0, j] <= margin) if contact else (S[0, j] >= -margin):
            clear = False
            break
    if clear:
        return -1.0
    for j in range(N_SUB + 1):
        S[1, j] = V[N]
    for k in range(N - 1, -1, -1):
        for j in range(N_SUB + 1):
            S[1, j] = S[1, j] * (dh * j) + V[k]
    shift = 1 if X[0] == 0.0 else 0
    for j in range(1, N_SUB + 1):
        s_prev = dh * (j - 1)
        s = h if j == N_SUB else dh * j
        v_prev = S[1, j - 1]
        v_s = S[1, j]
        # an extremum towards the surface in (s_prev, s): contact min (v − → +), flight max (+ → −)
        towards = (v_prev < 0.0 and v_s > 0.0) if contact else (v_prev > 0.0 and v_s < 0.0)
        # skip the root search when the extremum cannot reach the surface: x moves by at
        # most max|x'|·(s − s_prev) on the sub-interval (x' is monotone there; factor 2 margin)
        reach = 2.0 * max(abs(v_prev), abs(v_s)) * (s - s_prev)
        if contact:
            towards = towards and min(S[0, j - 1], S[0, j]) <= reach
        else:
            towards = towards and max(S[0, j - 1], S[0, j]) >= -reach
        if towards:
            s_ext = poly_root(V, N, 0, s_prev, s)
            if crosses_contact(contact, poly(X, N, s_ext, 0)):
                return poly_root(X, N, shift, s_prev, s_ext)
        x_s = S[0, j]
        if crosses_contact(contact, x_s):
            if x_s == 0.0:
                return s
            return poly_root(X, N, shift, s_prev, s)
    return -1.0


@njit(cache=True)
def _monotone_root(X, V, N, target, h):
    """The s ∈ [0, h] where the monotone x(s) (x' = V(s) of one sign) equals ``target``, x − target
    of opposite signs at 0 and h: Newton's method from the linear guess, kept in the shrinking
    bracket (a bisection where it leaves it), to 4e-16 relative."""
    x0 = X[0]
    up = V[0] > 0.0
    a = 0.0
    b = h
    s = min(max((target - x0) / V[0], 0.0), h)
    for _ in range(60):
        g = poly(X, N, s, 0) - target
        if g == 0.0:
            return s
        if (g < 0.0) == up:
            a = s
        else:
            b = s
        s_new = s - g / poly(V, N, s, 0)
        if not (a < s_new < b):
            s_new = 0.5 * (a + b)
        if abs(s_new - s) <= 4e-16 * max(1.0, s) or b - a <= 4e-16 * max(1.0, b):
            return s_new
        s = s_new
    return s


@njit(cache=True)
def segment_event(contact, X, V, XU, VU, N, h, lo, hi, S):
    """First s ∈ (0, h] where x on a table segment reaches its lower bound ``lo`` (returns
    (s, −1)) or its upper bound ``hi`` (returns (s, +1)); (−1, 0) if neither (:func:`crossing` on
    x − lo and on hi − x, the upper only before the lower's s). Fast path: where x is
    monotone on [0, h] (Σ_{k≥1} |v_k| h^k < |v_0|) and starts inside or on an end moving away
    from it, x(h) tells whether the bound ahead is reached, and its root is found on the
    bracket [0, h] at once. ``contact``: True, the caller's mode flag (a run-time bool, so that
    :func:`crossing` is compiled for one signature, not for the literal True as well)."""
    x0 = X[0]
    v0 = V[0]
    # strictly inside, or on an end (a step right after an event) moving away from it
    if (lo < x0 < hi) or (x0 == lo and v0 > 0.0) or (x0 == hi and v0 < 0.0):
        drift = 0.0
        hk = 1.0
        for k in range(1, N + 1):
            hk *= h
            drift += abs(V[k]) * hk
        if drift < abs(v0):
            bound = hi if v0 > 0.0 else lo
            if bound == math.inf:
                return -1.0, 0
            xh = poly(X, N, h, 0)
            if (xh < bound) if v0 > 0.0 else (xh > bound):
                return -1.0, 0
            return _monotone_root(X, V, N, bound, h), 1 if v0 > 0.0 else -1
    for k in range(N + 1):
        XU[k] = X[k]
    XU[0] = X[0] - lo
    s_lo = crossing(contact, XU, V, N, h, S)
    if hi == math.inf:
        return s_lo, -1 if s_lo >= 0.0 else 0
    XU[0] = hi - X[0]
    VU[0] = -V[0]
    for k in range(1, N + 1):
        XU[k] = -X[k]
        VU[k] = -V[k]
    s_hi = crossing(contact, XU, VU, N, s_lo if s_lo >= 0.0 else h, S)
    if s_hi >= 0.0 and (s_lo < 0.0 or s_hi < s_lo):
        return s_hi, 1
    return s_lo, -1 if s_lo >= 0.0 else 0
