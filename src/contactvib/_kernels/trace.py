"""Branch tracing along a frequency grid: Newton-corrected natural continuation with jumps (compiled).

A *trace* starts from a refined attractor at grid index ``i0`` and walks the grid in one
direction, as a laboratory sweep does, carrying the state:

1. predict the orbit point at the next frequency (secant through the last two points of the
   same segment), correct it by Newton shooting on the period-k map, accept it when it closes,
   is stable and its period is minimal (:func:`.settle.refine_stable_orbit`); if that fails, bridge the
   grid step by Newton-corrected sub-steps (halved down to 1/32 of it, :func:`bridge_orbit`) —
   a branch that bends fast between two grid points is kept, one that ends there is not;
2. otherwise (past a fold, a period doubling, or into chaos) integrate from the carried state
   until a new attractor is detected (:func:`.settle.settle`) — a *jump*;
3. a non-periodic attractor is followed by integrating from the carried state at every step.

Every attractor met is compared with a shared table of the attractors already known at that
grid index (same period and the orbit point equal to one of the known stroboscopic points to
``same_tol``, relative; non-periodic: the point inside a known cloud's bounding box). A known
attractor that has already been traced in this direction ends the trace (the rest would repeat
work); a new one is described and appended to the table. The table is shared by all traces of
one P_a level, so up-sweeps, down-sweeps and multi-start seeds never duplicate each other.

Hand-offs are records (named tuples of arrays or scalars, which numba compiles as structures):
the settings :class:`TraceSettings`, the table :class:`.table.KnownTable`, the output rows
:class:`.describe.TraceRows` (one row per new attractor point, described by
:func:`.describe.describe_point`) and the links between rows :class:`TraceLinks` (``jump`` = 0:
continued by Newton, 1: reached by a transient from the previous point).

The walk (:func:`trace`) is split into its steps: :func:`_continue_periodic` (Newton, then the
bridge), :func:`_jump` (the transient), :func:`_write_row` and :func:`_link`. These thin helpers
are compiled inline (``inline='always'``): numba links and re-optimises a callee's whole call
tree into every separately compiled caller, so a separately compiled layer above the integrators
costs seconds of compile time; a new helper on this path should be inlined likewise.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .describe import NP_LYAPUNOV, NP_RECORD, describe_point, floquet_pair, lyapunov_strobe
from .settle import refine_stable_orbit, settle
from .shooting import (
    MINIMAL_PERIOD_TOL,
    newton_map,
    newton_orbit,
    stable_monodromy,
    state_scale,
)
from .status import (
    ORIGIN_JUMP,
    ORIGIN_NEWTON,
    ORIGIN_START,
    SETTLE_NONPERIODIC,
    SETTLE_PERIODIC,
    STATUS_NEWTON_DIVERGED,
    STATUS_NEWTON_QUICK,
    STATUS_NEWTON_SINGULAR,
    STATUS_OK,
    STOP_FAILED,
    STOP_GRID_END,
    STOP_KNOWN,
    STOP_TABLE_FULL,
)
from .table import KIND_NONPERIODIC, KIND_PERIODIC, add_known, find_known

#: Transient limit when a non-periodic attractor is followed to the next frequency (the carried
#: state already lies on the attractor; a periodic window is still detected within it).
NP_FOLLOW = 100

#: Settings of a trace: ``rtol`` integrator tolerance of the shooting and the descriptions;
#: ``tol`` relative closure for accepting an orbit; ``kmax`` largest period detected;
#: ``max_periods`` transient limit after a jump [excitation periods]; ``detect_tol`` period
#: detection tolerance of the transient; ``rtol_transient`` its integrator tolerance;
#: ``same_tol`` relative distance under which two orbit points are the same attractor.
TraceSettings = namedtuple("TraceSettings", ["rtol", "tol", "kmax", "max_periods",
                                             "detect_tol", "rtol_transient", "same_tol"])

#: Links between output rows (global ids): ``a`` → ``b``, ``jump`` 0 (continued by Newton) or 1
#: (reached by a transient).
TraceLinks = namedtuple("TraceLinks", ["a", "b", "jump"])


def trace_settings(rtol, tol, kmax, max_periods, detect_tol, rtol_transient,
                   same_tol) -> TraceSettings:
    """A :class:`TraceSettings` with the field types the compiled trace expects."""
    return TraceSettings(float(rtol), float(tol), int(kmax), int(max_periods),
                         float(detect_tol), float(rtol_transient), float(same_tol))


def new_links(cap: int) -> TraceLinks:
    """A zeroed :class:`TraceLinks` with room for ``cap`` links."""
    return TraceLinks(np.zeros(cap, np.int64), np.zeros(cap, np.int64), np.zeros(cap, np.int64))


#: Newton steps (relative) below which the corrected point is checked by the description run
#: instead of another variational integration (the residual after such a step is ~ step²).
QUICK_STEP = 3e-5


@njit(cache=True)
def continue_orbit(zg, k, par, rtol, tol, rows, row, out_z, out_M):
    """Newton-correct the predicted period-k orbit point ``zg`` and describe it (row ``row`` of
    the :class:`.describe.TraceRows` ``rows``).

    Newton on the period map (:func:`.shooting.newton_map`, at most 10 evaluations, each over k
    periods with the variational equations) with a quick exit: once a step is below
    ``QUICK_STEP`` the corrected point is described (:func:`describe_point`, k periods without
    variational equations) and that run's end state decides closure, which saves the
    confirming variational integration; ``out_M`` is then the monodromy at the previous iterate
    (relative state difference ≤ QUICK_STEP); if it does not close, Newton goes on. Accepted
    only if the orbit closes to ``tol``, is stable (:func:`.shooting.stable_monodromy`)
    and no proper divisor of k closes (minimal period, checked on the described strobe points).
    Returns (accepted, closure).
    """
    z = np.empty(2)
    z[0] = zg[0]
    z[1] = zg[1]
    zn = np.empty(2)
    zend = np.empty(2)
    M = np.empty((2, 2))
    n_evals = 0
    while n_evals < 10:
        st, res, n = newton_map(z, k, par, rtol, rtol, tol, 10 - n_evals, QUICK_STEP, zn, M)
        n_evals += n
        if st == STATUS_NEWTON_SINGULAR or st == STATUS_NEWTON_DIVERGED:
            return False, res
        if st != STATUS_OK and st != STATUS_NEWTON_QUICK:
            return False, math.inf
        quick = st == STATUS_NEWTON_QUICK
        z[0] = zn[0]
        z[1] = zn[1]
        if not stable_monodromy(M):
            return False, res
        if describe_point(z, k, par, rtol, rows, row, zend) != STATUS_OK:
            return False, res
        sc = state_scale(z[0], z[1])
        if quick:
            res = max(abs(zend[0] - z[0]), abs(zend[1] - z[1])) / sc
            if res > tol:
                continue
        for dd in range(1, k):
            if k % dd == 0:
                dist = max(abs(rows.strobe[row, dd, 0] - z[0]), abs(rows.strobe[row, dd, 1] - z[1]))
                if dist / sc < MINIMAL_PERIOD_TOL:
                    return False, res
        out_z[0] = z[0]
        out_z[1] = z[1]
        for p in range(2):
            for q in range(2):
                out_M[p, q] = M[p, q]
        return True, res
    return False, math.inf


#: Sub-steps of a grid step tried before a lost orbit is declared a jump: down to 1/2**BRIDGE_DEPTH.
BRIDGE_DEPTH = 5
#: Longest period whose other strobe points are also tried as bridge starts (each try costs up to
#: BRIDGE_DEPTH Newton solves over k periods; a longer orbit is bridged from its carried point).
BRIDGE_PHASES_KMAX = 8


@njit(cache=True)
def stays_on_branch(z_new, z_pred, z_cur):
    """True when Newton from a secant predictor stayed on the branch.

    The correction ``|z_new − z_pred|`` must be at most twice the predicted change
    ``|z_pred − z_cur|`` (or 2 % of the state scale). A larger one means Newton converged to a
    coexisting orbit: the branch ended (at a fold) between the two points, and what a sweep
    does there is a jump, decided by the transient.
    """
    sc = state_scale(z_cur[0], z_cur[1])
    corr = max(abs(z_new[0] - z_pred[0]), abs(z_new[1] - z_pred[1]))
    d = max(abs(z_pred[0] - z_cur[0]), abs(z_pred[1] - z_cur[1]))
    return corr <= max(2.0 * d, 0.02 * sc)


@njit(cache=True)
def bridge_orbit(z, r_from, zp, r_prev, have_prev, r_to, k, par, rtol, tol, out_zg,
                 out_from):
    """Predictor at ``r_to`` for a period-k orbit known at ``r_from`` (and at ``r_prev`` if
    ``have_prev``), from Newton-corrected sub-steps in r (halved on failure, down to
    1/2**BRIDGE_DEPTH of the grid step), each stable orbit extrapolated linearly to the next
    and kept only if it stays on the branch (:func:`stays_on_branch`).

    Used when the one-step continuation fails: the branch may only bend fast between two grid
    points. Returns 0 when the orbit is lost between (a fold, a period doubling, an end of the
    branch); otherwise writes the predictor ``out_zg`` and the last sub-step's orbit point
    ``out_from`` and returns 2 if ``out_zg`` is a secant prediction, 1 if it is that point itself.
    """
    span = r_to - r_from
    h = 0.5 * span
    h_min = abs(span) / 2.0**BRIDGE_DEPTH
    zc = z.copy()
    zq = zp.copy()
    rc = r_from
    rq = r_prev
    have = have_prev
    zg = np.empty(2)
    oz = np.empty(2)
    oM = np.empty((2, 2))
    par_s = par.copy()
    while True:
        r_new = rc + h
        if (r_new - r_to) * span >= -1e-12 * abs(span):
            r_new = r_to
        w = (r_new - rc) / (rc - rq) if have else 0.0
        zg[0] = zc[0] + w * (zc[0] - zq[0])
        zg[1] = zc[1] + w * (zc[1] - zq[1])
        if r_new == r_to:
            out_zg[0] = zg[0]
            out_zg[1] = zg[1]
            out_from[0] = zc[0]
            out_from[1] = zc[1]
            return 2 if have else 1
        par_s[4] = r_new
        st, _res = newton_orbit(zg, k, par_s, rtol, rtol, tol, np.int64(8), oz, oM)
        if (st == STATUS_OK and stable_monodromy(oM)
                and (not have or stays_on_branch(oz, zg, zc))):
            zq[0] = zc[0]
            zq[1] = zc[1]
            rq = rc
            zc[0] = oz[0]
            zc[1] = oz[1]
            rc = r_new
            have = True
        else:
            h *= 0.5
            if abs(h) < h_min * (1.0 - 1e-9):
                return 0


@njit(cache=True, inline='always')
def _continue_periodic(z, zp, have_prev, k, pts, r_here, r_prev, r_next, par, cfg, rows, row,
                       out_z, out_M, out_from):
    """Continue the period-k orbit through ``z`` at ``r_here`` to ``r_next`` (``par[4]``).

    Newton from the secant predictor through ``zp`` (at ``r_prev``, if ``have_prev``), kept only
    if it stays on the branch (:func:`stays_on_branch`); if that fails, the grid step is bridged
    by sub-steps (:func:`bridge_orbit`) from the carried point (with its secant) and then, for
    k ≤ :data:`BRIDGE_PHASES_KMAX`, from the orbit's other strobe points ``pts[:k]`` (Newton's
    reach differs from phase to phase of a period-k orbit: a strobe point close to an impact is a
    poor start). On success the orbit point, monodromy and the phase point it was continued from
    are in ``out_z``, ``out_M``, ``out_from`` and row ``row`` of ``rows`` describes it. Returns
    (accepted, closure).
    """
    zg = np.empty(2)
    zb = np.empty(2)  # last orbit point of a bridge
    if have_prev:
        zg[0] = 2.0 * z[0] - zp[0]
        zg[1] = 2.0 * z[1] - zp[1]
    else:
        zg[0] = z[0]
        zg[1] = z[1]
    ok, res = continue_orbit(zg, k, par, cfg.rtol, cfg.tol, rows, row, out_z, out_M)
    if ok and have_prev and not stays_on_branch(out_z, zg, z):
        ok = False  # Newton went over to a coexisting orbit: this branch ended
    out_from[0] = z[0]
    out_from[1] = z[1]
    n_phases = k if k <= BRIDGE_PHASES_KMAX else 0
    for j in range(-1, n_phases if not ok else -1):
        if j < 0:
            zs, zq, hv, rq = z, zp, have_prev, r_prev
        else:
            zs = pts[j]
            if zs[0] == z[0] and zs[1] == z[1]:
                continue
            zq, hv, rq = zs, np.bool_(False), 0.0
        how = bridge_orbit(zs, r_here, zq, rq, hv, r_next, k, par, cfg.rtol, cfg.tol, zg,
                           zb)
        if how:
            ok, res = continue_orbit(zg, k, par, cfg.rtol, cfg.tol, rows, row, out_z, out_M)
            ok = ok and (how == 1 or stays_on_branch(out_z, zg, zb))
            if ok:
                out_from[0] = zs[0]
                out_from[1] = zs[1]
                break
    return ok, res


@njit(cache=True, inline='always')
def _copy_matrix(dst, src):
    """``dst[:, :] = src`` as a loop (a slice copy compiles numba's shape-error path: ~1.5 s)."""
    for a in range(src.shape[0]):
        for b in range(src.shape[1]):
            dst[a, b] = src[a, b]


@njit(cache=True, inline='always')
def _jump(z, kind, k, closure, par, cfg, hist, M):
    """Integrate from ``z`` until an attractor is detected (:func:`.settle.settle`).

    On success ``z`` (and ``M`` for a periodic one) hold the new attractor's point. Returns
    (ok, kind, k, origin, closure) of the attractor reached.
    """
    oz = np.empty(2)
    oM = np.empty((2, 2))
    n_max = cfg.max_periods if kind == KIND_PERIODIC else min(cfg.max_periods, NP_FOLLOW)
    st, kk, n_done, res = settle(z, 0.0, par, cfg.kmax, np.int64(4), n_max, cfg.detect_tol,
                                 cfg.rtol_transient, cfg.rtol, cfg.tol, hist, oz, oM)
    if st == SETTLE_PERIODIC:
        z[0] = oz[0]
        z[1] = oz[1]
        _copy_matrix(M, oM)
        return True, KIND_PERIODIC, kk, ORIGIN_JUMP, res
    origin = ORIGIN_JUMP if kind == KIND_PERIODIC else ORIGIN_NEWTON
    if st == SETTLE_NONPERIODIC:
        z[0] = hist[n_done, 0]
        z[1] = hist[n_done, 1]
        return True, KIND_NONPERIODIC, 0, origin, closure
    return False, kind, k, origin, closure


@njit(cache=True, inline='always')
def _write_row(rows, r, i, kind, k, z, origin, M, closure, par, rtol_transient):
    """The identity (grid index, kind, period, point, origin) and stability of row ``r``:
    Floquet multipliers and closure (periodic) or the Lyapunov exponent (non-periodic)."""
    rows.i[r] = i
    rows.kind[r] = kind
    rows.k[r] = k if kind == KIND_PERIODIC else 0
    rows.z[r, 0] = z[0]
    rows.z[r, 1] = z[1]
    rows.origin[r] = origin
    if kind == KIND_PERIODIC:
        floquet_pair(M, rows.mu_re[r], rows.mu_im[r])
        rows.closure[r] = closure
        rows.lyap[r] = math.nan
    else:
        rows.mu_re[r, 0] = math.nan
        rows.mu_re[r, 1] = math.nan
        rows.mu_im[r, 0] = math.nan
        rows.mu_im[r, 1] = math.nan
        rows.closure[r] = math.inf
        rows.lyap[r] = lyapunov_strobe(z, par, rtol_transient, np.int64(NP_LYAPUNOV))


@njit(cache=True, inline='always')
def _link(links, n, a, b, origin):
    """Append the link ``a`` → ``b`` (none if ``a`` < 0); returns the new link count."""
    if a < 0:
        return n
    links.a[n] = a
    links.b[n] = b
    links.jump[n] = 1 if origin == ORIGIN_JUMP else 0
    return n + 1


@njit(cache=True, inline="always")
def _refine_start(z, k, par, cfg, M):
    """Newton-refine the period-k orbit through ``z`` and reduce k to its minimal period
    (:func:`.settle.refine_stable_orbit`); on success ``z`` and ``M`` become the orbit point and its
    monodromy. Returns (ok, k, closure)."""
    oz = np.empty(2)
    oM = np.empty((2, 2))
    ok, kk, res = refine_stable_orbit(z, k, par, cfg.rtol, cfg.tol, oz, oM)
    if not ok:
        return False, k, res
    z[0] = oz[0]
    z[1] = oz[1]
    _copy_matrix(M, oM)
    return True, kk, res


@njit(cache=True)
def trace(z0, k0, kind0, i0, direction, r_grid, par_in, cfg, table, rows, row_base, links):
    """Trace from the attractor (``z0``, period ``k0``, ``kind0``) at grid index ``i0``.

    Parameters
    ----------
    direction : int
        +1 (up in frequency) or −1.
    r_grid : float64[n_f]
        Frequency ratios r = f_e/f_n0 of the grid.
    par_in : float64[5]
        ``[m2, l, c, p, r]`` (``r`` is overwritten by the grid's).
    cfg : TraceSettings
    table : .table.KnownTable
        Read and extended in place (``cov[i, s, 0/1]`` marks slots traced downwards/upwards).
    rows : .describe.TraceRows
        Output rows 0, 1, … of this trace; they get global ids ``row_base + n``.
    links : TraceLinks
        Output links (global ids).

    Returns
    -------
    n_rows, n_links, stop_reason, i_stop
    """
    n_f = r_grid.shape[0]
    d_slot = 1 if direction > 0 else 0
    par = par_in.copy()
    z = z0.copy()
    k = k0
    kind = kind0
    zp = np.empty(2)  # previous accepted orbit point on this segment (for the secant)
    z_from = np.empty(2)
    have_prev = False
    oz = np.empty(2)
    oM = np.empty((2, 2))
    hist = np.empty((cfg.max_periods + 1, 2))
    M = np.zeros((2, 2))
    closure = 0.0
    if kind == KIND_PERIODIC:  # refine the start: the minimal period of a closed stable orbit
        par[4] = r_grid[i0]
        ok, k, closure = _refine_start(z, k, par, cfg, M)
        if not ok:
            return 0, 0, STOP_FAILED, i0
    n_rows = np.int64(0)
    n_links = 0
    prev_row = -1
    i = i0
    origin = ORIGIN_START
    res = 0.0
    zend = np.empty(2)
    described = False  # row n_rows already holds the description of z
    while True:
        par[4] = r_grid[i]
        # ---- is it known here?
        s = find_known(table, i, z, k, kind, cfg.same_tol)
        if s >= 0:
            row = table.row[i, s]
            n_links = _link(links, n_links, prev_row, row, origin)
            if table.cov[i, s, d_slot]:
                return n_rows, n_links, STOP_KNOWN, i
            table.cov[i, s, d_slot] = True
            prev_row = row
        else:
            if table.n[i] >= table.k.shape[1]:
                return n_rows, n_links, STOP_TABLE_FULL, i
            r = n_rows
            if not described:
                n_per = k if kind == KIND_PERIODIC else NP_RECORD
                if describe_point(z, n_per, par, cfg.rtol, rows, r, zend) != STATUS_OK:
                    return n_rows, n_links, STOP_FAILED, i
            _write_row(rows, r, i, kind, k, z, origin, M, closure, par, cfg.rtol_transient)
            s = add_known(table, i, kind, k, rows.strobe[r], rows.n_strobe[r], row_base + r,
                          d_slot)
            if kind != KIND_PERIODIC:  # carry on from the end of the recorded cloud
                nb = rows.n_strobe[r]
                z[0] = rows.strobe[r, nb - 1, 0]
                z[1] = rows.strobe[r, nb - 1, 1]
            n_links = _link(links, n_links, prev_row, row_base + r, origin)
            prev_row = row_base + r
            n_rows += 1
        # ---- next grid point: Newton continuation, else a jump
        i_next = i + direction
        if i_next < 0 or i_next >= n_f:
            return n_rows, n_links, STOP_GRID_END, i
        par[4] = r_grid[i_next]
        described = False
        if kind == KIND_PERIODIC:
            r_prev = r_grid[i - direction] if have_prev else 0.0
            described, res = _continue_periodic(z, zp, have_prev, k, table.pts[i, s], r_grid[i],
                                                r_prev, r_grid[i_next], par, cfg, rows, n_rows,
                                                oz, oM, z_from)
        if described:
            zp[0] = z_from[0]
            zp[1] = z_from[1]
            have_prev = True
            z[0] = oz[0]
            z[1] = oz[1]
            _copy_matrix(M, oM)
            closure = res
            origin = ORIGIN_NEWTON
        else:
            have_prev = False
            ok, kind, k, origin, closure = _jump(z, kind, k, closure, par, cfg, hist, M)
            if not ok:
                return n_rows, n_links, STOP_FAILED, i
        i = i_next
