"""Small dense linear systems ``A x = b`` (compiled, pure): the kernels' one place for them.

* :func:`solve2` — 2×2 by Cramer's rule, ``x = [[d, −b], [−c, a]] r / (a d − b c)``: the Newton
  step of the period-k map, ``(M − I) dz = −g`` (:func:`.shooting.newton_step`);
* :func:`solve3` — 3×3 by Cramer's rule (the determinant and three column replacements): the
  Newton step of friction's tangential period map (:mod:`.friction_newton`);
* :func:`solve_dense` — n×n (n ≤ 8 in practice) by Gaussian elimination with partial pivoting:
  the bordered systems of the pseudo-arclength corrector and the branch tangent
  (:func:`.continuation.bordered_newton_step`, :func:`.continuation.null_vector`).

All report a singular (or non-finite) system instead of raising. Larger systems (harmonic
balance, the continuation of many unknowns) use LAPACK through ``numpy.linalg.solve``.

References
----------
G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins (2013), §3.2, §3.4.
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, inline='always')
def solve2(a, b, c, d, r0, r1):
    """Solve ``[[a, b], [c, d]] x = (r0, r1)`` by Cramer's rule.

    Returns
    -------
    ok : bool
        False when the determinant ``a d − b c`` is 0 or not finite (``x`` is then (0, 0)).
    x0, x1 : float
        ``(d r0 − b r1) / det`` and ``(a r1 − c r0) / det``.
    """
    det = a * d - b * c
    if det == 0.0 or not math.isfinite(det):
        return False, 0.0, 0.0
    return True, (d * r0 - b * r1) / det, (a * r1 - c * r0) / det


@njit(cache=True)
def solve_dense(A, y, out):
    """Solve ``A x = y`` (A: (n, n), y: (n,)) into ``out`` by Gaussian elimination with partial
    pivoting; ``A`` and ``y`` are overwritten. Returns False (``out`` undefined) when a pivot is
    0 or not finite."""
    n = A.shape[0]
    for c in range(n):
        p = c
        for i in range(c + 1, n):
            if abs(A[i, c]) > abs(A[p, c]):
                p = i
        if A[p, c] == 0.0 or not math.isfinite(A[p, c]):
            return False
        if p != c:
            for j in range(n):
                tmp = A[c, j]
                A[c, j] = A[p, j]
                A[p, j] = tmp
            tmp = y[c]
            y[c] = y[p]
            y[p] = tmp
        for i in range(c + 1, n):
            f = A[i, c] / A[c, c]
            for j in range(c, n):
                A[i, j] -= f * A[c, j]
            y[i] -= f * y[c]
    for i in range(n - 1, -1, -1):
        acc = y[i]
        for j in range(i + 1, n):
            acc -= A[i, j] * out[j]
        out[i] = acc / A[i, i]
    return True


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
