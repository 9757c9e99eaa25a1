"""Branch tracing along a frequency grid: Newton-corrected natural continuation with jumps (compiled).

A *trace* starts from a refined attractor at grid index ``i0`` and walks the grid in one
direction, as a laboratory sweep does, carrying the state:

1. predict the orbit point at the next frequency (secant through the last two points of the
   same segment), correct it by Newton shooting on the period-k map, accept it when it closes,
   is stable and its period is minimal (:func:`.settle._refine`); if that fails, bridge the
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

Outputs are flat per-row arrays (one row per new attractor point) and links between rows
(``jump`` = 0: continued by Newton, 1: reached by a transient from the previous point).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from .status import (ORIGIN_JUMP, ORIGIN_NEWTON, ORIGIN_START, STATUS_OK,  # noqa: F401
                     STATUS_RECORD_FULL, STOP_FAILED, STOP_GRID_END, STOP_KNOWN, STOP_TABLE_FULL)
from .orbit import find_extrema, record_orbit, sample_records
from .settle import SETTLE_NONPERIODIC, SETTLE_PERIODIC, _refine, settle, settle_core
from .shooting import STABILITY_TOL, floquet_abs_max, newton_orbit, newton_step, state_scale, strobe_map

#: Stored extrema per attractor point (periodic orbits need 2 × minima; clouds are truncated).
EXT_MAX = 256
#: Stored stroboscopic points per attractor point (period k ≤ kmax; clouds: the last ones).
STROBE_MAX = 32
#: Harmonic amplitudes stored per point, at frequencies j·f_e/k, j = 1..HARM_MAX.
HARM_MAX = 64
#: Samples per excitation period for the harmonic analysis (Nyquist: 64 f_e).
N_SAMPLES = 128
#: Periods recorded to describe a non-periodic attractor.
NP_RECORD = 32
#: Periods used for the largest Lyapunov exponent of the stroboscopic map.
NP_LYAPUNOV = 64
#: Transient limit when a non-periodic attractor is followed to the next frequency (the carried
#: state already lies on the attractor; a periodic window is still detected within it).
NP_FOLLOW = 100

KIND_PERIODIC = 0
KIND_NONPERIODIC = 1


@njit(cache=True)
def lyapunov_strobe(z, par, rtol, n_periods):
    """Largest Lyapunov exponent of the stroboscopic map [1/excitation period] from ``z``.

    Tangent vector propagated by the monodromy of each period and renormalised (Benettin et al.
    1980); NaN if the integration fails.
    """
    cur = z.copy()
    nxt = np.empty(2)
    M = np.empty((2, 2))
    w0 = 1.0 / math.sqrt(2.0)
    w1 = w0
    acc = 0.0
    for _ in range(n_periods):
        if strobe_map(cur, 1, par, rtol, rtol, nxt, M) != STATUS_OK:
            return math.nan
        a = M[0, 0] * w0 + M[0, 1] * w1
        b = M[1, 0] * w0 + M[1, 1] * w1
        nrm = math.sqrt(a * a + b * b)
        if not (nrm > 0.0 and math.isfinite(nrm)):
            return math.nan
        acc += math.log(nrm)
        w0 = a / nrm
        w1 = b / nrm
        cur[0] = nxt[0]
        cur[1] = nxt[1]
    return acc / n_periods


@njit(cache=True)
def describe_point(z, n_per, par, rtol, row, o_xmin, o_xmax, o_flight, o_nmin, o_next, o_ext_t,
                   o_ext_x, o_ext_min, o_strobe, o_nstrobe, o_harm, o_end):
    """Extrema, A_pp, contact loss, strobe points and harmonics of ``n_per`` periods from ``z``.

    Writes row ``row`` of the output arrays and the end state ``P^n_per(z)`` into ``o_end``;
    returns a :mod:`.flow` status.
    """
    T = 2.0 * math.pi / par[4]
    cap = 256 * n_per
    while True:
        rec, z_end, t_flight, n_events, st = record_orbit(z, 0.0, n_per, par, rtol, cap)
        if st == STATUS_RECORD_FULL:
            cap *= 4
            continue
        break
    if st != STATUS_OK:
        return st
    o_end[0] = z_end[0]
    o_end[1] = z_end[1]
    t_e, x_e, m_e = find_extrema(rec)
    n_e = t_e.shape[0]
    xmin = math.inf
    xmax = -math.inf
    nmin = 0
    for j in range(n_e):
        xmin = min(xmin, x_e[j])
        xmax = max(xmax, x_e[j])
        if m_e[j]:
            nmin += 1
    if n_e == 0:
        for j in range(rec.shape[0]):
            xmin = min(xmin, rec[j, 3])
            xmax = max(xmax, rec[j, 3])
    o_xmin[row] = xmin
    o_xmax[row] = xmax
    o_flight[row] = t_flight / (n_per * T)
    o_nmin[row] = nmin
    n_keep = min(n_e, EXT_MAX)
    o_next[row] = n_keep
    for j in range(n_keep):
        o_ext_t[row, j] = t_e[j]
        o_ext_x[row, j] = x_e[j]
        o_ext_min[row, j] = m_e[j]
    # stroboscopic points (the last STROBE_MAX of them)
    n_s = min(n_per, STROBE_MAX)
    ts = np.empty(n_s)
    for j in range(n_s):
        ts[j] = (n_per - n_s + j) * T
    xs, vs, _cs = sample_records(rec, ts)
    for j in range(n_s):
        o_strobe[row, j, 0] = xs[j]
        o_strobe[row, j, 1] = vs[j]
    o_nstrobe[row] = n_s
    # harmonics at j f_e / n_per by a direct DFT of uniform samples
    N = N_SAMPLES * n_per
    tt = np.empty(N)
    for q in range(N):
        tt[q] = q * (n_per * T) / N
    xq, _v, _c = sample_records(rec, tt)
    cos_q = np.empty(N)
    sin_q = np.empty(N)
    for q in range(N):
        cos_q[q] = math.cos(2.0 * math.pi * q / N)
        sin_q[q] = math.sin(2.0 * math.pi * q / N)
    for j in range(1, HARM_MAX + 1):
        if j > N // 2 - 1:
            o_harm[row, j - 1] = math.nan
            continue
        re = 0.0
        im = 0.0
        iq = 0
        for q in range(N):
            re += xq[q] * cos_q[iq]
            im -= xq[q] * sin_q[iq]
            iq += j
            if iq >= N:
                iq -= N
        amp = 2.0 * math.sqrt(re * re + im * im) / N
        o_harm[row, j - 1] = amp
    return STATUS_OK


@njit(cache=True)
def _eig2(M, out_re, out_im, row):
    tr = M[0, 0] + M[1, 1]
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    disc = 0.25 * tr * tr - det
    if disc >= 0.0:
        s = math.sqrt(disc)
        out_re[row, 0] = 0.5 * tr + s
        out_re[row, 1] = 0.5 * tr - s
        out_im[row, 0] = 0.0
        out_im[row, 1] = 0.0
    else:
        s = math.sqrt(-disc)
        out_re[row, 0] = 0.5 * tr
        out_re[row, 1] = 0.5 * tr
        out_im[row, 0] = s
        out_im[row, 1] = -s


@njit(cache=True)
def find_known(i, z, k, kind, t_n, t_k, t_kind, t_pts, t_box, same_tol):
    """Slot of the attractor known at grid index ``i`` that ``z`` lies on, or −1."""
    sc = state_scale(z[0], z[1])
    for s in range(t_n[i]):
        if t_kind[i, s] != kind:
            continue
        if kind == KIND_PERIODIC:
            if t_k[i, s] != k:
                continue
            for j in range(k):
                d = max(abs(z[0] - t_pts[i, s, j, 0]), abs(z[1] - t_pts[i, s, j, 1]))
                if d <= same_tol * max(sc, state_scale(t_pts[i, s, j, 0], t_pts[i, s, j, 1])):
                    return s
        else:
            wx = 0.05 * (t_box[i, s, 1] - t_box[i, s, 0]) + 1e-9
            wv = 0.05 * (t_box[i, s, 3] - t_box[i, s, 2]) + 1e-9
            if (t_box[i, s, 0] - wx <= z[0] <= t_box[i, s, 1] + wx
                    and t_box[i, s, 2] - wv <= z[1] <= t_box[i, s, 3] + wv):
                return s
    return -1


#: Newton steps (relative) below which the corrected point is checked by the description run
#: instead of another variational integration (the residual after such a step is ~ step²).
QUICK_STEP = 3e-5


@njit(cache=True)
def continue_orbit(zg, k, par, rtol, close_tol, row, o_xmin, o_xmax, o_flight, o_nmin, o_next,
                   o_ext_t, o_ext_x, o_ext_min, o_strobe, o_nstrobe, o_harm, out_z, out_M):
    """Newton-correct the predicted period-k orbit point ``zg`` and describe it (row ``row``).

    Each Newton iteration integrates the variational equations over k periods. Once a step is
    below ``QUICK_STEP`` the corrected point is described (:func:`describe_point`, k periods
    without variational equations) and that run's end state decides closure, which saves the
    confirming variational integration; ``out_M`` is then the monodromy at the previous iterate
    (relative state difference ≤ QUICK_STEP). Accepted only if the orbit closes to
    ``close_tol``, is stable (|μ| ≤ 1 + 1e-6) and no proper divisor of k closes (minimal period,
    checked on the described strobe points). Returns (accepted, closure).
    """
    z = np.empty(2)
    z[0] = zg[0]
    z[1] = zg[1]
    pz = np.empty(2)
    zend = np.empty(2)
    M = np.empty((2, 2))
    for _it in range(10):
        if strobe_map(z, k, par, rtol, rtol, pz, M) != STATUS_OK:
            return False, math.inf
        g0 = pz[0] - z[0]
        g1 = pz[1] - z[1]
        sc = state_scale(z[0], z[1])
        res = max(abs(g0), abs(g1)) / sc
        quick = False
        if res > close_tol:
            st, dz0, dz1, step = newton_step(M, g0, g1, sc)
            if st != STATUS_OK:
                return False, res
            z[0] += dz0
            z[1] += dz1
            if step > QUICK_STEP:
                continue
            quick = True
        if floquet_abs_max(M) > 1.0 + STABILITY_TOL:
            return False, res
        if describe_point(z, k, par, rtol, row, o_xmin, o_xmax, o_flight, o_nmin, o_next, o_ext_t,
                          o_ext_x, o_ext_min, o_strobe, o_nstrobe, o_harm, zend) != STATUS_OK:
            return False, res
        if quick:
            sc = state_scale(z[0], z[1])
            res = max(abs(zend[0] - z[0]), abs(zend[1] - z[1])) / sc
            if res > close_tol:
                continue
        for dd in range(1, k):
            if k % dd == 0:
                dist = max(abs(o_strobe[row, dd, 0] - z[0]), abs(o_strobe[row, dd, 1] - z[1]))
                if dist / sc < 1e-6:
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
def bridge_orbit(z, r_from, zp, r_prev, have_prev, r_to, k, par, rtol, close_tol, out_zg,
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
        st, _res = newton_orbit(zg, k, par_s, rtol, rtol, close_tol, 8, oz, oM)
        if (st == STATUS_OK and floquet_abs_max(oM) <= 1.0 + STABILITY_TOL
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


@njit(cache=True)
def trace(z0, k0, kind0, i0, direction, r_grid, par_in, rtol, close_tol, kmax, max_periods,
          detect_tol, rtol_transient, same_tol, row_base,
          t_n, t_k, t_kind, t_pts, t_box, t_row, t_cov,
          o_i, o_kind, o_k, o_z, o_mu_re, o_mu_im, o_closure, o_xmin, o_xmax, o_flight, o_nmin,
          o_next, o_ext_t, o_ext_x, o_ext_min, o_strobe, o_nstrobe, o_harm, o_lyap,
          o_origin, l_a, l_b, l_jump):
    """Trace from the attractor (``z0``, period ``k0``, ``kind0``) at grid index ``i0``.

    ``direction`` is +1 (up in frequency) or −1. Table arrays ``t_*`` (per grid index, per slot)
    are read and extended in place; ``t_cov[i, s, 0/1]`` marks slots traced downwards/upwards.
    New rows get global ids ``row_base + n``.

    Returns
    -------
    n_rows, n_links, stop_reason, i_stop
    """
    n_f = r_grid.shape[0]
    MAXA = t_k.shape[1]
    d_slot = 1 if direction > 0 else 0
    par = par_in.copy()
    z = z0.copy()
    k = k0
    kind = kind0
    zp = np.empty(2)  # previous accepted orbit point on this segment (for the secant)
    zb = np.empty(2)  # last orbit point of a bridge
    have_prev = False
    oz = np.empty(2)
    oM = np.empty((2, 2))
    hist = np.empty((max_periods + 1, 2))
    n_rows = 0
    n_links = 0
    prev_row = -1
    i = i0
    origin = ORIGIN_START
    closure = 0.0
    M = np.zeros((2, 2))
    zend = np.empty(2)
    described = False  # row n_rows already holds the description of z
    if kind == KIND_PERIODIC:
        par[4] = r_grid[i]
        ok, kk, res = _refine(z, k, par, rtol, close_tol, oz, oM)
        if not ok:
            return 0, 0, STOP_FAILED, i
        k = kk
        z[0] = oz[0]
        z[1] = oz[1]
        M[:, :] = oM
        closure = res
    while True:
        par[4] = r_grid[i]
        # ---- is it known here?
        s = find_known(i, z, k, kind, t_n, t_k, t_kind, t_pts, t_box, same_tol)
        if s >= 0:
            row = t_row[i, s]
            if prev_row >= 0:
                l_a[n_links] = prev_row
                l_b[n_links] = row
                l_jump[n_links] = 1 if origin == ORIGIN_JUMP else 0
                n_links += 1
            if t_cov[i, s, d_slot]:
                return n_rows, n_links, STOP_KNOWN, i
            t_cov[i, s, d_slot] = True
            prev_row = row
        else:
            if t_n[i] >= MAXA:
                return n_rows, n_links, STOP_TABLE_FULL, i
            r = n_rows
            o_i[r] = i
            o_kind[r] = kind
            o_k[r] = k if kind == KIND_PERIODIC else 0
            o_z[r, 0] = z[0]
            o_z[r, 1] = z[1]
            o_origin[r] = origin
            if not described:
                n_per = k if kind == KIND_PERIODIC else NP_RECORD
                st = describe_point(z, n_per, par, rtol, r, o_xmin, o_xmax, o_flight, o_nmin,
                                    o_next, o_ext_t, o_ext_x, o_ext_min, o_strobe, o_nstrobe,
                                    o_harm, zend)
                if st != STATUS_OK:
                    return n_rows, n_links, STOP_FAILED, i
            s = t_n[i]
            t_kind[i, s] = kind
            t_row[i, s] = row_base + r
            t_cov[i, s, d_slot] = True
            t_cov[i, s, 1 - d_slot] = False
            if kind == KIND_PERIODIC:
                _eig2(M, o_mu_re, o_mu_im, r)
                o_closure[r] = closure
                o_lyap[r] = math.nan
                t_k[i, s] = k
                for j in range(k):
                    t_pts[i, s, j, 0] = o_strobe[r, j, 0]
                    t_pts[i, s, j, 1] = o_strobe[r, j, 1]
            else:
                o_mu_re[r, 0] = math.nan
                o_mu_re[r, 1] = math.nan
                o_mu_im[r, 0] = math.nan
                o_mu_im[r, 1] = math.nan
                o_closure[r] = math.inf
                o_lyap[r] = lyapunov_strobe(z, par, rtol_transient, NP_LYAPUNOV)
                t_k[i, s] = 0
                nb = o_nstrobe[r]
                t_box[i, s, 0] = math.inf
                t_box[i, s, 1] = -math.inf
                t_box[i, s, 2] = math.inf
                t_box[i, s, 3] = -math.inf
                for j in range(nb):
                    t_box[i, s, 0] = min(t_box[i, s, 0], o_strobe[r, j, 0])
                    t_box[i, s, 1] = max(t_box[i, s, 1], o_strobe[r, j, 0])
                    t_box[i, s, 2] = min(t_box[i, s, 2], o_strobe[r, j, 1])
                    t_box[i, s, 3] = max(t_box[i, s, 3], o_strobe[r, j, 1])
                # carry on from the end of the recorded cloud
                z[0] = o_strobe[r, nb - 1, 0]
                z[1] = o_strobe[r, nb - 1, 1]
            t_n[i] += 1
            if prev_row >= 0:
                l_a[n_links] = prev_row
                l_b[n_links] = row_base + r
                l_jump[n_links] = 1 if origin == ORIGIN_JUMP else 0
                n_links += 1
            prev_row = row_base + r
            n_rows += 1
        # ---- next grid point
        i_next = i + direction
        if i_next < 0 or i_next >= n_f:
            return n_rows, n_links, STOP_GRID_END, i
        par[4] = r_grid[i_next]
        accepted = False
        described = False
        if kind == KIND_PERIODIC:
            zg = np.empty(2)
            if have_prev:
                zg[0] = 2.0 * z[0] - zp[0]
                zg[1] = 2.0 * z[1] - zp[1]
            else:
                zg[0] = z[0]
                zg[1] = z[1]
            ok, res = continue_orbit(zg, k, par, rtol, close_tol, n_rows, o_xmin, o_xmax, o_flight,
                                     o_nmin, o_next, o_ext_t, o_ext_x, o_ext_min, o_strobe,
                                     o_nstrobe, o_harm, oz, oM)
            if ok and have_prev and not stays_on_branch(oz, zg, z):
                ok = False  # Newton went over to a coexisting orbit: this branch ended
            z_from = z.copy()  # the phase point the accepted orbit was continued from
            # lost: bridge the step by sub-steps, from the carried point (with its secant) and
            # then from the orbit's other strobe points (Newton's reach differs from phase to
            # phase of a period-k orbit: a strobe point close to an impact is a poor start)
            for j in range(-1, k if not ok else -1):
                if j < 0:
                    zs, zq, hv = z, zp, have_prev
                    rq = r_grid[i - direction] if have_prev else 0.0
                else:
                    zs = t_pts[i, s, j]
                    if zs[0] == z[0] and zs[1] == z[1]:
                        continue
                    zq, hv, rq = zs, False, 0.0
                how = bridge_orbit(zs, r_grid[i], zq, rq, hv, r_grid[i_next], k, par, rtol,
                                   close_tol, zg, zb)
                if how:
                    ok, res = continue_orbit(zg, k, par, rtol, close_tol, n_rows, o_xmin, o_xmax,
                                             o_flight, o_nmin, o_next, o_ext_t, o_ext_x,
                                             o_ext_min, o_strobe, o_nstrobe, o_harm, oz, oM)
                    ok = ok and (how == 1 or stays_on_branch(oz, zg, zb))
                    if ok:
                        z_from[0] = zs[0]
                        z_from[1] = zs[1]
                        break
            if ok:
                described = True
                zp[0] = z_from[0]
                zp[1] = z_from[1]
                have_prev = True
                z[0] = oz[0]
                z[1] = oz[1]
                M[:, :] = oM
                closure = res
                origin = ORIGIN_NEWTON
                accepted = True
        if not accepted:
            n_max = max_periods if kind == KIND_PERIODIC else min(max_periods, NP_FOLLOW)
            st, kk, n_done, res = settle(z, 0.0, par, kmax, 4, n_max, detect_tol, rtol_transient,
                                         rtol, close_tol, hist, oz, oM)
            have_prev = False
            origin = ORIGIN_JUMP if kind == KIND_PERIODIC else ORIGIN_NEWTON
            if st == SETTLE_PERIODIC:
                kind = KIND_PERIODIC
                k = kk
                z[0] = oz[0]
                z[1] = oz[1]
                M[:, :] = oM
                closure = res
                origin = ORIGIN_JUMP
            elif st == SETTLE_NONPERIODIC:
                if kind == KIND_PERIODIC:
                    origin = ORIGIN_JUMP
                kind = KIND_NONPERIODIC
                k = 0
                z[0] = hist[n_done, 0]
                z[1] = hist[n_done, 1]
            else:
                return n_rows, n_links, STOP_FAILED, i
        i = i_next


@njit(cache=True, parallel=True)
def settle_known_many(Z, phases, i, par, kmax, max_periods, detect_tol, rtol_transient, rtol_refine,
                      close_tol, capture_tol, t_n, t_k, t_kind, t_pts):
    """:func:`.settle.settle_core` for many starts (numba threads over the starts), each stopped
    early once it comes within ``capture_tol`` of a stable periodic attractor known at grid index
    ``i`` (``SETTLE_CAPTURED``; the table slot is returned as ``k``).

    Returns status, k (period, or the captured slot), z (refined point or last strobe point).
    """
    m = 0
    for s in range(t_n[i]):
        if t_kind[i, s] == KIND_PERIODIC:
            m += t_k[i, s]
    cap_pts = np.empty((m, 2))
    cap_id = np.empty(m, np.int64)
    m = 0
    for s in range(t_n[i]):
        if t_kind[i, s] == KIND_PERIODIC:
            for j in range(t_k[i, s]):
                cap_pts[m, 0] = t_pts[i, s, j, 0]
                cap_pts[m, 1] = t_pts[i, s, j, 1]
                cap_id[m] = s
                m += 1
    N = Z.shape[0]
    status = np.empty(N, np.int64)
    kk = np.zeros(N, np.int64)
    zs = np.empty((N, 2))
    for q in prange(N):
        hist = np.empty((max_periods + 1, 2))
        oz = np.empty(2)
        oM = np.zeros((2, 2))
        st, k, n, _res = settle_core(Z[q], phases[q], par, kmax, 4, max_periods, detect_tol,
                                     rtol_transient, rtol_refine, close_tol, cap_pts, cap_id,
                                     capture_tol, hist, oz, oM)
        status[q] = st
        kk[q] = k
        if st == SETTLE_PERIODIC:
            zs[q, 0] = oz[0]
            zs[q, 1] = oz[1]
        else:
            zs[q, 0] = hist[n, 0]
            zs[q, 1] = hist[n, 1]
    return status, kk, zs
