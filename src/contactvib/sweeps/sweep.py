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

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from contactvib.model import (
    ContactModel,
    ParameterError,
)
from contactvib.sweeps.dataset import TRACE_ROOTS
from contactvib.sweeps.level_progress import report_points
from contactvib.sweeps.newton_seeds import late_newton_seeds, newton_seeds
from contactvib.sweeps.settings import SweepSettings, frequency_grid, multistart_indices

if TYPE_CHECKING:
    from contactvib._kernels.describe import TraceRows
    from contactvib._kernels.trace import TraceLinks

__all__ = ["SweepSettings", "LevelTrace", "TraceStop", "frequency_grid", "multistart_indices",
           "trace_level", "compile_late_kernels_first"]

_MAXA = 48  # attractors per frequency in the shared table

#: Largest |x|, |x'| of a small-amplitude seed worth a Newton start [y0, y0 ω_n0]. Near the linear
#: resonance the series diverges (1e6–1e16 y0 at 1450–1500 Hz, 0.3–0.65 Q); Newton shooting from
#: there never converges and costs up to a second an attempt. Every stored orbit is far below:
#: the largest strobe point of paper.nc is x = 1.8e4 (4 mm, in flight near 30 Hz at 0.90 Q).
SEED_STATE_MAX = 1e6


@dataclass(frozen=True)
class TraceStop:
    """Where one trace of a level started and why it stopped.

    Attributes
    ----------
    label : str
        "up-sweep", "down-sweep", "reverse", "perturbation seed", "multi-start" or "continuation".
    direction : int
        +1 up in frequency, −1 down.
    f_start_hz, f_stop_hz : float
        First and last grid frequency of the trace [Hz].
    reason : int
        ``STOP_*`` code of :mod:`contactvib._kernels.trace` (text: ``dataset.STOP_REASONS``).
    root : str
        How the trace's family was started (:data:`TRACE_ROOTS`).
    """

    label: str
    direction: int
    f_start_hz: float
    f_stop_hz: float
    reason: int
    root: str


@dataclass(frozen=True)
class LevelTrace:
    """All attractor points of one P_a level (:func:`trace_level`), nondimensional.

    Attributes
    ----------
    rows : contactvib._kernels.describe.TraceRows
        Per-row arrays, one row per attractor point (grid index ``i``, kind, period, orbit
        point, multipliers, range, extrema, strobe points, harmonics, …; empty if none).
    found_by : ndarray of int
        Per row: index into :data:`TRACE_ROOTS` of the trace that first reached it.
    basin : ndarray of float
        Per row: basin fraction at the multi-start frequencies, NaN where not measured.
    links : contactvib._kernels.trace.TraceLinks
        Row ``a`` → row ``b``, ``jump`` 0 (continued by Newton) or 1 (a transient).
    f_hz : ndarray
        The frequency grid [Hz].
    stops : list of TraceStop
        One per trace, in the order they ran.
    pa_over_q : float
        Excitation amplitude P_a/Q.
    """

    rows: TraceRows
    found_by: np.ndarray
    basin: np.ndarray
    links: TraceLinks
    f_hz: np.ndarray
    stops: list
    pa_over_q: float

    @property
    def n_rows(self) -> int:
        """Number of attractor points."""
        return int(self.rows.i.size)


class LevelState:
    """Shared table and accumulated rows of one P_a level (internal)."""

    def __init__(self, model: ContactModel, pa_over_q: float, f: np.ndarray, st: SweepSettings):
        from contactvib._kernels import trace as tk
        from contactvib._kernels.table import new_table

        self.tk = tk
        self.model = model
        self.st = st
        self.f = f
        self.r = f / model.f_n0
        self.par = st.excitation_at(model, pa_over_q, f[0]).kernel_parameters()
        self.cfg = tk.trace_settings(st.rtol, st.close_tol, st.kmax, st.max_periods, st.detect_tol,
                                     st.rtol_transient, st.same_tol)
        self.table = new_table(f.size, _MAXA, 16)
        self.chunks: list = []  # TraceRows of each trace
        self.found_by: list[np.ndarray] = []
        self.links: list = []  # TraceLinks of each trace
        self.n_rows = 0
        self.stops: list[TraceStop] = []
        self.queue: list[tuple] = []  # traces to run: (z, k, kind, i0, direction, label, root)

    def drain(self):
        """Run the queued traces, and a reverse trace from every jump landing they make."""
        while self.queue:
            z, k, kind, i0, direction, label, root = self.queue.pop(0)
            for gid in self.trace(z, k, kind, i0, direction, label, root):
                zz, kk, kd, ii = self.row(gid)
                self.queue.append((zz, kk, kd, ii, -direction, "reverse", root))

    def trace_both_ways(self, z, k, kind, i, root):
        """Trace a new attractor at grid index ``i`` up and then down (label = root)."""
        self.queue.append((z, k, kind, i, +1, root, root))
        self.queue.append((z, k, kind, i, -1, root, root))
        self.drain()

    def trace(self, z, k, kind, i0, direction, label, root):
        """Run one trace; returns the new rows' (global) indices of jump landings."""
        from contactvib._kernels.describe import new_rows
        from contactvib.interrupts import check_interrupt

        check_interrupt()  # between kernel calls: where a deferred Ctrl-C is honoured
        tk = self.tk
        cap = self.f.size + 1
        o = new_rows(cap)
        links = tk.new_links(cap)
        n_rows, n_links, stop, i_stop = tk.trace(
            np.asarray(z, float), int(k), int(kind), int(i0), int(direction), self.r, self.par,
            self.cfg, self.table, o, self.n_rows, links)
        self.stops.append(TraceStop(label, direction, float(self.f[i0]), float(self.f[i_stop]),
                                    int(stop), root))
        if n_rows:
            self.chunks.append(type(o)(*(v[:n_rows].copy() for v in o)))
            self.found_by.append(np.full(n_rows, TRACE_ROOTS.index(root), np.int64))
        if n_links:
            self.links.append(type(links)(*(v[:n_links].copy() for v in links)))
        base = self.n_rows
        self.n_rows += n_rows
        return [(base + j) for j in range(n_rows)
                if o.origin[j] == tk.ORIGIN_JUMP and o.kind[j] == tk.KIND_PERIODIC]

    def row(self, gid):
        """(z, k, kind, i) of global row ``gid``."""
        for c in self.chunks:
            n = c.i.size
            if gid < n:
                return c.z[gid], int(c.k[gid]), int(c.kind[gid]), int(c.i[gid])
            gid -= n
        raise IndexError(gid)

    def known_slot(self, i, z, k, kind):
        return self.tk.find_known(self.table, i, np.asarray(z, float), int(k), int(kind),
                                  self.cfg.same_tol)

    def result(self, basin: np.ndarray, pa_over_q: float) -> LevelTrace:
        """The accumulated rows, links and stops as a :class:`LevelTrace`."""
        from contactvib._kernels.describe import new_rows

        rows = (type(self.chunks[0])(*(np.concatenate(c) for c in zip(*self.chunks)))
                if self.chunks else new_rows(0))
        found_by = np.concatenate(self.found_by) if self.found_by else np.zeros(0, np.int64)
        links = (self.tk.TraceLinks(*(np.concatenate(c) for c in zip(*self.links)))
                 if self.links else self.tk.new_links(0))
        return LevelTrace(rows=rows, found_by=found_by, basin=basin, links=links, f_hz=self.f,
                          stops=self.stops, pa_over_q=float(pa_over_q))


def _settle_from(level: LevelState, i: int, z, phase: float = 0.0):
    from contactvib._kernels.settle import SETTLE_NONPERIODIC, SETTLE_PERIODIC, settle

    st = level.st
    par = level.par.copy()
    par[4] = level.r[i]
    hist = np.empty((st.max_periods + 1, 2))
    oz = np.empty(2)
    oM = np.empty((2, 2))
    s, k, n, _res = settle(np.asarray(z, float), phase, par, st.kmax, 4, st.max_periods,
                           st.detect_tol, st.rtol_transient, st.rtol, st.close_tol, hist, oz, oM)
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
    ok, k, _res = refine_stable_orbit(z, 1, par, st.rtol, st.close_tol, oz, oM)
    return oz.copy() if ok and k == 1 else None


def _multistart_at(lv: LevelState, model: ContactModel, pa_over_q: float, i: int) -> list:
    """Perturbation seed and multi-start at grid index ``i``: trace every new attractor up and
    down; returns the basin observations [(row, fraction of the box starts)]."""
    from contactvib._kernels.settle import SETTLE_CAPTURED, SETTLE_NONPERIODIC, SETTLE_PERIODIC
    from contactvib._kernels.table import settle_known_many
    from contactvib.interrupts import check_interrupt
    from contactvib.steady.attractors import ballistic_seeds, start_box
    from contactvib.sweeps.verdict import settle_nonperiodic_start

    check_interrupt()
    st = lv.st
    exc = st.excitation_at(model, pa_over_q, lv.f[i])
    Zb, phb = start_box(exc, st.multistart_starts, st.seed + i)
    Zs, phs = ballistic_seeds(exc)
    Z = np.vstack([Zb, Zs])
    ph = np.concatenate([phb, phs])
    par = lv.par.copy()
    par[4] = lv.r[i]
    zs = _small_amplitude_seed(model, exc, par, st)
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


def trace_level(model: ContactModel, pa_over_q: float, settings: SweepSettings) -> LevelTrace:
    """All attractors along the frequency grid at one P_a level, as flat arrays (see module doc).

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
    for i0, direction, label in ((0, +1, "up-sweep"), (f.size - 1, -1, "down-sweep")):
        res = _settle_from(lv, i0, (1.0, 0.0))
        if res is not None:
            lv.queue.append((res[0], res[1], res[2], i0, direction, label, "sweep"))
    lv.drain()
    starts = multistart_indices(st)
    report_points(pa_over_q, 2 * f.size // 5)
    observations = []
    for n, i in enumerate(starts, 1):
        observations.append(_multistart_at(lv, model, pa_over_q, int(i)))
        report_points(pa_over_q, 2 * f.size // 5 + 2 * f.size * n // (5 * len(starts)))
    late_newton_seeds(lv, model, pa_over_q, starts)
    continue_unstable_parts(lv, model, pa_over_q)  # stable parts beyond a jump (root "continuation")
    basin = np.full(lv.n_rows, np.nan)
    for obs in observations:
        for gid, frac in obs:
            basin[gid] = frac
    from contactvib.sweeps.verdict import drop_unsettled

    return drop_unsettled(lv.result(basin, pa_over_q), model, st.rtol_transient, st.max_periods,
                          st.excitation)


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
    from contactvib.continuation.shooting import ContinuationError, ContinuationSettings, continue_orbit

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
    tk.continue_orbit(z.copy(), k1, par, st.rtol, st.close_tol, new_rows(1), np.int64(0),
                      np.empty(2), np.empty((2, 2)))
    r = float(par[4])
    tk.bridge_orbit(z.copy(), r, z.copy(), r, np.bool_(False), r, k1, par, st.rtol, st.close_tol,
                    np.empty(2), np.empty(2))
    lyapunov_strobe(z.copy(), par, st.rtol_transient, np.int64(NP_LYAPUNOV))
    try:
        continue_orbit(model, exc, z, 1, "f_e", "down",
                       ContinuationSettings(fmin_hz=0.9 * f0, fmax_hz=f0, max_points=2, max_failures=2,
                                            rtol=st.rtol, tol=st.close_tol))
    except (ContinuationError, ParameterError, FloatingPointError, np.linalg.LinAlgError):
        pass
    newton_orbit(z.copy(), 1, par, st.rtol, st.rtol, st.close_tol, 8, np.empty(2), np.empty((2, 2)))
    settle_known_many(z.reshape(1, 2).copy(), np.zeros(1), 0, lv.par.copy(), lv.cfg, st.capture_tol,
                      lv.table)
