"""Test functions of the special points of a branch of period-k orbits, and their location.

For the period-k stroboscopic map with monodromy ``M`` (2×2, Floquet multipliers μ1, μ2)::

    fold (saddle-node)      det(M − I) = (1 − μ1)(1 − μ2)          one multiplier crosses +1
    period doubling         det(M + I) = (1 + μ1)(1 + μ2)          one multiplier crosses −1
    Neimark–Sacker          det M − 1 = |μ|² − 1  (complex pair)    the pair crosses |μ| = 1
    grazing                 x_min = min over the orbit of y/y0      the orbit touches y = 0

A fold is detected by the sign change of the parameter component of the oriented branch tangent
(which is ``det(M − I)`` up to a positive factor, see :mod:`contactvib._kernels.continuation`)
and located, like the others, by the Illinois (modified regula falsi) iteration on the
pseudo-arclength between the two branch points that bracket the sign change; each trial point is
corrected back onto the branch.

Neimark–Sacker points cannot occur on this model's branches while the contact is damped: by
Liouville's formula ``det M = exp(−∫ c x^l / m2 dτ)`` over the contact phases (the saltation
matrix is the identity for ``l > 0``, and flight is conservative), so ``|μ1 μ2| < 1`` on every
orbit that touches the contact; the test is still evaluated (it matters for ``h_n = 0``).

References
----------
Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer (2004), Ch. 10.
"""

from __future__ import annotations

import math

import numpy as np

from contactvib._kernels.roots import illinois_trial, illinois_update

__all__ = ["fold_test", "pd_test", "ns_test", "locate_zero"]


def fold_test(M: np.ndarray) -> float:
    """det(M − I): zero when a multiplier equals +1."""
    return float((M[0, 0] - 1.0) * (M[1, 1] - 1.0) - M[0, 1] * M[1, 0])


def pd_test(M: np.ndarray) -> float:
    """det(M + I): zero when a multiplier equals −1."""
    return float((M[0, 0] + 1.0) * (M[1, 1] + 1.0) - M[0, 1] * M[1, 0])


def ns_test(M: np.ndarray) -> float:
    """det M − 1 for a complex pair of multipliers; NaN when they are real."""
    tr = M[0, 0] + M[1, 1]
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    if 0.25 * tr * tr - det >= 0.0:
        return math.nan
    return float(det - 1.0)


def locate_zero(func, a: float, b: float, fa: float, fb: float, xtol: float, max_iter: int = 60):
    """Zero of ``func`` on [a, b] (``fa``, ``fb`` of opposite sign) by the Illinois method.

    The kernels' root finder (:mod:`contactvib._kernels.roots`) driven step by step
    (``illinois_trial``, ``illinois_update``) rather than :func:`~contactvib._kernels.roots.illinois_root`
    itself, because ``func`` is a Python callable (a corrector run onto the branch) that may fail:
    ``func(s)`` returns ``(value, payload)`` or ``None`` when it cannot be evaluated (then the
    bracket is bisected). Returns ``(s, value, payload)`` of the last evaluated point inside the
    bracket, or ``None`` when nothing could be evaluated.
    """
    best = None
    side = 0
    for _ in range(max_iter):
        if abs(b - a) <= xtol:
            break
        s = illinois_trial(a, b, fa, fb)
        out = func(s)
        if out is None:
            s = 0.5 * (a + b)
            out = func(s)
            if out is None:
                return best
        fs, payload = out
        best = (s, fs, payload)
        if fs == 0.0:
            break
        a, b, fa, fb, side = illinois_update(a, b, fa, fb, s, fs, side)
    return best
