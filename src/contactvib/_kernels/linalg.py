"""Small dense linear algebra of the kernels (compiled, pure): solvers of fixed small size
without allocation of a LAPACK call's work arrays."""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def solve3(a, b, x):
    """x = a⁻¹ b for a 3 × 3 system (Cramer's rule: the determinant and three column
    replacements); ``a``, ``b`` are not modified. Returns False where a is singular
    (|det| < 1e-300 or not finite) or x is not finite."""
    det = _det3(a[0, 0], a[0, 1], a[0, 2], a[1, 0], a[1, 1], a[1, 2], a[2, 0], a[2, 1], a[2, 2])
    if not math.isfinite(det) or abs(det) < 1e-300:
        return False
    x[0] = _det3(b[0], a[0, 1], a[0, 2], b[1], a[1, 1], a[1, 2], b[2], a[2, 1], a[2, 2]) / det
    x[1] = _det3(a[0, 0], b[0], a[0, 2], a[1, 0], b[1], a[1, 2], a[2, 0], b[2], a[2, 2]) / det
    x[2] = _det3(a[0, 0], a[0, 1], b[0], a[1, 0], a[1, 1], b[1], a[2, 0], a[2, 1], b[2]) / det
    return math.isfinite(x[0]) and math.isfinite(x[1]) and math.isfinite(x[2])


@njit(cache=True, inline="always")
def _det3(m00, m01, m02, m10, m11, m12, m20, m21, m22):
    """det of the 3 × 3 matrix of the given rows, expanded along the first row."""
    return (m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20)
            + m02 * (m10 * m21 - m11 * m20))
