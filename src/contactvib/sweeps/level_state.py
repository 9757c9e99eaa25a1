"""The state of one P_a level while :func:`contactvib.sweeps.sweep.trace_level` walks its
frequency grid (:class:`LevelState`: the shared table of known attractors, the queued traces, the
accumulated rows) and what it returns (:class:`LevelTrace`, one :class:`TraceStop` per trace).

A leaf of the sweep: :mod:`contactvib.sweeps.sweep` and :mod:`contactvib.sweeps.newton_seeds`
both work on a LevelState, and neither is imported here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from contactvib.sweeps.dataset import TRACE_ROOTS
from contactvib.sweeps.stage_times import stage

if TYPE_CHECKING:
    from contactvib._kernels.describe import TraceRows
    from contactvib._kernels.trace import TraceLinks
    from contactvib.model import ContactModel
    from contactvib.sweeps.settings import SweepSettings

__all__ = ["LevelState", "LevelTrace", "TraceStop"]

_MAXA = 48  # attractors per frequency in the shared table


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
    verdicts : dict or None
        Per row, what the attractor search's rule earns it (:func:`.verdict.judge_rows`):
        ``attractor_type``, ``true_period``, ``lyapunov_per_s`` and ``lyapunov_stderr_per_s``
        (n, 2); None before the rows are judged.
    """

    rows: TraceRows
    found_by: np.ndarray
    basin: np.ndarray
    links: TraceLinks
    f_hz: np.ndarray
    stops: list
    pa_over_q: float
    verdicts: dict | None = None

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
        self.cfg = tk.trace_settings(st.rtol, st.tol, st.kmax, st.max_periods, st.detect_tol,
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
        with stage("trace (compiled tracer)"):
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
