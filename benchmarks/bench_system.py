#!/usr/bin/env python
"""Systems of several coordinates: n-DOF kernels vs scipy DOP853, equal accuracy and the same attractor search.

Run from the repository root::

    python -m benchmarks system            # full run (a few minutes; writes results_system.json)
    python -m benchmarks system --quick    # a smoke test

Systems (the operating points of ``contactvib attractors --system``):

* ``rocking``: the rocking unit (``rocking_system(ContactModel(), e=0.01)``), P_a = 0.5 Q,
  f_e = 1300 Hz;
* ``file_2N``: ``examples/two_dof_stop.toml``, P_a = 2 N, f_e = 0.2 Hz;
* ``file_0.1N``: the same file, P_a = 0.1 N, f_e = 0.095 Hz.

For each, in one run:

1. Equal-accuracy integration throughput. Trajectories from the search's own starts (its start
   box and seed). The reference one-period map P_ref is the compiled stroboscopic map at
   rtol = atol = 1e-13 (checked against scipy at 1e-13 on two points). The error of a method is
   max over its stroboscopic pairs z_n -> z_{n+1} of |z_{n+1} − P_ref(z_n)|∞ / max(1, |P_ref|∞)
   in the scaled state of the compiled form. scipy: :func:`contactvib.testing.integrate_system`
   (solve_ivp DOP853 mode by mode, a terminal event on each contact, no Liouville integral) at
   rtol 1e-10 (atol 1e-10 of each coordinate's length scale), period by period, one core. The
   compiled kernels (one period = one ``strobe_map`` period, :mod:`contactvib._kernels.system_settle`)
   in a numba ``prange`` ensemble at the loosest tolerance of a scan whose error is ≤ scipy's.
   Ratio: scipy's seconds per trajectory-period over the compiled kernels' (wall, all numba
   threads; and on one thread).
2. The same attractor search: :func:`~contactvib.steady.system_attractors.find_system_attractors`
   with ``--starts`` starts (wall, warm compile cache), against the same search driven by scipy:
   the same starts in the same order, the same settling rule (a period k ≤ kmax when the last k
   stroboscopic points repeat to ``settle_tol``, capture within 1e-4 of a stable orbit found, at
   most ``default_max_periods`` periods), one period of scipy per step at the loosest rtol of
   1e-10, 3e-11, 1e-11, ... whose stroboscopic error (part 1's measure) is ≤ that of the compiled
   search's rtol 1e-10 (equal accuracy; ``--search-scipy-rtol`` sets it), a detected
   orbit refined by Newton with a finite-difference Jacobian of scipy's k-period map (rtol 1e-11)
   and its stable points kept for capture; the attractors' measurement (512 samples a period) is
   left out of scipy's time and counted in the compiled one. scipy runs only the first
   ``--scipy-starts`` starts; its time is scaled per start to ``--starts``. The ratio on the same
   few starts (compiled search of just those) is reported too.

Every ratio is given in wall time and in CPU time of the process (``time.process_time``: steadier
than wall time on a machine shared with other jobs).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
from pathlib import Path

import numba
import numpy as np
import scipy
from numba import njit, prange

from benchmarks import result_path
from contactvib._kernels import system_map as km
from contactvib._kernels.status import STATUS_OK
from contactvib._kernels.system_flow import system_arrays
from contactvib._kernels.system_settle import one_period
from contactvib.model import ContactModel
from contactvib.model.rocking import rocking_system
from contactvib.model.system_file import load_system
from contactvib.steady.system_attractors import _start_box, default_max_periods, find_system_attractors
from contactvib.testing import integrate_system

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "examples" / "two_dof_stop.toml"
RTOL_REF = 1e-13
SCIPY_TOL = 1e-10
TOL_SCAN = [1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10, 3e-11, 1e-11, 1e-12]
SCIPY_SCAN = [1e-10, 3e-11, 1e-11, 3e-12, 1e-12]
SETTLE_TOL, CAPTURE_TOL, KMAX, SEARCH_RTOL = 1e-7, 1e-4, 8, 1e-10


def systems():
    m = ContactModel()
    f = load_system(EXAMPLE)
    return [("rocking", rocking_system(m, e=0.01), 0.5 * m.Q, 1300.0,
             "rocking_system(ContactModel(), e=0.01), 0.5 Q, 1300 Hz"),
            ("file_2N", f, 2.0, 0.2, "examples/two_dof_stop.toml, 2 N, 0.2 Hz"),
            ("file_0.1N", f, 0.1, 0.095, "examples/two_dof_stop.toml, 0.1 N, 0.095 Hz")]


@njit(parallel=True, cache=True)
def ensemble(sa, X, n_periods, rtol):
    """Every row of X (scaled) integrated ``n_periods`` periods; hist[i, p] = strobe point p."""
    N, n2 = X.shape
    T = 2.0 * math.pi / sa.r
    hist = np.full((N, n_periods + 1, n2), np.nan)
    status = np.zeros(N, np.int64)
    for i in prange(N):
        y = X[i].copy()
        mode = np.zeros(sa.U.shape[0], dtype=np.bool_)
        for c in range(n2):
            hist[i, 0, c] = y[c]
        for p in range(1, n_periods + 1):
            st = one_period(sa, y, mode, T, rtol)
            if st != STATUS_OK:
                status[i] = st
                break
            for c in range(n2):
                hist[i, p, c] = y[c]
    return hist, status


def timed(fn, *a, repeat=1, **kw):
    """(wall [s], CPU time of the process [s], result): the least of ``repeat`` calls each."""
    wall = cpu = math.inf
    out = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn(*a, **kw)
        wall, cpu = min(wall, time.perf_counter() - t0), min(cpu, time.process_time() - c0)
    return wall, cpu, out


class ScipyMap:
    """One or k periods of :func:`contactvib.testing.integrate_system` on the scaled state."""

    def __init__(self, system, pa, fe, form):
        self.s, self.pa, self.fe, self.sc = system, pa, fe, form.scales
        self.periods = 0

    def __call__(self, x, rtol, k=1):
        z = self.sc.to_si(np.asarray(x, float))
        atol = rtol * np.asarray(self.sc.length, float)
        for j in range(k):
            z, _, _ = integrate_system(self.s, self.pa, self.fe, z, (j + 1) / self.fe, rtol=rtol, atol_q=atol,
                                       t0=j / self.fe, liouville=False)
        self.periods += k
        return self.sc.to_scaled(z)


def rel_err(z, ref):
    return np.max(np.abs(z - ref), axis=1) / np.maximum(1.0, np.max(np.abs(ref), axis=1))


def equal_accuracy(name, sa, smap, X, a, n_threads):
    """Part 1: the scipy error and cost, the tolerance scan, the work unit."""
    def ref_map(Z):
        h, st = ensemble(sa, np.ascontiguousarray(Z), 1, RTOL_REF)
        if st.any():
            raise RuntimeError("reference integration failed")
        return h[:, 1, :]

    Xs = X[:a.scipy_traj]
    zf, zt = [], []
    t0, c0 = time.perf_counter(), time.process_time()
    for x in Xs:
        y = x.copy()
        for _ in range(a.scipy_periods):
            y1 = smap(y, SCIPY_TOL)
            zf.append(y)
            zt.append(y1)
            y = y1
    sp_wall, sp_cpu = time.perf_counter() - t0, time.process_time() - c0
    n_sp = len(Xs) * a.scipy_periods
    zf, zt = np.array(zf), np.array(zt)
    e_sp = rel_err(zt, ref_map(zf))
    chk = zf[[0, len(zf) // 2]]
    agree = float(np.max(rel_err(np.array([smap(z, RTOL_REF) for z in chk]), ref_map(chk))))
    scan = []
    for tol in TOL_SCAN:
        h, st = ensemble(sa, np.ascontiguousarray(Xs), a.scipy_periods, tol)
        ok = np.all(np.isfinite(h[:, 1:, :]), axis=2).reshape(-1)
        e = rel_err(h[:, 1:, :].reshape(-1, h.shape[2])[ok], ref_map(h[:, :-1, :].reshape(-1, h.shape[2])[ok]))
        scan.append({"tol": tol, "strobe_err_max": float(e.max()), "failed": int((st != 0).sum())})
    # the scipy tolerance of the search: the loosest whose error is <= the compiled search's (rtol 1e-10)
    target = next(x["strobe_err_max"] for x in scan if x["tol"] == SEARCH_RTOL)
    sp_scan = []
    for tol in SCIPY_SCAN:
        e = rel_err(np.array([smap(z, tol) for z in zf[:a.scipy_periods * 2]]), ref_map(zf[:a.scipy_periods * 2]))
        sp_scan.append({"rtol": tol, "strobe_err_max": float(e.max())})
        if e.max() <= target:
            break
    search_rtol = sp_scan[-1]["rtol"]
    chosen = next((s["tol"] for s in scan if s["strobe_err_max"] <= e_sp.max() and s["failed"] == 0), TOL_SCAN[-1])
    Xw = np.ascontiguousarray(np.tile(X, (max(1, a.work_starts // len(X)), 1))[:a.work_starts])
    n_tp = len(Xw) * a.work_periods
    wall, _cpu, (h, st) = timed(ensemble, sa, Xw, a.work_periods, chosen, repeat=3)
    numba.set_num_threads(1)
    wall1, cpu1, _ = timed(ensemble, sa, Xw, a.work_periods, chosen, repeat=3)
    numba.set_num_threads(n_threads)
    sp_per, cv_per, cv1_per = sp_wall / n_sp, wall / n_tp, wall1 / n_tp
    ratio_cpu = (sp_cpu / n_sp) / (cpu1 / n_tp)
    print(f"  [{name}] scipy 1e-10: {sp_per * 1e3:.2f} ms/period, strobe err {e_sp.max():.1e} "
          f"(ref vs scipy 1e-13 {agree:.1e}); compiled at tol {chosen:.0e}: {cv_per * 1e6:.1f} us/period "
          f"({n_threads} threads), {cv1_per * 1e6:.1f} us (1 thread) -> {sp_per / cv_per:.0f}x, "
          f"1 thread {sp_per / cv1_per:.0f}x, CPU time on one core each {ratio_cpu:.0f}x", flush=True)
    return {"scipy_search_rtol": search_rtol, "scipy_tol_scan": sp_scan,
            "scipy": {"rtol": SCIPY_TOL, "trajectories": len(Xs), "periods_each": a.scipy_periods, "wall_s": sp_wall,
                      "cpu_s": sp_cpu, "s_per_trajectory_period": sp_per, "strobe_err_max": float(e_sp.max()),
                      "strobe_err_median": float(np.median(e_sp)), "reference_vs_scipy_1e-13": agree},
            "tol_scan": scan, "matched_tol": chosen,
            "compiled": {"trajectories": len(Xw), "periods_each": a.work_periods, "wall_s": wall,
                         "threads": n_threads, "s_per_trajectory_period": cv_per, "wall_1thread_s": wall1,
                         "s_per_trajectory_period_1thread": cv1_per, "cpu_1thread_s": cpu1,
                         "failed": int((st != 0).sum())},
            "ratio": sp_per / cv_per, "ratio_1thread": sp_per / cv1_per, "ratio_cpu_1thread": ratio_cpu}


def _repeats(hist, k, tol):
    if len(hist) < 2 * k + 1:
        return False
    return all(np.max(np.abs(hist[-1 - j] - hist[-1 - j - k])) <= tol * max(1.0, np.max(np.abs(hist[-1 - j])))
               for j in range(k))


def _near(x, pts, tol):
    return bool(np.any(np.max(np.abs(pts - x), axis=1) <= tol * max(1.0, float(np.max(np.abs(x))))))


def scipy_newton(smap, x, k, rtol=1e-11, close=1e-9, it_max=8):
    """Newton on P^k(x) − x with a forward-difference Jacobian of scipy's k-period map: (x, J) or None."""
    n2 = x.size
    for _ in range(it_max):
        px = smap(x, rtol, k)
        r = px - x
        if np.max(np.abs(r)) <= close * max(1.0, np.max(np.abs(x))):
            J = np.empty((n2, n2))
            for c in range(n2):
                d = 1e-7 * max(1.0, abs(x[c]))
                xp = x.copy()
                xp[c] += d
                J[:, c] = (smap(xp, rtol, k) - px) / d
            return x, J
        J = np.empty((n2, n2))
        for c in range(n2):
            d = 1e-7 * max(1.0, abs(x[c]))
            xp = x.copy()
            xp[c] += d
            J[:, c] = (smap(xp, rtol, k) - px) / d
        try:
            x = x - np.linalg.solve(J - np.eye(n2), r)
        except np.linalg.LinAlgError:
            return None
    return None


def scipy_search(smap, X, kmax, max_periods, rtol):
    """The search's settling rule driven by scipy (module docstring): per start its outcome and time."""
    found, rows = [], []
    for x0 in X:
        t0 = time.perf_counter()
        hist, how = [x0], ("unsettled", 0)
        for _ in range(max_periods):
            hist.append(smap(hist[-1], rtol))
            del hist[:-2 * kmax - 1]
            cap = next((i for i, f in enumerate(found)
                        if f["stable"] and _near(hist[-1], f["points"], CAPTURE_TOL)), None)
            if cap is not None:
                how = ("captured", cap)
                break
            k = next((k for k in range(1, kmax + 1) if _repeats(hist, k, SETTLE_TOL)), None)
            if k is not None:
                how = ("periodic", k)
                break
        if how[0] == "periodic":
            k = how[1]
            res = scipy_newton(smap, hist[-1].copy(), k)
            if res is not None:
                xo, J = res
                pts = [xo]
                for _ in range(k - 1):
                    pts.append(smap(pts[-1], 1e-11))
                stable = bool(np.max(np.abs(np.linalg.eigvals(J))) <= 1.0 + 1e-6)
                if not any(f["k"] == k and _near(xo, f["points"], 1e-4) for f in found):
                    found.append({"k": k, "points": np.array(pts), "stable": stable})
        rows.append({"outcome": how[0], "k": int(how[1]), "wall_s": time.perf_counter() - t0})
    return rows, found


def search(name, system, pa, fe, form, smap, a, sp_rtol):
    """Part 2: the compiled search with --starts starts and with the first --scipy-starts, and scipy's."""
    find_system_attractors(system, pa, fe, n_starts=2, nonperiodic=False, seeds=False)  # compile / load
    mp = default_max_periods(system, fe, SETTLE_TOL)
    # the settling alone (scipy's side settles, it does not judge the unsettled starts)
    wall, cpu, r = timed(find_system_attractors, system, pa, fe, n_starts=a.starts, repeat=2, nonperiodic=False,
                         seeds=False)
    wall_few, cpu_few, r_few = timed(find_system_attractors, system, pa, fe, n_starts=a.scipy_starts, repeat=2,
                                     nonperiodic=False, seeds=False)
    X = _start_box(system, form, pa, fe, a.scipy_starts, 0)
    smap.periods = 0
    t0, c0 = time.perf_counter(), time.process_time()
    rows, found = scipy_search(smap, X, KMAX, mp, sp_rtol)
    sp_wall, sp_cpu = time.perf_counter() - t0, time.process_time() - c0
    sp_scaled = sp_wall / a.scipy_starts * a.starts
    R = {"max_periods": mp, "kmax": KMAX, "settle_tol": SETTLE_TOL, "rtol": SEARCH_RTOL, "scipy_rtol": sp_rtol,
         "threads": numba.get_num_threads(),
         "compiled": {"starts": a.starts, "wall_s": wall, "cpu_s": cpu, "n_unsettled": r.n_unsettled,
                      "n_failed": r.n_failed,
                      "attractors": [{"period": int(x.period), "hits": int(x.hits), "stable": bool(x.stable)}
                                     for x in r]},
         "compiled_same_starts": {"starts": a.scipy_starts, "wall_s": wall_few, "cpu_s": cpu_few,
                                  "n_unsettled": r_few.n_unsettled,
                                  "periods": sorted(int(x.period) for x in r_few)},
         "scipy": {"starts": a.scipy_starts, "wall_s": sp_wall, "cpu_s": sp_cpu, "periods_integrated": smap.periods,
                   "s_per_period": sp_wall / max(smap.periods, 1), "outcomes": rows,
                   "periods": sorted(f["k"] for f in found), "wall_s_scaled_to_starts": sp_scaled},
         "ratio": sp_scaled / wall, "ratio_same_starts": sp_wall / wall_few,
         "ratio_cpu": sp_cpu / a.scipy_starts * a.starts / cpu, "ratio_cpu_same_starts": sp_cpu / cpu_few}
    print(f"  [{name}] search (scipy at rtol {sp_rtol:.0e}): compiled {a.starts} starts {wall:.2f} s "
          f"({len(r)} attractors, periods "
          f"{[x.period for x in r]}, {r.n_unsettled} unsettled); scipy {a.scipy_starts} starts {sp_wall:.1f} s "
          f"-> scaled {sp_scaled:.0f} s: {R['ratio']:.0f}x; same {a.scipy_starts} starts: compiled {wall_few:.3f} s, "
          f"{R['ratio_same_starts']:.0f}x; CPU time {R['ratio_cpu']:.0f}x, "
          f"same starts {R['ratio_cpu_same_starts']:.0f}x",
          flush=True)
    return R


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small work units (a smoke test)")
    ap.add_argument("--starts", type=int, default=64, help="starts of the compiled search (64)")
    ap.add_argument("--scipy-starts", type=int, default=2, help="starts of the scipy-driven search (2)")
    ap.add_argument("--scipy-traj", type=int, default=4, help="scipy trajectories of part 1 (4)")
    ap.add_argument("--scipy-periods", type=int, default=5, help="periods of each (5)")
    ap.add_argument("--work-starts", type=int, default=64, help="compiled trajectories of part 1 (64)")
    ap.add_argument("--work-periods", type=int, default=100, help="periods of each (100)")
    ap.add_argument("--only", default=None, help="one system: rocking, file_2N or file_0.1N")
    ap.add_argument("--no-search", action="store_true", help="part 1 only")
    ap.add_argument("--search-scipy-rtol", type=float, default=None,
                    help="scipy's rtol in the search (default: the loosest of 1e-10, 3e-11, ... whose error is <= "
                         "the compiled search's at rtol 1e-10)")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all)")
    ap.add_argument("--out", default=str(result_path(__name__)))
    a = ap.parse_args(argv)
    if a.quick:
        a.starts, a.scipy_starts, a.scipy_traj, a.scipy_periods, a.work_starts, a.work_periods = 8, 1, 2, 2, 8, 10
    if a.threads:
        numba.set_num_threads(a.threads)
    n_threads = numba.get_num_threads()
    R = {"environment": {"python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
                         "numba": numba.__version__, "cpu": platform.processor() or platform.machine(),
                         "os_cpu_count": os.cpu_count(), "numba_threads": n_threads,
                         "load_average_1min": os.getloadavg()[0] if hasattr(os, "getloadavg") else None},
         "command": "python -m benchmarks system " + " ".join(argv if argv is not None else sys.argv[1:]),
         "systems": {}}
    print(f"n-DOF kernels vs scipy DOP853; numba threads = {n_threads}")
    for name, system, pa, fe, label in systems():
        if a.only and name != a.only:
            continue
        form = system.kernel_form(pa, fe)
        sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
        smap = ScipyMap(system, pa, fe, form)
        X = _start_box(system, form, pa, fe, max(a.scipy_traj, 8), 0)
        out = {"label": label, "pa_newton": pa, "fe_hz": fe, "n": system.n, "contacts": len(system.contacts)}
        km.strobe_map(sa, X[0].copy(), 1, 1e-10, 1e-10, np.empty(X.shape[1]), np.empty((0, 0)))
        print(f"{name}: {label}", flush=True)
        out["equal_accuracy"] = equal_accuracy(name, sa, smap, X, a, n_threads)
        if not a.no_search:
            sp_rtol = a.search_scipy_rtol or out["equal_accuracy"]["scipy_search_rtol"]
            out["search"] = search(name, system, pa, fe, form, smap, a, sp_rtol)
        R["systems"][name] = out
    line = "-" * 96
    print(line)
    print("ratios scipy / compiled: integration at equal accuracy (wall, all threads | CPU, one core each); "
          "attractor search (wall | CPU)")
    print(f"{'system':<12}{'tol':>8}{'integ. wall':>13}{'integ. CPU':>12}{'search wall':>13}{'search CPU':>12}")
    for name, o in R["systems"].items():
        e = o["equal_accuracy"]
        s = o.get("search", {})
        print(f"{name:<12}{e['matched_tol']:>8.0e}{e['ratio']:>12.0f}x{e['ratio_cpu_1thread']:>11.0f}x"
              f"{s.get('ratio', math.nan):>12.0f}x{s.get('ratio_cpu', math.nan):>11.0f}x")
    print(line)
    R["args"] = vars(a)
    Path(a.out).write_text(json.dumps(R, indent=1))
    print(f"results written to {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
