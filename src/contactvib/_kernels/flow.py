"""Event-located DOP853 flow of the nondimensional contact oscillator (compiled, pure).

Equation (``x = y/y0``, ``τ = ω_n0 t``, ``par = [m2, l, c, p, r]``)::

    x'' = [1 − x^m2 − c x^l x' + p cos(r τ)] / m2    contact mode (x > 0)
    x'' = [1 + p cos(r τ)] / m2                      flight mode  (x ≤ 0)

State vectors are ``[x, v]`` (n = 2) or ``[x, v, Φ11, Φ12, Φ21, Φ22]`` (n = 6) with the
variational equation ``Φ' = J Φ``, or that and ``[s_x, s_v]`` (n = 8), the sensitivity to the
frequency ratio r: ``s' = J s + (0, ∂x''/∂r)`` (the continuation's parameter column). Each
mode is integrated with its own smooth right-hand side; crossings of ``x = 0`` are located
on the 7th-order dense output (a sign change at the step ends, or a dip through zero at an
interior extremum of ``x``), the step is re-taken to end exactly on the switching instant, and
the monodromy is multiplied by the saltation matrix
``S = I + (f⁺ − f⁻) eₓᵀ / v`` (the identity for contact laws whose force is continuous at
``x = 0``, i.e. every law with ``l > 0`` or ``h_n = 0``).

The step's system-independent pieces (tableau, solution, error norm, step-size controller,
dense output) are :mod:`.dop853`'s; the stages here work on scalars (one law evaluation each).

Kernels never raise on the caller's behalf: they return integer status codes (``STATUS_*``).

References
----------
E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
Springer (1993), Sec. II.5 (DOP853), II.6 (dense output), II.6 (discontinuities).
R. I. Leine, H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*,
Springer (2004), Ch. 2 (saltation matrix).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .contact import (
    contact_force,
    contact_partials,
    force,
    force_partials,
    forcing,
    forcing_dr,
    is_paper_vector,
)
from .dop853 import (  # noqa: F401  (dense_value, interpolant: also the flow's names for its callers)
    A,
    C,
    dense_value,
    error_norm,
    interpolant,
    landing_step,
    next_step,
    solution,
    step_factor,
)
from .roots import illinois_root
from .status import (  # noqa: F401
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RECORD_FULL,
    STATUS_STEP_TOO_SMALL,
    STATUS_TOO_MANY_EVENTS,
)

#: Columns of a step record: t_old, h, contact flag, x_old, v_old, then F[0..6] for x and v.
REC_T, REC_H, REC_MODE, REC_X, REC_V, REC_F = 0, 1, 2, 3, 4, 5
REC_WIDTH = 5 + 14

_H_AFTER_EVENT = 0.05  # step cap right after a switching instant [τ]; the controller adapts


@njit(cache=True, inline="always")
def law_acceleration(paper, contact, t, x, v, par):
    """x'' of the given mode at (τ, x, x') [nondimensional]: [1 + p cos rτ − f(x, x')]/m2 in
    contact, f the contact law (:func:`.contact.force`). ``paper``: ``par`` is the paper's law
    under a force (:func:`.contact.is_paper_vector`), computed by its own expression. A caller that passes a
    constant gets only that branch compiled into its loop (the paper's stages stay as lean as
    before the law library: the generic branch in every stage cost ~15 % of the shooting)."""
    if paper:
        f = 1.0 + par[3] * math.cos(par[4] * t)
        if contact:
            f -= force(x, v, par[0], par[1], par[2])
        return f / par[0]
    f = forcing(t, par)
    if contact:
        f -= contact_force(x, v, par)
    return f / par[0]


@njit(cache=True, inline="always")
def law_jacobian_row(paper, contact, x, v, par):
    """(∂x''/∂x, ∂x''/∂x') of the given mode at (x, x') [nondimensional]: −(∂f/∂x, ∂f/∂v)/m2;
    ``paper`` as :func:`law_acceleration`'s."""
    if not contact:
        return 0.0, 0.0
    m2 = par[0]
    if paper:
        fx, fv = force_partials(x, v, m2, par[1], par[2])
    else:
        fx, fv = contact_partials(x, v, par)
    return -fx / m2, -fv / m2


@njit(cache=True, inline="always")
def acceleration(contact, t, x, v, par):
    """x'' of the given mode at (τ, x, x') [nondimensional] (:func:`law_acceleration`)."""
    return law_acceleration(is_paper_vector(par), contact, t, x, v, par)


@njit(cache=True, inline="always")
def jacobian_row(contact, x, v, par):
    """(∂x''/∂x, ∂x''/∂x') of the given mode at (x, x') [nondimensional] (:func:`law_jacobian_row`)."""
    return law_jacobian_row(is_paper_vector(par), contact, x, v, par)


@njit(cache=True)
def rhs(contact, t, y, par, out):
    """Right-hand side of the state (n = 2), state + variational equation (n = 6), or those and
    the sensitivity ``s = ∂(x, x')/∂r`` (n = 8): ``s' = J s + (0, ∂x''/∂r)``."""
    x = y[0]
    v = y[1]
    out[0] = v
    out[1] = acceleration(contact, t, x, v, par)
    if y.shape[0] >= 6:
        j21, j22 = jacobian_row(contact, x, v, par)
        out[2] = y[4]
        out[3] = y[5]
        out[4] = j21 * y[2] + j22 * y[4]
        out[5] = j21 * y[3] + j22 * y[5]
        if y.shape[0] == 8:
            out[6] = y[7]
            out[7] = j21 * y[6] + j22 * y[7] + forcing_dr(t, par) / par[0]


@njit(cache=True)
def _stages(contact, t, y, h, par, K, s_first, s_last, n):
    """K[s] = f(t + C[s] h, y + h Σ_{j<s} A[s, j] K[j]) for s = s_first..s_last − 1.

    Works on scalars (a call per stage with array views costs more than the stage itself);
    ``n`` = 2 integrates the state, 6 the state and the variational equation, 8 also the
    sensitivity to r (:func:`rhs`). The law is chosen
    once per call, outside the stage loop (:func:`law_acceleration`)."""
    if is_paper_vector(par):
        _stage_loop(True, contact, t, y, h, par, K, s_first, s_last, n)
    else:
        _stage_loop(False, contact, t, y, h, par, K, s_first, s_last, n)


@njit(cache=True, inline="always")
def _stage_loop(paper, contact, t, y, h, par, K, s_first, s_last, n):
    """The stages of :func:`_stages` for a law known to be (``paper``) the paper's or not."""
    for s in range(s_first, s_last):
        ax = 0.0
        av = 0.0
        for j in range(s):
            a = A[s, j]
            ax += a * K[j, 0]
            av += a * K[j, 1]
        x = y[0] + h * ax
        v = y[1] + h * av
        ts = t + C[s] * h
        K[s, 0] = v
        K[s, 1] = law_acceleration(paper, contact, ts, x, v, par)
        if n >= 6:
            p0 = 0.0
            p1 = 0.0
            p2 = 0.0
            p3 = 0.0
            for j in range(s):
                a = A[s, j]
                p0 += a * K[j, 2]
                p1 += a * K[j, 3]
                p2 += a * K[j, 4]
                p3 += a * K[j, 5]
            f11 = y[2] + h * p0
            f12 = y[3] + h * p1
            f21 = y[4] + h * p2
            f22 = y[5] + h * p3
            j21, j22 = law_jacobian_row(paper, contact, x, v, par)
            K[s, 2] = f21
            K[s, 3] = f22
            K[s, 4] = j21 * f11 + j22 * f21
            K[s, 5] = j21 * f12 + j22 * f22
            if n == 8:
                q0 = 0.0
                q1 = 0.0
                for j in range(s):
                    a = A[s, j]
                    q0 += a * K[j, 6]
                    q1 += a * K[j, 7]
                sx = y[6] + h * q0
                sv = y[7] + h * q1
                K[s, 6] = sv
                K[s, 7] = j21 * sx + j22 * sv + forcing_dr(ts, par) / par[0]


@njit(cache=True)
def _rk_step(contact, t, y, f, h, par, rtol, atol, K, ynew, fnew):
    """One DOP853 step (:mod:`.dop853`); fills K[0..12], ``ynew``, ``fnew``; returns the error
    norm (<1: accept)."""
    n = y.shape[0]
    for i in range(n):
        K[0, i] = f[i]
    _stages(contact, t, y, h, par, K, 1, 12, n)
    solution(K, y, h, n, ynew)
    rhs(contact, t + h, ynew, par, fnew)
    for i in range(n):
        K[12, i] = fnew[i]
    return error_norm(K, y, ynew, h, n, atol, rtol)


@njit(cache=True)
def _dense(contact, t, y, ynew, h, par, K, F):
    """Fill F[7, 2] with the 7th-order interpolant of x and v over the last step."""
    _stages(contact, t, y, h, par, K, 13, 16, 2)  # the interpolant needs x and v only
    interpolant(K, y, ynew, h, 2, F)


#: Width of the θ bracket below which a dense-output root is accepted (θ ∈ [0, 1]): strictly
#: below 4e-16, as :func:`.roots.illinois_root` accepts widths ≤ ``xtol``.
DENSE_XTOL = float(np.nextafter(4e-16, 0.0))


@njit(cache=True, inline='always')
def _dense_offset(theta, args):
    """Component ``args[2]`` of the dense output (``args[0]``, ``args[1]``) at θ, minus ``args[3]``."""
    return dense_value(args[0], args[1], theta, args[2]) - args[3]


@njit(cache=True)
def dense_root(F, y_old, comp, level, a, b):
    """Root of component − level on [a, b] ⊂ [0, 1] (a sign change assumed), Illinois method
    (:func:`.roots.illinois_root`)."""
    fa = dense_value(F, y_old, a, comp) - level
    fb = dense_value(F, y_old, b, comp) - level
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    return illinois_root(_dense_offset, (F, y_old, comp, level), a, b, fa, fb, DENSE_XTOL, 200)


@njit(cache=True)
def crosses_contact(contact, x):
    """True where x lies on the far side of the switching surface for the current mode."""
    if contact:
        return x <= 0.0
    return x > 0.0


@njit(cache=True)
def _record(rec, irec, t, h, contact, y_old, F):
    if irec >= rec.shape[0]:
        return irec + 1
    rec[irec, REC_T] = t
    rec[irec, REC_H] = h
    rec[irec, REC_MODE] = 1.0 if contact else 0.0
    rec[irec, REC_X] = y_old[0]
    rec[irec, REC_V] = y_old[1]
    for q in range(7):
        rec[irec, REC_F + 2 * q] = F[q, 0]
        rec[irec, REC_F + 2 * q + 1] = F[q, 1]
    return irec + 1


@njit(cache=True)
def _event_fraction(contact, t, y, ynew, h, par, K, F, record):
    """Fraction θ ∈ [0, 1] of the step [t, t + h] (from ``y`` to ``ynew``) at which x first
    reaches the switching surface of this mode, or −1: a sign change at the step's end, or a dip
    through zero at an interior extremum of x (a sign change of x'), located on the dense output.
    Fills ``F`` with the step's interpolant when it is needed (always when ``record``)."""
    vflip = (y[1] < 0.0) != (ynew[1] < 0.0)
    cross_end = crosses_contact(contact, ynew[0])
    theta_ev = -1.0
    if record or vflip or cross_end:
        _dense(contact, t, y, ynew, h, par, K, F)
        lo = 0.0
        if vflip:
            th_v = dense_root(F, y, 1, 0.0, 0.0, 1.0)
            if crosses_contact(contact, dense_value(F, y, th_v, 0)):
                theta_ev = dense_root(F, y, 0, 0.0, 0.0, th_v)
            lo = th_v
        if theta_ev < 0.0 and cross_end:
            theta_ev = dense_root(F, y, 0, 0.0, lo, 1.0)
    return theta_ev


@njit(cache=True)
def _switch_mode(contact, t, y, ynew, par):
    """Land on the switching surface: ``y`` ← ``ynew`` with x = 0, the monodromy (n = 6) and the
    sensitivity to r (n = 8: the switching surface x = 0 does not depend on r) multiplied by the
    saltation matrix S = I + (f⁺ − f⁻) eₓᵀ / v; returns the new mode."""
    n = y.shape[0]
    for i in range(n):
        y[i] = ynew[i]
    y[0] = 0.0
    v = y[1]
    new_contact = not contact
    if n >= 6 and v != 0.0:
        jump = (acceleration(new_contact, t, 0.0, v, par) - acceleration(contact, t, 0.0, v, par)) / v
        y[4] += jump * y[2]
        y[5] += jump * y[3]
        if n == 8:
            y[7] += jump * y[6]
    return new_contact


@njit(cache=True)
def initial_mode(x, v):
    """Contact mode for x > 0, or x = 0 moving into the contact."""
    return x > 0.0 or (x == 0.0 and v > 0.0)


@njit(cache=True)
def advance(y, t, t_end, contact, h, par, rtol, atol, rec, irec, max_steps):
    """Integrate ``y`` in place from τ = ``t`` to exactly ``t_end``, switching modes at x = 0.

    Parameters
    ----------
    y : float64[2], float64[6] or float64[8]
        State (and flattened monodromy Φ, row-major; and the sensitivity to r) at ``t``;
        overwritten with the state at ``t_end``.
    t, t_end : float
        Start and end [τ].
    contact : bool
        Mode at ``t``.
    h : float
        Step-size proposal [τ].
    par : float64[5]
        ``[m2, l, c, p, r]``.
    rtol, atol : float
        Local error tolerances (atol in units of y0 and y0 ω_n0).
    rec : float64[:, REC_WIDTH]
        Step records (dense output per accepted step); pass shape (0, REC_WIDTH) for none.
    irec : int
        First free row of ``rec``.
    max_steps : int
        Step limit for this call.

    Returns
    -------
    contact : bool
        Mode at the end.
    h : float
        Step proposal for a following call.
    irec : int
        Next free row of ``rec`` (``> rec.shape[0]`` means records were lost).
    n_steps : int
        Accepted steps.
    t_flight : float
        Time spent in flight mode [τ].
    n_events : int
        Switching instants crossed.
    status : int
        ``STATUS_OK`` or an error code.
    """
    n = y.shape[0]
    record = rec.shape[0] > 0
    K = np.empty((16, n))
    F = np.zeros((7, 2))
    f = np.empty(n)
    ynew = np.empty(n)
    fnew = np.empty(n)
    rhs(contact, t, y, par, f)
    n_steps = 0
    n_events = 0
    t_flight = 0.0
    rejected = False
    status = STATUS_OK
    span = abs(t_end) + abs(t) + 1.0
    while t < t_end:
        if n_steps >= max_steps:
            status = STATUS_MAX_STEPS
            break
        remaining = t_end - t
        h_try, landing = landing_step(h, remaining)
        if h_try < 1e-15 * span:
            if landing:
                t = t_end
                break
            status = STATUS_STEP_TOO_SMALL
            break
        err = _rk_step(contact, t, y, f, h_try, par, rtol, atol, K, ynew, fnew)
        if not (err < 1.0):
            h = h_try * step_factor(err, rejected)
            rejected = True
            continue
        h_next = h_try * step_factor(err, rejected)
        rejected = False
        theta_ev = _event_fraction(contact, t, y, ynew, h_try, par, K, F, record)
        if theta_ev >= 0.0:
            # re-take the step so that it ends exactly on the switching instant
            h_ev = theta_ev * h_try
            _rk_step(contact, t, y, f, h_ev, par, rtol, atol, K, ynew, fnew)
            if record:
                _dense(contact, t, y, ynew, h_ev, par, K, F)
                irec = _record(rec, irec, t, h_ev, contact, y, F)
            if not contact:
                t_flight += h_ev
            t = t + h_ev
            contact = _switch_mode(contact, t, y, ynew, par)
            rhs(contact, t, y, par, f)
            h = min(h_next, _H_AFTER_EVENT)
            n_events += 1
            n_steps += 1
            if n_events > 100 * max_steps // 1000 + 1000:
                status = STATUS_TOO_MANY_EVENTS
                break
            continue
        if record:
            irec = _record(rec, irec, t, h_try, contact, y, F)
        if not contact:
            t_flight += h_try
        t = t_end if landing else t + h_try
        for i in range(n):
            y[i] = ynew[i]
            f[i] = fnew[i]
        # a step shortened to land on t_end says nothing against the longer proposal
        h = next_step(h, h_next, landing)
        n_steps += 1
        if not (math.isfinite(y[0]) and math.isfinite(y[1])):
            status = STATUS_NONFINITE
            break
    if record and irec > rec.shape[0] and status == STATUS_OK:
        status = STATUS_RECORD_FULL
    return contact, h, irec, n_steps, t_flight, n_events, status
