"""Basins of attraction of a :class:`~contactvib.model.system.System` on a 2-D slice of its
state space: a grid over two named state components, each start labelled by the attractor it
reaches.

The slice
---------
A state component is named by a coordinate (``q1``, ``y``, ``theta``: the displacement, in µm or
µrad) or by a coordinate with ``_dot`` (its rate, in mm/s or mrad/s). The grid varies the two
named components; every other component stays at the slice's base state: the static state
(q_s, 0) by default, or a state the caller gives (e.g. a point of an attractor). Starts are at
phase 0 of the excitation. The default ranges are the attractor search's box
(:func:`~contactvib.steady.system_attractors.start_box`) along the two components.

Procedure
---------
1. :func:`~contactvib.steady.system_attractors.find_system_attractors` runs first (same
   ``kmax``, ``max_periods`` and tolerances, with its verdict on the starts without a period:
   chaotic and quasi-periodic attractors, long periods); its attractors are the labels
   ``0 .. n−1`` in its order.
2. Every grid start is settled by the search's compiled kernel
   (:func:`contactvib._kernels.system_settle.settle_starts`, both cores, Ctrl-C ends it within
   one period) with the stroboscopic points of the stable attractors as capture points: a start
   that comes within ``CAPTURE_TOL`` of one (relative, scaled state) takes its label.
3. A start that settles on a period ``k ≤ kmax`` without being captured is refined by Newton
   shooting to its orbit of minimal period
   (:func:`~contactvib.steady.system_attractors.settled_orbit`) and matched to the known orbits;
   a stable orbit the search did not find becomes a new label ``n, n+1, …`` (basin fraction on
   the grid).
4. A start that settles on nothing within ``max_periods`` takes the label of the search's
   non-periodic attractor whose strobe cloud its next ``WINDOW`` strobe points lie on
   (:func:`~contactvib.steady.system_verdict.match_cloud`, the search's own test). Starts that
   reach none of them, or an unstable orbit, or whose integration failed get label −1 (the grid
   gives no verdict of its own: a non-periodic attractor the search missed stays −1).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np

from contactvib._kernels import system_settle as ks
from contactvib._kernels.status import SETTLE_CAPTURED, SETTLE_FAILED, SETTLE_INTERRUPTED, SETTLE_PERIODIC
from contactvib._kernels.system_flow import system_arrays
from contactvib.errors import ComputationError
from contactvib.interrupts import new_stop_flag, run_interruptible
from contactvib.model import ParameterError, check_int, check_range
from contactvib.model.checks import MEMORY_MAX, check_memory
from contactvib.model.system import System, check_excitation
from contactvib.steady.system_attractors import (
    STARTS_DEFAULT,
    SystemAttractorSet,
    check_system_search,
    default_max_periods,
    find_system_attractors,
    measure_attractor,
    same_orbit_index,
    settled_orbit,
    start_box,
)
from contactvib.steady.system_orbits import DISPLAY_UNITS
from contactvib.steady.system_verdict import match_cloud, strobe_projection
from contactvib.steady.transients import WINDOW

__all__ = ["system_basins", "SystemBasinMap", "state_component", "default_slice", "check_system_basins",
           "default_slice_box",
           "CAPTURE_TOL", "GRID_DEFAULT"]

#: Capture distance of a grid start from a stable attractor's stroboscopic point (relative to
#: max(1, |x|∞), scaled state): the search's.
CAPTURE_TOL = 1e-4
#: The search's settling tolerance and integrator tolerance (its defaults).
SETTLE_TOL = 1e-7
RTOL = 1e-10
#: Default grid (points along the first and the second component).
GRID_DEFAULT = (100, 100)
#: Grid starts per call of the settling kernel (progress and Ctrl-C between calls).
CHUNK = 512
#: Bytes kept per grid point (start, label, settled point; rounded up).
_BYTES_PER_POINT = 256


def state_component(system: System, name: str) -> tuple[int, str, float]:
    """The index in the state (q, q̇) of the component ``name`` (a coordinate, or a coordinate
    with ``_dot``), its display unit and the factor from SI to it."""
    text = str(name).strip()
    rate = text.endswith("_dot")
    coord = text[:-4] if rate else text
    if coord not in system.coordinates:
        known = ", ".join(f"{c}, {c}_dot" for c in system.coordinates)
        raise ParameterError("slice", name, f"must name a state component: {known}")
    j = system.coordinates.index(coord)
    u = DISPLAY_UNITS[system.units[j]]
    return (system.n + j, u[2], u[3]) if rate else (j, u[0], u[1])


def default_slice(system: System) -> tuple[str, str]:
    """The first contact's coordinate (the largest |w_j| of its direction; the first coordinate
    without contacts) and its rate."""
    j = int(np.argmax(np.abs(system.directions[0]))) if system.contacts else 0
    c = system.coordinates[j]
    return c, f"{c}_dot"


def default_slice_box(system: System, pa_newton: float, fe_hz: float, axes, base_state=None) -> tuple:
    """The ranges ((a_min, a_max), (b_min, b_max)) [display units] of the components ``axes``:
    the attractor search's half-widths (:func:`~contactvib.steady.system_attractors.start_box`)
    about the base state (default the static state at rest)."""
    form = system.kernel_form(pa_newton, fe_hz)
    centre, half = start_box(system, form, pa_newton, fe_hz)
    si = form.scales.to_si(centre + half) - form.scales.to_si(centre)  # the half-widths [SI]
    base = form.scales.to_si(centre) if base_state is None else np.asarray(base_state, float)
    box = []
    for name in axes:
        i, _unit, f = state_component(system, name)
        box.append((float((base[i] - si[i]) * f), float((base[i] + si[i]) * f)))
    return tuple(box)


def check_system_basins(system: System, axes, grid, box, base_state, kmax, max_periods, n_starts, seed):
    """The basin map's settings, checked before any computation: ``(axes, (index_a, index_b),
    grid, box or None, base_state (SI) or None, kmax, max_periods, n_starts, seed)``."""
    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a contactvib.model.System")
    axes = default_slice(system) if axes is None else tuple(axes)
    if len(axes) != 2:
        raise ParameterError("slice", axes, "must name two state components")
    idx = tuple(state_component(system, a)[0] for a in axes)
    if idx[0] == idx[1]:
        raise ParameterError("slice", axes, "must name two different state components")
    if not (hasattr(grid, "__len__") and len(grid) == 2):
        raise ParameterError("grid", grid, "must be two counts (points along each component)")
    grid = (check_int("n_a", grid[0], 2, 4000), check_int("n_b", grid[1], 2, 4000))
    check_memory("grid", f"{grid[0]}x{grid[1]}", float(grid[0]) * grid[1] * _BYTES_PER_POINT,
                 int(math.sqrt(MEMORY_MAX / _BYTES_PER_POINT)))
    if box is not None:
        if not (hasattr(box, "__len__") and len(box) == 2 and all(hasattr(r, "__len__") and len(r) == 2 for r in box)):
            raise ParameterError("box", box, "must be ((a_min, a_max), (b_min, b_max)) in display units")
        a0 = check_range("a_min", box[0][0], -math.inf, False)
        a1 = check_range("a_max", box[0][1], a0, False, lower_name="a_min")
        b0 = check_range("b_min", box[1][0], -math.inf, False)
        b1 = check_range("b_max", box[1][1], b0, False, lower_name="b_min")
        box = ((a0, a1), (b0, b1))
    if base_state is not None:
        base_state = np.asarray(base_state, float).reshape(-1)
        if base_state.size != 2 * system.n or not np.all(np.isfinite(base_state)):
            raise ParameterError("base_state", base_state, f"must be {2 * system.n} finite numbers (q, q̇) [SI]")
    n_starts, seed, kmax, mp = check_system_search(n_starts, seed, kmax,
                                                   1 if max_periods is None else max_periods)
    return axes, idx, grid, box, base_state, kmax, (None if max_periods is None else mp), n_starts, seed


@dataclass(frozen=True)
class SystemBasinMap:
    """Basins of attraction of a system on a 2-D slice of its state space.

    Attributes
    ----------
    axes : (str, str)
        The two state components (``q1``, ``q1_dot``, …).
    units : (str, str)
        Their display units (µm, µrad, mm/s, mrad/s as "um", "urad", "mm/s", "mrad/s").
    a, b : ndarray
        The grid's values of the first (n_a) and second (n_b) component [display units].
    labels : ndarray of int64, shape (n_b, n_a)
        The attractor reached from (a[j], b[i]): an index into ``attractors``, or −1.
    attractors : list of SystemAttractor
        The search's attractors (labels ``0..n_known−1``, basin fraction of its random box), then
        those only the grid reached (basin fraction on the grid).
    n_known : int
    search : SystemAttractorSet
    base_state : ndarray (2n,)
        The state [SI] of the components the grid does not vary.
    indices : (int, int)
        The two components' indices in the state (q, q̇).
    factors : (float, float)
        Their factors from SI to the display units.
    n_failed, n_unsettled : int
        Grid starts whose integration failed, or that reached no known attractor (label −1).
    base_given : bool
        Whether ``base_state`` was given (else the static state at rest).
    """

    axes: tuple
    units: tuple
    a: np.ndarray
    b: np.ndarray
    labels: np.ndarray
    attractors: list
    n_known: int
    search: SystemAttractorSet
    base_state: np.ndarray
    indices: tuple
    factors: tuple
    n_failed: int = 0
    n_unsettled: int = 0
    base_given: bool = False

    @property
    def n_points(self) -> int:
        return int(self.labels.size)

    def fraction(self, label: int) -> tuple[float, float]:
        """Share of the grid starts with ``label`` [1] and its standard error sqrt(p(1−p)/N) (a
        lower bound: neighbouring grid points are correlated)."""
        p = float(np.count_nonzero(self.labels == label)) / self.n_points
        return p, math.sqrt(p * (1.0 - p) / self.n_points)

    def fractions(self) -> list[dict]:
        """One entry per label, then label −1: ``{"label", "period", "minima_per_period",
        "attractor_type", "fraction", "stderr"}`` (period and minima null for a non-periodic
        attractor)."""
        rows = []
        for label, a in [*enumerate(self.attractors), (-1, None)]:
            p, se = self.fraction(label)
            rows.append({"label": label, "period": None if a is None or not a.period else int(a.period),
                         "minima_per_period": None if a is None or not a.period else int(a.minima_per_period),
                         "attractor_type": None if a is None else a.attractor_type, "fraction": p, "stderr": se})
        return rows

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib basins --system ... --json``."""
        s = self.search
        return {"pa_newton": float(s.pa_newton), "fe_hz": float(s.fe_hz),
                "natural_frequencies_hz": [float(f) for f in s.natural_frequencies_hz],
                "slice": list(self.axes), "slice_units": list(self.units),
                "grid": [int(self.a.size), int(self.b.size)],
                "range_a": [float(self.a[0]), float(self.a[-1])], "range_b": [float(self.b[0]), float(self.b[-1])],
                "base_state_si": [float(x) for x in self.base_state],
                "n_points": self.n_points, "n_failed": int(self.n_failed), "n_unsettled": int(self.n_unsettled),
                "n_known": int(self.n_known), "max_periods": int(s.settings["max_periods"]),
                "units": {"m": "um", "rad": "urad", "rate of m": "mm/s", "rate of rad": "mrad/s", "force": "N",
                          "f": "Hz", "base_state_si": "m, rad, m/s, rad/s"},
                "fractions": self.fractions(),
                "attractors": [{"label": i, **a.to_dict()} for i, a in enumerate(self.attractors)]}

    def to_json(self, **kw) -> str:
        return json.dumps(self.to_dict(), **kw)

    def strobe(self, label: int) -> tuple[np.ndarray, np.ndarray]:
        """The stroboscopic points of attractor ``label`` along the two components [display units]."""
        a = self.attractors[label]
        return tuple(a.strobe[:, i] * f for i, f in zip(self.indices, self.factors))

    def to_dataset(self):
        """An xarray Dataset: ``label`` (b, a), per attractor its period, minima, fraction and the
        stroboscopic points along the slice; units in each variable's ``units`` attribute."""
        import xarray as xr

        atts = self.attractors
        labels = np.arange(-1, len(atts))
        fr = np.array([self.fraction(int(k)) for k in labels]).reshape(-1, 2)
        pts = [self.strobe(i) for i in range(len(atts))]
        strobe_label = np.concatenate([np.full(p[0].size, i) for i, p in enumerate(pts)] or [[]]).astype(np.int64)
        (na, nb), (ua, ub) = self.axes, self.units
        s = self.search
        return xr.Dataset(
            {"label": (("b", "a"), self.labels, {"units": "1", "long_name": "attractor reached (-1: none)"}),
             "period": ("attractor", np.array([a.period for a in atts], np.int64),
                        {"units": "excitation periods", "long_name": "period (0: non-periodic)"}),
             "attractor_type": ("attractor", np.array([a.attractor_type for a in atts], dtype=object),
                                {"units": "1", "long_name": "periodic, quasi-periodic or chaotic"}),
             "minima_per_period": ("attractor", np.array([a.minima_per_period for a in atts], np.int64),
                                   {"units": "1"}),
             "fraction": ("label_all", fr[:, 0], {"units": "1"}),
             "stderr": ("label_all", fr[:, 1], {"units": "1", "note": "sqrt(p(1-p)/N), a lower bound"}),
             "strobe_label": ("strobe", strobe_label, {"units": "1"}),
             "strobe_a": ("strobe", np.concatenate([p[0] for p in pts] or [[]]).astype(float),
                          {"units": ua, "long_name": na}),
             "strobe_b": ("strobe", np.concatenate([p[1] for p in pts] or [[]]).astype(float),
                          {"units": ub, "long_name": nb})},
            coords={"a": ("a", self.a, {"units": ua, "long_name": na}),
                    "b": ("b", self.b, {"units": ub, "long_name": nb}),
                    "attractor": ("attractor", np.arange(len(atts))), "label_all": ("label_all", labels)},
            attrs={"pa_newton": float(s.pa_newton), "fe_hz": float(s.fe_hz), "slice": f"{na},{nb}",
                   "n_known": int(self.n_known), "n_failed": int(self.n_failed), "n_unsettled": int(self.n_unsettled),
                   "base_state_si": json.dumps([float(x) for x in self.base_state]),
                   "settings": json.dumps({k: v for k, v in s.settings.items()})})


def system_basins(system: System, pa_newton: float, fe_hz: float, *, axes=None, grid=GRID_DEFAULT, box=None,
                  base_state=None, kmax: int = 8, max_periods: int | None = None, n_starts: int = STARTS_DEFAULT,
                  seed: int = 0, progress=None) -> SystemBasinMap:
    """Basins of attraction on a grid over two state components at phase 0 of P_a cos(2π f_e t).

    Parameters
    ----------
    system : System
    pa_newton, fe_hz : float
        P_a [N] ≥ 0, f_e [Hz] > 0.
    axes : (str, str), optional
        The two state components (:func:`state_component`); default :func:`default_slice`.
    grid : (int, int)
        Points along the first and the second component (each 2..4000).
    box : ((float, float), (float, float)), optional
        Their ranges [display units: µm, µrad, mm/s, mrad/s], ends included; default the search's
        box (:func:`~contactvib.steady.system_attractors.start_box`).
    base_state : array_like (2n,), optional
        The other components [SI]; default the static state at rest.
    kmax, max_periods, n_starts, seed
        Of the attractor search (:func:`find_system_attractors`, its default tolerances
        ``SETTLE_TOL`` and ``RTOL``), whose transient limit the grid starts use too.
    progress : callable, optional
        ``progress(done, total)`` over the grid starts (once with 0 before the first).
    """
    axes, idx, grid, box, base, kmax, max_periods, n_starts, seed = check_system_basins(
        system, axes, grid, box, base_state, kmax, max_periods, n_starts, seed)
    pa, fe = check_excitation(pa_newton, fe_hz)
    settle_tol, rtol = SETTLE_TOL, RTOL
    if max_periods is None:
        max_periods = default_max_periods(system, fe, settle_tol)
    search = find_system_attractors(system, pa, fe, n_starts=n_starts, seed=seed, kmax=kmax, max_periods=max_periods,
                                    settle_tol=settle_tol, rtol=rtol)
    form = system.kernel_form(pa, fe)
    sc = form.scales
    sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
    _idx, units, factors = zip(*(state_component(system, a) for a in axes))
    if base is None:
        base = np.concatenate([system.static_state(), np.zeros(system.n)])
    if box is None:
        box = default_slice_box(system, pa, fe, axes, base)
    a = np.linspace(box[0][0], box[0][1], grid[0])
    b = np.linspace(box[1][0], box[1][1], grid[1])
    A, B = np.meshgrid(a / factors[0], b / factors[1])
    Z = np.tile(base, (A.size, 1))
    Z[:, idx[0]], Z[:, idx[1]] = A.ravel(), B.ravel()
    X = np.ascontiguousarray(sc.to_scaled(Z))

    found = [{"orbit": att.orbit, "points": sc.to_scaled(att.strobe), "hits": 0}
             for att in search.attractors]
    clouds = {i: {"cloud": strobe_projection(sa, f["points"][-2 * WINDOW:])} for i, f in enumerate(found)
              if f["orbit"] is None}
    n_known = len(found)
    labels = np.full(X.shape[0], -1, np.int64)
    n_failed = 0
    stop = new_stop_flag()
    if progress is not None:
        progress(0, X.shape[0])
    j = 0
    while j < X.shape[0]:
        caps = [(i, f["points"]) for i, f in enumerate(found) if f["orbit"] is not None and f["orbit"].stable]
        pts = np.concatenate([p for _, p in caps]) if caps else np.empty((0, X.shape[1]))
        ids = np.concatenate([np.full(len(p), i, np.int64) for i, p in caps]) if caps else np.empty(0, np.int64)
        chunk = X[j:j + CHUNK]
        how, kk, xs, _n = run_interruptible(ks.settle_starts, sa, np.ascontiguousarray(chunk), kmax, max_periods,
                                            settle_tol, np.ascontiguousarray(pts), ids, CAPTURE_TOL, rtol, stop,
                                            stop=stop)
        if (how == SETTLE_INTERRUPTED).any():
            raise KeyboardInterrupt
        for q in range(len(how)):
            h = int(how[q])
            if h == SETTLE_CAPTURED:
                labels[j + q] = int(kk[q])
            elif h == SETTLE_FAILED:
                n_failed += 1
            elif h == SETTLE_PERIODIC:
                labels[j + q] = _orbit_label(system, pa, fe, sa, form, xs[q], int(kk[q]), found)
            elif clouds:
                labels[j + q] = _cloud_label(sa, xs[q], rtol, clouds)
        j += len(how)
        if progress is not None:
            progress(j, X.shape[0])
    labels = labels.reshape(grid[1], grid[0])
    n = labels.size
    new = [measure_attractor(system, pa, fe, {**f, "hits": int(np.count_nonzero(labels == n_known + i))}, n)
           for i, f in enumerate(found[n_known:])]
    return SystemBasinMap(axes=axes, units=units, a=a, b=b, labels=labels, attractors=[*search.attractors, *new],
                          n_known=n_known, search=search, base_state=base, indices=idx, factors=factors,
                          n_failed=n_failed,
                          n_unsettled=int(np.count_nonzero(labels < 0)) - n_failed, base_given=base_state is not None)


def _orbit_label(system, pa, fe, sa, form, x, k, found: list) -> int:
    """The label of the stable orbit a grid start settled on (period k at the scaled point x):
    an equal orbit of ``found``, or a new one appended to it; −1 for an unstable orbit or one
    Newton's method cannot refine."""
    try:
        orbit, points = settled_orbit(system, pa, fe, sa, form, x, k)
    except ComputationError:
        return -1
    if not orbit.stable:
        return -1
    periodic = [i for i, f in enumerate(found) if f["orbit"] is not None]
    i = same_orbit_index(orbit, points, [found[i] for i in periodic])
    if i is None:
        found.append({"orbit": orbit, "points": points, "hits": 0})
        return len(found) - 1
    return periodic[i]


def _cloud_label(sa, x, rtol, clouds: dict) -> int:
    """The label of the non-periodic attractor (``clouds``: label → record with its projected
    "cloud") whose cloud the strobe points after the unsettled scaled point x lie on, or −1."""
    labels = list(clouds)
    try:
        i, _pts, _proj = match_cloud(sa, x, rtol, [clouds[k] for k in labels])
    except ComputationError:
        return -1
    return -1 if i is None else labels[i]
