"""The attractors of a :class:`~contactvib.model.system.System` at one operating point: a
multi-start search.

Starts are drawn in a box about the static state (q_s, 0) in the scaled state of the compiled form
(``contactvib.model.system_kernel``: each coordinate in its length L_j, set by the contacts' static
deflections, each rate in L_j ω): half-widths of 2, or 1.5 times the linear response to the force
where that is larger; before them, the ballistic seeds (free flights of one and two periods under
the static load, :mod:`.system_starts`) reach the large orbits that lose contact, which such a box
cannot. Basin fractions count the box starts only. Each start is settled by integrating period by
period until its stroboscopic points repeat with a period k ≤ kmax (every one of the last k points
within ``settle_tol`` of the point k periods before it, relative to max(1, |x|∞)) or it comes
within ``capture_tol`` of a stable orbit already found; a detected orbit is refined by Newton
shooting (:func:`~contactvib.steady.system_orbits.periodic_orbit`), which gives its Floquet
multipliers. Equal orbits (the same period and a common stroboscopic point within ``SAME_TOL``) are
grouped.

A start that settles on no period ≤ kmax within ``max_periods`` periods is judged as the 1-DOF
search judges one (:mod:`.system_verdict`): periodic with a long period, chaotic, quasi-periodic,
or unsettled with its reason (counted in ``unsettled_reasons``); non-periodic attractors reached
by several starts are merged and get a basin fraction like periodic ones.
A start whose orbit Newton's method cannot refine is unsettled ("Newton failed").

Each attractor is measured on ``MEASURE_SAMPLES`` samples per period of its orbit (extrema to
about 3e-5 of the range), its mean contact forces by Gauss–Legendre quadrature on every
integration step (:func:`~contactvib.steady.system_orbits.mean_contact_forces`); a non-periodic
one likewise over ``NONPERIODIC_MEASURE_PERIODS`` periods from its last strobe point.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numba
import numpy as np

from contactvib._kernels import system_settle as ks
from contactvib._kernels.status import SETTLE_CAPTURED, SETTLE_FAILED, SETTLE_INTERRUPTED, SETTLE_PERIODIC
from contactvib._kernels.system_flow import system_arrays
from contactvib.errors import ComputationError
from contactvib.interrupts import new_stop_flag, run_interruptible
from contactvib.model import ParameterError, check_int, check_range
from contactvib.model.checks import KMAX_SEARCH_MAX
from contactvib.model.system import System, check_excitation
from contactvib.steady.lyapunov import LyapunovSpectrum
from contactvib.steady.results import dofs_and_contacts, lyapunov_fields
from contactvib.steady.system_orbits import (
    DISPLAY_UNITS,
    SystemOrbit,
    mean_contact_forces,
    simulate_system,
)
from contactvib.steady.system_starts import box_starts, seed_states, start_box
from contactvib.steady.system_verdict import SAME_TOL, add_orbit, judge_start, same_orbit_index, settled_orbit

__all__ = ["SystemAttractor", "SystemAttractorSet", "find_system_attractors", "check_system_search",
           "default_max_periods", "orbit_columns", "start_box", "settled_orbit", "same_orbit_index",
           "measure_attractor", "check_bounded",
           "SAME_TOL", "MEASURE_SAMPLES", "STARTS_DEFAULT", "MAX_PERIODS_DEFAULT", "NONPERIODIC_MEASURE_PERIODS"]

#: Samples per excitation period of the measured orbit.
MEASURE_SAMPLES = 512
#: Defaults of the search: random starts, least transient limit [periods] (``default_max_periods``),
#: the limit's largest default.
STARTS_DEFAULT = 64
MAX_PERIODS_DEFAULT = 400
MAX_PERIODS_AUTO_MAX = 20_000
#: Largest number of starts and of periods per start.
STARTS_MAX = 100_000
MAX_PERIODS_MAX = 1_000_000
#: Periods over which a non-periodic attractor's ranges and mean contact forces are measured.
NONPERIODIC_MEASURE_PERIODS = 64


@dataclass(frozen=True, eq=False)
class SystemAttractor:
    """An attractor of a system; displacements in display units (µm, µrad).

    Attributes
    ----------
    orbit : SystemOrbit or None
        The refined orbit (SI state at phase 0, monodromy, multipliers) of a periodic attractor;
        None for a chaotic or quasi-periodic one.
    strobe : ndarray (k, 2n)
        Its stroboscopic points [SI] (a non-periodic one: the last 2·WINDOW of its verdict's run).
    minima_per_period : int
        Local minima of the first contact's deflection (of the first coordinate without a contact)
        over one period of the orbit (0 for a non-periodic attractor).
    basin_fraction : float
        Fraction of the starts that settled on it.
    hits : int
        Starts that settled on it.
    columns : dict
        The keyword arguments of :func:`~contactvib.steady.results.dofs_and_contacts` (a
        non-periodic attractor: over ``NONPERIODIC_MEASURE_PERIODS`` periods).
    fe_hz : float
        The excitation frequency [Hz] (for the exponents per second).
    kind : str
        "periodic", "quasi-periodic" or "chaotic".
    spectrum : LyapunovSpectrum or None
        The Benettin spectrum of a non-periodic attractor's verdict (None for a periodic one).

    Its JSON carries ``attractor_type``, ``lyapunov_per_s`` (descending: ln ``|μ_i|`` / (k T) of a
    periodic one, Benettin's of the others), ``lyapunov_stderr_per_s`` (zeros for a periodic one)
    and ``kaplan_yorke_dimension`` (a chaotic one's; null for the others).
    """

    orbit: SystemOrbit | None
    strobe: np.ndarray
    minima_per_period: int
    basin_fraction: float
    hits: int
    columns: dict
    fe_hz: float = math.nan
    kind: str = "periodic"
    spectrum: LyapunovSpectrum | None = None

    @property
    def period(self) -> int:
        """The period k [excitation periods]; 0 for a non-periodic attractor."""
        return self.orbit.k if self.orbit is not None else 0

    @property
    def state(self) -> np.ndarray:
        """An SI state (q, q̇) at phase 0 on the attractor."""
        return self.orbit.z if self.orbit is not None else self.strobe[-1]

    @property
    def floquet_multipliers(self) -> np.ndarray:
        return self.orbit.floquet_multipliers if self.orbit is not None else np.empty(0, complex)

    @property
    def floquet_abs_max(self) -> float:
        return float(np.max(np.abs(self.orbit.floquet_multipliers))) if self.orbit is not None else math.nan

    @property
    def stable(self) -> bool:
        """Floquet stability of a periodic attractor; True for a non-periodic one (an attractor)."""
        return self.orbit.stable if self.orbit is not None else True

    @property
    def attractor_type(self) -> str:
        """"periodic", "quasi-periodic" or "chaotic"."""
        return self.kind

    @property
    def lyapunov_per_s(self) -> np.ndarray:
        """The 2n exponents [1/s], descending: ln ``|μ_i|`` / (k T) of the Floquet multipliers
        (T = 1/f_e), or the Benettin run's."""
        if self.orbit is None:
            return self.spectrum.exponents_per_s
        with np.errstate(divide="ignore"):
            return np.sort(np.log(np.abs(self.floquet_multipliers)) * self.fe_hz / self.period)[::-1]

    @property
    def lyapunov_stderr_per_s(self) -> np.ndarray:
        """Standard errors [1/s] of :attr:`lyapunov_per_s` (0 for Floquet exponents)."""
        return self.spectrum.stderr_per_s if self.orbit is None else np.zeros(self.lyapunov_per_s.size)

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib attractors --system ... --json`` for this attractor
        (``period``, ``floquet_*``, ``stable`` and ``closure`` null for a non-periodic one)."""
        periodic = self.orbit is not None
        lyap = lyapunov_fields(self.kind, self.lyapunov_per_s, self.lyapunov_stderr_per_s)
        if self.kind != "chaotic":  # λ1 = 0 within its error bar (a torus) is not a positive λ1
            lyap["kaplan_yorke_dimension"] = None
        return {"period": int(self.period) if periodic else None,
                "minima_per_period": int(self.minima_per_period) if periodic else None,
                "floquet_multipliers": [[float(m.real), float(m.imag)] for m in self.floquet_multipliers]
                if periodic else None,
                "floquet_abs_max": self.floquet_abs_max if periodic else None,
                "stable": bool(self.stable) if periodic else None,
                "basin_fraction": float(self.basin_fraction), "hits": int(self.hits),
                "closure": float(self.orbit.closure) if periodic else None,
                **lyap, **dofs_and_contacts(**self.columns)}


@dataclass(frozen=True, eq=False)
class SystemAttractorSet:
    """All attractors found at one operating point, largest first-coordinate range first.

    Attributes
    ----------
    attractors : tuple of SystemAttractor
    natural_frequencies_hz : ndarray (n,)
        :meth:`System.linear_modes`.
    pa_newton, fe_hz : float
        The excitation P_a [N], f_e [Hz].
    n_starts, n_unsettled, n_failed : int
        Starts; those that settled on no attractor (the verdict's "unsettled"); those whose
        integration failed.
    settings : dict
        The search's settings.
    unsettled_reasons : dict
        Unsettled starts counted by the verdict's reason.
    """

    attractors: tuple
    natural_frequencies_hz: np.ndarray
    pa_newton: float
    fe_hz: float
    n_starts: int
    n_unsettled: int
    n_failed: int
    settings: dict = field(default_factory=dict)
    unsettled_reasons: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.attractors)

    def __iter__(self):
        return iter(self.attractors)

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib attractors --system ... --json``."""
        return {"natural_frequencies_hz": [float(f) for f in self.natural_frequencies_hz],
                "pa_newton": float(self.pa_newton), "fe_hz": float(self.fe_hz), "n_starts": int(self.n_starts),
                "n_unsettled": int(self.n_unsettled), "n_failed": int(self.n_failed),
                "unsettled_fraction": self.n_unsettled / max(self.n_starts, 1),
                "n_seeds": int(self.settings.get("n_seeds", 0)),
                "unsettled_reasons": {str(k): int(v) for k, v in self.unsettled_reasons.items()},
                "max_periods": int(self.settings.get("max_periods", 0)),
                "units": {"m": "um", "rad": "urad", "force": "N", "f": "Hz"},
                "attractors": [a.to_dict() for a in self.attractors]}

    def to_json(self, **kw) -> str:
        return json.dumps(self.to_dict(), **kw)


def default_max_periods(system: System, fe_hz: float, settle_tol: float = 1e-7) -> int:
    """The transient limit [periods]: 1.5 times the periods the slowest mode of the system
    linearised at its static state (contacts engaged there with their stiffness and damping)
    takes to decay by ``settle_tol``; a growing mode (negative damping: a self-excited system,
    whose contacts must limit the growth) counts with its growth rate, the time it takes to grow
    by 1/``settle_tol``; at least ``MAX_PERIODS_DEFAULT``, at most ``MAX_PERIODS_AUTO_MAX`` (also
    for an undamped mode)."""
    qs = system.static_state()
    n = system.n
    Kt = system.tangent_stiffness(qs)
    Ct = np.array(system.C) + sum((c.damping_rate(c.deflection(qs)) * np.outer(c.w, c.w) for c in system.contacts),
                                  np.zeros((n, n)))
    Minv = np.linalg.inv(system.M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ Kt, -Minv @ Ct]])
    rates = -np.real(np.linalg.eigvals(A))
    sigma = float(np.min(rates))
    if sigma < 0.0:  # growth at −sigma; the slowest decaying mode still counts
        sigma = min(-sigma, float(np.min(rates[rates > 0.0], initial=math.inf)))
    if not sigma > 0.0:
        return MAX_PERIODS_AUTO_MAX
    periods = 1.5 * math.log(1.0 / settle_tol) * fe_hz / sigma
    return int(min(MAX_PERIODS_AUTO_MAX, max(MAX_PERIODS_DEFAULT, math.ceil(periods))))


def check_system_search(n_starts=STARTS_DEFAULT, seed=0, kmax=8, max_periods=MAX_PERIODS_DEFAULT) -> tuple:
    """The search's settings, checked: (n_starts, seed, kmax, max_periods)."""
    return (check_int("n_starts", n_starts, 1, STARTS_MAX), check_int("seed", seed, 0),
            check_int("kmax", kmax, 1, KMAX_SEARCH_MAX), check_int("max_periods", max_periods, 1, MAX_PERIODS_MAX))


_start_box = box_starts  # the search's random starts (tests call it by this name)


def _capture(found: list) -> tuple[np.ndarray, np.ndarray]:
    """The stroboscopic points of the stable orbits found (rows) and their indices in ``found``."""
    caps = [(i, f["points"]) for i, f in enumerate(found) if f["orbit"].stable]
    if not caps:
        return np.empty((0, 0)), np.empty(0, np.int64)
    return np.concatenate([p for _, p in caps]), np.concatenate([np.full(len(p), i, np.int64) for i, p in caps])


def _settled(sa, starts: np.ndarray, found: list, kmax, max_periods, tol, rtol):
    """Each start settled period by period (:func:`.system_settle.settle_start`), in order:
    ("periodic", k, x), ("captured", index in ``found``, x), ("unsettled", 0, x) or ("failed", 0, x).

    Start j is captured by the stable orbits in ``found`` when it is taken, as if the starts were
    settled one after another; the starts run in batches on the numba threads, and the rest of a
    batch is settled again when the caller has added a stable orbit in the meantime. The kernel
    runs in a helper thread (:func:`contactvib.interrupts.run_interruptible`): Ctrl-C ends it
    within one excitation period."""
    names = {SETTLE_PERIODIC: "periodic", SETTLE_CAPTURED: "captured", SETTLE_FAILED: "failed"}
    threads = numba.get_num_threads()
    j, batch, stop = 0, threads, new_stop_flag()
    while j < len(starts):
        pts, ids = _capture(found)
        how, kk, xs, _n = run_interruptible(ks.settle_starts, sa, starts[j:j + batch], kmax, max_periods, tol,
                                            pts.reshape(-1, starts.shape[1]), ids, 1e-4, rtol, stop, stop=stop)
        if (how == SETTLE_INTERRUPTED).any():
            raise KeyboardInterrupt
        for q in range(len(how)):
            if len(_capture(found)[1]) != len(ids):
                batch = threads  # a new stable orbit: settle the rest again with it
                break
            j += 1
            yield names.get(int(how[q]), "unsettled"), int(kk[q]), xs[q]
        else:  # batches grow while no orbit is new (on one thread: one start at a time)
            batch = min(2 * batch, 8 * threads) if threads > 1 else 1


def find_system_attractors(system: System, pa_newton: float, fe_hz: float, *, n_starts: int = STARTS_DEFAULT,
                           seed: int = 0, kmax: int = 8, max_periods: int | None = None,
                           settle_tol: float = 1e-7, rtol: float = 1e-10, progress=None,
                           nonperiodic: bool = True, seeds: bool = True) -> SystemAttractorSet:
    """The attractors of ``system`` under P_a cos(2π f_e t) by a multi-start search.

    Parameters
    ----------
    system : System
    pa_newton, fe_hz : float
        P_a [N] ≥ 0, f_e [Hz] > 0.
    n_starts, seed : int
        Random starts in the box (module docstring) and the generator's seed.
    kmax : int
        Largest period [excitation periods] detected while settling (1..64).
    max_periods : int, optional
        Transient limit per start [periods]; default :func:`default_max_periods`.
    settle_tol : float
        Relative repetition of the stroboscopic points that counts as settled.
    rtol : float
        Integrator tolerance while settling and in the verdict (Newton refines at 1e-12).
    progress : callable, optional
        ``progress(done, total)`` after each start (and once with 0 before the first).
    nonperiodic : bool
        Judge the starts without a period ≤ kmax (the module's verdict: long periods, chaotic and
        quasi-periodic attractors); False: count them unsettled ("no period <= kmax") and report
        periodic attractors only (the continuation's seeds, the system sweeps without their
        ``nonperiodic`` setting).
    seeds : bool
        Also start from the ballistic seeds (:func:`~contactvib.steady.system_starts.seed_states`:
        free flights of one and two periods under the static load), first; an attractor only a
        seed reaches has basin fraction 0 (the basins count the box starts).
    """
    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a contactvib.model.System")
    pa, fe = check_excitation(pa_newton, fe_hz)
    settle_tol = check_range("settle_tol", settle_tol, 0.0, False, upper=1e-3)
    if max_periods is None:
        max_periods = default_max_periods(system, fe, settle_tol)
    n_starts, seed, kmax, max_periods = check_system_search(n_starts, seed, kmax, max_periods)
    rtol = check_range("rtol", rtol, 1e-14, True, upper=1e-6)
    check_bounded(system)
    form = system.kernel_form(pa, fe)
    sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
    found: list[dict] = []
    clouds: list[dict] = []
    reasons: dict = {}
    seed_x = seed_states(system, form, fe) if seeds else np.empty((0, 2 * system.n))
    n_seeds, total = len(seed_x), n_starts + len(seed_x)
    if progress is not None:
        progress(0, total)

    def tick(j):
        if progress is not None:
            progress(j, total)

    judge = (lambda x: judge_start(system, pa, fe, sa, form, x, kmax, rtol, found, clouds)) if nonperiodic else None
    _run_starts(system, pa, fe, sa, form, seed_x, found, {}, judge, (kmax, max_periods, settle_tol, rtol), tick)
    for rec in (*found, *clouds):  # the basins count the box starts only
        rec["hits"] = 0
    n_failed = _run_starts(system, pa, fe, sa, form, box_starts(system, form, pa, fe, n_starts, seed), found, reasons,
                           judge, (kmax, max_periods, settle_tol, rtol), lambda j: tick(n_seeds + j))
    attractors = [measure_attractor(system, pa, fe, f, n_starts) for f in found]
    attractors += [_measure_cloud(system, pa, fe, c, n_starts) for c in clouds]
    attractors.sort(key=lambda a: -a.columns["dof_app"][0])
    return SystemAttractorSet(attractors=tuple(attractors), natural_frequencies_hz=system.linear_modes(),
                              pa_newton=pa, fe_hz=fe, n_starts=n_starts, n_unsettled=sum(reasons.values()),
                              n_failed=n_failed,
                              settings={"n_starts": n_starts, "seed": seed, "kmax": kmax, "max_periods": max_periods,
                                        "settle_tol": settle_tol, "rtol": rtol, "nonperiodic": bool(nonperiodic),
                                        "n_seeds": n_seeds},
                              unsettled_reasons=dict(sorted(reasons.items())))


def _run_starts(system, pa, fe, sa, form, starts, found: list, reasons: dict, judge, knobs, tick) -> int:
    """Settle ``starts`` (scaled rows) and count each on an orbit of ``found`` (a new one added),
    or by ``judge(x)`` (None: on an attractor; else the reason it is unsettled, counted in
    ``reasons``; ``judge`` None: "no period <= kmax"); ``knobs`` = (kmax, max_periods, settle_tol,
    rtol); ``tick(j)`` after start j. Returns the starts whose integration failed."""
    kmax, max_periods, settle_tol, rtol = knobs
    n_failed = 0
    for j, (how, k, x) in enumerate(_settled(sa, starts, found, kmax, max_periods, settle_tol, rtol)):
        try:
            if how == "failed":
                raise ComputationError("the settling of a start failed", stage="integration")
            if how == "captured":
                found[k]["hits"] += 1
            elif how == "unsettled":
                why = judge(x) if judge is not None else "no period <= kmax"
                if why:
                    reasons[why] = reasons.get(why, 0) + 1
            else:
                add_orbit(system, pa, fe, sa, form, x, k, found)
        except ComputationError as e:
            if e.stage == "newton":
                reasons["Newton failed"] = reasons.get("Newton failed", 0) + 1
            else:
                n_failed += 1
        tick(j + 1)
    return n_failed


def check_bounded(system: System) -> None:
    """Refuse a system whose motion cannot be bounded: a mode of M q̈ + C q̇ + K q = 0 that grows
    (negative damping: a self-excited coordinate) and that no contact acts on — its left
    eigenvector ψ has no component along any contact's force direction M⁻¹ w_i, so no contact
    force can limit its growth (a system without contacts: every growing mode)."""
    n = system.n
    Minv = np.linalg.inv(np.array(system.M, float))
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-Minv @ np.array(system.K, float), -Minv @ np.array(system.C, float)]])
    lam, left = np.linalg.eig(A.T)
    forces = [Minv @ np.asarray(c.direction, float) for c in system.contacts]
    for j in np.flatnonzero(lam.real > 1e-12 * max(1.0, float(np.max(np.abs(lam))))):
        psi = left[n:, j]
        if not any(abs(psi @ f) > 1e-9 * np.linalg.norm(psi) * np.linalg.norm(f) for f in forces):
            raise ParameterError(
                "system.damping", f"{np.diag(system.C).tolist()} N s/m on the diagonal",
                f"gives a mode growing at {lam[j].real:.3g} 1/s ({abs(lam[j].imag) / (2 * math.pi):.4g} Hz) that "
                f"{'no contact acts on' if forces else 'no contact limits (there is none)'}: it grows without bound "
                f"and has no attractor; add a contact in its direction or make its damping positive")


def _minima(d: np.ndarray) -> int:
    """Local minima of a cyclic sample (strict on the left, the right may be level)."""
    return int(np.sum((d < np.roll(d, 1)) & (d <= np.roll(d, -1))))


def orbit_columns(system: System, pa: float, fe: float, z, k: int) -> tuple[dict, int]:
    """The columns of :func:`~contactvib.steady.results.dofs_and_contacts` of the period-``k``
    orbit through the SI state ``z`` at P_a [N], f_e [Hz] (``MEASURE_SAMPLES`` samples per period),
    and the local minima per period of the first contact's deflection (of the first coordinate
    without a contact)."""
    n = system.n
    z = np.asarray(z, float)
    h = simulate_system(system, pa, fe, z[:n], z[n:], n_periods=k, samples_per_period=MEASURE_SAMPLES,
                        rtol=1e-12)
    q = h.q[:, :-1]
    t = h.t_ms[:-1] * 1e-3
    h1 = 2.0 * np.abs(q @ np.exp(-2j * math.pi * fe * t)) / t.size
    si = q / np.array([DISPLAY_UNITS[u][1] for u in system.units])[:, None]
    minima = _minima(system.directions[0] @ si if system.contacts else si[0])
    open_ = ~h.in_contact[:, :-1]
    mean_f = mean_contact_forces(system, pa, fe, z, k)
    cols = dict(dof_name=system.coordinates, dof_unit=h.q_units, dof_min=q.min(axis=1), dof_max=q.max(axis=1),
                dof_app=np.ptp(q, axis=1), dof_h1=h1, contact_name=h.contacts,
                contact_loses_contact=open_.any(axis=1), contact_loss_frac=open_.mean(axis=1),
                contact_mean_force_n=mean_f)
    return cols, minima


def measure_attractor(system: System, pa: float, fe: float, f: dict, n_starts: int) -> SystemAttractor:
    """The attractor of the record ``f`` ("orbit", scaled "points", "hits"), its basin fraction
    ``hits / n_starts``, measured on its orbit (:func:`orbit_columns`)."""
    orbit = f["orbit"]
    cols, minima = orbit_columns(system, pa, fe, orbit.z, orbit.k)
    return SystemAttractor(orbit=orbit, strobe=_points_si(f["points"], system, pa, fe), minima_per_period=minima,
                           basin_fraction=f["hits"] / n_starts, hits=f["hits"], columns=cols, fe_hz=fe)


def _measure_cloud(system: System, pa: float, fe: float, c: dict, n_starts: int) -> SystemAttractor:
    """A non-periodic attractor measured over NONPERIODIC_MEASURE_PERIODS periods from its last
    strobe point."""
    strobe = _points_si(c["points"], system, pa, fe)
    cols, _ = orbit_columns(system, pa, fe, strobe[-1], NONPERIODIC_MEASURE_PERIODS)
    return SystemAttractor(orbit=None, strobe=strobe, minima_per_period=0, basin_fraction=c["hits"] / n_starts,
                           hits=c["hits"], columns=cols, fe_hz=fe, kind=c["kind"], spectrum=c["spec"])


def _points_si(points: np.ndarray, system: System, pa: float, fe: float) -> np.ndarray:
    """Scaled stroboscopic points (rows) in SI."""
    sc = system.kernel_form(pa, fe).scales
    return np.array([sc.to_si(p) for p in points])
