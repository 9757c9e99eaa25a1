"""Event-located DOP853 flow of a structure of n coordinates with m contact elements (compiled, pure).

Scaled equation (``contactvib.model.system_kernel``: x = q/L, τ = ω t, ξ_i = δ_i / y0_i)::

    x'' = g0 + gb cos(r τ) − Kx x − Cx x' − Σ_i mode_i Aw_i f_i(ξ_i, ξ_i'),
    ξ_i = U_i · x − γ_i,    ξ_i' = U_i · x'

``f_i`` is the compiled contact law (:func:`.contact.contact_force`, its partials from
:func:`.contact.contact_partials`) on the element's parameter row ``rows[i]``; ``mode_i`` is the
element's mode (1: in contact). The state is ``y = [x (n), x' (n)]`` or, with the variational
equation, ``[x, x', Φ (2n × 2n, row-major)]`` with ``Φ' = J Φ``,
``J = [[0, I], [∂x''/∂x, ∂x''/∂x']]`` of the current modes.

Each mode combination is integrated with its own smooth right-hand side. After an accepted step
every element is checked for a switch of ``ξ_i`` through 0 (a sign change at the step's ends, or
a dip through zero at an interior extremum of ξ_i, where ξ_i' changes sign), located on the 7th-
order dense output of ξ_i = U_i · x (:func:`.flow.dense_root` on the element's combination of the
interpolant); the earliest switch wins, the step is re-taken to end on it, x is projected onto
ξ_i = 0, the element's mode flips and the monodromy is multiplied by the saltation matrix::

    S = I + [0; Δa] [U_iᵀ, 0] / ξ_i',    Δa = ∓ Aw_i f_i(0, ξ_i')  (entering / leaving)

the identity where the element's force is continuous at ξ = 0 (any law with power damping l > 0,
or Hunt–Crossley damping of a spring with F_s(0) = 0). Its determinant is 1 (Δa has no position
part), so Liouville's formula det Φ = exp(∫ trace J dτ) holds across the switches.

The DOP853 step itself — stage states, the 8th-order solution, the error norm, the step-size
controller, the landing on an interval's end and the dense output — is :mod:`.dop853`'s, shared
with the 1-DOF flow and the friction contact; only the right-hand side, the elements' events and
the modes are this module's.

The step's helpers (:func:`rhs`, :func:`_stages`, :func:`_rk_step`, :func:`_dense`,
:func:`_event_fraction`) are inlined into :func:`advance`: a call hands over every array of the
:class:`SystemArrays` record with its reference count, which cost a third of a step.

Kernels never raise on the caller's behalf: they return integer status codes (:mod:`.status`).

References
----------
E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
Springer (1993), Sec. II.5–II.6 (DOP853, dense output, discontinuities).
R. I. Leine, H. Nijmeijer, *Dynamics and Bifurcations of Non-Smooth Mechanical Systems*,
Springer (2004), Ch. 2 (saltation matrix).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .contact import P_DAMPING, P_SPRING, contact_force, contact_partials, force, force_partials
from .dop853 import (
    C,
    dense_value,
    error_norm,
    interpolant,
    landing_step,
    next_step,
    solution,
    stage_state,
    step_factor,
)
from .flow import crosses_contact, dense_root
from .status import (
    STATUS_MAX_STEPS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_RECORD_FULL,
    STATUS_STEP_TOO_SMALL,
    STATUS_TOO_MANY_EVENTS,
)

#: The scaled system (``contactvib.model.system_kernel.KernelForm``'s arrays), compiled as one record;
#: ``paper[i]``: row i is the power spring with power damping (its scalar path, :func:`.contact.force`).
SystemArrays = namedtuple("SystemArrays", ("Kx", "Cx", "g0", "gb", "r", "U", "gam", "Aw", "rows", "paper"))

_H_AFTER_EVENT = 0.05  # step cap right after a switching instant [τ]; the controller adapts
#: Steps allowed per unit of τ·r/2π (one excitation period) by the callers below.
MAX_STEPS_PER_PERIOD = 2_000_000

#: Gauss–Legendre nodes and weights on [0, 1] for the mean forces (8 points: exact to degree 15
#: in θ, so the paper's law x² + c x x' on the step's 7th-degree interpolant is integrated exactly).
_GX, _GW = np.polynomial.legendre.leggauss(8)
GAUSS_X = 0.5 * (_GX + 1.0)
GAUSS_W = 0.5 * _GW


def system_arrays(Kx, Cx, g0, gb, r, U, gam, Aw, rows) -> SystemArrays:
    """The :class:`SystemArrays` record with contiguous float64 arrays (fixed types: one compile)."""
    def c(a):
        return np.ascontiguousarray(a, dtype=np.float64)

    rows = c(rows)
    paper = (rows[:, P_SPRING] == 0.0) & (rows[:, P_DAMPING] == 0.0)
    return SystemArrays(c(Kx), c(Cx), c(g0), c(gb), float(r), c(U), c(gam), c(Aw), rows, paper)


def rec_width(n, m):
    """Columns of a step record: t, h, the m modes, the 2n state components at the step's start,
    then the interpolant F[0..6] of the 2n components (q-major)."""
    return 2 + m + 16 * n


@njit(cache=True, inline="always")
def element_state(sa, i, y):
    """(ξ_i, ξ_i') of element i at the state ``y`` = [x, x', ...]."""
    n = sa.Kx.shape[0]
    xi = -sa.gam[i]
    xv = 0.0
    for k in range(n):
        u = sa.U[i, k]
        xi += u * y[k]
        xv += u * y[n + k]
    return xi, xv


@njit(cache=True, inline="always")
def law_force(paper, sa, i, xi, xv):
    """f_i(ξ, ξ') [units of W_i]: :func:`.contact.contact_force` on row i; the power spring with
    power damping (``sa.paper[i]``, or every element when ``paper`` is the constant True)
    through its scalar path :func:`.contact.force`. As :func:`.flow.law_acceleration`'s
    ``paper``: a caller that passes the constant True compiles no call of the general law into
    its loop (that call alone, never taken, doubled the cost of a step)."""
    if paper or sa.paper[i]:
        return force(xi, xv, sa.rows[i, 0], sa.rows[i, 1], sa.rows[i, 2])
    return contact_force(xi, xv, sa.rows[i])


@njit(cache=True, inline="always")
def law_partials(paper, sa, i, xi, xv):
    """(∂f_i/∂ξ, ∂f_i/∂ξ') (:func:`.contact.contact_partials`; :func:`.contact.force_partials`),
    ``paper`` as :func:`law_force`'s."""
    if paper or sa.paper[i]:
        return force_partials(xi, xv, sa.rows[i, 0], sa.rows[i, 1], sa.rows[i, 2])
    return contact_partials(xi, xv, sa.rows[i])


@njit(cache=True)
def element_force(sa, i, xi, xv):
    """f_i(ξ, ξ') [units of W_i] of element i (:func:`law_force`)."""
    return law_force(False, sa, i, xi, xv)


@njit(cache=True)
def all_paper(sa):
    """True when every element is the power spring with power damping (the scalar path)."""
    for i in range(sa.paper.shape[0]):
        if not sa.paper[i]:
            return False
    return True


@njit(cache=True, inline="always")
def rhs_row(paper, sa, mode, t, y, out, row, nvar, Jx, Jv):
    """Right-hand side of the state (``nvar`` False) or state and variational equation into
    ``out[row]``; ``Jx``, ``Jv`` (n × n) receive ∂x''/∂x and ∂x''/∂x' when ``nvar``; ``paper`` as
    :func:`law_force`'s. Inlined into the stage loop: a call per stage with an array view costs
    more than the stage itself."""
    n = sa.Kx.shape[0]
    cr = math.cos(sa.r * t)
    for j in range(n):
        out[row, j] = y[n + j]
        a = sa.g0[j] + sa.gb[j] * cr
        for k in range(n):
            a -= sa.Kx[j, k] * y[k] + sa.Cx[j, k] * y[n + k]
        out[row, n + j] = a
    if nvar:
        for j in range(n):
            for k in range(n):
                Jx[j, k] = -sa.Kx[j, k]
                Jv[j, k] = -sa.Cx[j, k]
    for i in range(mode.shape[0]):
        if not mode[i]:
            continue
        xi, xv = element_state(sa, i, y)
        f = law_force(paper, sa, i, xi, xv)
        for j in range(n):
            out[row, n + j] -= sa.Aw[i, j] * f
        if nvar:
            fx, fv = law_partials(paper, sa, i, xi, xv)
            for j in range(n):
                a = sa.Aw[i, j]
                for k in range(n):
                    Jx[j, k] -= a * fx * sa.U[i, k]
                    Jv[j, k] -= a * fv * sa.U[i, k]
    if nvar:
        n2 = 2 * n
        for r in range(n):
            for col in range(n2):
                out[row, n2 + r * n2 + col] = y[n2 + (n + r) * n2 + col]
        for r in range(n):
            for col in range(n2):
                s = 0.0
                for k in range(n):
                    s += Jx[r, k] * y[n2 + k * n2 + col] + Jv[r, k] * y[n2 + (n + k) * n2 + col]
                out[row, n2 + (n + r) * n2 + col] = s


@njit(cache=True, inline="always")
def rhs(sa, mode, t, y, out, nvar, Jx, Jv):
    """:func:`rhs_row` into the vector ``out``."""
    out2 = out.reshape((1, out.shape[0]))
    if all_paper(sa):
        rhs_row(True, sa, mode, t, y, out2, 0, nvar, Jx, Jv)
    else:
        rhs_row(False, sa, mode, t, y, out2, 0, nvar, Jx, Jv)


@njit(cache=True, inline="always")
def _stages(sa, mode, t, y, h, K, ys, s_first, s_last, N, nvar, Jx, Jv):
    """K[s] = f(t + C[s] h, y + h Σ_{j<s} A[s, j] K[j]) for s = s_first..s_last − 1 (the first
    ``N`` components); the scalar path of the power law compiled alone when every element takes
    it (:func:`law_force`)."""
    if all_paper(sa):
        _stage_loop(True, sa, mode, t, y, h, K, ys, s_first, s_last, N, nvar, Jx, Jv)
    else:
        _stage_loop(False, sa, mode, t, y, h, K, ys, s_first, s_last, N, nvar, Jx, Jv)


@njit(cache=True, inline="always")
def _stage_loop(paper, sa, mode, t, y, h, K, ys, s_first, s_last, N, nvar, Jx, Jv):
    """The stages of :func:`_stages` for ``paper`` (a constant) True or False."""
    for s in range(s_first, s_last):
        stage_state(K, y, h, s, N, ys)
        rhs_row(paper, sa, mode, t + C[s] * h, ys, K, s, nvar, Jx, Jv)


@njit(cache=True, inline="always")
def _rk_step(sa, mode, t, y, f, h, rtol, atol, K, ys, ynew, fnew, Jx, Jv):
    """One DOP853 step; fills K[0..12], ``ynew``, ``fnew``; returns the error norm (< 1: accept)."""
    N = y.shape[0]
    nvar = N > 2 * sa.Kx.shape[0]
    for i in range(N):
        K[0, i] = f[i]
    _stages(sa, mode, t, y, h, K, ys, 1, 12, N, nvar, Jx, Jv)
    solution(K, y, h, N, ynew)
    rhs(sa, mode, t + h, ynew, fnew, nvar, Jx, Jv)
    for i in range(N):
        K[12, i] = fnew[i]
    return error_norm(K, y, ynew, h, N, atol, rtol)


@njit(cache=True, inline="always")
def _dense(sa, mode, t, y, ynew, h, K, ys, F, Jx, Jv):
    """Fill F[7, 2n] with the 7th-order interpolant of x and x' over the last step."""
    n2 = 2 * sa.Kx.shape[0]
    _stages(sa, mode, t, y, h, K, ys, 13, 16, n2, False, Jx, Jv)
    interpolant(K, y, ynew, h, n2, F)


@njit(cache=True)
def _element_interpolant(sa, i, F, E):
    """E[7, 2]: the interpolant of (ξ_i, ξ_i') from the state's F[7, 2n]."""
    n = sa.Kx.shape[0]
    for q in range(7):
        a = 0.0
        b = 0.0
        for k in range(n):
            a += sa.U[i, k] * F[q, k]
            b += sa.U[i, k] * F[q, n + k]
        E[q, 0] = a
        E[q, 1] = b


@njit(cache=True, inline="always")
def _event_fraction(sa, mode, t, y, ynew, h, K, ys, F, E, eo, record, fresh, Jx, Jv):
    """(θ, i): the earliest fraction θ ∈ [0, 1] of the step at which an element i switches, or
    (−1, −1). ``fresh[i]``: element i switched at the step's start (its ξ taken as exactly 0, no
    dip through its surface at once). Another element that starts strictly on the far side of
    its surface (one that switched at the same instant as a fresh one, within rounding) switches
    at θ = 0. Fills ``F`` with the step's interpolant when needed (always when ``record``)."""
    best = 2.0
    which = -1
    have = False
    for i in range(mode.shape[0]):
        xi0, xv0 = element_state(sa, i, y)
        if not fresh[i] and ((xi0 < 0.0) if mode[i] else (xi0 > 0.0)):
            return 0.0, i
        xi1, xv1 = element_state(sa, i, ynew)
        vflip = (xv0 < 0.0) != (xv1 < 0.0)
        cross_end = crosses_contact(mode[i], xi1)
        if not (vflip or cross_end):
            continue
        if not have:
            _dense(sa, mode, t, y, ynew, h, K, ys, F, Jx, Jv)
            have = True
        _element_interpolant(sa, i, F, E)
        eo[0] = 0.0 if fresh[i] else xi0
        eo[1] = xv0
        th = -1.0
        lo = 0.0
        if vflip:
            th_v = dense_root(E, eo, 1, 0.0, 0.0, 1.0)
            if not fresh[i] and crosses_contact(mode[i], dense_value(E, eo, th_v, 0)):
                th = dense_root(E, eo, 0, 0.0, 0.0, th_v)
            lo = th_v
        if th < 0.0 and cross_end:
            th = dense_root(E, eo, 0, 0.0, lo, 1.0)
        if th >= 0.0 and th < best:
            best = th
            which = i
    if record and not have:
        _dense(sa, mode, t, y, ynew, h, K, ys, F, Jx, Jv)
    if which < 0:
        return -1.0, -1
    return best, which


@njit(cache=True)
def _switch(sa, mode, i, y):
    """Land on element i's surface: x projected onto ξ_i = 0, the monodromy (if carried)
    multiplied by the saltation matrix (module docstring), the element's mode flipped."""
    n = sa.Kx.shape[0]
    n2 = 2 * n
    xi, _ = element_state(sa, i, y)
    uu = 0.0
    for k in range(n):
        uu += sa.U[i, k] * sa.U[i, k]
    for k in range(n):
        y[k] -= sa.U[i, k] * xi / uu
    _, xv = element_state(sa, i, y)
    entering = not mode[i]
    if y.shape[0] > n2 and xv != 0.0:
        f = element_force(sa, i, 0.0, xv)
        if f != 0.0:
            scale = (-f if entering else f) / xv
            for col in range(n2):
                s = 0.0
                for k in range(n):
                    s += sa.U[i, k] * y[n2 + k * n2 + col]
                for r in range(n):
                    y[n2 + (n + r) * n2 + col] += scale * sa.Aw[i, r] * s
    mode[i] = entering


@njit(cache=True)
def initial_modes(sa, y, mode):
    """Each element's mode at ``y``: contact for ξ > 0, or ξ = 0 moving into the contact."""
    for i in range(mode.shape[0]):
        xi, xv = element_state(sa, i, y)
        mode[i] = xi > 0.0 or (xi == 0.0 and xv > 0.0)


@njit(cache=True)
def _record(rec, irec, t, h, mode, y, F):
    if irec >= rec.shape[0]:
        return irec + 1
    m = mode.shape[0]
    n2 = F.shape[1]
    rec[irec, 0] = t
    rec[irec, 1] = h
    for i in range(m):
        rec[irec, 2 + i] = 1.0 if mode[i] else 0.0
    o = 2 + m
    for k in range(n2):
        rec[irec, o + k] = y[k]
    o += n2
    for q in range(7):
        for k in range(n2):
            rec[irec, o + q * n2 + k] = F[q, k]
    return irec + 1


@njit(cache=True)
def advance(sa, y, t, t_end, mode, h, rtol, atol, rec, irec, max_steps):
    """Integrate ``y`` in place from τ = ``t`` to exactly ``t_end``, switching element modes.

    Parameters
    ----------
    sa : SystemArrays
    y : float64[2n] or float64[2n + 4n²]
        State (and flattened monodromy, row-major); overwritten with the state at ``t_end``.
    t, t_end : float
        Start and end [τ].
    mode : bool[m]
        Element modes at ``t``; overwritten with the modes at ``t_end``.
    h : float
        Step-size proposal [τ].
    rtol, atol : float
        Local error tolerances (atol in the units L_j, L_j ω of the scaled state).
    rec : float64[:, rec_width(n, m)]
        Step records; shape (0, ·) for none.
    irec : int
        First free row of ``rec``.
    max_steps : int
        Step limit for this call.

    Returns
    -------
    h, irec, n_steps, n_events, status
        Step proposal for a following call, next free record row (> rec.shape[0]: records
        lost), accepted steps, switches located, status code.
    """
    n2 = 2 * sa.Kx.shape[0]
    N = y.shape[0]
    nvar = N > n2
    record = rec.shape[0] > 0
    K = np.empty((16, N))
    ys = np.empty(N)
    F = np.zeros((7, n2))
    E = np.zeros((7, 2))
    eo = np.zeros(2)
    f = np.empty(N)
    ynew = np.empty(N)
    fnew = np.empty(N)
    Jx = np.empty((n2 // 2, n2 // 2))
    Jv = np.empty((n2 // 2, n2 // 2))
    rhs(sa, mode, t, y, f, nvar, Jx, Jv)
    n_steps = 0
    n_events = 0
    rejected = False
    fresh = np.zeros(mode.shape[0], dtype=np.bool_)
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
        err = _rk_step(sa, mode, t, y, f, h_try, rtol, atol, K, ys, ynew, fnew, Jx, Jv)
        if not (err < 1.0):
            h = h_try * step_factor(err, rejected)
            rejected = True
            continue
        h_next = h_try * step_factor(err, rejected)
        rejected = False
        theta, which = _event_fraction(sa, mode, t, y, ynew, h_try, K, ys, F, E, eo, record, fresh, Jx, Jv)
        if which >= 0:
            h_ev = theta * h_try
            _rk_step(sa, mode, t, y, f, h_ev, rtol, atol, K, ys, ynew, fnew, Jx, Jv)
            if record and h_ev > 0.0:
                _dense(sa, mode, t, y, ynew, h_ev, K, ys, F, Jx, Jv)
                irec = _record(rec, irec, t, h_ev, mode, y, F)
            t = t + h_ev
            for i in range(N):
                y[i] = ynew[i]
            _switch(sa, mode, which, y)
            if h_ev > 0.0:
                fresh[:] = False
            fresh[which] = True
            rhs(sa, mode, t, y, f, nvar, Jx, Jv)
            h = min(h_next, _H_AFTER_EVENT)
            n_events += 1
            n_steps += 1
            if n_events > 100 * max_steps // 1000 + 1000:
                status = STATUS_TOO_MANY_EVENTS
                break
            continue
        fresh[:] = False
        if record:
            irec = _record(rec, irec, t, h_try, mode, y, F)
        t = t_end if landing else t + h_try
        for i in range(N):
            y[i] = ynew[i]
            f[i] = fnew[i]
        h = next_step(h, h_next, landing)
        n_steps += 1
        finite = True
        for i in range(n2):
            finite = finite and math.isfinite(y[i])
        if not finite:
            status = STATUS_NONFINITE
            break
    if record and irec > rec.shape[0] and status == STATUS_OK:
        status = STATUS_RECORD_FULL
    return h, irec, n_steps, n_events, status
