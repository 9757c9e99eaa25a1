"""Coexisting attractors at one operating point (P_a, f_e): multi-start search.

Procedure
---------
1. Starts: ``n_starts`` states drawn uniformly (fixed seed) from a box around the static
   equilibrium scaled by y0 and the excitation, ``x = y/y0 ∈ [1 − a, 1 + a]``,
   ``x' = ẏ/(y0 ω_n0) ∈ [−a, a]`` with ``a = 2 + 10 P_a/Q``; plus deterministic *ballistic
   seeds* that a y0-scaled box cannot reach: take-off from ``y = 0`` upwards with the speed
   that gives a free flight of ``j`` excitation periods (``ẏ = −j g T / 2`` times 0.5, 0.75,
   1), at four phases. They find the open primary branch at low frequency (flights of hundreds
   of µm) and the period-j "bouncing" orbits at high frequency.
2. Every start is integrated in parallel (numba threads) until its stroboscopic points near a
   cycle of period ``k ≤ kmax``; the cycle is refined by Newton shooting and accepted when it
   closes to 1e-10, is stable and has no shorter period (:mod:`contactvib._kernels.settle`).
3. Orbits are de-duplicated by the sameness rule (same period, stroboscopic sets equal to 1e-6
   relative in some cyclic order). A start that finds no period within ``max_periods`` (by
   default long enough for the linear decay in contact, :func:`.transients.transient_periods`)
   is judged by its Lyapunov spectrum over 2000 further periods (:func:`.transients.search_verdict`):
   a stable orbit of period kmax < k ≤ 512 in its strobe sequence is periodic (its true period); chaotic
   when λ1 > 3 standard errors and its cloud is recurrent; quasi-periodic when ``|λ1|`` ≤ 3 standard
   errors and its section is a closed curve; otherwise (a free flight that never touches the
   contact, still converging, drifting) it is *unsettled*: counted in ``n_unsettled``, with an
   ``UnsettledWarning``, never reported as an attractor. Non-periodic attractors are
   de-duplicated by the overlap of their clouds.
4. Two waves: the first ``FIRST_WAVE`` box starts and the seeds run to the end (step 2); the
   other box starts are stopped as soon as a stroboscopic point comes within ``capture_tol``
   (relative) of a strobe point of a stable periodic orbit found by the first wave, and are
   counted for that orbit without another Newton refinement. Starts that are not captured run
   to the end as in step 2, so attractors the first wave missed are still found.
5. The basin fraction of an attractor is the share of the *box* starts that reached it.

The starts run in a helper thread (:func:`contactvib.interrupts.run_interruptible`), so that
Ctrl-C ends the search within one excitation period of integration; a search estimated
beyond :data:`.transients.WORK_MAX_STEPS` steps is refused before it starts, and an undamped
model (h_n = 0) is refused: it has no attractors.
"""

from __future__ import annotations

import warnings

import numpy as np

from contactvib._kernels.settle import settle_capture_many
from contactvib._kernels.status import SETTLE_CAPTURED, SETTLE_NONPERIODIC, SETTLE_PERIODIC
from contactvib.call_forms import old_form
from contactvib.interrupts import new_stop_flag, run_interruptible
from contactvib.model import (
    CAPTURE_TOL_MAX,
    KMAX_SEARCH_MAX,
    Excitation,
    check_excitation,
    check_int,
    check_range,
)
from contactvib.model.checks import MEMORY_MAX, check_memory
from contactvib.steady.orbits import CLOSE_TOL, RTOL_REFINE, describe_orbit, same_orbit, strobe_points
from contactvib.steady.results import AttractorSet
from contactvib.steady.transients import (
    WINDOW,
    check_damped,
    check_work,
    estimated_seconds,
    same_cloud,
    search_verdict,
    transient_periods,
)

__all__ = ["find_attractors", "check_search", "start_box", "box_half_width", "ballistic_seeds",
           "default_max_periods", "settle_starts", "group_outcomes", "same_cloud", "UnsettledWarning"]

#: Box starts of the first wave, which run to the end and supply the capture points.
FIRST_WAVE = 64


class UnsettledWarning(RuntimeWarning):
    """Some starts of an attractor search did not settle within ``max_periods``."""


def box_half_width(excitation: Excitation) -> float:
    """Half-width ``a = 2 + 10 P_a/Q`` of the start box, nondimensional: x = y/y0 ∈ [1 − a, 1 + a],
    x' = ẏ/(y0 ω_n0) ∈ [−a, a]."""
    return 2.0 + 10.0 * excitation.pa_over_q


def start_box(excitation: Excitation, n: int, seed: int = 0):
    """``n`` random nondimensional starts (x, x') and phases 0 from the physics box."""
    a = box_half_width(excitation)
    rng = np.random.default_rng(seed)
    Z = np.column_stack([rng.uniform(1.0 - a, 1.0 + a, n), rng.uniform(-a, a, n)])
    return Z, np.zeros(n)


def ballistic_seeds(excitation: Excitation, max_flight_periods: int = 2):
    """Take-off states at y = 0 for free flights of 1..``max_flight_periods`` periods."""
    m2 = excitation.model.m2
    T = excitation.tau_period
    Z, ph = [], []
    for j in range(1, max_flight_periods + 1):
        v_take_off = j * T / (2.0 * m2)  # x'' = 1/m2 in flight (gravity alone)
        for s in (0.5, 0.75, 1.0):
            for phase in (0.0, 0.25, 0.5, 0.75):
                Z.append((0.0, -s * v_take_off))
                ph.append(phase)
    return np.array(Z, float).reshape(-1, 2), np.array(ph, float)


def group_outcomes(groups: list[dict], excitation: Excitation, in_box, rtol: float, outcomes: tuple, *,
                   kmax: int = 0, reasons: dict | None = None) -> tuple[int, int, int, np.ndarray]:
    """Add the ``outcomes`` of :func:`settle_capture_many` (its tuple of outputs) to ``groups`` (one dict per attractor:
    period, strobe or tail, z, M, res, hits, box, type, spectrum) by the sameness rules, a start
    without a period ≤ ``kmax`` judged by :func:`.transients.search_verdict` unless its strobe cloud overlaps
    one judged a non-periodic attractor already (:func:`.transients.same_cloud`), the verdict's
    reason of each unsettled start counted in ``reasons`` (if given); return the failures, the
    unsettled starts, the unsettled box starts and each start's group index (int64[N], −1 for
    failed and unsettled starts)."""
    status, period, _n_periods, residual, z_star, monodromy, tail = outcomes
    n_failed = n_unsettled = n_unsettled_box = 0
    labels = np.full(status.shape[0], -1, np.int64)
    for i in range(status.shape[0]):
        outcome = (int(status[i]), int(period[i]), z_star[i], monodromy[i], float(residual[i]))
        spectrum = None
        known = None if outcome[0] != SETTLE_NONPERIODIC else \
            next((j for j, g in enumerate(groups) if g["period"] is None and same_cloud(g["tail"], tail[i])), None)
        if known is not None:
            outcome = (SETTLE_CAPTURED, known, None, None, 0.0)  # on a cloud already judged an attractor
        elif outcome[0] == SETTLE_NONPERIODIC:
            v = search_verdict(excitation, tail[i], rtol, kmax)
            spectrum = v.spectrum
            if v.kind == "unsettled":
                if reasons is not None:
                    reasons[v.reason] = reasons.get(v.reason, 0) + 1
                n_unsettled += 1
                n_unsettled_box += int(in_box[i])
                continue
            if v.kind == "periodic":
                outcome = (SETTLE_PERIODIC, v.period, v.z, v.monodromy, v.residual)
        if outcome[0] == SETTLE_CAPTURED:
            g = groups[outcome[1]]
        elif outcome[0] == SETTLE_PERIODIC:
            g = _periodic_group(groups, excitation, *outcome[1:])
        elif outcome[0] == SETTLE_NONPERIODIC:
            for g in groups:
                if g["period"] is None and same_cloud(g["tail"], v.cloud):
                    break
            else:
                g = {"period": None, "tail": v.cloud.copy(), "z": v.cloud[-1].copy(), "M": None,
                     "res": np.inf, "hits": 0, "box": 0, "type": v.kind, "spectrum": spectrum}
                groups.append(g)
        else:
            n_failed += 1
            continue
        g["hits"] += 1
        g["box"] += int(in_box[i])
        labels[i] = next(j for j, h in enumerate(groups) if h is g)
    return n_failed, n_unsettled, n_unsettled_box, labels


def _periodic_group(groups: list[dict], excitation: Excitation, k: int, z, M, res: float) -> dict:
    """The group of the period-k orbit through ``z`` (monodromy ``M``, closure ``res``): an equal
    one of ``groups`` (:func:`.orbits.same_orbit`) or a new one appended."""
    pts = strobe_points(excitation, z, k)
    for g in groups:
        if g["period"] == k and same_orbit(g["strobe"], pts):
            return g
    g = {"period": k, "strobe": pts, "z": np.array(z, float), "M": np.array(M, float), "res": float(res),
         "hits": 0, "box": 0, "type": "periodic", "spectrum": None}
    groups.append(g)
    return g


def default_max_periods(excitation: Excitation, detect_tol: float = 1e-4) -> int:
    """The automatic transient limit of a search [excitation periods]: for a start
    ``3 + 10 P_a/Q`` y0 away (:func:`.transients.transient_periods`)."""
    return transient_periods(excitation, detect_tol, 3.0 + 10.0 * excitation.pa_over_q)


def settle_starts(excitation: Excitation, Z, phases, kmax: int, max_periods: int, detect_tol: float,
                  rtol_transient: float, cap_pts, cap_id, capture_tol: float):
    """:func:`~contactvib._kernels.settle.settle_capture_many` on the starts ``Z`` (float[N, 2],
    nondimensional) at ``phases`` in a helper thread (Ctrl-C ends it within one period), with
    the search's refinement settings; its outputs."""
    stop = new_stop_flag()
    return run_interruptible(settle_capture_many, np.ascontiguousarray(Z, float),
                             np.ascontiguousarray(phases, float), excitation.kernel_parameters(), kmax, 4,
                             max_periods, detect_tol, rtol_transient, RTOL_REFINE, CLOSE_TOL, 2 * WINDOW,
                             cap_pts, cap_id, capture_tol, stop, stop=stop)


#: Bytes per start of the search's arrays (start, outcome, 64-point tail, grouping; rounded up).
_BYTES_PER_START = 2048
#: Bytes per stroboscopic point of a transient's history (one history per numba thread).
_BYTES_PER_HISTORY_ROW = 16


#: Estimated wall time [s] beyond which a search reports progress chunk by chunk.
LONG_SEARCH_S = 5.0
#: Chunks per wave of a long search (each a parallel kernel call over its starts).
PROGRESS_CHUNKS = 50


def _chunks(n: int, k: int) -> list[slice]:
    """At most ``k`` consecutive slices covering ``range(n)``, none empty, each of at least two
    starts per numba thread where there are enough (the kernel's parallelism is over starts)."""
    from numba import get_num_threads

    k = max(1, min(k, n // (2 * get_num_threads())))
    edges = sorted({round(n * j / k) for j in range(k + 1)})
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:])] or [slice(0, 0)]


def check_search(n_starts, seed, kmax, max_periods) -> tuple[int, int, int, int | None]:
    """The checked sizes of :func:`find_attractors`: ``(n_starts, seed, kmax, max_periods)``
    (``max_periods`` None: chosen by :func:`find_attractors` from the damping).

    Besides their ranges, their arrays must fit in :data:`~contactvib.model.checks.MEMORY_MAX`:
    half of it for the per-start arrays, half for the transient histories (``max_periods + 1``
    points per thread)."""
    from numba import get_num_threads

    n_starts = check_int("n_starts", n_starts, 1)
    seed = check_int("seed", seed, 0)
    kmax = check_int("kmax", kmax, 1, KMAX_SEARCH_MAX)
    half = MEMORY_MAX // 2
    check_memory("n_starts", n_starts, 2.0 * n_starts * _BYTES_PER_START, half // _BYTES_PER_START)
    if max_periods is None:
        return n_starts, seed, kmax, None
    max_periods = check_int("max_periods", max_periods, 4 * kmax)
    row = _BYTES_PER_HISTORY_ROW * get_num_threads()
    check_memory("max_periods", max_periods, 2.0 * (max_periods + 1) * row, half // row - 1)
    return n_starts, seed, kmax, max_periods


@old_form("model", "excitation", "n_starts", "seed", "kmax", "max_periods", "seeds", "detect_tol",
          "rtol_transient", "capture_tol", "progress")
def find_attractors(excitation: Excitation, *, n_starts: int = 512, seed: int = 0, kmax: int = 8,
                    max_periods: int | None = None, seeds: bool = True, detect_tol: float = 1e-4,
                    rtol_transient: float = 1e-8, capture_tol: float = 3e-3,
                    progress=None) -> AttractorSet:
    """All attractors reached from the start box and the ballistic seeds.

    Parameters
    ----------
    excitation : Excitation
        The operating point (its model, ``excitation.model``, must be damped: h_n > 0).
    n_starts : int
        Random starts in the box (≥ 1).
    seed : int
        Random seed of the box sample (≥ 0).
    kmax : int
        Largest period searched, in excitation periods (1..64).
    max_periods : int or None
        Transient limit per start [excitation periods] (≥ 4 kmax; a non-periodic attractor needs
        ≥ 128 to be proven one); None: twice the
        linear decay time in contact from the box to ``detect_tol``, at least 400
        (``contactvib.steady.transients.transient_periods``). A start that finds no period by then is a
        non-periodic attractor if its strobe cloud proves one, else it is counted as unsettled.
    seeds : bool
        Add the ballistic seeds.
    detect_tol : float
        Relative stroboscopic distance that triggers a Newton refinement.
    rtol_transient : float
        Integrator tolerance during transients (refinement always uses 1e-12).
    capture_tol : float
        Relative distance to a known orbit's strobe point at which a second-wave start is
        counted for that orbit (0: every start runs to the end).
    progress : callable or None
        Called as ``progress(done, total)`` with the starts finished and all starts: once with
        ``done = 0`` when the inputs are checked and the integration begins (the CLI prints its
        header then), and after each wave; with it, a search estimated beyond ``LONG_SEARCH_S`` (5)
        seconds (``steady.transients.estimated_seconds``) runs its starts in about
        ``PROGRESS_CHUNKS`` (50) chunks per wave and reports after each (the same results).

    Returns
    -------
    AttractorSet
        With ``n_unsettled`` starts that did not settle (an ``UnsettledWarning`` says so).
    """
    model = check_excitation(excitation).model
    check_damped(model, "the attractor search")
    n_starts, seed, kmax, max_periods = check_search(n_starts, seed, kmax, max_periods)
    detect_tol = check_range("detect_tol", detect_tol, 0.0, False)
    rtol_transient = check_range("rtol_transient", rtol_transient, 0.0, False)
    capture_tol = check_range("capture_tol", capture_tol, 0.0, True, upper=CAPTURE_TOL_MAX)
    Zb, phb = start_box(excitation, n_starts, seed)
    if seeds:
        Zs, phs = ballistic_seeds(excitation)
    else:
        Zs, phs = np.empty((0, 2)), np.empty(0)
    auto = max_periods is None
    if auto:
        max_periods = default_max_periods(excitation, detect_tol)
    work = check_work(excitation, n_starts + Zs.shape[0], max_periods)  # before the memory: names f_n0
    chunks = PROGRESS_CHUNKS if progress is not None and estimated_seconds(work) > LONG_SEARCH_S else 1
    if auto:
        check_search(n_starts, seed, kmax, max_periods)  # the memory of the chosen limit
    n_first = min(n_starts, FIRST_WAVE)
    groups: list[dict] = []  # each: period, strobe or tail, z, M, res, hits, box, type, spectrum
    counts = np.zeros(3, np.int64)  # failed, unsettled, unsettled box starts
    reasons: dict[str, int] = {}  # unsettled starts by the verdict's reason

    def run(Z, ph, in_box, cap_pts, cap_id):
        parts = []
        for sl in _chunks(Z.shape[0], chunks):
            parts.append(settle_starts(excitation, Z[sl], ph[sl], kmax, max_periods, detect_tol, rtol_transient,
                                       cap_pts, cap_id, capture_tol))
            done[0] += sl.stop - sl.start
            if progress is not None and (chunks > 1 or sl.stop == Z.shape[0]):
                progress(done[0], n_starts + Zs.shape[0])
        out = parts[0] if len(parts) == 1 else tuple(np.concatenate(a) for a in zip(*parts))
        counts[:] += group_outcomes(groups, excitation, in_box, rtol_transient, out, kmax=kmax, reasons=reasons)[:3]

    done = [0]
    if progress is not None:
        progress(0, n_starts + Zs.shape[0])
    no_pts, no_id = np.empty((0, 2)), np.empty(0, np.int64)
    run(np.vstack([Zb[:n_first], Zs]), np.concatenate([phb[:n_first], phs]),
        np.arange(n_first + Zs.shape[0]) < n_first, no_pts, no_id)
    if n_starts > n_first:
        periodic = [(j, g) for j, g in enumerate(groups) if g["period"] is not None]
        cap_pts = np.vstack([g["strobe"] for _j, g in periodic]) if periodic else no_pts
        cap_id = np.array([j for j, g in periodic for _p in range(g["period"])], np.int64)
        run(Zb[n_first:], phb[n_first:], np.ones(n_starts - n_first, bool), cap_pts, cap_id)
    n_failed, n_unsettled, n_unsettled_box = (int(c) for c in counts)
    if n_unsettled:
        warnings.warn(UnsettledWarning(
            f"{n_unsettled} of {n_starts + Zs.shape[0]} starts ({n_unsettled_box / n_starts:.1%} of "
            f"the box) did not settle within {max_periods} periods and are not counted as "
            f"attractors: raise max_periods (--max-periods), or kmax (--kmax) if an orbit's period "
            f"exceeds {kmax}"), stacklevel=2)

    attractors = [
        describe_orbit(excitation, g["z"], g["period"], monodromy=g["M"], closure=g["res"],
                       basin_fraction=g["box"] / n_starts, hits=g["hits"], kind=g["type"],
                       spectrum=g["spectrum"])
        for g in groups
    ]
    attractors.sort(key=lambda a: -a.app_um)
    if attractors:
        model.check_motion(max(a.ymax_um for a in attractors), "an attractor")
    return AttractorSet(
        model=model.parameters(),
        excitation=excitation.describe(),
        attractors=attractors,
        fn0_hz=model.f_n0,
        y0_um=model.units.y_um,
        pa_over_q=excitation.pa_over_q,
        fe_hz=excitation.f_e,
        n_box=n_starts,
        n_seeds=Zs.shape[0],
        n_failed=n_failed,
        n_unsettled=n_unsettled,
        unsettled_fraction=n_unsettled_box / n_starts,
        unsettled_reasons=dict(sorted(reasons.items())),
        settings={"n_starts": n_starts, "seed": seed, "kmax": kmax, "max_periods": max_periods,
                  "seeds": seeds, "detect_tol": detect_tol, "rtol_transient": rtol_transient,
                  "capture_tol": capture_tol, "first_wave": n_first,
                  "rtol_refine": RTOL_REFINE, "tol": CLOSE_TOL},
    )
