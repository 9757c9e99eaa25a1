"""The contact law, compiled: the single definition of the force that acts in contact (pure).

Power law (Kostek 2013, Eq. 2.5, nondimensional ``x = y/y0``, ``v = x' = dx/dτ``)::

    f(x, v) = x^m2 + c x^l v          (contact mode, x > 0; c = 2 m2 ζ)

so that the contact mode of the oscillator is ``m2 x'' = 1 + p cos(rτ) − f(x, x')``. Below zero
the powers are continued oddly, ``x^a → −|x|^a`` (:func:`pow_ext`), so that the contact mode's
right-hand side stays smooth where an integrator's stage samples it slightly past ``x = 0``.

Everything that evaluates the law is built from the functions here:

* :func:`force`, :func:`force_partials`: f and (∂f/∂x, ∂f/∂v), used by the DOP853 right-hand
  side and its variational equation (:mod:`.flow`) and, vectorised with the contact/flight switch
  ``x > 0``, by :func:`force_array` (harmonic balance, :class:`contactvib.model.PowerLaw`);
* :func:`series_contact`: the Taylor-coefficient recurrence of the contact mode for integer
  exponents (the Taylor flow, :mod:`.taylor`), from the Cauchy products of the integer powers
  (:func:`power_table_update`), with the symmetric-square specialisation for ``m2 = 2, l = 1``,
  and :func:`series_exponential`, the same for the exponential spring (series of ``e^{ax}``);
* :func:`power_series_partial`: J. C. P. Miller's recurrence for the power series of
  ``(1 + u)^α`` (any real α), used by the perturbation series.

For the paper's law (m2 = 2, l = 1) the floating-point operation order is fixed (``x·|x|``, the
order of the additions), so that ``contactvib paper`` is bit-identical from version to version.
What a new law must provide: ``contactvib.model.contact_law`` ("For developers").

References
----------
D. E. Knuth, *The Art of Computer Programming* vol. 2, Sec. 4.7 (powers of power series, Miller's
recurrence). À. Jorba, M. Zou, *Experimental Mathematics* 14 (2005) 99–117 (Taylor recurrences).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: 1/k for k < 64 without a division (the Taylor orders stay below 64).
INV = np.array([0.0] + [1.0 / k for k in range(1, 64)])


@njit(cache=True)
def pow_ext(x, a):
    """x^a for x > 0, continued oddly (−|x|^a) below zero; 1 for a = 0."""
    if a == 1.0:  # integer exponents of the common laws, without a pow call
        return x
    if a == 2.0:
        return x * abs(x)
    if x > 0.0:
        return x**a
    if a == 0.0:
        return 1.0
    return -((-x) ** a)


@njit(cache=True)
def dpow_ext(x, a):
    """d/dx of :func:`pow_ext`: a |x|^(a−1) (0 at x = 0 when a < 1, and for a = 0)."""
    if a == 0.0:
        return 0.0
    if a == 1.0:
        return 1.0
    if a == 2.0:
        return 2.0 * abs(x)
    ax = abs(x)
    if ax == 0.0:
        return 0.0  # a > 1: 0; 0 < a < 1: the one-sided limit is infinite, 0 by convention
    return a * ax ** (a - 1.0)


@njit(cache=True)
def force(x, v, m2, l, c):
    """Contact force f = x^m2 + c x^l v [nondimensional, units of the weight Q] (odd continuation
    below zero)."""
    return pow_ext(x, m2) + c * pow_ext(x, l) * v


@njit(cache=True)
def force_partials(x, v, m2, l, c):
    """(∂f/∂x, ∂f/∂v) of :func:`force`: (m2 |x|^(m2−1) + c l |x|^(l−1) v, c x^l)."""
    return dpow_ext(x, m2) + c * dpow_ext(x, l) * v, c * pow_ext(x, l)


@njit(cache=True)
def force_array(x, v, m2, l, c, f, fx, fv):
    """Vectorised contact force with the mode switch: f, ∂f/∂x, ∂f/∂v at x > 0, zero at x ≤ 0.

    ``x``, ``v`` and the outputs ``f``, ``fx``, ``fv`` are 1-D arrays of one length.
    """
    for i in range(x.shape[0]):
        if x[i] > 0.0:
            f[i] = force(x[i], v[i], m2, l, c)
            fx[i], fv[i] = force_partials(x[i], v[i], m2, l, c)
        else:
            f[i] = 0.0
            fx[i] = 0.0
            fv[i] = 0.0


# ----------------------------------------------------------------------------------- families
# The parameter vector of every kernel (built by ``contactvib.model.Excitation.kernel_parameters``)::
#
#     par = [kappa, l, c, p, r, spring, damping, excitation, s1, s2, n_exc, off_exc, <data>]
#
# kappa: the nondimensional mass k_lin y0 / W (= m2 for the power law), W = Q + F_pre the static
# load (the unit of force); l, c: damping exponent and coefficient; p, r: level and frequency
# ratio. A vector of length 5 is the power law under a harmonic force (the codes below all 0).
P_SPRING, P_DAMPING, P_EXCITATION = 5, 6, 7
P_S1, P_S2 = 8, 9  # spring parameters: power (m2, -); exponential (a, b); table (n, offset)
P_NEXC, P_OEXC = 10, 11  # excitation components (count, offset of their triples)
HEADER = 12

SPRING_POWER, SPRING_EXPONENTIAL, SPRING_TABLE = 0, 1, 2
DAMPING_POWER, DAMPING_HUNT_CROSSLEY = 0, 1
EXCITATION_FORCE, EXCITATION_BASE, EXCITATION_HARMONICS, EXCITATION_SPECTRUM = 0, 1, 2, 3


@njit(cache=True, inline="always")
def is_paper_vector(par):
    """True for a vector of length 5 (no family header): the paper's law under a harmonic force."""
    return par.shape[0] <= P_SPRING


@njit(cache=True)
def is_paper_family(par):
    """True for the power spring with power damping (the kernels' original law, ``force``)."""
    return is_paper_vector(par) or (par[P_SPRING] == 0.0 and par[P_DAMPING] == 0.0)


@njit(cache=True)
def table_interval(x, par):
    """Index i of the table interval [x_i, x_{i+1}) holding 0 <= x < x_{n-1} (bisection)."""
    n = int(par[P_S1])
    o = int(par[P_S2])
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if par[o + mid] <= x:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True)
def _table_spring(x, par):
    """Table law: (f, df/dx) of the cubic Hermite interpolant through the knots (x_i, f_i) with
    the slopes d_i (PCHIP, computed by the model), linear beyond the last knot, odd below 0."""
    n = int(par[P_S1])
    o = int(par[P_S2])
    sign = 1.0
    if x < 0.0:
        x = -x
        sign = -1.0
    xn = par[o + n - 1]
    if x >= xn:
        d = par[o + 3 * n - 1]
        return sign * (par[o + 2 * n - 1] + d * (x - xn)), d
    i = table_interval(x, par)
    x0 = par[o + i]
    h = par[o + i + 1] - x0
    f0 = par[o + n + i]
    f1 = par[o + n + i + 1]
    d0 = par[o + 2 * n + i] * h
    d1 = par[o + 2 * n + i + 1] * h
    s = (x - x0) / h
    s2 = s * s
    s3 = s2 * s
    f = (2.0 * s3 - 3.0 * s2 + 1.0) * f0 + (s3 - 2.0 * s2 + s) * d0 + (-2.0 * s3 + 3.0 * s2) * f1 \
        + (s3 - s2) * d1
    df = ((6.0 * s2 - 6.0 * s) * f0 + (3.0 * s2 - 4.0 * s + 1.0) * d0 + (-6.0 * s2 + 6.0 * s) * f1
          + (3.0 * s2 - 2.0 * s) * d1) / h
    return sign * f, df


@njit(cache=True)
def spring(x, par):
    """Nondimensional spring force f_s(x) = F_s(x y0)/W and its stiffness df_s/dx.

    power: x^m2; exponential: b (exp(a x) − 1) with a = y0/λ, b = S c_e / W; table: the
    interpolated curve. Continued smoothly (oddly) below x = 0.
    """
    code = par[P_SPRING] if par.shape[0] > P_SPRING else 0.0
    if code == SPRING_EXPONENTIAL:
        a = par[P_S1]
        b = par[P_S2]
        return b * math.expm1(a * x), a * b * math.exp(a * x)
    if code == SPRING_TABLE:
        return _table_spring(x, par)
    m2 = par[P_S1] if par.shape[0] > P_SPRING else par[0]
    return pow_ext(x, m2), dpow_ext(x, m2)


@njit(cache=True)
def contact_force(x, v, par):
    """Contact force f(x, v) = f_s(x) + f_d(x, v) [units of W] of any law family.

    Damping: power ``c x^l v`` (the paper's) or Hunt–Crossley ``c f_s(x) v`` (c = α y0 ω_n0).
    The paper's family goes through :func:`force` unchanged (bit-identical results).
    """
    if is_paper_family(par):
        return force(x, v, par[0], par[1], par[2])
    fs, _k = spring(x, par)
    if par[P_DAMPING] == DAMPING_HUNT_CROSSLEY:
        return fs + par[2] * fs * v
    return fs + par[2] * pow_ext(x, par[1]) * v


@njit(cache=True)
def contact_partials(x, v, par):
    """(∂f/∂x, ∂f/∂v) of :func:`contact_force`."""
    if is_paper_family(par):
        return force_partials(x, v, par[0], par[1], par[2])
    fs, k = spring(x, par)
    c = par[2]
    if par[P_DAMPING] == DAMPING_HUNT_CROSSLEY:
        return k + c * k * v, c * fs
    return k + c * dpow_ext(x, par[1]) * v, c * pow_ext(x, par[1])


@njit(cache=True)
def contact_force_array(x, v, par, f, fx, fv):
    """Vectorised :func:`contact_force` and partials with the mode switch (0 at x <= 0)."""
    for i in range(x.shape[0]):
        if x[i] > 0.0:
            f[i] = contact_force(x[i], v[i], par)
            fx[i], fv[i] = contact_partials(x[i], v[i], par)
        else:
            f[i] = 0.0
            fx[i] = 0.0
            fv[i] = 0.0


@njit(cache=True)
def forcing_amplitude(par):
    """Amplitude of the fundamental [units of W]: p (force), p r² (base motion: p = κ U/y0)."""
    if par.shape[0] > P_EXCITATION and par[P_EXCITATION] == EXCITATION_BASE:
        return par[3] * par[4] * par[4]
    return par[3]


@njit(cache=True)
def forcing(t, par):
    """The right-hand side's constant and excitation, 1 + e(τ) [units of W].

    force: 1 + p cos rτ; base: 1 + p r² cos rτ; harmonics: 1 + p cos rτ + Σ a_j cos(k_j r τ + φ_j);
    spectrum: 1 + Σ a_j cos(ω_j τ + φ_j) (ω_j nondimensional, the random force's components).
    """
    if par.shape[0] <= P_EXCITATION or par[P_EXCITATION] == EXCITATION_FORCE:
        return 1.0 + par[3] * math.cos(par[4] * t)
    code = par[P_EXCITATION]
    r = par[4]
    if code == EXCITATION_BASE:
        return 1.0 + par[3] * r * r * math.cos(r * t)
    n = int(par[P_NEXC])
    o = int(par[P_OEXC])
    if code == EXCITATION_HARMONICS:
        s = 1.0 + par[3] * math.cos(r * t)
        for j in range(n):
            s += par[o + 3 * j + 1] * math.cos(par[o + 3 * j] * r * t + par[o + 3 * j + 2])
        return s
    s = 1.0
    for j in range(n):
        s += par[o + 3 * j + 1] * math.cos(par[o + 3 * j] * t + par[o + 3 * j + 2])
    return s


@njit(cache=True)
def forcing_dr(t, par):
    """∂/∂r of :func:`forcing` at fixed τ [units of W]: −p τ sin rτ (force), p (2r cos rτ −
    r² τ sin rτ) (base), −p τ sin rτ − Σ a_j k_j τ sin(k_j r τ + φ_j) (harmonics), 0 (spectrum:
    its frequencies do not follow r)."""
    r = par[4]
    if par.shape[0] <= P_EXCITATION or par[P_EXCITATION] == EXCITATION_FORCE:
        return -par[3] * t * math.sin(r * t)
    code = par[P_EXCITATION]
    if code == EXCITATION_BASE:
        return par[3] * (2.0 * r * math.cos(r * t) - r * r * t * math.sin(r * t))
    if code == EXCITATION_HARMONICS:
        n = int(par[P_NEXC])
        o = int(par[P_OEXC])
        s = -par[3] * t * math.sin(r * t)
        for j in range(n):
            kj = par[o + 3 * j]
            s -= par[o + 3 * j + 1] * kj * t * math.sin(kj * r * t + par[o + 3 * j + 2])
        return s
    return 0.0


@njit(cache=True)
def power_table_update(n, X, W, qmax):
    """Cauchy products: W[q, n] = (x^q)_n = Σ_j W[q−1, j] X[n−j] for q = 2..qmax (W[1] = X).

    Needs X[0..n] and W[q, 0..n−1]; row q of ``W`` holds the Taylor coefficients of x^q.
    """
    W[1, n] = X[n]
    for q in range(2, qmax + 1):
        acc = 0.0
        for j in range(n + 1):
            acc += W[q - 1, j] * X[n - j]
        W[q, n] = acc


@njit(cache=True, inline="always")
def _series_square(E, X, V, N, c):
    """:func:`series_contact` for m2 = 2, l = 1: both terms from the one series x².

    x x' = (x²)'/2, and (x²)_n = S + 2 x_0 x_n with the old terms S summed symmetrically first,
    so that the newest coefficient x_n = v_{n−1}/n enters last and the recurrence's critical path
    is two operations (about 90 ns for order 14).
    """
    x0 = X[0]
    p_k = x0 * x0  # (x²)_k
    for k in range(N):
        n = k + 1
        s = 0.0
        for j in range((n + 1) // 2 - 1, 0, -1):
            s += X[j] * X[n - j]
        s = 2.0 * s
        if n % 2 == 0:
            s += X[n // 2] * X[n // 2]
        alpha = 0.5 * INV[n]
        hc = 0.5 * c * n
        A = alpha * (E[k] - p_k - hc * s)
        B = alpha * hc * 2.0 * x0
        xn = V[k] * INV[n]
        X[n] = xn
        V[n] = A - B * xn
        p_k = s + 2.0 * x0 * xn


@njit(cache=True, inline="always")
def series_contact(E, X, V, W, N, m2, l, c):
    """Taylor coefficients of the contact mode ``m2 x'' = E(τ) − f(x, x')`` (integer m2, l).

    Recurrence ``x_{k+1} = v_k/(k+1)``, ``v_{k+1} = [E_k − (x^m2)_k − c (x^l x')_k] / (m2 (k+1))``
    where the damping term is a derivative, ``x^l x' = (x^(l+1))'/(l+1)``, so its k-th
    coefficient is (k+1)/(l+1) (x^(l+1))_{k+1} and only the powers of x are multiplied out.

    Parameters
    ----------
    E : float64[N]
        Taylor coefficients of the excitation side (1 + p cos rτ about τ0).
    X, V : float64[N + 1]
        X[0], V[0] given (x, x' at τ0); X[1..N], V[1..N] written.
    W : float64[≥ max(m2, l + 1) + 1, N + 1]
        Work array for the powers (rows 1..max(m2, l + 1) written; row 0 untouched).
    N : int
        Order.
    m2, l, c : float
        Law parameters (integers m2 ≥ 1, l ≥ 0).
    """
    im2 = int(m2)
    il = int(l)
    if im2 == 2 and il == 1:
        _series_square(E, X, V, N, c)
        return
    inv_m2 = 1.0 / m2
    qmax = max(im2, il + 1)
    x0 = X[0]
    W[1, 0] = x0
    for q in range(2, qmax + 1):
        W[q, 0] = W[q - 1, 0] * x0
    for k in range(N):
        X[k + 1] = V[k] * INV[k + 1]
        power_table_update(k + 1, X, W, qmax)
        a = E[k] - W[im2, k]
        if c != 0.0:
            a -= c * (k + 1) / (il + 1) * W[il + 1, k + 1]
        V[k + 1] = a * inv_m2 * INV[k + 1]


@njit(cache=True)
def power_series_partial(alpha, u, w, n, out):
    """Miller's recurrence for ``w = (1 + u)^α`` (any real α) without its newest term.

    With ``u = Σ_{k≥1} u_k εᵏ`` and ``w = Σ_k w_k εᵏ`` (``w_0 = 1``)::

        w_n = (1/n) Σ_{k=1}^{n} [(α+1) k − n] u_k w_{n−k} = α u_n + out

    ``out`` receives the sum over k = 1..n−1 (zero for n = 1), which involves only lower orders.
    Rows of ``u`` and ``w`` (shape (≥ n+1, M)) are orders; columns are M independent samples.
    """
    M = out.shape[0]
    for i in range(M):
        out[i] = 0.0
    for k in range(1, n):
        a = (alpha + 1.0) * k - n
        for i in range(M):
            out[i] += a * u[k, i] * w[n - k, i]
    for i in range(M):
        out[i] /= n


@njit(cache=True, inline="always")
def series_exponential(E, X, V, W, G, N, par):
    """Taylor coefficients of the contact mode ``κ x'' = E(τ) − b (e^{ax} − 1) − f_d(x, x')`` of
    the exponential spring, with power damping ``c x^l x'`` (integer l) or Hunt–Crossley damping
    ``c b (e^{ax} − 1) x'``.

    The series of ``G = e^{ax}`` follows from ``G' = a x' G`` (Knuth, 4.7): with ``(x')_i = V_i``,
    ``G_{k+1} = a/(k+1) Σ_{i=0..k} V_i G_{k−i}``, started at ``G_0 = exp(a x_0)``; the spring's
    coefficients are ``b G_k`` (k ≥ 1) and ``b expm1(a x_0)`` (k = 0, without cancellation). Then
    ``x_{k+1} = v_k/(k+1)``, ``v_{k+1} = [E_k − b Ĝ_k − (f_d)_k] / (κ (k+1))``, with
    ``(x^l x')_k = (k+1)/(l+1) (x^{l+1})_{k+1}`` (:func:`power_table_update`; for l = 1 the
    symmetric sum of ``(x²)_{k+1}``) or
    ``((e^{ax} − 1) x')_k = R_k + V_k expm1(a x_0)``, where ``R_k = Σ_{i<k} V_i G_{k−i}`` is the
    sum that also gives ``G_{k+1} = a/(k+1) (R_k + V_k G_0)``.

    Parameters
    ----------
    E : float64[N]
        Taylor coefficients of the excitation side (1 + e(τ) about τ0).
    X, V : float64[N + 1]
        X[0], V[0] given (x, x' at τ0); X[1..N], V[1..N] written.
    W : float64[≥ l + 2, N + 1]
        Work array for the powers of x (power damping; rows 1..l+1 written).
    G : float64[N + 1]
        Work row, receives the coefficients of e^{ax}.
    N : int
        Order.
    par : float64[:]
        Kernel parameters: κ = par[0], l = par[1], c = par[2], a = par[P_S1] = y0/λ,
        b = par[P_S2] = S c_e / W.
    """
    kappa = par[0]
    c = par[2]
    a = par[P_S1]
    b = par[P_S2]
    hunt_crossley = par[P_DAMPING] == DAMPING_HUNT_CROSSLEY
    il = int(par[1])
    inv_kappa = 1.0 / kappa
    x0 = X[0]
    G[0] = math.exp(a * x0)
    em = math.expm1(a * x0)
    g0 = G[0]
    if not hunt_crossley and il != 1:
        W[1, 0] = x0
        for q in range(2, il + 2):
            W[q, 0] = W[q - 1, 0] * x0
    for k in range(N):
        n = k + 1
        X[n] = V[k] * INV[n]
        r = 0.0
        for i in range(k):
            r += V[i] * G[k - i]
        G[n] = a * INV[n] * (r + V[k] * g0)
        f = E[k] - b * (em if k == 0 else G[k])
        if hunt_crossley:
            f -= c * b * (r + V[k] * em)
        elif il == 1:  # (x²)_n, the symmetric sum
            s2 = 0.0
            for j in range((n + 1) // 2):
                s2 += X[j] * X[n - j]
            s2 = 2.0 * s2
            if n % 2 == 0:
                s2 += X[n // 2] * X[n // 2]
            f -= c * n * 0.5 * s2
        elif c != 0.0:
            power_table_update(n, X, W, il + 1)
            f -= c * n / (il + 1) * W[il + 1, n]
        V[n] = f * inv_kappa * INV[n]
