"""Taylor-series flow of the contact oscillator for polynomial contact laws (compiled, pure).

For integer exponents ``m2`` and ``l`` each mode of the nondimensional equation (:mod:`.flow`)
has a polynomial right-hand side plus the forcing ``p cos(rτ)``, so the Taylor coefficients of
the solution about ``τ0`` follow from a recurrence (automatic differentiation)::

    x_{k+1} = v_k / (k+1),      v_{k+1} = a_k / (k+1),
    a_k = [δ_k0 − (x^m2)_k − c (x^l v)_k + p γ_k] / m2     contact mode (x > 0)
    a_k = [δ_k0 + p γ_k] / m2                              flight mode  (x ≤ 0)

with Cauchy products for the powers (the contact law's recurrence, :func:`.contact.series_contact`)
and ``γ_k = r^k/k! · cos(rτ0 + kπ/2)``. The exponential spring ``b (e^{ax} − 1)`` has a
recurrence too, from ``G = e^{ax}``, ``G' = a x' G`` (:func:`.contact.series_exponential`):
``G_{k+1} = a/(k+1) Σ_{i≤k} (x')_i G_{k−i}``. The table law's PCHIP spring is a cubic on each
interval between rows, so its series there is exact (:func:`.contact_table.series_table`); it is only
C¹ at the rows, which :func:`advance_taylor_table` treats as events like x = 0 (a step ends on
the row, the next one takes the next interval's cubic), at a lower order (TABLE_ORDER), since
those steps are short. :func:`series_law` says which applies. A step of order
``N`` has length ``h = SAFETY · min_{k=N−1,N} (tol·s / |c_k|)^(1/k)`` (Jorba & Zou 2005), ``c_k``
the last coefficients of x and v and ``s = 1 + |x0|`` or ``1 + |v0|`` (``atol = rtol = tol``):
no step is ever rejected. The step's polynomial is its own dense output. A crossing of
``x = 0`` (a sign change, or a dip through zero at an interior extremum) is excluded cheaply
when the quadratic part's extreme on [0, h] clears the bound ``Σ_{k≥3} |x_k| h^k`` on the rest,
or when x at ``N_SUB + 1`` points clears ``(h/N_SUB)²/8 · max|x''|``; otherwise it is searched
on the sub-intervals (with x' for dips) and located by the Illinois method on the polynomial.
The step is cut there and the mode switches; no step is re-taken. For the paper's law
(m2 = 2, l = 1) a period costs about a quarter of the DOP853 time of :mod:`.flow` at equal error
(about 20 steps of 0.22 µs at 360 Hz).

This integrates the state only (no variational equation, no step records): it is the
transient integrator of :mod:`.settle` and of the ensembles. Non-integer exponents and the
multi-frequency excitations fall back to :func:`.flow.advance` (:func:`advance_state`).

References
----------
À. Jorba, M. Zou, "A software package for the numerical integration of ODEs by means of
high-order Taylor methods", *Experimental Mathematics* 14 (2005) 99–117.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contact import (
    DAMPING_HUNT_CROSSLEY,
    EXCITATION_BASE,
    P_DAMPING,
    P_EXCITATION,
    P_S1,
    P_S2,
    P_SPRING,
    SPRING_EXPONENTIAL,
    SPRING_POWER,
    SPRING_TABLE,
    forcing_amplitude,
    is_paper_family,
    is_paper_vector,
    series_contact,
    series_exponential,
)
from .contact_table import series_table, table_segment
from .flow import REC_WIDTH, advance
from .series_roots import N_SUB, crossing, poly, segment_event
from .status import (
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_STEP_TOO_SMALL,
    STATUS_TOO_MANY_EVENTS,
)

SAFETY = 0.8
MAX_EXPONENT = 8  # integer exponents up to this use the Taylor flow
ORDER_MIN, ORDER_MAX = 8, 28
TABLE_ORDER = 10  # series order in contact on the table law (its steps end at the rows)
INV = np.array([0.0] + [1.0 / k for k in range(1, ORDER_MAX + 2)])  # 1/k without a division


@njit(cache=True)
def damping_exponent(par):
    """The exponent l of the damping term c x^l x' of a polynomial law: the power damping's l, or
    for Hunt–Crossley damping on the power spring (c f_s(x) x' = c x^m2 x') l = m2; −1 for any
    other law (no series)."""
    if is_paper_family(par):
        return par[1]
    if par[P_SPRING] == SPRING_POWER and par[P_DAMPING] == DAMPING_HUNT_CROSSLEY and par[0] == par[P_S1]:
        return par[P_S1]
    return -1.0


@njit(cache=True)
def is_polynomial_law(par):
    """True for the power spring with power or Hunt–Crossley damping under a force or base
    motion at f_e (the right-hand side is a polynomial plus one cosine) when m2 and the damping
    exponent (:func:`damping_exponent`) are integers ≤ MAX_EXPONENT."""
    if par.shape[0] > P_EXCITATION and par[P_EXCITATION] > EXCITATION_BASE:
        return False
    m2 = par[0]
    l = damping_exponent(par)
    return (m2 == math.floor(m2) and l == math.floor(l) and 1.0 <= m2 <= MAX_EXPONENT
            and 0.0 <= l <= MAX_EXPONENT)


#: What :func:`series_law` answers: no series (DOP853), the power spring's polynomial
#: recurrence (:func:`.contact.series_contact`), the exponential spring's
#: (:func:`.contact.series_exponential`), the table law's (:func:`.contact_table.series_table`,
#: on :func:`advance_taylor_table`).
SERIES_NONE, SERIES_POWER, SERIES_EXPONENTIAL, SERIES_TABLE = 0, 1, 2, 3


@njit(cache=True)
def series_law(par):
    """Which Taylor recurrence integrates this law's contact mode (``SERIES_*``): the polynomial
    laws (:func:`is_polynomial_law`), and the exponential and table springs with Hunt–Crossley
    damping or power damping of integer exponent l ≤ MAX_EXPONENT under a force or base motion
    at f_e (the table's segment by segment, :func:`advance_taylor_table`); ``SERIES_NONE``
    (DOP853) for any other law or excitation."""
    if is_polynomial_law(par):
        return SERIES_POWER
    if is_paper_vector(par) or par[P_EXCITATION] > EXCITATION_BASE:
        return SERIES_NONE
    l = par[1]
    if not (par[P_DAMPING] == DAMPING_HUNT_CROSSLEY or (l == math.floor(l) and 0.0 <= l <= MAX_EXPONENT)):
        return SERIES_NONE
    if par[P_SPRING] == SPRING_EXPONENTIAL:
        return SERIES_EXPONENTIAL
    if par[P_SPRING] == SPRING_TABLE:
        return SERIES_TABLE
    return SERIES_NONE


@njit(cache=True)
def order_for(tol):
    """Series order for a local tolerance: about −0.6 ln(tol) + 6 (15 at 1e-7, 18 at 1e-9, 23 at
    1e-12); at equal error the cost per period is flat within 10 % from 16 to 20."""
    n = int(-0.6 * math.log(max(tol, 1e-16)) + 6.0)
    return min(ORDER_MAX, max(ORDER_MIN, n))


@njit(cache=True)
def _rotation(k, ct, st):
    """cos(rτ0 + kπ/2) from ct = cos rτ0, st = sin rτ0 (the forcing's k-th coefficient is
    p r^k/k! times this)."""
    m = k & 3
    return ct if m == 0 else (-st if m == 1 else (-ct if m == 2 else st))


#: Row of the series work array (:func:`series_work`) that holds p r^k/k!; row 0 holds E_k,
#: rows 1..MAX_EXPONENT + 1 the powers of x and row EXP_ROW the series of exp(a x).
FORCING_ROW = MAX_EXPONENT + 2
EXP_ROW = MAX_EXPONENT + 3


@njit(cache=True)
def series_work(par, N):
    """Work array of :func:`series_prepared`, with the forcing magnitudes p r^k/k! (k < N) that
    do not depend on τ0 computed once: shape (MAX_EXPONENT + 4, N + 1)."""
    W = np.empty((MAX_EXPONENT + 4, N + 1))  # every entry read is written first
    fk = forcing_amplitude(par)  # p r^k / k!
    r = par[4]
    for k in range(N):
        W[FORCING_ROW, k] = fk
        fk *= r * INV[k + 1]
    return W


@njit(cache=True, inline="always")
def _excitation_series(t, r, N, F, E):
    """E[k] = δ_k0 + F_k cos(rτ0 + kπ/2), k < N: Taylor coefficients of 1 + p cos(rτ) about
    τ0 = t, with F_k = p r^k/k!."""
    ct = math.cos(r * t)
    st = math.sin(r * t)
    mst = -st
    mct = -ct
    k = 0
    while k + 4 <= N:  # the rotation's four cases unrolled (branch-free, vectorisable)
        E[k] = F[k] * ct + 0.0
        E[k + 1] = F[k + 1] * mst + 0.0
        E[k + 2] = F[k + 2] * mct + 0.0
        E[k + 3] = F[k + 3] * st + 0.0
        k += 4
    for j in range(k, N):
        E[j] = F[j] * _rotation(j, ct, st) + 0.0
    if N > 0:
        E[0] = F[0] * ct + 1.0


@njit(cache=True, inline="always")
def series_prepared(contact, t, x0, v0, par, N, X, V, W):
    """Taylor coefficients X[0..N], V[0..N] of x and x' about τ = t.

    Flight: ``m2 x'' = E``; contact: the contact law's recurrence ``m2 x'' = E − f(x, x')``
    (:func:`.contact.series_contact`, about 90 ns for order 14 for the paper's law, or
    :func:`.contact.series_exponential` for the exponential spring), with E the
    coefficients of 1 + p cos rτ. ``W``: work array from :func:`series_work` (same par, N).
    """
    m2 = par[0]
    X[0] = x0
    V[0] = v0
    E = W[0]
    _excitation_series(t, par[4], N, W[FORCING_ROW], E)
    if contact:
        if not is_paper_vector(par) and par[P_SPRING] == SPRING_EXPONENTIAL:
            series_exponential(E, X, V, W, W[EXP_ROW], N, par)
        else:
            series_contact(E, X, V, W, N, m2, damping_exponent(par), par[2])
        return
    inv_m2 = 1.0 / m2
    for k in range(N):  # flight: x'' = (1 + p cos rτ)/m2
        X[k + 1] = V[k] * INV[k + 1]
        V[k + 1] = E[k] * inv_m2 * INV[k + 1]


@njit(cache=True)
def series(contact, t, x0, v0, par, N, X, V):
    """:func:`series_prepared` with its own work array (for tests and single use)."""
    series_prepared(contact, t, x0, v0, par, N, X, V, series_work(par, N))


@njit(cache=True)
def step_size(X, V, N, tol):
    """Jorba–Zou step from the last two coefficients (relative + absolute tolerance ``tol``)."""
    sx = 1.0 + abs(X[0])
    sv = 1.0 + abs(V[0])
    h = math.inf
    for k in (N - 1, N):
        e = max(abs(X[k]) / sx, abs(V[k]) / sv)
        if e > 0.0:
            h = min(h, (tol / e) ** (1.0 / k))
    return SAFETY * h


@njit(cache=True, inline="always")
def _loop_start(t, t_end):
    """The counters of a Taylor flow's loop: ``(n_steps, n_events, t_flight, h, span, status)``,
    ``span`` the scale of τ that round-off is measured against."""
    return 0, 0, 0.0, 0.0, abs(t_end) + abs(t) + 1.0, STATUS_OK


@njit(cache=True, inline="always")
def _clipped(h, t, t_end, span):
    """The step ``h`` from ``t`` clipped to end on ``t_end``: ``(h, landing, stop, t, status)``;
    ``stop`` when the loop ends here: the remaining interval is below round-off (landed: t =
    ``t_end``) or the step is (STATUS_STEP_TOO_SMALL)."""
    remaining = t_end - t
    landing = h >= remaining
    if landing:
        h = remaining
    if h < 1e-15 * span:
        if landing:
            return h, landing, True, t_end, STATUS_OK
        return h, landing, True, t, STATUS_STEP_TOO_SMALL
    return h, landing, False, t, STATUS_OK


@njit(cache=True, inline="always")
def _counted_event(n_events, max_steps):
    """One more contact/flight switch: ``(n_events, status)``, STATUS_TOO_MANY_EVENTS beyond
    the allowance of :func:`.flow.advance`."""
    n_events += 1
    if n_events > 100 * max_steps // 1000 + 1000:
        return n_events, STATUS_TOO_MANY_EVENTS
    return n_events, STATUS_OK


@njit(cache=True, inline="always")
def _stepped(y, X, V, N, h, contact, t, t_end, landing, t_flight):
    """``y`` at the end of a step of the series (X, V) of length ``h``: ``(t, t_flight,
    status)``, STATUS_NONFINITE when the state is not finite."""
    y[0] = poly(X, N, h, 0)
    y[1] = poly(V, N, h, 0)
    if not contact:
        t_flight += h
    t = t_end if landing else t + h
    return t, t_flight, STATUS_OK if math.isfinite(y[0]) and math.isfinite(y[1]) else STATUS_NONFINITE


@njit(cache=True, inline="always")
def _final_status(status, t, t_end, n_steps, max_steps):
    """The status of a loop that ran while ``t < t_end``, ``n_steps < max_steps`` and the status
    was OK: STATUS_MAX_STEPS when the steps ran out before ``t_end``."""
    if status == STATUS_OK and t < t_end and n_steps >= max_steps:
        return STATUS_MAX_STEPS
    return status


@njit(cache=True)
def advance_taylor(y, t, t_end, contact, par, tol, max_steps):
    """Integrate the state ``y = [x, v]`` in place from τ = ``t`` to exactly ``t_end``.

    Returns ``(contact, h_last, n_steps, t_flight, n_events, status)`` as :func:`.flow.advance`
    does (without records).
    """
    N = order_for(tol)
    X = np.empty(N + 1)
    V = np.empty(N + 1)
    W = series_work(par, N)
    S = np.empty((2, N_SUB + 1))
    n_steps, n_events, t_flight, h, span, status = _loop_start(t, t_end)
    while t < t_end and n_steps < max_steps and status == STATUS_OK:
        series_prepared(contact, t, y[0], y[1], par, N, X, V, W)
        h, landing, stop, t, status = _clipped(step_size(X, V, N, tol), t, t_end, span)
        if stop:
            break
        s_ev = crossing(contact, X, V, N, h, S)
        n_steps += 1
        if s_ev >= 0.0:
            if not contact:
                t_flight += s_ev
            y[1] = poly(V, N, s_ev, 0)
            y[0] = 0.0
            t = t + s_ev
            contact = not contact
            n_events, status = _counted_event(n_events, max_steps)
            continue
        t, t_flight, status = _stepped(y, X, V, N, h, contact, t, t_end, landing, t_flight)
    return contact, h, n_steps, t_flight, n_events, _final_status(status, t, t_end, n_steps, max_steps)


@njit(cache=True)
def advance_taylor_table(y, t, t_end, contact, par, tol, max_steps):
    """:func:`advance_taylor` for the table law: in contact the Taylor series of the segment's
    cubic (:func:`.contact.series_table`), each arrival at a row x_i an event that ends the step
    on x = x_i exactly and moves to the next segment (the PCHIP is only C¹ there; x = 0 leaves
    the contact). Returns ``(contact, h_last, n_steps, t_flight, n_events, status)``, n_events
    counting the contact/flight switches only."""
    N = order_for(tol)
    N_c = min(N, TABLE_ORDER)  # contact: steps end at the rows, a lower order does
    X = np.empty(N + 1)
    V = np.empty(N + 1)
    XU = np.empty(N + 1)
    VU = np.empty(N + 1)
    W = series_work(par, N)
    P = np.empty((4, N + 1))
    S = np.empty((2, N_SUB + 1))
    n_rows = int(par[P_S1])
    o = int(par[P_S2])
    seg = table_segment(y[0], par) if contact else 0
    n_steps, n_events, t_flight, h, span, status = _loop_start(t, t_end)
    while t < t_end and n_steps < max_steps and status == STATUS_OK:
        X[0] = y[0]
        V[0] = y[1]
        M = N_c if contact else N
        if contact:
            _excitation_series(t, par[4], M, W[FORCING_ROW], W[0])
            series_table(W[0], X, V, W, P, M, par, seg)
        else:
            series_prepared(False, t, y[0], y[1], par, N, X, V, W)
        h, landing, stop, t, status = _clipped(step_size(X, V, M, tol), t, t_end, span)
        if stop:
            break
        n_steps += 1
        if contact:
            hi = par[o + seg + 1] if seg < n_rows - 1 else math.inf
            s_ev, side = segment_event(contact, X, V, XU, VU, M, h, par[o + seg], hi, S)
        else:
            s_ev = crossing(contact, X, V, M, h, S)
            side = 1
        if s_ev >= 0.0:
            y[1] = poly(V, M, s_ev, 0)
            t = t + s_ev
            if not contact:
                t_flight += s_ev
            if contact and not (seg == 0 and side < 0):
                seg += side
                y[0] = par[o + seg] if side > 0 else par[o + seg + 1]
                continue
            y[0] = 0.0
            contact = not contact
            seg = 0
            n_events, status = _counted_event(n_events, max_steps)
            continue
        t, t_flight, status = _stepped(y, X, V, M, h, contact, t, t_end, landing, t_flight)
    return contact, h, n_steps, t_flight, n_events, _final_status(status, t, t_end, n_steps, max_steps)


@njit(cache=True)
def advance_state(y, t, t_end, contact, h, par, tol, max_steps):
    """State-only flow from τ = ``t`` to ``t_end``: Taylor series for the laws that have one
    (:func:`series_law`), else DOP853.

    Returns ``(contact, h, n_steps, t_flight, n_events, status)``.
    """
    kind = series_law(par)
    if kind == SERIES_TABLE:
        return advance_taylor_table(y, t, t_end, contact, par, tol, max_steps)
    if kind != SERIES_NONE:
        return advance_taylor(y, t, t_end, contact, par, tol, max_steps)
    contact, h, _i, ns, tf, ne, st = advance(y, t, t_end, contact, h, par, tol, tol,
                                             np.empty((0, REC_WIDTH)), np.int64(0),
                                             np.int64(max_steps))
    return contact, h, ns, tf, ne, st
