"""Trajectory-periods per second per core of the atlas's own trajectory work.

``bench_atlas.py`` reports levels per minute; this script adds the other rate of the atlas's performance:
trajectory-periods per second per core. One numba thread (``numba.set_num_threads(1)``, and every
kernel timed here is serial anyway), CPU time of this process (``time.process_time``) taken around
the kernel calls only, each kernel warmed by one call before timing (warm numba cache assumed).

Run from the repository root (about 45 s of one core with a warm numba cache; a first run after
a kernel change adds the compile, ~15–30 s, which is not timed)::

    PYTHONPATH=src python benchmarks/bench_trajectory_rate.py          # writes results_trajectory_rate.json
    PYTHONPATH=src python benchmarks/bench_trajectory_rate.py --every 2    # every 2nd multi-start frequency
    PYTHONPATH=src python benchmarks/bench_trajectory_rate.py --quick      # smoke test (~6 s)

What is counted
---------------
1. **Multi-start transients** (most of the periods a level integrates, though not most of its
   CPU: the settle calls below cost 0.8–1.8 CPU s per level against ~8 in ``bench_atlas.py``,
   where the continuation post-pass and the tracing dominate). The 12-level slice of
   ``bench_atlas.py`` (``np.linspace(0.05, 1.0, 12)``, formatted ``{:.4g}``), the default
   ``SweepSettings()`` (30–2000 Hz at 1 Hz), every multi-start frequency
   (``multistart_indices``; 49 of them, all used by default: the full slice costs ~22 s of CPU;
   ``--every N`` keeps every N-th, recorded in the JSON as ``frequency_subsample_every``),
   and at each the sweep's own starts: ``start_box(exc, 24, seed + i)`` plus the 24
   ``ballistic_seeds(exc)`` (as ``sweep._multistart_at`` builds them). Each start is settled by the
   serial kernel ``_kernels.settle.settle`` with the arguments of ``sweep._settle_from`` (kmax 8,
   min_periods 4, max_periods 300, detect_tol 1e-4, Taylor transient at 1e-8, Newton refinement
   at 1e-10 to closure 1e-9).

   * *Periods counted*: ``n`` (the kernel's 3rd return value) **plus the first, partial period**
     ``1 − phase0`` that ``settle_core`` integrates before it stores strobe point 0. So a box
     start (phase 0) that returns ``n`` has integrated ``n + 1`` periods. The sum of the bare
     ``n`` is reported too (``periods_n_only``).
   * *CPU time*: the whole ``settle`` call, i.e. transient **and** period detection **and** the
     Newton refinement (``refine_stable_orbit``: variational DOP853 shooting at 1e-10, divisor checks), whose
     periods are *not* counted. This is ``periods_per_s_per_core`` (the honest "what a settle
     call delivers" rate). To separate the two, the same transient is re-run in a benchmark-local
     ``@njit`` loop over ``taylor.advance_state`` (exactly ``settle_core``'s calls, same end
     state, checked bit for bit): ``transient_only_periods_per_s_per_core``; the difference of
     the two CPU times is the detection + refinement share.
   * Not the same as the sweep's multi-start: there ``settle_known_many`` stops a start as soon
     as it comes within ``capture_tol`` of an attractor already known at that frequency, so the
     sweep integrates fewer periods from the same starts. This counts each start's full serial
     settle, as ``_settle_from`` runs it. Sweeps, traces, Newton seeds and the continuation
     post-pass are not counted here.

2. **Periodic orbits, stroboscopic map.** Period-1 orbits found by settling the rest state
   (1, 0) (as the sweeps start) at 4 levels × 6 frequencies; each is classified by one period of
   ``flow.advance`` (flight time > 0: loss of contact). ``shooting.strobe_map(z, K, par, rtol,
   rtol, out, np.empty((0, 0)))`` (as ``steady/orbits.py`` calls it, DOP853) is timed over K
   periods (K chosen for ~0.1 s, best of 3) at rtol 1e-10 (the sweep's shooting tolerance) and
   1e-12 (``orbits.RTOL_REFINE``), and with the monodromy (``out_M`` 2×2, Newton's variational
   integration) at 1e-10. Reported per orbit, summed over in-contact vs loss-of-contact orbits,
   and side by side at each f_e (``rtol_1e-10_by_frequency``): a period is 2π/r long in τ, so
   the rate per period is set mostly by f_e (12k/s at 60 Hz, up to 160k/s at 1200 Hz).

3. **scipy for context.** 20 of the 48 starts (evenly picked) at one level and multi-start
   frequency (0.6545 Q, nearest to 360 Hz): ``solve_ivp(method="DOP853", rtol=1e-8, atol=1e-8)``
   integrates the same equations for the same periods as the kernel did (partial first period,
   then ``n`` periods, one ``solve_ivp`` run per period, restarted at every terminal event
   x = 0 with x set to 0 and the mode switched, as ``bench_attractors.py`` does). Ratios of
   periods/s against the kernel's transient-only and whole-settle rates on the same starts.
   The tolerances are nominally equal but not equivalent (Taylor step rule vs DOP853 error
   estimate); ``bench_attractors.py`` compares at equal strobe error.
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numba
import numpy as np
import scipy
from numba import njit

from benchmarks import result_path
from contactvib._kernels.flow import REC_WIDTH, advance, initial_mode
from contactvib._kernels.settle import SETTLE_FAILED, SETTLE_PERIODIC, settle
from contactvib._kernels.shooting import MAX_STEPS_PER_PERIOD, strobe_map
from contactvib._kernels.status import STATUS_OK
from contactvib._kernels.taylor import advance_state
from contactvib.model import ContactModel
from contactvib.steady.attractors import ballistic_seeds, start_box
from contactvib.sweeps.sweep import SweepSettings, frequency_grid, multistart_indices
from contactvib.testing import integrate_modes, power_law_rhs

HERE = Path(__file__).resolve().parent

ORBIT_LEVELS = ("0.05", "0.4818", "0.9136", "1")
ORBIT_FREQS = (60.0, 200.0, 360.0, 800.0, 1200.0, 1500.0)
SCIPY_LEVEL, SCIPY_FE = "0.6545", 360.0


@njit(cache=False)
def replay_transient(z, phase0, par, n, tol):
    """``settle_core``'s transient without detection or refinement: the partial first period,
    then ``n`` periods of ``taylor.advance_state``. Returns (x, v, steps, t_flight, events, status)."""
    T = 2.0 * math.pi / par[4]
    y = np.empty(2)
    y[0] = z[0]
    y[1] = z[1]
    contact = initial_mode(y[0], y[1])
    h = 0.01
    contact, h, ns, tf, ne, st = advance_state(y, phase0 * T, T, contact, h, par, tol, MAX_STEPS_PER_PERIOD)
    steps, t_flight, events = ns, tf, ne
    for _ in range(n):
        if st != STATUS_OK:
            break
        contact, h, ns, tf, ne, st = advance_state(y, 0.0, T, contact, h, par, tol, MAX_STEPS_PER_PERIOD)
        steps += ns
        t_flight += tf
        events += ne
    return y[0], y[1], steps, t_flight, events, st


def _starts(model, pa, f, i, st):
    exc = model.excitation(float(pa), float(f[i]))
    Zb, phb = start_box(exc, st.n_starts, st.seed + int(i))
    Zs, phs = ballistic_seeds(exc)
    return np.vstack([Zb, Zs]), np.concatenate([phb, phs])


def _par(model, pa, f, i):
    """As ``LevelState.par`` with ``par[4] = r[i]`` (``sweep._settle_from``)."""
    par = model.excitation(float(pa), float(f[0])).kernel_parameters().copy()
    par[4] = f[i] / model.f_n0
    return par


def _settle_one(z, phase, par, st, hist, oz, oM):
    """``sweep._settle_from``'s kernel call; returns (status, k, n, cpu seconds)."""
    t0 = time.process_time()
    s, k, n, _res = settle(np.asarray(z, float), float(phase), par, st.kmax, 4, st.max_periods,
                           st.detect_tol, st.rtol_transient, st.rtol, st.tol, hist, oz, oM)
    return int(s), int(k), int(n), time.process_time() - t0


def multistart_transients(model, st, levels, every) -> dict:
    f = frequency_grid(st)
    idx = multistart_indices(st)[::every]
    hist = np.empty((st.max_periods + 1, 2))
    oz, oM = np.empty(2), np.empty((2, 2))
    # warm both kernels (cache load / compile) outside the timing
    par = _par(model, levels[0], f, idx[0])
    c0 = time.process_time()
    _settle_one((1.0, 0.0), 0.0, par, st, hist, oz, oM)
    c1 = time.process_time()
    replay_transient(np.array([1.0, 0.0]), 0.0, par, 3, st.rtol_transient)
    c2 = time.process_time()
    warmup = {"settle_first_call_cpu_s": round(c1 - c0, 2), "replay_compile_cpu_s": round(c2 - c1, 2)}
    print("warm-up", warmup, flush=True)
    per_level = []
    i_scipy = int(idx[np.argmin(np.abs(f[idx] - SCIPY_FE))])
    keep = {"i": i_scipy, "rows": []}
    mismatch = 0
    for pa in levels:
        acc = dict(starts=0, periodic=0, nonperiodic=0, failed=0, periods=0.0, periods_n=0,
                   settle_cpu=0.0, replay_cpu=0.0, steps=0, events=0, t_flight=0.0, t_total=0.0)
        for i in idx:
            Z, ph = _starts(model, pa, f, i, st)
            par = _par(model, pa, f, i)
            T = 2.0 * math.pi / par[4]
            for j in range(Z.shape[0]):
                s, _k, n, cpu = _settle_one(Z[j], ph[j], par, st, hist, oz, oM)
                acc["starts"] += 1
                acc["settle_cpu"] += cpu
                if s == SETTLE_FAILED:
                    acc["failed"] += 1
                    continue
                acc["periodic" if s == SETTLE_PERIODIC else "nonperiodic"] += 1
                acc["periods"] += n + 1.0 - ph[j]
                acc["periods_n"] += n
                end = hist[n].copy()
                t0 = time.process_time()
                x, v, ns, tf, ne, rst = replay_transient(np.asarray(Z[j], float), float(ph[j]), par, n,
                                                         st.rtol_transient)
                acc["replay_cpu"] += time.process_time() - t0
                if rst != STATUS_OK or x != end[0] or v != end[1]:
                    mismatch += 1
                acc["steps"] += ns
                acc["events"] += ne
                acc["t_flight"] += tf
                acc["t_total"] += (n + 1.0 - ph[j]) * T
                if pa == SCIPY_LEVEL and i == i_scipy:
                    keep["rows"].append((j, n, cpu))
        row = {
            "pa_over_q": pa, "starts": acc["starts"], "periodic": acc["periodic"],
            "nonperiodic_at_max_periods": acc["nonperiodic"], "failed": acc["failed"],
            "periods": round(acc["periods"], 2), "periods_n_only": acc["periods_n"],
            "mean_periods_per_start": round(acc["periods"] / max(1, acc["starts"]), 1),
            "settle_cpu_s": round(acc["settle_cpu"], 3),
            "periods_per_s_per_core": round(acc["periods"] / acc["settle_cpu"]),
            "transient_cpu_s": round(acc["replay_cpu"], 3),
            "transient_only_periods_per_s_per_core": round(acc["periods"] / acc["replay_cpu"]),
            "detection_refinement_share_of_settle_cpu": round(1.0 - acc["replay_cpu"] / acc["settle_cpu"], 3),
            "taylor_steps_per_period": round(acc["steps"] / max(1.0, acc["periods"]), 1),
            "contact_events_per_period": round(acc["events"] / max(1.0, acc["periods"]), 2),
            "flight_time_fraction": round(acc["t_flight"] / max(1e-300, acc["t_total"]), 3),
        }
        per_level.append(row)
        print(json.dumps(row), flush=True)
    tot_p = sum(r["periods"] for r in per_level)
    tot_c = sum(r["settle_cpu_s"] for r in per_level)
    tot_t = sum(r["transient_cpu_s"] for r in per_level)
    res = {
        "levels": list(levels), "multistart_frequencies_total": int(multistart_indices(st).size),
        "frequency_subsample_every": every, "multistart_frequencies_used": int(idx.size),
        "frequencies_hz_used": [float(f[i]) for i in idx],
        "starts": sum(r["starts"] for r in per_level),
        "periods": round(tot_p, 2), "periods_n_only": sum(r["periods_n_only"] for r in per_level),
        "settle_cpu_s": round(tot_c, 2), "periods_per_s_per_core": round(tot_p / tot_c),
        "transient_cpu_s": round(tot_t, 2), "transient_only_periods_per_s_per_core": round(tot_p / tot_t),
        "detection_refinement_share_of_settle_cpu": round(1.0 - tot_t / tot_c, 3),
        "replay_end_state_mismatches": mismatch, "warmup": warmup,
        "per_level": per_level,
    }
    return res, keep


def _time_strobe(z, K, par, rtol, jac, reps=3):
    out = np.empty(2)
    M = np.empty((2, 2)) if jac else np.empty((0, 0))
    best = math.inf
    for _ in range(reps):
        t0 = time.process_time()
        s = strobe_map(z, K, par, rtol, rtol, out, M)
        best = min(best, time.process_time() - t0)
    return best, s, out


def strobe_orbits(model, st, budget_s) -> dict:
    hist = np.empty((st.max_periods + 1, 2))
    oz, oM = np.empty(2), np.empty((2, 2))
    rows = []
    warm = False
    for pa in ORBIT_LEVELS:
        for fe in ORBIT_FREQS:
            par = model.excitation(float(pa), fe).kernel_parameters()
            s, k, n, _cpu = _settle_one((1.0, 0.0), 0.0, par, st, hist, oz, oM)
            if s != SETTLE_PERIODIC or k != 1:
                rows.append({"pa_over_q": pa, "fe_hz": fe, "skipped": f"settle status {s}, period {k}"})
                continue
            z = oz.copy()
            if not warm:
                for jac in (False, True):
                    _time_strobe(z, 1, par, st.rtol, jac, reps=1)
                warm = True
            y = z.copy()
            T = 2.0 * math.pi / par[4]
            _c, _h, _i, ns, tf, ne, _s = advance(y, 0.0, T, initial_mode(y[0], y[1]), 0.01, par, 1e-12, 1e-12,
                                                 np.empty((0, REC_WIDTH)), np.int64(0),
                                                 np.int64(MAX_STEPS_PER_PERIOD))
            row = {"pa_over_q": pa, "fe_hz": fe, "z": [float(z[0]), float(z[1])],
                   "loss_of_contact": bool(tf > 0.0), "flight_fraction": round(tf / T, 3),
                   "contact_events_per_period": int(ne), "dop853_steps_per_period_1e-12": int(ns)}
            for name, rtol, jac in (("rtol_1e-10", 1e-10, False), ("rtol_1e-12", 1e-12, False),
                                    ("rtol_1e-10_monodromy", 1e-10, True)):
                t1, _s1, _o = _time_strobe(z, 20, par, rtol, jac, reps=1)
                K = int(min(200_000, max(20, 20 * budget_s / max(t1, 1e-6))))
                t, s2, out = _time_strobe(z, K, par, rtol, jac)
                drift = float(np.max(np.abs(out - z)) / max(1.0, np.max(np.abs(z))))
                row[name] = {"periods": K, "cpu_s": round(t, 4), "periods_per_s_per_core": round(K / t),
                             "status": int(s2), "end_drift_rel": float(f"{drift:.2g}")}
            rows.append(row)
            print(json.dumps(row), flush=True)
    summary = {}
    for group, lc in (("in_contact", False), ("loss_of_contact", True)):
        g = [r for r in rows if "skipped" not in r and r["loss_of_contact"] == lc]
        summary[group] = {"orbits": len(g)}
        for name in ("rtol_1e-10", "rtol_1e-12", "rtol_1e-10_monodromy"):
            if g:
                p = sum(r[name]["periods"] for r in g)
                c = sum(r[name]["cpu_s"] for r in g)
                rates = [r[name]["periods_per_s_per_core"] for r in g]
                summary[group][name] = {"periods_per_s_per_core": round(p / c), "min": min(rates),
                                        "max": max(rates)}
    # the period's length in τ is 2π/r: compare in-contact and loss-of-contact orbits at one f_e
    same_f = {}
    for fe in ORBIT_FREQS:
        g = [r for r in rows if "skipped" not in r and r["fe_hz"] == fe]
        same_f[f"{fe:g}"] = {grp: {r["pa_over_q"]: r["rtol_1e-10"]["periods_per_s_per_core"]
                                   for r in g if r["loss_of_contact"] == lc}
                             for grp, lc in (("in_contact", False), ("loss_of_contact", True))}
    summary["rtol_1e-10_by_frequency"] = same_f
    return {"orbits": rows, "summary": summary}


def make_scipy(par):
    """Span from τ = t to T of the paper's equation, switching mode at every x = 0
    (:func:`contactvib.testing.integrate_modes`, DOP853, rtol = atol = 1e-8)."""
    f_contact, f_flight = power_law_rhs(par)
    T = 2.0 * math.pi / float(par[4])

    def span(y, t, contact):
        run = integrate_modes(f_contact, f_flight, y, t, T, contact=contact, rtol=1e-8, atol=1e-8)
        return run.y, run.contact

    return span, T


def scipy_context(model, st, keep, n_starts) -> dict:
    f = frequency_grid(st)
    i = keep["i"]
    Z, ph = _starts(model, SCIPY_LEVEL, f, i, st)
    par = _par(model, SCIPY_LEVEL, f, i)
    span, T = make_scipy(par)
    rows = keep["rows"]
    pick = sorted({int(round(x)) for x in np.linspace(0, len(rows) - 1, n_starts)})
    sp_cpu = k_set = k_tr = periods = 0.0
    diffs = []
    for q in pick:
        j, n, settle_cpu = rows[q]
        z, phase = Z[j], float(ph[j])
        t0 = time.process_time()
        x, v, *_r = replay_transient(np.asarray(z, float), phase, par, n, st.rtol_transient)
        k_tr += time.process_time() - t0
        k_set += settle_cpu
        t0 = time.process_time()
        y, contact = span(z, phase * T, initial_mode(z[0], z[1]))
        for _ in range(n):
            y, contact = span(y, 0.0, contact)
        sp_cpu += time.process_time() - t0
        periods += n + 1.0 - phase
        diffs.append(max(abs(y[0] - x), abs(y[1] - v)) / max(1.0, abs(x), abs(v)))
    sp_rate = periods / sp_cpu
    return {"pa_over_q": SCIPY_LEVEL, "fe_hz": float(f[i]), "starts": len(pick),
            "start_indices": [rows[q][0] for q in pick], "periods": round(periods, 2),
            "scipy_cpu_s": round(sp_cpu, 2), "scipy_periods_per_s_per_core": round(sp_rate, 1),
            "kernel_transient_cpu_s": round(k_tr, 4), "kernel_settle_cpu_s": round(k_set, 4),
            "kernel_transient_periods_per_s_per_core": round(periods / k_tr),
            "kernel_settle_periods_per_s_per_core": round(periods / k_set),
            "ratio_kernel_transient_over_scipy": round(periods / k_tr / sp_rate, 1),
            "ratio_kernel_settle_over_scipy": round(periods / k_set / sp_rate, 1),
            "end_state_rel_diff_median": float(f"{np.median(diffs):.2g}"),
            "end_state_rel_diff_max": float(f"{np.max(diffs):.2g}")}


def _git(*a) -> str:
    try:
        return subprocess.run(["git", *a], cwd=HERE.parent, capture_output=True, text=True).stdout.strip()
    except OSError:
        return ""


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--every", type=int, default=1, help="use every N-th multi-start frequency")
    ap.add_argument("--scipy-starts", type=int, default=20)
    ap.add_argument("--quick", action="store_true", help="3 levels, every 8th frequency, 4 scipy starts")
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    numba.set_num_threads(1)
    wall0, cpu0 = time.perf_counter(), time.process_time()
    st = SweepSettings()
    model = ContactModel()
    levels = [f"{p:.4g}" for p in np.linspace(0.05, 1.0, 12)]
    every, n_scipy, budget = args.every, args.scipy_starts, 0.1
    if args.quick:
        levels, every, n_scipy, budget = [levels[0], levels[7], levels[-1]], 8, 4, 0.02
    res = {
        "date_utc": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H:%M"),
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
        "load_average_at_start": [round(x, 2) for x in os.getloadavg()],
        "python": platform.python_version(), "numba": numba.__version__, "numpy": np.__version__,
        "scipy": scipy.__version__, "numba_threads": numba.get_num_threads(), "quick": args.quick,
        "git_head": _git("rev-parse", "--short", "HEAD"),
        "src_uncommitted": _git("status", "--porcelain", "--", "src").splitlines(),
    }
    phases = res["part_cpu_s"] = {}
    c = time.process_time()
    ms, keep = multistart_transients(model, st, levels, every)
    res["multistart_transients"] = ms
    phases["1_multistart"], c = round(time.process_time() - c, 1), time.process_time()
    res["strobe_map_orbits"] = strobe_orbits(model, st, budget)
    phases["2_strobe_map"], c = round(time.process_time() - c, 1), time.process_time()
    if keep["rows"]:
        res["scipy_dop853_1e-8"] = scipy_context(model, st, keep, n_scipy)
    phases["3_scipy"] = round(time.process_time() - c, 1)
    res["load_average_at_end"] = [round(x, 2) for x in os.getloadavg()]
    res["git_head_at_end"] = _git("rev-parse", "--short", "HEAD")
    res["src_uncommitted_at_end"] = _git("status", "--porcelain", "--", "src").splitlines()
    if res["src_uncommitted_at_end"] != res["src_uncommitted"] or res["git_head_at_end"] != res["git_head"]:
        print("warning: src/ changed during the run; the numbers mix two versions", file=sys.stderr)
    res["script_wall_s"] = round(time.perf_counter() - wall0, 1)
    res["script_cpu_s"] = round(time.process_time() - cpu0, 1)
    Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps({k: v for k, v in res.items() if k not in ("multistart_transients", "strobe_map_orbits")}
                     | {"multistart_transients": {k: v for k, v in ms.items() if k != "per_level"},
                        "strobe_map_summary": res["strobe_map_orbits"]["summary"]}, indent=1))


if __name__ == "__main__":
    main()
