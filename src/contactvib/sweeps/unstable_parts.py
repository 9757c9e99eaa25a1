"""Stable parts that only continuation reaches: a post-pass of :func:`.sweep.trace_level`.

A trace follows a stable orbit by Newton until it loses stability (a fold, a period doubling, a
Neimark–Sacker point) and then jumps. The branch it leaves may become stable again further on —
the 1/5 at 0.90 Q, whose period-1 branch loses stability by period doubling near 250 Hz going
down, regains it through a second doubling near 113 Hz and stays stable down to a fold near
102 Hz (paper S3.7: divided). Its basin is small (0.6–2.3 % of the box) and no sweep lands on it.

The post-pass (:func:`continue_unstable_parts`): for every periodic row from which a trace
jumped, the orbit is continued (pseudo-arclength in f_e, :class:`.continuation.shooting.
OrbitProblem` through :func:`.continuation.shooting.continue_orbit`) in the trace's direction
within a bounded frequency window (:data:`WINDOW_RATIO`) and a bounded number of points
(:data:`MAX_POINTS`). Where the continued branch is stable again over a grid frequency, the
orbit is refined there by Newton shooting and, if no trace holds it yet, traced up and down with
the root ``"continuation"``. New jump ends found that way are continued in turn (at most
:data:`MAX_ROUNDS` rounds).
"""

from __future__ import annotations

import numpy as np

__all__ = ["continue_unstable_parts", "WINDOW_RATIO", "MAX_POINTS", "MAX_ROUNDS", "PERIOD_MAX"]

#: Frequency window of one continuation: [f / ratio, f · ratio] around the jump end, in the
#: trace's direction (the 1/5 at 0.90 Q is unstable from 250 Hz down to 113 Hz: ratio 2.2).
WINDOW_RATIO = 2.5
#: Continuation points per jump end.
MAX_POINTS = 80
#: Rounds of the post-pass (new traces may end in new jumps).
MAX_ROUNDS = 3
#: Longest period continued: a continuation point of a period-k orbit integrates k excitation
#: periods per Newton step, and the long-period orbits (9–16: the superharmonic windows'
#: ultrasubharmonics and period doublings) are found by the fill-in multi-starts instead.
PERIOD_MAX = 8


def _jump_ends(lv) -> list:
    """(row, direction) of every periodic row of period ≤ :data:`PERIOD_MAX` from which a trace
    jumped."""
    ends = []
    for c in lv.links:
        for a, b, jump in zip(c.a, c.b, c.jump):
            if not jump:
                continue
            _z, k, kind, i_a = lv.row(int(a))
            _zb, _kb, _kdb, i_b = lv.row(int(b))
            if kind == 0 and i_b != i_a and k <= PERIOD_MAX:
                ends.append((int(a), 1 if i_b > i_a else -1))
    return ends


def _continue(lv, model, pa_over_q, z, k, i, direction):
    """The branch through the periodic orbit (z, k) at grid index i, continued one way."""
    from contactvib.continuation.shooting import ContinuationSettings, continue_orbit
    from contactvib.errors import ComputationError
    from contactvib.model import ParameterError

    f0 = float(lv.f[i])
    lo = max(float(lv.f[0]), f0 / WINDOW_RATIO) if direction < 0 else f0
    hi = min(float(lv.f[-1]), f0 * WINDOW_RATIO) if direction > 0 else f0
    lo, hi = (lo - 1e-9 * f0, hi + 1e-9 * f0)
    # the sweep's integrator tolerance (not the 1e-12 of `continue`): the branch only locates the
    # stable parts; each seed is refined at the sweep's tolerances before it is traced. Only the
    # points' stability is used: the special points are not located (no branch point changes)
    settings = ContinuationSettings(fmin_hz=lo, fmax_hz=hi, max_points=MAX_POINTS, max_failures=20,
                                    rtol=lv.st.rtol, tol=lv.st.tol, locate=False)
    try:
        return continue_orbit(lv.st.excitation_at(model, pa_over_q, f0), z, k, parameter="f_e",
                              direction="up" if direction > 0 else "down", settings=settings)
    except (ComputationError, ParameterError, FloatingPointError, np.linalg.LinAlgError):
        return None


def _stable_again(branch) -> list:
    """Index ranges [a, b] of the stable segments after the branch's first unstable point."""
    stable = np.asarray(branch.stable, bool)
    unstable = np.flatnonzero(~stable)
    if unstable.size == 0:
        return []
    segments = []
    j = int(unstable[0])
    n = stable.size
    while j < n:
        if stable[j]:
            a = j
            while j + 1 < n and stable[j + 1]:
                j += 1
            segments.append((a, j))
        j += 1
    return segments


def _seed_in(lv, branch, a, b, k):
    """A refined stable orbit of period k at a grid index inside the segment [a, b], or None."""
    from contactvib._kernels.settle import refine_stable_orbit

    fe = branch.fe_hz[a:b + 1]
    if fe.size < 2:
        return None
    i_lo = int(np.ceil((fe.min() - lv.f[0]) / lv.st.df_hz - 1e-9))
    i_hi = int(np.floor((fe.max() - lv.f[0]) / lv.st.df_hz + 1e-9))
    i_lo, i_hi = max(i_lo, 0), min(i_hi, lv.f.size - 1)
    if i_hi < i_lo:
        return None
    i = (i_lo + i_hi) // 2
    j = int(np.argmin(np.abs(fe - lv.f[i]))) + a
    par = lv.par.copy()
    par[4] = lv.r[i]
    oz = np.empty(2)
    oM = np.empty((2, 2))
    ok, kk, _res = refine_stable_orbit(np.asarray(branch.state[j], float), k, par, lv.st.rtol,
                           lv.st.tol, oz, oM)
    if not ok or kk != k:  # refine_stable_orbit accepts stable orbits only
        return None
    return i, oz.copy()


def continue_unstable_parts(lv, model, pa_over_q: float) -> int:
    """Continue every trace's jump end through its unstable part; trace the stable parts reached.

    Parameters
    ----------
    lv : contactvib.sweeps.level_state.LevelState
        The level's shared table and rows after the sweeps and multi-start.
    model : ContactModel
    pa_over_q : float

    Returns
    -------
    int
        Number of new traces started (root ``"continuation"``).
    """
    from contactvib.interrupts import check_interrupt

    done: set = set()
    started = 0
    for _round in range(MAX_ROUNDS):
        ends = [e for e in _jump_ends(lv) if e not in done]
        if not ends:
            break
        for gid, direction in ends:
            done.add((gid, direction))
            check_interrupt()
            z, k, _kind, i = lv.row(gid)
            branch = _continue(lv, model, pa_over_q, z, k, i, direction)
            if branch is None:
                continue
            for a, b in _stable_again(branch):
                seed = _seed_in(lv, branch, a, b, k)
                if seed is None or lv.known_slot(seed[0], seed[1], k, 0) >= 0:
                    continue
                lv.trace_both_ways(seed[1], k, 0, seed[0], "continuation")
                started += 1
    return started
