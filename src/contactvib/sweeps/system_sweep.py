"""One force level of a :class:`~contactvib.model.system.System` over a frequency grid: its
periodic attractors found by laboratory sweeps and followed from multi-start searches, and the
non-periodic ones that the search's verdict finds where they settle on no period ≤ kmax.

The walk (all states at phase 0 of P(t) = P_a cos(2π f_e t), in the scaled state of
``contactvib.model.system_kernel``):

* an up-sweep from rest at the static state at f_min and a down-sweep from the up-sweep's last
  orbit at f_max; at each grid point the orbit of the previous point is continued by Newton
  shooting (:func:`~contactvib.steady.system_orbits.periodic_orbit`, the same period) from its
  state; where Newton's method fails or the orbit it reaches is unstable, the attractor is lost
  and the previous state is settled by integration, period by period, until its stroboscopic
  points repeat with a period k ≤ kmax (a jump, then refined by Newton);
* every ``search_every`` grid points a multi-start search
  (:func:`~contactvib.steady.system_attractors.find_system_attractors`, ``n_starts`` starts); each
  stable attractor not yet known there is followed up and down the grid in the same way until it
  lands on a known attractor or is lost without settling.

Stable periodic orbits are stored (the settled motions). Where the settling finds no period
≤ kmax within ``max_periods`` (a non-periodic motion or a long transient), a sweep goes on to the
next point from the state where the settling ended (the trace counts these points), and a
followed attractor ends. With ``nonperiodic`` (the default) the sweep's state there gets the
verdict of the attractor search (:func:`~contactvib.steady.system_verdict.judge_start`: chaotic,
quasi-periodic, a stable orbit of period kmax < k ≤ 512, or unsettled), and the searches run it
on their starts that settle on no period ≤ kmax; the attractors it finds are stored (a cloud
once per grid point: :func:`~contactvib.steady.transients.same_cloud`), not followed, with their
Lyapunov spectra, and the walks go on as without them, so the periodic orbits of period ≤ kmax
are the same rows, bit for bit; the verdict's rows come after them. A non-periodic row is
measured over ``NONPERIODIC_MEASURE_PERIODS`` periods from its last strobe point
(:func:`~contactvib.steady.system_attractors.orbit_columns`), its strobe points the verdict's last
2·WINDOW. Each stored orbit is measured once on one
recorded run of its k periods (``contactvib._kernels.system_map.record_span``): the extrema of every
coordinate refined on the dense output to ~1e-9 of the range, its component at f_e, the minima per
period of the first contact's deflection, each contact's open fraction and mean force (Gauss–Legendre
on every step). The sweeps' settling is one compiled call (``system_settle.settle_start``, the search's own); the
searches settle their starts period by period in Python
(:func:`~contactvib.steady.system_attractors.find_system_attractors`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from contactvib._kernels import system_map as km
from contactvib._kernels.status import STATUS_OK, STATUS_RECORD_FULL
from contactvib._kernels.system_flow import rec_width, system_arrays
from contactvib.errors import ComputationError
from contactvib.model import ParameterError, check_int, check_range
from contactvib.model.checks import KMAX_SEARCH_MAX
from contactvib.model.system import System, check_excitation
from contactvib.steady.system_orbits import DISPLAY_UNITS, periodic_orbit
from contactvib.steady.transients import same_cloud
from contactvib.sweeps.settings import check_grid, grid_frequencies

__all__ = ["SystemSweepSettings", "SystemLevel", "sweep_system_level", "SAME_TOL", "MEASURE_SAMPLES"]

#: Two orbits at one grid point are the same when they have the same period and a stroboscopic point
#: of one lies within this of one of the other's (relative to max(1, |x|∞), scaled state).
SAME_TOL = 1e-4
#: Samples per period of the measurement (the extrema are refined between them).
MEASURE_SAMPLES = 512
#: Relative repetition of the stroboscopic points that counts as settled.
SETTLE_TOL = 1e-7


@dataclass(frozen=True)
class SystemSweepSettings:
    """The grid and the searches of a system's sweep.

    Attributes
    ----------
    fmin_hz, fmax_hz, df_hz : float
        The grid f_min + j Δf ≤ f_max [Hz] (checked as a sweep's:
        :func:`contactvib.sweeps.settings.check_grid`).
    search_every : int
        Grid points between multi-start searches (the first point included); 0: sweeps only.
    n_starts, seed : int
        Starts of each search and the generator's seed.
    kmax : int
        Largest period detected [excitation periods].
    max_periods : int
        Transient limit of a settling [periods].
    rtol : float
        Integrator tolerance while settling (Newton and the measurement run at 1e-12).
    nonperiodic : bool
        Judge the grid points and search starts that settle on no period ≤ kmax
        (:mod:`contactvib.steady.system_verdict`) and keep the attractors the verdict finds:
        chaotic, quasi-periodic, periodic with a period above kmax; False: periodic ones only.
    """

    fmin_hz: float
    fmax_hz: float
    df_hz: float
    search_every: int = 10
    n_starts: int = 6
    seed: int = 0
    kmax: int = 8
    max_periods: int = 2000
    rtol: float = 1e-10
    nonperiodic: bool = True

    def __post_init__(self):
        for name, value in zip(("fmin_hz", "fmax_hz", "df_hz"), check_grid(self.fmin_hz, self.fmax_hz, self.df_hz)):
            object.__setattr__(self, name, value)
        object.__setattr__(self, "search_every", check_int("search_every", self.search_every, 0))
        object.__setattr__(self, "n_starts", check_int("n_starts", self.n_starts, 1, 10_000))
        object.__setattr__(self, "seed", check_int("seed", self.seed, 0))
        object.__setattr__(self, "kmax", check_int("kmax", self.kmax, 1, KMAX_SEARCH_MAX))
        object.__setattr__(self, "max_periods", check_int("max_periods", self.max_periods, 1, 1_000_000))
        object.__setattr__(self, "rtol", check_range("rtol", self.rtol, 1e-14, True, upper=1e-6))
        if not isinstance(self.nonperiodic, (bool, np.bool_)):
            raise ParameterError("nonperiodic", self.nonperiodic, "must be True or False")
        object.__setattr__(self, "nonperiodic", bool(self.nonperiodic))

    def grid(self) -> np.ndarray:
        """The frequencies [Hz] f_min + j Δf ≤ f_max (+ 1e-9 Δf)."""
        return grid_frequencies(self.fmin_hz, self.fmax_hz, self.df_hz)

    def to_dict(self) -> dict:
        return asdict(self)


@dataclass
class SystemLevel:
    """The attractors of one level: ``rows`` (one dict per stored attractor: ``i`` grid index,
    ``k`` (0: non-periodic), ``z`` SI state, ``mu`` multipliers (NaN: non-periodic), ``closure``,
    ``origin``, ``found_by``, ``basin``, ``strobe`` (k, 2n) SI, the measurement's ``columns``,
    ``type`` (periodic / chaotic / quasi-periodic), ``verdict`` (found by the verdict) and for a
    non-periodic one ``lyap``/``lyap_se`` (2n) [1/s]), ``links`` (row a, row b, jump) of
    consecutive points of a walk, ``traces`` (one dict per walk) and the grid ``f_hz``."""

    pa_newton: float
    f_hz: np.ndarray
    rows: list = field(default_factory=list)
    links: list = field(default_factory=list)
    traces: list = field(default_factory=list)


def sweep_system_level(system: System, pa_newton: float, settings: SystemSweepSettings, progress=None) -> SystemLevel:
    """The stable attractors of ``system`` at P_a = ``pa_newton`` [N] on the grid of ``settings``
    (module docstring). ``progress(points_done)`` after each grid point of the sweeps."""
    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a contactvib.model.System")
    if not isinstance(settings, SystemSweepSettings):
        raise ParameterError("settings", settings, "must be a SystemSweepSettings")
    pa, _f = check_excitation(pa_newton, settings.fmin_hz)
    walker = _Walker(system, pa, settings)
    walker.sweeps(progress)
    walker.searches()
    return _verdict_rows_last(walker.level)


def _verdict_rows_last(level: SystemLevel) -> SystemLevel:
    """``level`` with the rows of the verdict's attractors after the others (their order kept
    within each group; links renumbered): the periodic rows of periods ≤ kmax are stored as
    without the verdict."""
    order = sorted(range(len(level.rows)), key=lambda r: level.rows[r]["verdict"])
    new = {old: j for j, old in enumerate(order)}
    level.rows = [level.rows[r] for r in order]
    level.links = [(new[a], new[b], jump) for a, b, jump in level.links]
    return level


class _Walker:
    """The known orbits per grid point and the walks between them."""

    def __init__(self, system: System, pa: float, st: SystemSweepSettings):
        self.system, self.pa, self.st = system, pa, st
        self.level = SystemLevel(pa, st.grid())
        self.known: list[list[tuple]] = [[] for _ in self.level.f_hz]  # (k, scaled strobe points, row)
        self.clouds: list[list[tuple]] = [[] for _ in self.level.f_hz]  # (the verdict's record, row)
        self._arrays: dict = {}

    def arrays(self, i: int):
        """(SystemArrays, KernelForm) at grid point i."""
        if i not in self._arrays:
            form = self.system.kernel_form(self.pa, float(self.level.f_hz[i]))
            sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
            self._arrays[i] = (sa, form)
        return self._arrays[i]

    # ------------------------------------------------------------------ the walks
    def sweeps(self, progress) -> None:
        n = self.level.f_hz.size
        sc = self.arrays(0)[1].scales
        rest = sc.to_scaled(np.concatenate([self.system.static_state(), np.zeros(self.system.n)]))
        end = self.walk(0, None, rest, 0, +1, "sweep up", "sweep", False, progress)
        # from the up-sweep's orbit at f_max where it got there, else from rest
        _row, x, k = end if end is not None and self.level.rows[end[0]]["i"] == n - 1 else (None, rest, 0)
        self.walk(n - 1, None, x, k, -1, "sweep down", "sweep", False,
                  None if progress is None else (lambda j: progress(n + j)))

    def searches(self) -> None:
        from contactvib.steady.system_attractors import find_system_attractors

        st = self.st
        if st.search_every <= 0:
            return
        for i in range(0, self.level.f_hz.size, st.search_every):
            fe = float(self.level.f_hz[i])
            found = None
            for nonperiodic in dict.fromkeys((st.nonperiodic, False)):  # a failed verdict: the periodic search
                try:
                    found = find_system_attractors(self.system, self.pa, fe, n_starts=st.n_starts, seed=st.seed + i,
                                                   kmax=st.kmax, max_periods=st.max_periods, rtol=st.rtol,
                                                   nonperiodic=nonperiodic, seeds=False)
                    break
                except ComputationError:
                    continue
            if found is None:
                continue
            sc = self.arrays(i)[1].scales
            for a in found:
                if not a.stable:
                    continue
                if a.orbit is None or a.period > st.kmax:  # the verdict's: stored, not followed
                    try:
                        self.keep_verdict(i, a)
                    except ComputationError:  # its measurement failed: not stored
                        pass
                    continue
                x = sc.to_scaled(a.orbit.z)
                pts = np.array([sc.to_scaled(p) for p in a.strobe])
                if self.find(i, a.period, pts) is not None:
                    continue
                row = self.add(i, a.orbit, pts, "start", "multi-start", a.basin_fraction)
                for direction, label in ((+1, "up"), (-1, "down")):
                    self.walk(i + direction, row, x, a.period, direction, f"multi-start {fe:g} Hz {label}",
                              "multi-start", True, None)

    def walk(self, i, prev, x, k, direction, label, root, stop_known, progress):
        """Continue (x, k) from row ``prev`` (None: a start, ``k`` = 0: settle first) along the grid
        from index ``i`` in ``direction``; returns (row, x, k) at the last point reached or None."""
        n = self.level.f_hz.size
        f_start = float(self.level.f_hz[min(max(i, 0), n - 1)])
        stop, last, i0 = "grid end", None, i
        j = unsettled = 0
        chain = None  # the walk's non-periodic row at the previous grid point
        while 0 <= i < n:
            got = self.step(i, x, k)
            if got[0] == "unsettled":
                if stop_known or got[1] is None:  # a followed attractor is lost; a failed integration
                    stop = "lost (no period <= kmax settled)"
                    break
                if self.st.nonperiodic:  # the motion there judged; the sweep goes on from it unchanged
                    try:
                        row = self.judge(i, got[1], "start" if i == i0 else "jump", root)
                    except ComputationError:  # a refinement or measurement failed: nothing stored
                        row = None
                    if chain is not None and row is not None and self.level.rows[row]["k"] == 0 \
                            and self.level.rows[chain]["type"] == self.level.rows[row]["type"]:
                        self.link(chain, row, "newton")
                    chain = row if row is not None and self.level.rows[row]["k"] == 0 else None
                # the laboratory sweep goes on from where the motion is
                prev, x, k, unsettled, i = None, got[1], 0, unsettled + 1, i + direction
                continue
            chain = None
            how, orbit, pts = got
            row = self.find(i, orbit.k, pts)
            if row is None:
                row = self.add(i, orbit, pts, "start" if prev is None else how, root, math.nan)
            elif stop_known:
                self.link(prev, row, how)
                stop = "reached a known attractor"
                break
            self.link(prev, row, how)
            prev, x, k = row, pts[0], orbit.k
            last = (row, x, k)
            j += 1
            if progress is not None:
                progress(j)
            i += direction
        f_stop = float(self.level.f_hz[min(max(i - direction, 0), n - 1)])
        self.level.traces.append({"label": label, "direction": direction, "f_start_hz": f_start,
                                  "f_stop_hz": f_stop, "stop": stop, "root": root, "unsettled": unsettled})
        return last

    def link(self, a, b, how) -> None:
        if a is not None and a != b:
            self.level.links.append((a, b, int(how == "jump")))

    # ------------------------------------------------------------------ one grid point
    def step(self, i, x, k):
        """The attractor at grid point i reached from the scaled state x (period k of the previous
        point, 0: none): ("newton" | "jump", orbit, scaled strobe points), or ("unsettled", the
        state where the settling ended, or None where it failed)."""
        fe = float(self.level.f_hz[i])
        sa, form = self.arrays(i)
        sc = form.scales
        if k:
            try:
                orbit = periodic_orbit(self.system, self.pa, fe, sc.to_si(x), k)
                if orbit.stable:
                    return ("newton",) + self.least_period(i, orbit)
            except ComputationError:
                pass
        xs, ks = self.settle(sa, x)
        if not ks:
            return "unsettled", xs
        try:
            orbit = periodic_orbit(self.system, self.pa, fe, sc.to_si(xs), ks)
            orbit, pts = self.least_period(i, orbit)
        except ComputationError:
            return "unsettled", xs
        return ("jump", orbit, pts) if orbit.stable else ("unsettled", xs)

    def least_period(self, i, orbit):
        """(orbit, its k scaled strobe points) with k reduced to the least period."""
        sa, form = self.arrays(i)
        sc = form.scales
        pts = _strobes(sa, sc.to_scaled(orbit.z), orbit.k)
        for d in range(1, orbit.k):
            if orbit.k % d == 0 and _near(pts[0], pts[d:d + 1], SAME_TOL * 1e-2):
                orbit = periodic_orbit(self.system, self.pa, float(self.level.f_hz[i]), orbit.z, d)
                return orbit, _strobes(sa, sc.to_scaled(orbit.z), d)
        return orbit, pts

    def settle(self, sa, x):
        """Integrate period by period from x (compiled: ``system_settle.settle_start``, the search's own): (x, k) once
        the last k points repeat, else (the last state, 0), or (None, 0) where the integration fails."""
        from contactvib._kernels.system_settle import SETTLE_FAILED, SETTLE_PERIODIC, settle_start

        out = np.empty(x.size)
        how, k, _p = settle_start(sa, np.ascontiguousarray(x, dtype=float), self.st.kmax, self.st.max_periods,
                                  SETTLE_TOL, np.empty((0, x.size)), np.empty(0, np.int64), 0.0, self.st.rtol,
                                  np.zeros(1, np.int64), out)
        if how == SETTLE_FAILED or not np.all(np.isfinite(out)):
            return None, 0
        return out, int(k) if how == SETTLE_PERIODIC else 0

    def find(self, i, k, pts):
        """The row of the orbit known at grid point i that equals (k, pts), or None."""
        for kk, p, row in self.known[i]:
            if kk == k and _near(pts[0], p, SAME_TOL):
                return row
        return None

    def add(self, i, orbit, pts, origin, found_by, basin, verdict=False) -> int:
        """Measure and store a new orbit at grid point i; its row index (``verdict``: found by the
        verdict, a period above kmax)."""
        sa, form = self.arrays(i)
        columns, minima = measure_system_orbit(self.system, sa, form, orbit.z, orbit.k)
        row = len(self.level.rows)
        self.level.rows.append({"i": i, "k": orbit.k, "z": orbit.z, "mu": orbit.floquet_multipliers,
                                "closure": orbit.closure, "origin": origin, "found_by": found_by, "basin": basin,
                                "strobe": form.scales.to_si(pts.T).T, "minima": minima, "columns": columns,
                                "type": "periodic", "verdict": bool(verdict)})
        self.known[i].append((orbit.k, pts, row))
        return row

    # ------------------------------------------------------------------ the verdict's attractors
    def judge(self, i, x, origin, found_by):
        """The verdict (:func:`~contactvib.steady.system_verdict.judge_start`) on the scaled state x
        where a sweep settled on no period ≤ kmax at grid point i: the row of the attractor it lies
        on (stored when new: a chaotic or quasi-periodic cloud, an orbit of period above kmax), or
        None (unsettled)."""
        from contactvib.steady.system_verdict import judge_start

        sa, form = self.arrays(i)
        fe = float(self.level.f_hz[i])
        found, clouds = [], [c for c, _row in self.clouds[i]]
        hits = [c["hits"] for c in clouds]
        if judge_start(self.system, self.pa, fe, sa, form, x, self.st.kmax, self.st.rtol, found, clouds):
            return None
        if found:  # an orbit of period above kmax
            orbit, pts = found[0]["orbit"], found[0]["points"]
            row = self.find(i, orbit.k, pts)
            return row if row is not None else self.add(i, orbit, pts, origin, found_by, math.nan, verdict=True)
        for (c, row), h in zip(self.clouds[i], hits):
            if c["hits"] != h:  # on a cloud stored before
                return row
        return self.add_cloud(i, clouds[-1], origin, found_by, math.nan)

    def keep_verdict(self, i, a) -> None:
        """Store the search's attractor ``a`` at grid point i that its verdict found (non-periodic, or
        a period above kmax) unless it is known there."""
        from contactvib.steady.system_verdict import strobe_projection

        sa, form = self.arrays(i)
        pts = np.array([form.scales.to_scaled(p) for p in a.strobe])
        if a.orbit is not None:
            if self.find(i, a.period, pts) is None:
                self.add(i, a.orbit, pts, "start", "multi-start", a.basin_fraction, verdict=True)
            return
        cloud = strobe_projection(sa, pts)
        if any(same_cloud(c["cloud"], cloud) for c, _row in self.clouds[i]):
            return
        rec = {"kind": a.kind, "cloud": cloud, "spec": a.spectrum, "hits": a.hits, "points": pts}
        self.add_cloud(i, rec, "start", "multi-start", a.basin_fraction, (a.columns, np.asarray(a.strobe)))

    def add_cloud(self, i, rec, origin, found_by, basin, measured=None) -> int:
        """Store the non-periodic attractor ``rec`` (a verdict's record: "kind", projected "cloud",
        "spec", scaled strobe "points") at grid point i, measured over
        ``NONPERIODIC_MEASURE_PERIODS`` periods from its last strobe point unless ``measured`` =
        (columns, SI strobe points) is given; its row index."""
        from contactvib.steady.system_attractors import NONPERIODIC_MEASURE_PERIODS, orbit_columns

        form = self.arrays(i)[1]
        columns, strobe = measured if measured is not None else (None, form.scales.to_si(np.asarray(rec["points"]).T).T)
        if columns is None:
            columns, _m = orbit_columns(self.system, self.pa, float(self.level.f_hz[i]), strobe[-1],
                                        NONPERIODIC_MEASURE_PERIODS)
        n2 = 2 * self.system.n
        row = len(self.level.rows)
        self.level.rows.append({"i": i, "k": 0, "z": strobe[-1], "mu": np.full(n2, complex(math.nan, math.nan)),
                                "closure": math.nan, "origin": origin, "found_by": found_by, "basin": basin,
                                "strobe": strobe, "minima": -1, "columns": columns, "type": rec["kind"],
                                "verdict": True, "lyap": np.asarray(rec["spec"].exponents_per_s, float),
                                "lyap_se": np.asarray(rec["spec"].stderr_per_s, float)})
        self.clouds[i].append((rec, row))
        return row


def _near(x, points, tol) -> bool:
    return bool(np.any(np.max(np.abs(np.asarray(points) - x), axis=1) <= tol * max(1.0, float(np.max(np.abs(x))))))


def _strobes(sa, x, k) -> np.ndarray:
    """The k scaled stroboscopic points of the orbit through x (rtol 1e-12)."""
    pts, out, phi = [np.array(x, float)], np.empty(x.size), np.empty((0, 0))
    for _ in range(k - 1):
        if km.strobe_map(sa, np.ascontiguousarray(pts[-1]), 1, 1e-12, 1e-12, out, phi) != STATUS_OK:
            raise ComputationError("the stroboscopic points of an orbit", stage="integration")
        pts.append(out.copy())
    return np.array(pts)


def _record(sa, n, m, x, k):
    """Step records of k periods from the scaled state x at rtol 1e-12: (rec, rows)."""
    rows = 4096 * k
    while True:
        rec = np.empty((rows, rec_width(n, m)))
        nrec, st = km.record_span(sa, np.ascontiguousarray(x), int(k), 1e-12, 1e-12, rec, np.empty(x.size))
        if st == STATUS_RECORD_FULL:
            rows = 2 * int(nrec)
            continue
        if st != STATUS_OK:
            raise ComputationError("the measurement run of an orbit failed", stage="integration")
        return rec, int(nrec)


def _sample(rec, nrec, m, tau, n2):
    ys, modes = np.empty((n2, tau.size)), np.zeros((m, tau.size), dtype=np.bool_)
    km.sample_records(rec, nrec, m, tau, ys, modes)
    return ys, modes


def _refined_extremum(rec, nrec, m, n2, j, tau, s, sign, span):
    """The extremum (sign +1: maximum, −1: minimum) of coordinate j near the sample s of the
    cyclic grid ``tau``: two rounds of 33 dense-output samples about the best one."""
    h = tau[1] - tau[0]
    t0, best = tau[s], None
    for _ in range(2):
        t = np.mod(t0 + np.linspace(-h, h, 33), span)  # the orbit is periodic: wrap at its ends
        order = np.argsort(t)
        v = np.empty(t.size)
        v[order] = _sample(rec, nrec, m, t[order], n2)[0][j]
        q = int(np.argmax(sign * v))
        t0, best, h = t[q], v[q], h / 16.0
    return best


def _extremum(rec, nrec, m, n2, j, tau, v, sign, span) -> float:
    """The largest value of sign × coordinate j: every sampled local maximum of ``v`` (= sign ×
    the samples) within 1e-3 of the range of the sampled largest refined, the best kept."""
    top, rng = float(np.max(v)), float(np.ptp(v))
    peaks = np.flatnonzero((v >= np.roll(v, 1)) & (v >= np.roll(v, -1)) & (v >= top - 1e-3 * rng - 1e-300))
    return max(sign * _refined_extremum(rec, nrec, m, n2, j, tau, int(s), sign, span) for s in peaks[:16])


def measure_system_orbit(system: System, sa, form, z, k: int) -> tuple[dict, int]:
    """The ``dof``/``contact`` columns (the keywords of
    :func:`contactvib.steady.results.dofs_and_contacts`, display units) and the minima per period of
    the first contact's deflection (of the first coordinate without contacts) of the period-``k``
    orbit through the SI state ``z`` at phase 0 (module docstring)."""
    n, m = system.n, len(system.contacts)
    sc = form.scales
    rec, nrec = _record(sa, n, m, sc.to_scaled(z), k)
    span = k * form.tau_period
    tau = np.linspace(0.0, span, k * MEASURE_SAMPLES, endpoint=False)
    ys, modes = _sample(rec, nrec, m, tau, 2 * n)
    lo, hi = np.empty(n), np.empty(n)
    for j in range(n):
        lo[j] = -_extremum(rec, nrec, m, 2 * n, j, tau, -ys[j], -1.0, span)
        hi[j] = _extremum(rec, nrec, m, 2 * n, j, tau, ys[j], +1.0, span)
    factor = np.array([DISPLAY_UNITS[u][1] for u in system.units])
    q = ys[:n] * (sc.length * factor)[:, None]
    phase = np.exp(-1j * (2.0 * math.pi / form.tau_period) * tau)
    h1 = 2.0 * np.abs(q @ phase) / tau.size
    defl = system.directions[0] @ (ys[:n] * sc.length[:, None]) if m else q[0]
    minima = int(np.sum((defl < np.roll(defl, 1)) & (defl <= np.roll(defl, -1))))
    mean = np.empty(m)
    km.mean_element_forces(sa, rec, nrec, mean)
    open_ = ~modes
    columns = dict(dof_name=system.coordinates, dof_unit=tuple(DISPLAY_UNITS[u][0] for u in system.units),
                   dof_min=lo * sc.length * factor, dof_max=hi * sc.length * factor,
                   dof_app=(hi - lo) * sc.length * factor, dof_h1=h1,
                   contact_name=tuple(c.name for c in system.contacts),
                   contact_loses_contact=open_.any(axis=1), contact_loss_frac=open_.mean(axis=1),
                   contact_mean_force_n=mean * sc.force / span)
    return columns, minima
