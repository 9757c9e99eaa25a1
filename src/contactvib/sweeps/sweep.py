"""Frequency sweeps: every attractor along a frequency grid, linked into branches (one P_a level).

Procedure (``trace_level``), all on one grid ``f_min, f_min + Δf, …, f_max``:

1. **Laboratory sweeps.** An up-sweep starts from rest at f_min and a down-sweep from rest at
   f_max; each carries the state from one frequency to the next. At each step the orbit is
   predicted (secant), corrected by Newton shooting and accepted while it stays stable; when it
   does not (a fold, a period doubling, chaos) the carried state is integrated until it settles
   on a new attractor — the jump a laboratory sweep makes (:mod:`contactvib._kernels.trace`).
2. **Reverse sweeps from every landing point.** Where a sweep jumped onto an attractor, a sweep
   in the opposite direction is started from it, so the branch it landed on is followed back to
   where it ends (e.g. the upper 1/2 branch down to low frequencies).
3. **Small-amplitude seeds.** At every multi-start frequency (below) the perturbation solution
   (:mod:`contactvib.frequency.perturbation`) is corrected by Newton shooting; a stable orbit no trace has
   met is traced up and down. This reaches the in-contact parts of superharmonic peaks that are
   cut off from the sweeps and have tiny basins (the 1/2 near 800 Hz at 0.90 Q: 0.4–4 % of the
   box).
4. **Multi-start seeds.** At ``multistart_per_octave`` frequencies per octave (geometric
   spacing: the resonance structure is self-similar, f_n0/m, and densest at low f_e) a
   multi-start search (random box scaled by
   y0 and P_a, plus ballistic seeds, :func:`contactvib.find_attractors`' procedure)
   looks for attractors no sweep has met; each new one is traced up and down. This is how the
   isolated parts of the 1/2 and 1/3 resonances (Kostek 2013, Sec. 3: "cannot be found with a
   sweeping signal") are found.
   **Period-2 Newton seeds** (at multi-start frequencies with f_e ≥ ``NEWTON_MIN_RATIO`` f_n0):
   the same box starts, shrunk towards the static equilibrium by 1/2, 1/4, 1/8 in turn, are
   corrected by Newton shooting as orbits of period 2 (the settle's refinement: minimal period,
   stable); each stable orbit no trace has met is traced up and down (root "multi-start"). This
   finds the ultrasubharmonic isolas (period 2 with 3 minima, and their period-4, -8 doublings
   by tracing on) whose basins are 0.2–1 % of the box: a 24-start search lands in them by
   chance, a Newton start converges to them from 2–9 % of the shrunk starts. They are not box
   hits, so they do not change the basin fractions.
   **Period-3, -4, -5 Newton seeds**, after the multi-start at every frequency: the first 8 box
   starts, as drawn and moved twice as far from the equilibrium in turn, corrected as orbits of
   period 3, 4, 5 (loosely first, :data:`NEWTON_SEEDS`). This finds bouncing orbits above f_n0
   (period 5 at 0.85 Q) and large orbits whose strobe points lie outside the box (period 3 at
   0.80 Q near 400 Hz); running after the multi-start, they trace only what it found nowhere.
   **Fill-in multi-starts** at ``fill_in_per_octave`` frequencies per octave (32: 2.2 % apart)
   between the multi-start frequencies, with ``fill_in_starts`` box starts each (12) and the same
   Newton seeds, no perturbation seed: the isolated ultrasubharmonic branches of the superharmonic
   windows (period 3 with 6 minima at 0.75 Q, 662–680 Hz; period 4 with 3 minima near
   1410–1435 Hz) live a few Hz to tens of Hz wide, between two multi-start frequencies 9 % apart.
   Periods up to ``kmax`` (16) are detected, so the period-9, -10, -12 and -16 orbits of these
   windows are traced as periodic orbits.
5. All traces share one table of known attractors per frequency; a trace that reaches an
   attractor already traced in its direction stops, so nothing is computed twice. Points
   continued by Newton are linked into branches; jumps are not links.

The basin fraction is measured at the multi-start frequencies only (NaN elsewhere). A box start
that reaches no attractor by the verdict of step 6 is counted for none (as in the attractor
search), so there the fractions sum to 1 minus the share of such starts.

6. A non-periodic point is kept only if the attractor search's verdict accepts it
   (:mod:`contactvib.sweeps.verdict`: recurrent strobe cloud, λ ≥ −LYAPUNOV_ZERO); unsettled
   transients are dropped with their links.
"""

from __future__ import annotations

import numpy as np

from contactvib.call_forms import old_form
from contactvib.model import (
    ContactModel,
    ParameterError,
)
from contactvib.sweeps.dataset import TRACE_ROOTS
from contactvib.sweeps.level_progress import report_points
from contactvib.sweeps.level_state import LevelState, LevelTrace, TraceStop
from contactvib.sweeps.newton_seeds import late_newton_seeds, newton_seeds
from contactvib.sweeps.settings import SweepSettings, fill_in_indices, frequency_grid, multistart_indices
from contactvib.sweeps.stage_times import stage

__all__ = ["SweepSettings", "LevelTrace", "TraceStop", "TRACE_ROOTS", "frequency_grid", "multistart_indices",
           "trace_level", "compile_late_kernels_first"]

#: Largest |x|, |x'| of a small-amplitude seed worth a Newton start [y0, y0 ω_n0]. Near the linear
#: resonance the series diverges (1e6–1e16 y0 at 1450–1500 Hz, 0.3–0.65 Q); Newton shooting from
#: there never converges and costs up to a second an attempt. Every stored orbit is far below:
#: the largest strobe point of paper.nc is x = 1.8e4 (4 mm, in flight near 30 Hz at 0.90 Q).
SEED_STATE_MAX = 1e6


def _settle_from(level: LevelState, i: int, z, phase: float = 0.0):
    from contactvib._kernels.settle import SETTLE_NONPERIODIC, SETTLE_PERIODIC, settle

    st = level.st
    par = level.par.copy()
    par[4] = level.r[i]
    hist = np.empty((st.max_periods + 1, 2))
    oz = np.empty(2)
    oM = np.empty((2, 2))
    s, k, n, _res = settle(np.asarray(z, float), phase, par, st.kmax, 4, st.max_periods,
                           st.detect_tol, st.rtol_transient, st.rtol, st.tol, hist, oz, oM)
    if s == SETTLE_PERIODIC:
        return oz, k, 0
    if s == SETTLE_NONPERIODIC:
        return hist[n].copy(), 0, 1
    return None


def _small_amplitude_seed(model, exc, par, st: SweepSettings):
    """Orbit point from the perturbation solution, corrected by Newton; None if not a stable orbit.

    The series (24 terms, Padé-summed, :mod:`contactvib.frequency.perturbation`) is the small-amplitude
    solution continued to this frequency; used only as a Newton start, valid or not.
    """
    from contactvib._kernels.settle import refine_stable_orbit
    from contactvib.frequency.perturbation import series_state

    if not model.is_paper_family or exc.kind != "force":
        return None  # the series is written for the power law (other laws: the other seeds)
    try:
        z = np.asarray(series_state(model, exc, terms=24), float)
    except (ValueError, FloatingPointError, ZeroDivisionError):
        return None
    if not np.all(np.isfinite(z)) or np.max(np.abs(z)) > SEED_STATE_MAX:
        return None
    oz = np.empty(2)
    oM = np.empty((2, 2))
    ok, k, _res = refine_stable_orbit(z, 1, par, st.rtol, st.tol, oz, oM)
    return oz.copy() if ok and k == 1 else None


def _multistart_at(lv: LevelState, model: ContactModel, pa_over_q: float, i: int, fill_in: bool = False) -> list:
    """Perturbation seed and multi-start at grid index ``i`` (a fill-in frequency: its own number
    of starts, no perturbation seed): trace every new attractor up and down; returns the basin
    observations [(row, fraction of the box starts)]."""
    from contactvib._kernels.settle import SETTLE_CAPTURED, SETTLE_NONPERIODIC, SETTLE_PERIODIC
    from contactvib._kernels.table import settle_known_many
    from contactvib.interrupts import check_interrupt
    from contactvib.steady.attractors import ballistic_seeds, start_box
    from contactvib.sweeps.verdict import settle_nonperiodic_start

    check_interrupt()
    st = lv.st
    exc = st.excitation_at(model, pa_over_q, lv.f[i])
    Zb, phb = start_box(exc, st.fill_in_starts if fill_in else st.n_starts, st.seed + i)
    Zs, phs = ballistic_seeds(exc)
    Z = np.vstack([Zb, Zs])
    ph = np.concatenate([phb, phs])
    par = lv.par.copy()
    par[4] = lv.r[i]
    with stage("perturbation seed"):
        zs = None if fill_in else _small_amplitude_seed(model, exc, par, st)
    if zs is not None and lv.known_slot(i, zs, 1, 0) < 0:
        lv.trace_both_ways(zs, 1, 0, i, "perturbation seed")
    status, kk, zz = settle_known_many(Z, ph, i, par, lv.cfg, st.capture_tol, lv.table)
    check_interrupt()
    found = []
    hits: dict[int, int] = {}
    for j in range(Z.shape[0]):
        if status[j] == SETTLE_CAPTURED:
            if j < Zb.shape[0]:
                gid = int(lv.table.row[i, kk[j]])
                hits[gid] = hits.get(gid, 0) + 1
            continue
        if status[j] == SETTLE_PERIODIC:
            z, k, kind = zz[j], int(kk[j]), 0
        elif status[j] == SETTLE_NONPERIODIC:  # an attractor only by the search's verdict
            res = settle_nonperiodic_start(model, pa_over_q, float(lv.f[i]), zz[j], st.rtol_transient,
                                           lambda z0: _settle_from(lv, i, z0), st.excitation)
            if res is None:
                continue
            z, k, kind = res
        else:
            continue
        found.append((j, z, k, kind))
        if lv.known_slot(i, z, k, kind) < 0:
            lv.trace_both_ways(z, k, kind, i, "multi-start")
    with stage("Newton seeds"):
        newton_seeds(lv, i, Zb, par, 0)
    for j, z, k, kind in found:
        if j >= Zb.shape[0]:
            continue
        s = lv.known_slot(i, z, k, kind)
        if s >= 0:
            gid = int(lv.table.row[i, s])
            hits[gid] = hits.get(gid, 0) + 1
    obs = [(gid, n / Zb.shape[0]) for gid, n in hits.items()]
    for s in range(lv.table.n[i]):
        gid = int(lv.table.row[i, s])
        if gid not in hits:
            obs.append((gid, 0.0))
    return obs


@old_form("model", "pa_over_q", "settings")
def trace_level(model: ContactModel, *, pa_over_q: float, settings: SweepSettings, seeds=()) -> LevelTrace:
    """All attractors along the frequency grid at one P_a level, as flat arrays (see module doc).

    ``seeds``: (grid index, orbit point (x, x') at phase 0 [y0, y0 ω_n0], period) of stable orbits
    found another way (``contactvib.sweeps.level_seeds``), traced up and down after the
    multi-start (root "level seed") where no trace has met them.

    As the level goes on it reports the frequency points done so far
    (``contactvib.sweeps.level_progress.report_points``, a no-op unless a run listens): two fifths
    of the grid once the sweeps (and their reverse traces) are done, four fifths once the
    multi-start frequencies are (the last fifth is the level's dataset: descriptions, Lyapunov
    exponents). It changes nothing computed.

    Returns
    -------
    LevelTrace
        The rows (per-row arrays, nondimensional), their basin fractions and the trace root that
        found them, the links between rows, the grid and one ``TraceStop`` per trace.
    """
    from contactvib.sweeps.unstable_parts import continue_unstable_parts

    st = settings
    f = frequency_grid(st)
    lv = LevelState(model, pa_over_q, f, st)
    with stage("sweeps: settle the grid's ends"):
        for i0, direction, label in ((0, +1, "up-sweep"), (f.size - 1, -1, "down-sweep")):
            res = _settle_from(lv, i0, (1.0, 0.0))
            if res is not None:
                lv.queue.append((res[0], res[1], res[2], i0, direction, label, "sweep"))
    lv.drain()
    starts = multistart_indices(st)
    probes = [(int(i), False) for i in starts] + [(int(i), True) for i in fill_in_indices(st)]
    report_points(pa_over_q, 2 * f.size // 5)
    observations = []
    for n, (i, fill_in) in enumerate(probes, 1):
        with stage("fill-in probes" if fill_in else "multi-start probes"):
            observations.append(_multistart_at(lv, model, pa_over_q, i, fill_in))
        report_points(pa_over_q, 2 * f.size // 5 + 2 * f.size * n // (5 * len(probes)))
    with stage("late Newton seeds"):
        late_newton_seeds(lv, model, pa_over_q, starts)
    with stage("level seeds"):
        for i, z, k in seeds:
            z = np.array(z, float)
            if lv.known_slot(int(i), z, int(k), 0) < 0:
                lv.trace_both_ways(z, int(k), 0, int(i), "level seed")
    with stage("unstable parts (continuation)"):
        continue_unstable_parts(lv, model, pa_over_q)  # stable parts beyond a jump (root "continuation")
    basin = np.full(lv.n_rows, np.nan)
    for obs in observations:
        for gid, frac in obs:
            basin[gid] = frac
    from contactvib.sweeps.verdict import drop_unsettled, judge_rows

    with stage("non-periodic verdict"):
        lt = drop_unsettled(lv.result(basin, pa_over_q), model, st.rtol_transient, st.max_periods, st.excitation)
    with stage("spectra and earned labels"):
        return judge_rows(lt, model, st.rtol_transient, st.kmax, st.excitation)


def compile_late_kernels_first(model: ContactModel, settings: SweepSettings) -> None:
    """Compile (or load from the cache) the kernels of a level that :func:`trace_level` does not
    call first. On a first run (cold cache) a pool's second worker runs this while the first
    starts a level, which compiles the settling kernels (:func:`.settle.settle` and below) and
    then the tracer: the two compile different kernels at once and each loads the other's from
    the cache. So the tracer's callees come first here (the table search, the description, the
    Newton continuation and bridge of :mod:`._kernels.trace`, the Lyapunov exponent), leaving the
    first worker only the tracer itself; then the continuation, Newton and multi-start kernels.
    Every call has the argument types of the real ones (one compiled specialization each);
    nothing is kept."""
    from contactvib._kernels import trace as tk
    from contactvib._kernels.describe import NP_LYAPUNOV, describe_point, lyapunov_strobe, new_rows
    from contactvib._kernels.shooting import newton_orbit
    from contactvib._kernels.table import find_known, settle_known_many
    from contactvib.continuation.shooting import ContinuationSettings, continue_orbit
    from contactvib.errors import ComputationError

    st = settings
    f0 = 0.5 * model.f_n0  # a small in-contact orbit: every kernel returns within milliseconds
    exc = model.excitation(0.1, f0)
    par = exc.kernel_parameters()
    z = np.array([1.0, 0.0])
    lv = LevelState(model, 0.1, np.array([f0]), st)
    k1 = np.int64(1)
    find_known(lv.table, np.int64(0), z.copy(), k1, np.int64(0), st.same_tol)
    tk.stays_on_branch(z.copy(), z.copy(), z.copy())
    describe_point(z.copy(), k1, par, st.rtol, new_rows(1), np.int64(0), np.empty(2))
    tk.continue_orbit(z.copy(), k1, par, st.rtol, st.tol, new_rows(1), np.int64(0),
                      np.empty(2), np.empty((2, 2)))
    r = float(par[4])
    tk.bridge_orbit(z.copy(), r, z.copy(), r, np.bool_(False), r, k1, par, st.rtol, st.tol,
                    np.empty(2), np.empty(2))
    lyapunov_strobe(z.copy(), par, st.rtol_transient, np.int64(NP_LYAPUNOV))
    try:
        continue_orbit(exc, z, 1, parameter="f_e", direction="down",
                       settings=ContinuationSettings(fmin_hz=0.9 * f0, fmax_hz=f0, max_points=2, max_failures=2,
                                                     rtol=st.rtol, tol=st.tol))
    except (ComputationError, ParameterError, FloatingPointError, np.linalg.LinAlgError):
        pass
    newton_orbit(z.copy(), 1, par, st.rtol, st.rtol, st.tol, 8, np.empty(2), np.empty((2, 2)))
    settle_known_many(z.reshape(1, 2).copy(), np.zeros(1), 0, lv.par.copy(), lv.cfg, st.capture_tol,
                      lv.table)
