"""Orbit diagrams: the stroboscopic points of every attractor along a grid of f_e (or P_a).

At the first grid point every attractor is found by the multi-start search
(:func:`contactvib.find_attractors`); at each next point every known attractor is continued from
its last state: ``n_periods`` transient periods are integrated (the attractor settles at the new
parameter), then ``n_periods`` recorded. A recorded sequence that repeats with a period
k ≤ max(kmax, n_periods/2) (to 1e-2 relative) is refined by Newton shooting and, when stable,
recorded as the k points of that orbit; otherwise the recorded points are the attractor's cloud. Every ``search_every``
points a fresh search adds attractors that appeared; the grid is walked up, then down again from
the attractors at its end (an attractor found late is followed back); an attractor that has become the same as an
earlier one (same orbit, or overlapping clouds) is dropped. Each attractor's points are coloured
by λ1 (``contactvib.steady.sections.largest_exponent``).

The grid points follow each other (each continues from the previous one's states); the one level
of parallelism is the search's (numba threads over its starts).

Units: f_e [Hz], P_a [Q], y [µm], ẏ [mm/s], contact-loss phase [fraction of the period], ẏ at the
loss [mm/s], λ1 [1/excitation period].
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from contactvib.model import (
    KMAX_SEARCH_MAX,
    WORKERS_MAX,
    ContactModel,
    ParameterError,
    check_choice,
    check_int,
    check_range,
)
from contactvib.steady.follow import excitation_at_point, walk_grid
from contactvib.steady.sections import SECTION_RTOL

__all__ = ["OrbitDiagramSettings", "orbit_diagram", "write_csv", "VARY", "MAX_GRID_POINTS"]

#: What an orbit diagram varies: the excitation frequency f_e [Hz] or amplitude P_a [Q].
VARY = ("fe", "pa")
#: Most grid points of one diagram.
MAX_GRID_POINTS = 5000
#: Most strobe points recorded per attractor and grid point.
MAX_PERIODS = 100_000


@dataclass(frozen=True)
class OrbitDiagramSettings:
    """The grid and the effort of :func:`orbit_diagram`.

    Attributes
    ----------
    vary : str
        ``"fe"`` (f_e [Hz] from ``start`` to ``stop``) or ``"pa"`` (P_a [Q]).
    start, stop, step : float
        The grid ``start, start + step, …`` up to ``stop`` (included within 1e-9 of a step);
        ``start < stop``, ``step > 0``, at most ``MAX_GRID_POINTS`` (5000) points.
    n_periods : int
        Transient periods before each record, and periods recorded (≥ 2).
    search_every : int
        A fresh attractor search every this many grid points (≥ 1; the first point always).
    n_starts : int
        Random starts of each search.
    kmax : int
        Largest period of the searches (a followed attractor's period is detected up to
        max(kmax, n_periods // 2)).
    """

    vary: str = "fe"
    start: float = 810.0
    stop: float = 818.0
    step: float = 0.25
    n_periods: int = 64
    search_every: int = 8
    n_starts: int = 128
    kmax: int = 8

    def __post_init__(self):
        check_choice("vary", self.vary, VARY)
        lo, hi, d = ("f_from", "f_to", "df") if self.vary == "fe" else ("pa_from", "pa_to", "dpa")
        unit = "Hz" if self.vary == "fe" else "Q"
        start = check_range(lo, self.start, 0.0, False, unit)
        stop = check_range(hi, self.stop, start, False, unit, lower_name=lo)
        step = check_range(d, self.step, 0.0, False, unit)
        n = math.floor((stop - start) / step + 1e-9) + 1
        if n > MAX_GRID_POINTS:
            smallest = (stop - start) / (MAX_GRID_POINTS - 1)
            raise ParameterError(d, self.step, f"gives {n} grid points from {lo} to {hi}; at most "
                                               f"{MAX_GRID_POINTS}: must be >= {smallest:.4g} {unit}", (lo, hi))
        object.__setattr__(self, "start", start)
        object.__setattr__(self, "stop", stop)
        object.__setattr__(self, "step", step)
        object.__setattr__(self, "n_periods", check_int("n_periods", self.n_periods, 2, MAX_PERIODS))
        object.__setattr__(self, "search_every", check_int("search_every", self.search_every, 1))
        object.__setattr__(self, "n_starts", check_int("n_starts", self.n_starts, 1))
        object.__setattr__(self, "kmax", check_int("kmax", self.kmax, 1, KMAX_SEARCH_MAX))

    def grid(self) -> np.ndarray:
        """The grid values [Hz or Q]."""
        n = math.floor((self.stop - self.start) / self.step + 1e-9) + 1
        return self.start + self.step * np.arange(n)


def orbit_diagram(model: ContactModel, *, pa_over_q: float | None = None, fe_hz: float | None = None,
                  settings: OrbitDiagramSettings | None = None, rtol: float = SECTION_RTOL, workers: int = 1,
                  progress=None):
    """The orbit diagram of ``model`` along f_e at ``pa_over_q`` (``settings.vary = "fe"``) or
    along P_a at ``fe_hz`` (``"pa"``).

    Returns
    -------
    xarray.Dataset
        Dimension ``point`` (one stroboscopic point of one attractor at one grid value): ``fe_hz``
        [Hz], ``pa_over_q`` [Q], ``grid_index``, ``attractor`` (its id, kept while it is
        followed), ``period`` [excitation periods, 0: non-periodic], ``k``, ``y_um`` [µm],
        ``ydot_mm_s`` [mm/s], ``lambda1`` [1/period]; dimension ``loss`` (one contact loss):
        ``loss_fe_hz``, ``loss_pa_over_q``, ``loss_grid_index``, ``loss_attractor``,
        ``loss_period``, ``phase_frac`` [fraction of the period], ``v_loss_mm_s`` [mm/s],
        ``loss_lambda1``. Writable with ``to_netcdf``.

    ``workers`` > 1 walks that many contiguous parts of the grid in as many processes (one numba
    thread each: the one level of parallelism), each part from its own search, overlapping its
    neighbour by one grid point where the attractors of both are matched (their ids joined);
    with one worker the searches use the numba threads. ``progress``, if given, is called as
    ``progress(done, total)`` after each grid point (each part, with workers).
    """
    settings = settings or OrbitDiagramSettings()
    workers = check_int("workers", workers, 1, WORKERS_MAX)
    fixed_symbol = "P_a/Q" if settings.vary == "fe" else "f_e"
    fixed = pa_over_q if settings.vary == "fe" else fe_hz
    if fixed is None:
        raise ParameterError(fixed_symbol, None, "must be given (the parameter held fixed)")
    grid = settings.grid()
    for v in (grid[0], grid[-1]):  # both ends are operating points the model accepts
        excitation_at_point(model, settings, fixed, v)
    u = model.units
    if workers > 1 and grid.size >= 2 * workers:
        from contactvib.steady.diagram_pool import walk_in_pool

        per_point = walk_in_pool(model, settings, fixed, grid, rtol, workers, progress)
    else:
        per_point = walk_grid(model, settings, fixed, grid, rtol, progress)
    cols: dict[str, list] = {k: [] for k in ("grid_index", "attractor", "period", "k", "x", "v", "lambda1")}
    loss: dict[str, list] = {k: [] for k in ("grid_index", "attractor", "period", "phase", "v", "lambda1")}
    for i, kept in enumerate(per_point):
        period_tau = excitation_at_point(model, settings, fixed, float(grid[i])).tau_period
        for t in kept:
            n, m = t.strobe.shape[0], t.loss_tau.size
            for name, val in (("grid_index", i), ("attractor", t.id), ("period", t.period or 0),
                              ("lambda1", t.lambda1)):
                cols[name].append(np.full(n, val))
                loss[name].append(np.full(m, val))
            cols["k"].append(np.arange(n))
            cols["x"].append(t.strobe[:, 0])
            cols["v"].append(t.strobe[:, 1])
            loss["phase"].append(np.mod(t.loss_tau, period_tau) / period_tau)
            loss["v"].append(t.loss_v)
    return _dataset(model, settings, fixed, grid, cols, loss, u)


def _cat(parts: list, dtype) -> np.ndarray:
    return np.concatenate(parts).astype(dtype) if parts else np.empty(0, dtype)


def _dataset(model, settings, fixed, grid, cols, loss, u):
    import json

    import xarray as xr

    gi, lgi = _cat(cols["grid_index"], np.int64), _cat(loss["grid_index"], np.int64)
    fe = (lambda g: np.full(g.size, fixed)) if settings.vary == "pa" else (lambda g: grid[g])
    pa = (lambda g: grid[g]) if settings.vary == "pa" else (lambda g: np.full(g.size, fixed))

    def var(dim, data, units, what):
        return (dim, data, {"units": units, "long_name": what})

    ds = xr.Dataset({
        "fe_hz": var("point", fe(gi), "Hz", "excitation frequency f_e"),
        "pa_over_q": var("point", pa(gi), "Q = M g", "excitation amplitude P_a"),
        "grid_index": var("point", gi, "1", "index of the grid value"),
        "attractor": var("point", _cat(cols["attractor"], np.int64), "1", "attractor id (kept while followed)"),
        "period": var("point", _cat(cols["period"], np.int64), "excitation periods",
                      "minimal period (0: non-periodic)"),
        "k": var("point", _cat(cols["k"], np.int64), "1", "stroboscopic point number (t = k/f_e)"),
        "y_um": var("point", u.position_um(_cat(cols["x"], float)), "um", "y at t = k/f_e"),
        "ydot_mm_s": var("point", _cat(cols["v"], float) * u.ydot_mm_s, "mm/s", "dy/dt at t = k/f_e"),
        "lambda1": var("point", _cat(cols["lambda1"], float), "1/excitation period",
                       "largest Lyapunov exponent of the stroboscopic map"),
        "loss_fe_hz": var("loss", fe(lgi), "Hz", "excitation frequency f_e"),
        "loss_pa_over_q": var("loss", pa(lgi), "Q = M g", "excitation amplitude P_a"),
        "loss_grid_index": var("loss", lgi, "1", "index of the grid value"),
        "loss_attractor": var("loss", _cat(loss["attractor"], np.int64), "1", "attractor id"),
        "loss_period": var("loss", _cat(loss["period"], np.int64), "excitation periods", "minimal period"),
        "phase_frac": var("loss", _cat(loss["phase"], float), "1 (fraction of the period)",
                          "excitation phase at the contact loss"),
        "v_loss_mm_s": var("loss", _cat(loss["v"], float) * u.ydot_mm_s, "mm/s", "dy/dt at the contact loss"),
        "loss_lambda1": var("loss", _cat(loss["lambda1"], float), "1/excitation period", "lambda1 of the attractor"),
    }, attrs={
        "title": "contactvib orbit diagram", "vary": settings.vary,
        "fixed": float(fixed), "fixed_units": "Q = M g" if settings.vary == "fe" else "Hz",
        "settings": json.dumps(dataclasses.asdict(settings)), "model": json.dumps(model.parameters(), default=str),
        "y0_um": float(u.y_um), "fn0_hz": float(model.f_n0),
    })
    return ds


def write_csv(ds, path, measure: str = "y"):
    """The diagram's points as CSV with a ``#`` units header: per strobe point (``measure`` "y")
    fe_hz, pa_over_q, attractor, kind, period, k, y_um, ydot_mm_s, lambda1; per contact loss
    ("v-loss") fe_hz, pa_over_q, attractor, kind, period, k, phase_frac, v_loss_mm_s, lambda1."""
    if measure == "y":
        cols = {"fe_hz": "fe_hz", "pa_over_q": "pa_over_q", "attractor": "attractor", "period": "period",
                "k": "k", "y_um": "y_um", "ydot_mm_s": "ydot_mm_s", "lambda1": "lambda1"}
    else:
        cols = {"fe_hz": "loss_fe_hz", "pa_over_q": "loss_pa_over_q", "attractor": "loss_attractor",
                "period": "loss_period", "phase_frac": "phase_frac", "v_loss_mm_s": "v_loss_mm_s",
                "lambda1": "loss_lambda1"}
    data = {name: ds[var].values for name, var in cols.items()}
    n = next(iter(data.values())).size
    lam = data["lambda1"]
    kind = np.where(data["period"] > 0, "periodic", np.where(lam > 0.0, "chaotic", "non-periodic"))
    header = ["# contactvib orbit-diagram: " + ("stroboscopic points at t = k/f_e" if measure == "y"
                                                else "states at each contact loss"),
              "# units: fe_hz [Hz], pa_over_q [Q = M g], period [excitation periods, 0: non-periodic], "
              "y_um [um], ydot_mm_s [mm/s], phase_frac [fraction of the excitation period], "
              "v_loss_mm_s [mm/s], lambda1 [1/excitation period]",
              ",".join(["fe_hz", "pa_over_q", "attractor", "kind", *list(cols)[3:]])]
    names = list(cols)
    lines = [",".join([repr(float(data["fe_hz"][i])), repr(float(data["pa_over_q"][i])), str(int(data["attractor"][i])),
                       str(kind[i]), *(_csv_value(data[c][i]) for c in names[3:])]) for i in range(n)]
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(header + lines) + "\n")
    return path


def _csv_value(v) -> str:
    if isinstance(v, (np.integer, int)):
        return str(int(v))
    v = float(v)
    return "" if math.isnan(v) else repr(v)
