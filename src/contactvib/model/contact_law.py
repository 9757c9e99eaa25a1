"""The contact law as an object: what force and damping act in contact, and their derivatives.

Power law (Kostek 2013, Eq. 2.5), nondimensional (``x = y/y0``, ``v = x' = dx/dτ``,
``τ = ω_n0 t``, force in units of the weight ``Q``)::

    f(x, v) = x^m2 + c x^l v       in contact (x > 0),        f = 0 in flight (x ≤ 0)

with ``c = 2 m2 ζ``; the oscillator is ``m2 x'' = 1 + p cos(rτ) − f(x, x')``. In SI units the
same law is ``F(y, ẏ) = S c_n y^m2 + S h_n y^l ẏ`` [N].

The compiled definition lives in :mod:`contactvib._kernels.contact`; this object calls it
(vectorised) and is what the numpy-level methods use: harmonic balance takes
:meth:`PowerLaw.force`, the perturbation series :meth:`PowerLaw.series_about_one`.

For developers
--------------
The law is defined once, in ``_kernels/contact.py`` (compiled); a law provides these four:

1. ``force(x, v, m2, l, c)`` — the scalar force f(x, v) in contact, continued smoothly below
   x = 0 (the DOP853 stages may sample there);
2. ``force_partials(x, v, m2, l, c)`` — (∂f/∂x, ∂f/∂v), for the Jacobian and the variational
   equation;
3. ``series_contact(E, X, V, W, N, m2, l, c)`` — the Taylor-coefficient recurrence of
   ``m2 x'' = E(τ) − f(x, x')`` given the excitation's coefficients E (for laws whose
   right-hand side is polynomial, built from the Cauchy products ``power_table_update``, and
   ``series_exponential`` for the exponential spring, ``contact_table.series_table`` for the
   table law interval by interval; :func:`contactvib._kernels.taylor.series_law` sends the others
   to DOP853);
4. the power series of its stiffness and damping parts about the static point ``x = 1 + u``
   (for the power law Miller's recurrence ``power_series_partial`` for ``(1 + u)^m2`` and
   ``(1 + u)^l``), exposed here as :meth:`PowerLaw.series_about_one`.

Everything else is built from these: ``force_array`` (the vectorised force with the flight
switch, :meth:`PowerLaw.force`), ``flow.acceleration``/``flow.jacobian_row``/``flow.rhs``, the
Taylor flow ``taylor.series_prepared``, the harmonic-balance residual and the perturbation
series contain no law of their own. The kernels receive the law as the first entries of the
parameter vector ``par = [m2, l, c, p, r]``. ``tests/model/test_contact_law.py`` checks all four
against each other, against a plain numpy formula and against scipy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["PowerLaw"]


@dataclass(frozen=True)
class PowerLaw:
    """Power-law contact ``f(x, v) = x^m2 + c x^l v`` (x > 0), 0 in flight (nondimensional).

    Parameters
    ----------
    m2 : float
        Stiffness exponent [1], ≥ 1 (2 for the paper). Also the linear stiffness
        ``∂f/∂x (1, 0) = m2`` of the static point, i.e. the nondimensional mass of the equation
        ``m2 x'' = 1 + p cos rτ − f``.
    l : float
        Damping exponent [1], ≥ 0 (1 for the paper).

    Examples
    --------
    >>> f, fx, fv = PowerLaw(2.0, 1.0).force([1.0, 2.0], [0.5, 0.0], 0.1)
    >>> f.tolist(), fx.tolist(), fv.tolist()
    ([1.05, 4.0], [2.05, 4.0], [0.1, 0.2])
    """

    m2: float = 2.0
    l: float = 1.0  # the paper's symbol

    def force(self, x, v, c: float):
        """Contact force and its partial derivatives, vectorised (numpy broadcasting).

        ``f = x^m2 + c x^l v``, ``∂f/∂x = m2 x^(m2−1) + c l x^(l−1) v``, ``∂f/∂v = c x^l`` for
        ``x > 0``; all three are 0 for ``x ≤ 0`` (flight). Evaluated by the compiled definition
        (``contactvib._kernels.contact.force``), element by element.

        Parameters
        ----------
        x, v : array_like
            Deflection x = y/y0 [1] and velocity x' = dx/dτ [1].
        c : float
            Damping coefficient c = 2 m2 ζ [1].

        Returns
        -------
        f, dfdx, dfdv : ndarray
            Of the broadcast shape of x and v [units of Q].
        """
        from contactvib._kernels.contact import force_array  # numba on first use only

        xb, vb = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(v, dtype=float))
        shape = xb.shape
        xf = np.ascontiguousarray(xb).ravel()
        vf = np.ascontiguousarray(vb).ravel()
        f = np.empty_like(xf)
        fx = np.empty_like(xf)
        fv = np.empty_like(xf)
        force_array(xf, vf, float(self.m2), float(self.l), float(c), f, fx, fv)
        return f.reshape(shape), fx.reshape(shape), fv.reshape(shape)

    def series_about_one(self, u: np.ndarray, W: np.ndarray, D: np.ndarray, n: int):
        """Order-``n`` power-series coefficients of the stiffness and damping parts about x = 1.

        With ``x = 1 + u``, ``u = Σ_{k≥1} u_k εᵏ``: ``W = (1+u)^m2`` and ``D = (1+u)^l``
        (Miller's recurrence, any real exponent). Returns ``(R, S)`` with
        ``W_n = m2 u_n + R`` and ``D_n = l u_n + S``: the parts without the newest term ``u_n``,
        which involve only orders below n (zero for n = 1).

        Parameters
        ----------
        u, W, D : ndarray (≥ n+1, M)
            Coefficients by order (rows) at M samples (columns); rows 0..n−1 of W and D known
            (W_0 = D_0 = 1), rows 1..n−1 of u known.
        n : int
            Order ≥ 1.

        Returns
        -------
        R, S : ndarray (M,)
        """
        from contactvib._kernels.contact import (
            power_series_partial,  # numba on first use only
        )

        R = np.empty(u.shape[1])
        S = np.empty(u.shape[1])
        power_series_partial(float(self.m2), u, W, n, R)
        power_series_partial(float(self.l), u, D, n, S)
        return R, S
