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
    *unsettled* and are counted, not reported.
"""

from __future__ import annotations

import math

import numpy as np

from contactvib._kernels.describe import NP_LYAPUNOV, lyapunov_strobe
from contactvib.model import ContactModel, Excitation, ParameterError

__all__ = ["transient_periods", "check_work", "check_damped", "cloud_verdict", "nonperiodic_verdict", "WINDOW",
           "MIN_TRANSIENT_PERIODS", "WORK_MAX_STEPS", "STEPS_PER_NATURAL_PERIOD", "LYAPUNOV_ZERO",
           "SECONDS_PER_STEP", "estimated_seconds", "duration_text"]

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


def _unsettled_cloud(tail: np.ndarray) -> str | None:
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
    why = _unsettled_cloud(tail)
    return (False, why) if why else _lyapunov_verdict(lyapunov)


def nonperiodic_verdict(excitation: Excitation, tail: np.ndarray, rtol: float) -> tuple[bool, str, float]:
    """Whether a start without a period reached a non-periodic attractor: ``(ok, type or reason,
    λ)`` (:func:`cloud_verdict`; λ is computed, at integrator tolerance ``rtol``, only for a
    recurrent cloud)."""
    why = _unsettled_cloud(tail)
    if why:
        return False, why, math.nan
    lyap = float(lyapunov_strobe(tail[-1].copy(), excitation.kernel_parameters(), rtol, NP_LYAPUNOV))
    return (*_lyapunov_verdict(lyap), lyap)
