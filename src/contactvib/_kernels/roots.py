"""Root of a scalar function on a bracket by the Illinois method (compiled, pure): the kernels'
one root finder.

The Illinois method is regula falsi whose retained end has its value halved when the same end is
kept twice in a row, which restores superlinear convergence (order ≈ 1.44) while the root stays
bracketed::

    c = (a f(b) − b f(a)) / (f(b) − f(a))     (the midpoint if c falls outside (a, b))

:func:`illinois_root` runs it on any compiled ``f(x, args)``; it is compiled into each caller
(``inline='always'``), so that ``f`` is a constant of the caller and the caller stays cacheable.
Its callers: the contact events and extrema on a DOP853 step's dense output
(:func:`.flow.dense_root`), the events on a Taylor step's polynomial
(:func:`.series_roots.poly_root`). The continuation's location of a test function's zero
(:func:`contactvib.continuation.bifurcations.locate_zero`, Python callables that may fail) steps
through the same :func:`illinois_trial` and :func:`illinois_update`.

References
----------
M. Dowell, P. Jarratt, "A modified regula falsi method for computing the root of an equation",
BIT 11 (1971) 168–174.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def illinois_trial(a, b, fa, fb):
    """The secant point of the bracket [a, b] (its midpoint if the secant falls outside or
    ``fa == fb``)."""
    if fb == fa:
        return 0.5 * (a + b)
    c = (a * fb - b * fa) / (fb - fa)
    if not (c > min(a, b) and c < max(a, b)):
        c = 0.5 * (a + b)
    return c


@njit(cache=True)
def illinois_update(a, b, fa, fb, c, fc, side):
    """Bracket [a, b] after the trial point c (value fc) of the Illinois method; the retained
    end's value is halved when the same side is kept twice. ``side``: 0 at the start, then the
    value returned last. Returns (a, b, fa, fb, side)."""
    if (fc > 0.0) == (fb > 0.0):
        b = c
        fb = fc
        if side == -1:
            fa *= 0.5
        side = -1
    else:
        a = c
        fa = fc
        if side == 1:
            fb *= 0.5
        side = 1
    return a, b, fa, fb, side


@njit(cache=True, inline='always')
def illinois_root(f, args, a, b, fa, fb, xtol, max_iter):
    """Root of ``f(x, args)`` on [a, b] by the Illinois method.

    Parameters
    ----------
    f : compiled function ``f(x, args) -> float``
    args : tuple
        Passed to ``f`` unchanged.
    a, b, fa, fb : float
        The bracket and ``f`` at its ends: non-zero, of opposite signs (the caller returns an
        end whose value is 0).
    xtol : float
        Stop when a trial point's bracket is no wider than ``xtol · max(1, |b|)``.
    max_iter : int
        Largest number of trial points.

    Returns
    -------
    float
        The first trial point where ``f`` is 0 or the bracket is that narrow (the last trial
        point after ``max_iter``; ``b`` when ``max_iter`` is 0).
    """
    side = 0
    c = b
    for _ in range(max_iter):
        c = illinois_trial(a, b, fa, fb)
        fc = f(c, args)
        if fc == 0.0 or abs(b - a) <= xtol * max(1.0, abs(b)):
            return c
        a, b, fa, fb, side = illinois_update(a, b, fa, fb, c, fc, side)
    return c
