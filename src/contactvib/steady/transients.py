"""Transients: how long a search must integrate, how much work that is, and whether a start
that found no period has reached a non-periodic attractor or has simply not settled yet.

Transient length
    In contact the linearised oscillator loses ``exp(−2π ζ / r)`` of its amplitude per
    excitation period (``r = f_e/f_n0``), so a start at distance ``a`` [y0] from its attractor
    needs ``n = ln(a / detect_tol) / (2π ζ / r)`` periods to come within the detection
    tolerance. :func:`transient_periods` takes twice that (free flights are undamped), at least
    :data:`MIN_TRANSIENT_PERIODS`.

Work
    The integrator takes about :data:`STEPS_PER_NATURAL_PERIOD` steps per natural period in
    contact, so ``max(1, 1/r)`` times that per excitation period, each about
    :data:`SECONDS_PER_STEP` on one core (:func:`estimated_seconds`). :func:`check_work` refuses
    a search whose step count is beyond :data:`WORK_MAX_STEPS` (about a quarter of an hour on two
    cores), naming both times and what reduces it (f_e, zeta, f_n0, the options).

Non-periodic or unsettled
    A start whose stroboscopic points found no period ``≤ kmax`` is a non-periodic attractor
    only when (i) its cloud is *recurrent*: the last window of :data:`WINDOW` strobe points
    lies in the window before it, point by point no farther from it than twice the typical
    spacing of points within a window (a transient drifts out of its earlier window; an
    attractor's cloud refills it) and keeps its spread (not below :data:`SPREAD_RATIO_MIN` of
    the window before: a spiral into a focus shrinks), and (ii) its largest Lyapunov exponent of the stroboscopic
    map is not negative (λ ≥ −:data:`~contactvib.labels.LYAPUNOV_ZERO`; a negative one
    means it is still converging, e.g. to an orbit of period above ``kmax``). Others are
    *unsettled* and are counted, not reported. The sweep (:mod:`contactvib.sweeps.verdict`) applies
    this rule, :func:`cloud_verdict`.

The search's verdict (:func:`search_verdict`, used by the attractor search and the basin map)
    A start without a period is followed :data:`VERDICT_PERIODS` periods further by Benettin's
    method (:func:`contactvib.steady.lyapunov.benettin`, :data:`VERDICT_BATCHES` batches), which
    gives its spectrum with standard errors. Then, with F = ``SIGMA_FACTOR`` = 3:

    * never in contact over that run (a free flight): *unsettled*;
    * a period kmax < k ≤ :data:`LONG_PERIOD_MAX` in the strobe sequence of the run's end, refined
      by Newton shooting to a stable orbit of that minimal period: *periodic* with its true period,
      however long (a start still converging onto an orbit of period ≤ kmax, which the settling
      would have found within a longer ``max_periods``, stays unsettled);
    * λ1 > F · stderr and a recurrent cloud (the strobe window at the run's end lies in the one
      before the run, as above): *chaotic*;
    * ``|λ1|`` ≤ F · stderr and the strobe points on closed curves
      (:func:`contactvib.steady.lyapunov.closed_curve`): *quasi-periodic*;
    * anything else (λ1 < −F · stderr without a period found, a drifting cloud): *unsettled*.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib._kernels.describe import NP_LYAPUNOV, lyapunov_strobe
from contactvib._kernels.settle import refine_stable_orbit
from contactvib.errors import ComputationError
from contactvib.model import ContactModel, Excitation, ParameterError
from contactvib.steady.lyapunov import LyapunovSpectrum, attractor_type, benettin, benettin_rows, closed_curve
from contactvib.steady.orbits import CLOSE_TOL, RTOL_REFINE

__all__ = ["transient_periods", "check_work", "check_damped", "cloud_verdict", "nonperiodic_verdict", "WINDOW",
           "MIN_TRANSIENT_PERIODS", "WORK_MAX_STEPS", "STEPS_PER_NATURAL_PERIOD", "LYAPUNOV_ZERO",
           "SECONDS_PER_STEP", "estimated_seconds", "duration_text", "search_verdict", "search_verdicts", "Verdict",
           "same_cloud", "VERDICT_PERIODS", "VERDICT_BATCHES", "LONG_PERIOD_MAX", "unsettled_cloud"]

#: Strobe points per window of the recurrence test (two windows are compared).
WINDOW = 64
#: Smallest automatic transient limit [excitation periods] (what a well-damped model gets).
MIN_TRANSIENT_PERIODS = 400
#: Integration steps per natural period in contact (measured: 18–20 for the Taylor flow).
STEPS_PER_NATURAL_PERIOD = 25.0
#: Largest search refused beyond: integration steps in all (~0.2 µs each per core).
WORK_MAX_STEPS = 1e10
#: Wall time of one integration step on one core [s] (~0.2 µs: the attractor search's rate).
SECONDS_PER_STEP = 2e-7
#: Largest Lyapunov exponent [1/period] separating the non-periodic types: below −LYAPUNOV_ZERO a
#: cloud is still converging, above +LYAPUNOV_ZERO it is chaotic (the 64-period estimate scatters
#: by about ±0.02 at the paper's attractors). The sweep's labels use the same threshold.
LYAPUNOV_ZERO = 0.02
#: Median distance of the last window from the one before, in units of the median spacing of
#: points within a window, up to which the cloud is recurrent.
RECURRENCE_RATIO = 2.0
#: Smallest ratio of the last window's spread (RMS distance from its centroid) to the one
#: before: a cloud spiralling into a focus with |μ| per period shrinks by |μ|^WINDOW (0.33 for
#: |μ| = 0.983, the paper's linear decay at 10 kHz); an attractor's cloud keeps its spread.
SPREAD_RATIO_MIN = 0.8
#: Periods of the search verdict's Benettin run, in batches for the error bar.
VERDICT_PERIODS = 2000
VERDICT_BATCHES = 10
#: Contact fraction of the verdict's run below which a start is in free flight (rounding of 1 − flight/total).
CONTACT_FRACTION_MIN = 1e-9
#: Longest period sought in the strobe sequence of a start without a period ≤ kmax.
LONG_PERIOD_MAX = 512
#: Relative return distance of a strobe point that proposes a long period to Newton's method.
LONG_PERIOD_TOL = 1e-3
#: Candidate long periods refined by Newton's method (the shortest returns first).
LONG_PERIOD_TRIES = 4


def transient_periods(excitation: Excitation, detect_tol: float, extent_y0: float) -> int:
    """Excitation periods for a start ``extent_y0`` [y0] away to settle within ``detect_tol``
    (relative), twice the linear decay time in contact; at least :data:`MIN_TRANSIENT_PERIODS`.
    ``zeta = 0`` gives the minimum (the caller refuses undamped models)."""
    zeta = excitation.model.zeta
    decay = 2.0 * math.pi * zeta / excitation.r  # amplitude decrement per period (log)
    if not decay > 0.0:
        return MIN_TRANSIENT_PERIODS
    n = 2.0 * math.log(max(extent_y0, 1.0) / detect_tol) / decay
    return int(max(MIN_TRANSIENT_PERIODS, math.ceil(min(n, 1e9))))


def steps_per_period(excitation: Excitation) -> float:
    """Estimated integration steps per excitation period."""
    return STEPS_PER_NATURAL_PERIOD * max(1.0, 1.0 / excitation.r)


def estimated_seconds(steps: float) -> float:
    """Wall time [s] of ``steps`` integration steps on this process's numba threads."""
    from numba import get_num_threads

    return float(steps) * SECONDS_PER_STEP / max(1, get_num_threads())


def duration_text(seconds: float) -> str:
    """``seconds`` in the unit a reader expects: "40 s", "8.2 min", "2.5 h", "3 days", "57 years"."""
    for unit, size in (("years", 3.156e7), ("days", 86400.0), ("h", 3600.0), ("min", 60.0)):
        if seconds >= 2.0 * size:
            return f"{seconds / size:.2g} {unit}"
    return f"{max(seconds, 1.0):.0f} s"


def check_work(excitation: Excitation, n_trajectories: int, n_periods: int,
               options: str = "--starts or --max-periods") -> float:
    """Refuse a computation of ``n_trajectories × n_periods`` excitation periods whose estimated
    step count exceeds :data:`WORK_MAX_STEPS` in one line (the steps and their factors, both
    times, and what reduces them: f_e, zeta, f_n0 and ``options``); return the estimate [steps]."""
    steps = float(n_trajectories) * float(n_periods) * steps_per_period(excitation)
    if steps > WORK_MAX_STEPS:
        m = excitation.model
        raise ParameterError(
            "f_e", f"{excitation.f_e:g} Hz",
            f"needs {steps:.2g} steps ({n_trajectories} trajectories × {n_periods:.3g} "
            f"periods × {steps_per_period(excitation):.3g} steps), about {duration_text(estimated_seconds(steps))} "
            f"here; at most {WORK_MAX_STEPS:.0e} steps (about {duration_text(estimated_seconds(WORK_MAX_STEPS))}) "
            f"are allowed: raise f_e or zeta, lower f_n0 = {m.f_n0:.6g} Hz, or reduce {options}")
    return steps


def check_damped(model: ContactModel, what: str) -> None:
    """Refuse an undamped model (h_n = 0) for an analysis that needs attractors."""
    if not model.zeta > 0.0:
        raise ParameterError(
            "h_n", model.h_n,
            f"must be > 0 for {what}: an undamped contact is conservative, its motions neither "
            f"settle nor have attractors (simulate works with h_n = 0)")


def _spacing(a: np.ndarray, b: np.ndarray, same: bool) -> np.ndarray:
    """Distance (max norm) of each row of ``a`` to the nearest row of ``b`` (not itself)."""
    d = np.max(np.abs(a[:, None, :] - b[None, :, :]), axis=2)
    if same:
        np.fill_diagonal(d, np.inf)
    return d.min(axis=1)


def unsettled_cloud(tail: np.ndarray) -> str | None:
    """Why the strobe points ``tail`` are not a settled cloud (too few, drifting, contracting),
    or None when they are recurrent and keep their spread."""
    if tail.shape[0] < 2 * WINDOW or not np.all(np.isfinite(tail)):
        return "too few strobe points"
    scale = np.ptp(tail, axis=0)
    scale = np.where(scale > 0.0, scale, 1.0)
    old, new = tail[:WINDOW] / scale, tail[WINDOW:] / scale
    spacing = max(float(np.median(_spacing(old, old, True))),
                  float(np.median(_spacing(new, new, True))), 1e-12)
    drift = max(float(np.median(_spacing(new, old, False))),
                float(np.median(_spacing(old, new, False))))
    if drift > RECURRENCE_RATIO * spacing:
        return "strobe cloud still drifting"
    spread_old = float(np.sqrt(np.mean(np.sum((old - old.mean(axis=0)) ** 2, axis=1))))
    spread_new = float(np.sqrt(np.mean(np.sum((new - new.mean(axis=0)) ** 2, axis=1))))
    if not spread_new >= SPREAD_RATIO_MIN * spread_old:
        return "strobe cloud still contracting"
    return None


def _lyapunov_verdict(lyapunov: float) -> tuple[bool, str]:
    if not math.isfinite(lyapunov):
        return False, "Lyapunov exponent not finite"
    if lyapunov < -LYAPUNOV_ZERO:
        return False, "still converging"
    return True, "chaotic" if lyapunov > LYAPUNOV_ZERO else "quasi-periodic"


def cloud_verdict(tail: np.ndarray, lyapunov: float) -> tuple[bool, str]:
    """Whether the strobe points ``tail`` (float[2·WINDOW, 2], oldest first, nondimensional) with
    largest Lyapunov exponent ``lyapunov`` [1/period] are a non-periodic attractor.

    Returns ``(True, "chaotic" | "quasi-periodic")`` or ``(False, reason)``.
    """
    why = unsettled_cloud(tail)
    return (False, why) if why else _lyapunov_verdict(lyapunov)


def nonperiodic_verdict(excitation: Excitation, tail: np.ndarray, rtol: float) -> tuple[bool, str, float]:
    """Whether a start without a period reached a non-periodic attractor: ``(ok, type or reason,
    λ)`` (:func:`cloud_verdict`; λ is computed, at integrator tolerance ``rtol``, only for a
    recurrent cloud)."""
    why = unsettled_cloud(tail)
    if why:
        return False, why, math.nan
    lyap = float(lyapunov_strobe(tail[-1].copy(), excitation.kernel_parameters(), rtol, NP_LYAPUNOV))
    return (*_lyapunov_verdict(lyap), lyap)


def same_cloud(a: np.ndarray, b: np.ndarray, frac: float = 0.05) -> bool:
    """Whether two strobe clouds (float[n, 2], NaN rows ignored) overlap: the median distance of
    each one's points to the other cloud is below ``frac`` of the larger extent."""
    a = a[np.isfinite(a[:, 0])]
    b = b[np.isfinite(b[:, 0])]
    if a.size == 0 or b.size == 0:
        return False
    extent = max(np.ptp(a, axis=0).max(), np.ptp(b, axis=0).max(), 1e-9)
    d_ab = np.min(np.max(np.abs(a[:, None, :] - b[None, :, :]), axis=2), axis=1)
    d_ba = np.min(np.max(np.abs(b[:, None, :] - a[None, :, :]), axis=2), axis=1)
    return bool(np.median(d_ab) < frac * extent and np.median(d_ba) < frac * extent)


@dataclass(frozen=True)
class Verdict:
    """What a start without a period ≤ kmax reached (:func:`search_verdict`).

    ``kind`` is "chaotic", "quasi-periodic", "periodic" or "unsettled" (``reason`` says why);
    ``spectrum`` the Benettin run's; for "periodic" ``period``, the refined orbit point ``z`` and
    its monodromy; ``cloud`` the strobe points after the run (nondimensional)."""

    kind: str
    reason: str
    spectrum: LyapunovSpectrum | None = None
    period: int = 0
    z: np.ndarray | None = None
    monodromy: np.ndarray | None = None
    residual: float = math.inf
    cloud: np.ndarray | None = None


def long_period(excitation: Excitation, pts: np.ndarray, kmin: int = 1):
    """A stable orbit of minimal period ``kmin`` ≤ k ≤ :data:`LONG_PERIOD_MAX` through the last of
    the strobe points ``pts`` (time order): the shortest returns k ≥ ``kmin`` within
    :data:`LONG_PERIOD_TOL` refined by Newton's method
    (:func:`~contactvib._kernels.settle.refine_stable_orbit`, minimal period); ``(k, z, M,
    residual)`` or None."""
    last = pts[-1]
    sc = max(1.0, float(np.max(np.abs(last))))
    kmax = min(LONG_PERIOD_MAX, pts.shape[0] - 1)
    d = np.max(np.abs(pts[-2:-kmax - 2:-1] - last), axis=1) / sc
    d[:kmin - 1] = np.inf
    par = excitation.kernel_parameters()
    for k in (np.flatnonzero(d < LONG_PERIOD_TOL)[:LONG_PERIOD_TRIES] + 1):
        oz, oM = np.empty(2), np.zeros((2, 2))
        ok, kk, res = refine_stable_orbit(last.copy(), int(k), par, RTOL_REFINE, CLOSE_TOL, oz, oM)
        if ok and kk >= kmin:
            return int(kk), oz, oM, float(res)
    return None


def search_verdict(excitation: Excitation, tail: np.ndarray, rtol: float, kmax: int = 0) -> Verdict:
    """The search's verdict on a start whose last strobe points are ``tail`` (nondimensional, time
    order, NaN rows allowed before the first) that found no period ≤ ``kmax`` while settling: the
    module's rule, integrator tolerance ``rtol``."""
    after = np.empty((2 * LONG_PERIOD_MAX + 1, 2))  # the run's last strobe points
    try:
        spec = benettin(excitation, tail[-1], VERDICT_PERIODS, VERDICT_BATCHES, 0, rtol, with_trace=False,
                        strobe=after)
    except ComputationError:
        spec = None
    return _verdict_of_run(excitation, tail, kmax, spec, after)


def search_verdicts(excitations, tails, rtol: float, kmax: int = 0) -> list[Verdict]:
    """:func:`search_verdict` of many starts (``tails[q]`` at ``excitations[q]``), their Benettin
    runs in one compiled call (:func:`contactvib.steady.lyapunov.benettin_rows`, on this process's
    numba threads); the same verdicts, in order."""
    if len(excitations) == 0:
        return []
    specs, after = benettin_rows(excitations, np.array([t[-1] for t in tails], float), VERDICT_PERIODS,
                                 VERDICT_BATCHES, rtol, strobe=2 * LONG_PERIOD_MAX + 1)
    return [_verdict_of_run(e, t, kmax, s, a) for e, t, s, a in zip(excitations, tails, specs, after)]


def _verdict_of_run(excitation: Excitation, tail: np.ndarray, kmax: int, spec: LyapunovSpectrum | None,
                    after: np.ndarray) -> Verdict:
    """The module's rule on the Benettin run ``spec`` (None: its integration failed) from ``tail[-1]``
    whose last strobe points are ``after``."""
    if spec is None:
        return Verdict("unsettled", "integration failed")
    if not spec.contact_fraction > CONTACT_FRACTION_MIN:
        return Verdict("unsettled", "free flight: no contact", spec)
    typ = attractor_type(spec)
    cloud = after[-2 * WINDOW:]
    if typ == "chaotic":
        before = tail[np.all(np.isfinite(tail), axis=1)][-WINDOW:]
        why = unsettled_cloud(np.vstack([before, after[-WINDOW:]])) if before.shape[0] == WINDOW else None
        return Verdict("unsettled", why, spec) if why else Verdict("chaotic", "λ1 > 3 stderr", spec, cloud=cloud)
    found = long_period(excitation, after, kmax + 1)
    if found is not None:
        k, z, M, res = found
        return Verdict("periodic", f"period {k}", spec, k, z, M, res)
    if typ == "quasi-periodic" and closed_curve(after) > 0:
        return Verdict("quasi-periodic", "closed curve, |λ1| ≤ 3 stderr", spec, cloud=cloud)
    return Verdict("unsettled", "still converging" if typ == "converging" else "no period, not a torus", spec)
