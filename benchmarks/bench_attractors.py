#!/usr/bin/env python
"""contactvib compiled kernels vs scipy ``solve_ivp`` (DOP853) at equal stroboscopic accuracy.

Standalone script (not a pytest test). Run from the repository root::

    PYTHONPATH=src python benchmarks/bench_attractors.py            # full run (~1-2 min)
    PYTHONPATH=src python benchmarks/bench_attractors.py --quick    # smaller work unit

Operating point: the paper's defaults, P_a = 0.65 Q, f_e = 360 Hz, whose four coexisting
period-1 attractors have the phase-0 orbit points (x = y/y0, v) ~ (-45.6107, 0.5061),
(1.3016, -0.1249), (3.3857, -1.2839), (-0.2552, 0.5431).

What is measured (all in one run, results printed and written to benchmarks/results_attractors.json):

1. Reference: the four orbits refined by Newton shooting at rtol = atol = 1e-13, and a
   reference one-period stroboscopic map P_ref(z) = strobe_map(z, 1, par, 1e-13, 1e-13).
2. Stroboscopic error of a method = max over all recorded strobe points z_n of
   |P_method(z_n) - P_ref(z_n)|_inf / max(1, |z|_inf)   (one-period map error, relative).
3. Work unit: 4 orbits x S perturbed starts x P periods = N trajectory-periods.
   * scipy: DOP853, rtol = atol = 1e-10, mode by mode (terminal events at x = 0), a few
     trajectories, cost scaled per trajectory-period (one core, pure Python loop).
   * contactvib: ``taylor.advance_state`` (the Taylor-series flow that the attractor search
     integrates its transients with) in a numba ``@njit(parallel=True)`` ensemble over all
     starts (both cores), starts interleaved across the orbits. Its tolerance is the loosest
     one whose stroboscopic error is <= scipy's. The same for ``flow.advance`` (DOP853, the
     shooting integrator) as a second row.
4. Newton (``shooting.newton_orbit``) of the four orbits to closure 1e-8, and ``settle.settle_many``
   from 64 perturbed starts per orbit (transient + period detection + Newton to 1e-8).
5. Compile time: first call vs second call, with the on-disk numba cache (warm) and in a fresh
   process with an empty NUMBA_CACHE_DIR (cold compile).
6. End-to-end ``python -m contactvib.cli attractors --pa 0.65 --fe 360 --json`` as a new process,
   compared with the wall time of ONE scipy DOP853 300-period trajectory.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numba
import numpy as np
import scipy
from numba import njit, prange

from benchmarks import result_path
from contactvib.model import ContactModel
from contactvib.testing import integrate_modes, power_law_rhs

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
SRC = ROOT / "src"

PA, FE = 0.65, 360.0
ORBIT_GUESS = np.array([[-45.6107, 0.5061], [1.3016, -0.1249], [3.3857, -1.2839], [-0.2552, 0.5431]])
RTOL_REF = 1e-13
SCIPY_TOL = 1e-10
TOL_SCAN = [1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10, 3e-11, 1e-11, 3e-12, 1e-12]
TOL_SCAN_TAYLOR = [1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 1e-10, 1e-11, 1e-12]
PERTURB = 1e-3  # relative perturbation of the starts around each orbit point


# --------------------------------------------------------------------------------------------
# compiled ensemble (benchmark-local; library kernels are called, not modified)
# --------------------------------------------------------------------------------------------
def _make_ensemble(method="taylor"):
    """Compiled ensemble over all starts; ``method`` "taylor": ``taylor.advance_state`` (the
    library's transient integrator), "dop853": ``flow.advance`` (its shooting integrator)."""
    from contactvib._kernels.flow import REC_WIDTH, STATUS_OK, advance, initial_mode
    from contactvib._kernels.shooting import MAX_STEPS_PER_PERIOD
    from contactvib._kernels.taylor import advance_state

    use_taylor = method == "taylor"

    @njit(parallel=True, cache=False)
    def ensemble(Z, n_periods, par, rtol, atol):
        """Integrate every row of Z for n_periods periods; hist[i, n] = strobe point n."""
        N = Z.shape[0]
        T = 2.0 * math.pi / par[4]
        hist = np.empty((N, n_periods + 1, 2))
        steps = np.zeros(N, np.int64)
        status = np.zeros(N, np.int64)
        for i in prange(N):
            y = np.empty(2)
            y[0] = Z[i, 0]
            y[1] = Z[i, 1]
            hist[i, 0, 0] = y[0]
            hist[i, 0, 1] = y[1]
            contact = initial_mode(y[0], y[1])
            h = 0.01
            rec = np.empty((0, REC_WIDTH))
            for n in range(1, n_periods + 1):
                if use_taylor:
                    contact, h, ns, _tf, _ne, st = advance_state(y, 0.0, T, contact, h, par, rtol,
                                                                 MAX_STEPS_PER_PERIOD)
                else:
                    contact, h, _ir, ns, _tf, _ne, st = advance(y, 0.0, T, contact, h, par, rtol,
                                                                atol, rec, 0, MAX_STEPS_PER_PERIOD)
                steps[i] += ns
                if st != STATUS_OK:
                    status[i] = st
                    for m in range(n, n_periods + 1):
                        hist[i, m, 0] = np.nan
                        hist[i, m, 1] = np.nan
                    break
                hist[i, n, 0] = y[0]
                hist[i, n, 1] = y[1]
        return hist, steps, status

    return ensemble


def strobe_error(z_from, z_to, ref_map):
    """Relative one-period error of the pairs z_from -> z_to against ref_map(z_from)."""
    ref = ref_map(z_from)
    sc = np.maximum(1.0, np.max(np.abs(ref), axis=1))
    e = np.max(np.abs(z_to - ref), axis=1) / sc
    return e


# --------------------------------------------------------------------------------------------
# scipy mode-by-mode DOP853
# --------------------------------------------------------------------------------------------
def make_scipy(par):
    """The reference one-period map: :func:`contactvib.testing.integrate_modes` (DOP853, mode by
    mode, terminal events at x = 0) on the paper's equation, counting evaluations and segments."""
    f_contact, f_flight = power_law_rhs(par)
    T = 2.0 * math.pi / float(par[4])

    def one_period(z, rtol, atol, counters):
        """Stroboscopic map over one period [0, T] (phase 0 at t = 0), mode by mode."""
        run = integrate_modes(f_contact, f_flight, np.asarray(z, float), 0.0, T, rtol=rtol, atol=atol)
        counters["nfev"] += run.nfev
        counters["segments"] += len(run.segments)
        counters["events"] += run.n_switches
        return run.y

    return one_period, T


# --------------------------------------------------------------------------------------------
def timed(fn, *a, repeat=1, **kw):
    best = math.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*a, **kw)
        best = min(best, time.perf_counter() - t0)
    return best, out


def starts_around(orbits, per_orbit, rng):
    Z = []
    for z in orbits:
        sc = max(1.0, abs(z[0]), abs(z[1]))
        dz = rng.uniform(-1, 1, size=(per_orbit, 2)) * PERTURB * sc
        dz[0] = 0.0  # the first start of each group is the orbit point itself
        Z.append(z + dz)
    return np.ascontiguousarray(np.concatenate(Z))


COLD_COMPILE_SNIPPET = r"""
import json, time, numpy as np
from contactvib.model import ContactModel
par = ContactModel().excitation(%r, %r).kernel_parameters()
out = {}
t0 = time.perf_counter()
from contactvib._kernels.shooting import strobe_map
from contactvib._kernels.settle import settle_many
out["import_s"] = time.perf_counter() - t0
z = np.array([1.3016, -0.1249]); oz = np.empty(2); e = np.empty((0, 0))
t0 = time.perf_counter(); strobe_map(z, 1, par, 1e-10, 1e-10, oz, e); out["strobe_map_first_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); strobe_map(z, 1, par, 1e-10, 1e-10, oz, e); out["strobe_map_second_s"] = time.perf_counter() - t0
Z = np.array([[1.3016, -0.1249]] * 2); ph = np.zeros(2)
t0 = time.perf_counter(); settle_many(Z, ph, par, 1, 4, 50, 1e-4, 1e-8, 1e-12, 1e-8, 4); out["settle_many_first_s"] = time.perf_counter() - t0
t0 = time.perf_counter(); settle_many(Z, ph, par, 1, 4, 50, 1e-4, 1e-8, 1e-12, 1e-8, 4); out["settle_many_second_s"] = time.perf_counter() - t0
print("RESULT " + json.dumps(out))
"""


def compile_times_cold():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    with tempfile.TemporaryDirectory() as d:
        env["NUMBA_CACHE_DIR"] = d
        t0 = time.perf_counter()
        p = subprocess.run([sys.executable, "-c", COLD_COMPILE_SNIPPET % (PA, FE)], env=env,
                           capture_output=True, text=True, cwd=ROOT)
        wall = time.perf_counter() - t0
    for line in p.stdout.splitlines():
        if line.startswith("RESULT "):
            r = json.loads(line[7:])
            r["process_wall_s"] = wall
            return r
    return {"error": (p.stderr or p.stdout)[-500:]}


def run_cli():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(SRC) + os.pathsep + env.get("PYTHONPATH", "")
    cmd = [sys.executable, "-m", "contactvib", "attractors", "--pa", str(PA), "--fe", str(FE), "--json"]
    runs = []
    for _ in range(2):
        t0 = time.perf_counter()
        try:
            p = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=ROOT, timeout=600)
        except Exception as exc:  # noqa: BLE001
            return {"available": False, "message": f"CLI could not run: {exc}"}
        wall = time.perf_counter() - t0
        if p.returncode != 0:
            return {"available": False, "message": f"CLI exited {p.returncode}: {(p.stderr or '')[-300:].strip()}"}
        runs.append(wall)
    try:
        data = json.loads(p.stdout)
        atts = data.get("attractors", data if isinstance(data, list) else [])
        n_att = len(atts)
        periods = [a.get("period") for a in atts if isinstance(a, dict)]
    except Exception:  # noqa: BLE001
        n_att, periods = None, None
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", "import contactvib.cli, contactvib.steady.attractors"], env=env, cwd=ROOT)
    t_import = time.perf_counter() - t0
    return {"available": True, "python_start_and_import_s": t_import, "command": " ".join(["PYTHONPATH=src", "python"] + cmd[1:]),
            "wall_first_s": runs[0], "wall_second_s": runs[1], "n_attractors": n_att,
            "periods": periods}


# --------------------------------------------------------------------------------------------
def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="smaller work unit (for a smoke test)")
    ap.add_argument("--starts", type=int, default=64, help="contactvib starts per orbit (64)")
    ap.add_argument("--periods", type=int, default=200, help="periods per contactvib trajectory (200)")
    ap.add_argument("--scipy-starts", type=int, default=8, help="scipy starts per orbit (8)")
    ap.add_argument("--scipy-periods", type=int, default=10, help="periods per scipy trajectory (10)")
    ap.add_argument("--scipy-long", type=int, default=300, help="periods of the single scipy run (300)")
    ap.add_argument("--threads", type=int, default=None, help="numba threads (default: all)")
    ap.add_argument("--no-cli", action="store_true")
    ap.add_argument("--no-cold", action="store_true", help="skip the cold-compile subprocess")
    ap.add_argument("--out", default=str(result_path(__name__)))
    a = ap.parse_args(argv)
    if a.quick:
        a.starts, a.periods, a.scipy_starts, a.scipy_periods, a.scipy_long = 16, 5, 1, 2, 30
    if a.threads:
        numba.set_num_threads(a.threads)
    n_threads = numba.get_num_threads()
    rng = np.random.default_rng(12345)
    R: dict = {"operating_point": {"pa_Q": PA, "fe_Hz": FE},
               "environment": {"python": platform.python_version(), "numpy": np.__version__,
                               "scipy": scipy.__version__, "numba": numba.__version__,
                               "cpu": platform.processor() or platform.machine(),
                               "os_cpu_count": os.cpu_count(), "numba_threads": n_threads,
                               "threading_layer": None}}
    print(f"contactvib vs scipy DOP853 at P_a={PA} Q, f_e={FE} Hz; numba threads = {n_threads}")

    par = np.ascontiguousarray(ContactModel().excitation(PA, FE).kernel_parameters(), dtype=np.float64)
    T = 2.0 * math.pi / par[4]
    R["par"] = par.tolist()
    R["period_tau"] = T

    # ---------------- compile times (warm on-disk cache, this process) ------------------------
    from contactvib._kernels.settle import settle_many
    from contactvib._kernels.shooting import newton_orbit, strobe_map

    nojac = np.empty((0, 0))
    comp = {}
    z0 = ORBIT_GUESS[1].copy()
    oz = np.empty(2)
    comp["strobe_map_first_s"], _ = timed(strobe_map, z0, 1, par, 1e-10, 1e-10, oz, nojac)
    comp["strobe_map_second_s"], _ = timed(strobe_map, z0, 1, par, 1e-10, 1e-10, oz, nojac)
    ensemble = _make_ensemble()
    Z2 = np.ascontiguousarray(ORBIT_GUESS[:2].copy())
    comp["ensemble_first_s"], _ = timed(ensemble, Z2, 1, par, 1e-10, 1e-10)   # own kernel: real JIT
    comp["ensemble_second_s"], _ = timed(ensemble, Z2, 1, par, 1e-10, 1e-10)
    sm_args = (np.ascontiguousarray(ORBIT_GUESS[:2].copy()), np.zeros(2), par, 1, 4, 50, 1e-4, 1e-8, 1e-12, 1e-8, 4)
    comp["settle_many_first_s"], _ = timed(settle_many, *sm_args)
    comp["settle_many_second_s"], _ = timed(settle_many, *sm_args)
    try:
        R["environment"]["threading_layer"] = numba.threading_layer()
    except Exception:  # noqa: BLE001
        pass
    R["compile_warm_cache"] = comp
    if not a.no_cold:
        print("cold compile in a fresh process with an empty NUMBA_CACHE_DIR ...", flush=True)
        R["compile_cold"] = compile_times_cold()

    # ---------------- reference orbits and reference map ---------------------------------------
    orbits = np.empty((4, 2))
    Ms = np.empty((4, 2, 2))
    ref_res = []
    for j, g in enumerate(ORBIT_GUESS):
        oM = np.empty((2, 2))
        st, res = newton_orbit(g.copy(), 1, par, RTOL_REF, RTOL_REF, 1e-12, 20, orbits[j], oM)
        Ms[j] = oM
        ref_res.append(float(res))
        if st != 0:
            print(f"WARNING: reference Newton for orbit {j} status {st}, residual {res:.2e}")
    mult = [np.abs(np.linalg.eigvals(M)).max() for M in Ms]
    R["reference_orbits"] = [{"x": float(o[0]), "v": float(o[1]), "closure": r, "floquet_abs_max": float(m)}
                             for o, r, m in zip(orbits, ref_res, mult)]

    ref_kernel = _make_ensemble("dop853")  # one period at rtol=atol=1e-13 (DOP853), in parallel

    def ref_map(Zp):
        Zp = np.ascontiguousarray(Zp, dtype=np.float64)
        h, _s, st = ref_kernel(Zp, 1, par, RTOL_REF, RTOL_REF)
        if st.any():
            raise RuntimeError("reference integration failed")
        return h[:, 1, :]

    # ---------------- scipy: per-period cost and strobe error at 1e-10 ------------------------
    one_period, _ = make_scipy(par)
    Zs = starts_around(orbits, a.scipy_starts, rng)
    cnt = {"nfev": 0, "segments": 0, "events": 0}
    zf, zt, per_orbit_time = [], [], np.zeros(4)
    t_all0 = time.perf_counter()
    for i, z in enumerate(Zs):
        j = i // a.scipy_starts
        y = z.copy()
        t0 = time.perf_counter()
        for _ in range(a.scipy_periods):
            y1 = one_period(y, SCIPY_TOL, SCIPY_TOL, cnt)
            zf.append(y.copy())
            zt.append(y1.copy())
            y = y1
        per_orbit_time[j] += time.perf_counter() - t0
    scipy_wall = time.perf_counter() - t_all0
    # best of three passes, as for contactvib (timed(..., repeat=3)); the first pass gave the data
    for _rep in range(2):
        t_rep0 = time.perf_counter()
        for z in Zs:
            y = z.copy()
            for _ in range(a.scipy_periods):
                y = one_period(y, SCIPY_TOL, SCIPY_TOL, {"nfev": 0, "segments": 0, "events": 0})
        scipy_wall = min(scipy_wall, time.perf_counter() - t_rep0)
    n_sp = len(Zs) * a.scipy_periods
    e_sp = strobe_error(np.array(zf), np.array(zt), ref_map)
    # cross-check the reference with scipy itself at 1e-13 on a few points
    chk_pts = np.array(zf[:: max(1, len(zf) // 4)][:4])
    cc = {"nfev": 0, "segments": 0, "events": 0}
    sp13 = np.array([one_period(z, RTOL_REF, RTOL_REF, cc) for z in chk_pts])
    ref13 = ref_map(chk_pts)
    ref_agree = float(np.max(np.max(np.abs(sp13 - ref13), axis=1) / np.maximum(1, np.max(np.abs(ref13), axis=1))))
    R["scipy"] = {"rtol": SCIPY_TOL, "atol": SCIPY_TOL, "method": "DOP853",
                  "trajectories": len(Zs), "periods_each": a.scipy_periods, "trajectory_periods": n_sp,
                  "wall_s": scipy_wall, "s_per_trajectory_period": scipy_wall / n_sp,
                  "s_per_period_by_orbit": (per_orbit_time / (a.scipy_starts * a.scipy_periods)).tolist(),
                  "nfev_per_period": cnt["nfev"] / n_sp, "events_per_period": cnt["events"] / n_sp,
                  "strobe_err_max": float(e_sp.max()), "strobe_err_median": float(np.median(e_sp)),
                  "reference_vs_scipy_1e-13": ref_agree}
    print(f"scipy DOP853 1e-10: {scipy_wall / n_sp * 1e3:.1f} ms per trajectory-period, "
          f"strobe error max {e_sp.max():.2e}; ref(contactvib 1e-13) vs scipy 1e-13: {ref_agree:.1e}")

    # ---------------- contactvib: tolerance scan on scipy's own starts and periods -------------
    # starts interleaved across the four orbits (a multi-start's starts come in random order; a
    # block per orbit would hand one thread all the cheap orbits and the other the dear ones)
    Zc = np.ascontiguousarray(starts_around(orbits, a.starts, rng).reshape(4, a.starts, 2)
                              .transpose(1, 0, 2).reshape(-1, 2))
    near = np.tile(orbits, (a.starts, 1))
    sub = Zs  # same start points and number of periods as the scipy sample: like for like
    n_sub_p = a.scipy_periods
    N_tp = len(Zc) * a.periods
    target = e_sp.max()

    def measure(ens, tols):
        scan = []
        for tol in tols:
            hist, steps, st = ens(sub, n_sub_p, par, tol, tol)
            zfrom = hist[:, :-1, :].reshape(-1, 2)
            zto = hist[:, 1:, :].reshape(-1, 2)
            ok = np.all(np.isfinite(zto), axis=1)
            e = strobe_error(zfrom[ok], zto[ok], ref_map)
            scan.append({"tol": tol, "strobe_err_max": float(e.max()), "strobe_err_median": float(np.median(e)),
                         "steps_per_period": float(steps.sum() / (len(sub) * n_sub_p)),
                         "failed": int((st != 0).sum())})
        chosen = next((s["tol"] for s in scan if s["strobe_err_max"] <= target and s["failed"] == 0), tols[-1])
        # the work unit at the matched tolerance (and at scipy's 1e-10)
        work = {}
        for label, tol in (("matched", chosen), ("same_tol_1e-10", SCIPY_TOL)):
            wall, (hist, steps, st) = timed(ens, Zc, a.periods, par, tol, tol, repeat=3)
            zfrom = hist[:, :-1, :].reshape(-1, 2)
            zto = hist[:, 1:, :].reshape(-1, 2)
            ok = np.all(np.isfinite(zto), axis=1)
            e = strobe_error(zfrom[ok], zto[ok], ref_map)
            dist = np.max(np.abs(hist[:, -1, :] - near), axis=1) / np.maximum(1, np.max(np.abs(near), axis=1))
            work[label] = {"tol": tol, "wall_s": wall, "trajectory_periods": N_tp, "threads": n_threads,
                           "tp_per_s": N_tp / wall, "tp_per_s_per_core": N_tp / wall / n_threads,
                           "steps_per_period": float(steps.sum() / N_tp), "failed": int((st != 0).sum()),
                           "strobe_err_max": float(e.max()), "strobe_err_median": float(np.median(e)),
                           "final_dist_to_orbit_max": float(dist.max())}
        # the same work unit on ONE thread (true per-core throughput, no scaling assumption)
        numba.set_num_threads(1)
        wall1, _ = timed(ens, Zc, a.periods, par, chosen, chosen, repeat=3)
        numba.set_num_threads(n_threads)
        work["matched_1thread"] = {"tol": chosen, "wall_s": wall1, "trajectory_periods": N_tp, "threads": 1,
                                   "tp_per_s": N_tp / wall1, "tp_per_s_per_core": N_tp / wall1,
                                   "parallel_efficiency": wall1 / (work["matched"]["wall_s"] * n_threads)}
        return scan, chosen, work

    scan, chosen, work = measure(ensemble, TOL_SCAN_TAYLOR)
    R["contactvib_tol_scan"] = scan
    R["contactvib_matched_tol"] = chosen
    R["contactvib_ensemble"] = work
    dop = _make_ensemble("dop853")
    scan_d, chosen_d, work_d = measure(dop, TOL_SCAN)
    R["contactvib_dop853"] = {"tol_scan": scan_d, "matched_tol": chosen_d, "ensemble": work_d}
    sp_per = scipy_wall / n_sp
    W = {"trajectory_periods": N_tp, "description": f"4 orbits x {a.starts} starts x {a.periods} periods",
         "scipy_wall_s_scaled": sp_per * N_tp, "scipy_tp_per_s_per_core": 1.0 / sp_per,
         "scipy_strobe_err_max": float(e_sp.max()),
         "contactvib_tol": chosen, "contactvib_wall_s": work["matched"]["wall_s"],
         "contactvib_tp_per_s_per_core": work["matched"]["tp_per_s_per_core"],
         "contactvib_strobe_err_max": work["matched"]["strobe_err_max"],
         "speedup_wall": sp_per * N_tp / work["matched"]["wall_s"],
         "speedup_per_core": work["matched"]["tp_per_s_per_core"] * sp_per,
         "speedup_1thread_vs_scipy": N_tp / work["matched_1thread"]["wall_s"] * sp_per}
    R["equal_accuracy_work_unit"] = W

    # ---------------- steady state to 1e-8: Newton, and settle_many --------------------------
    def newton4():
        out = np.empty((4, 2))
        res = []
        for j, g in enumerate(ORBIT_GUESS):
            oM = np.empty((2, 2))
            st, r = newton_orbit(g.copy(), 1, par, 1e-10, 1e-10, 1e-8, 20, out[j], oM)
            res.append((int(st), float(r)))
        return out, res
    t_newton, (zn, resn) = timed(newton4, repeat=3)
    err_n = np.max(np.abs(zn - orbits), axis=1) / np.maximum(1, np.max(np.abs(orbits), axis=1))
    R["newton_4_orbits"] = {"rtol": 1e-10, "tol": 1e-8, "wall_s": t_newton,
                            "status_residual": resn, "err_vs_reference_max": float(err_n.max())}
    Zsm = starts_around(orbits, a.starts, rng)
    phs = np.zeros(len(Zsm))
    sm = (Zsm, phs, par, 8, 4, 400, 1e-4, 1e-8, 1e-12, 1e-8, 4)
    t_sm, out = timed(settle_many, *sm, repeat=2)
    status, period, nper, _resid, zstar = out[0], out[1], out[2], out[3], out[4]
    okp = (status == 0) & (period == 1)
    near = np.repeat(orbits, a.starts, axis=0)
    err_sm = np.max(np.abs(zstar - near), axis=1) / np.maximum(1, np.max(np.abs(near), axis=1))
    R["settle_many"] = {"starts": len(Zsm), "wall_s": t_sm, "threads": n_threads,
                        "params": {"kmax": 8, "min_periods": 4, "max_periods": 400, "detect_tol": 1e-4,
                                   "rtol_transient": 1e-8, "rtol_refine": 1e-12, "tol": 1e-8},
                        "period1_found": int(okp.sum()), "mean_transient_periods": float(nper.mean()),
                        "err_vs_reference_max": float(err_sm[okp].max()) if okp.any() else None}

    # ---------------- end-to-end CLI vs one scipy 300-period trajectory ----------------------
    if a.no_cli:
        R["cli"] = {"available": False, "message": "skipped (--no-cli)"}
    else:
        print("end-to-end CLI (new process, twice) ...", flush=True)
        R["cli"] = run_cli()
        if not R["cli"]["available"]:
            print("CLI part skipped: " + R["cli"]["message"])
    print(f"one scipy DOP853 {a.scipy_long}-period trajectory ...", flush=True)
    z = Zs[a.scipy_starts * 1].copy()  # perturbed start near orbit 2 (1.3016, -0.1249)
    cl = {"nfev": 0, "segments": 0, "events": 0}
    t0 = time.perf_counter()
    for _ in range(a.scipy_long):
        z = one_period(z, SCIPY_TOL, SCIPY_TOL, cl)
    t_long = time.perf_counter() - t0
    R["scipy_long_trajectory"] = {"periods": a.scipy_long, "start_near_orbit": ORBIT_GUESS[1].tolist(),
                                  "wall_s": t_long, "final_dist_to_orbit":
                                  float(np.max(np.abs(z - orbits[1])) / max(1, np.max(np.abs(orbits[1]))))}

    # ---------------- report --------------------------------------------------------------------
    line = "-" * 96
    print("\n" + line)
    print("Reference orbits (Newton, rtol 1e-13):")
    for j, o in enumerate(R["reference_orbits"]):
        print(f"  {j}: x = {o['x']:+.10f}  v = {o['v']:+.10f}  closure {o['closure']:.1e}  |mu|max {o['floquet_abs_max']:.4f}")
    print(line)
    print("contactvib Taylor-series ensemble, tolerance scan (on scipy's starts and periods; one-period strobe error vs rtol-1e-13 DOP853 reference):")
    for s in scan:
        mark = "  <- matched" if s["tol"] == chosen else ""
        print(f"  tol {s['tol']:.0e}: err max {s['strobe_err_max']:.2e}  median {s['strobe_err_median']:.2e}"
              f"  steps/period {s['steps_per_period']:.0f}{mark}")
    print(line)
    print(f"Equal-accuracy work unit: {W['description']} = {N_tp} trajectory-periods")
    hdr = f"{'method':<40}{'tol':>8}{'wall [s]':>12}{'strobe err':>12}{'tp/s/core':>12}{'cores':>7}"
    print(hdr)
    print(f"{'scipy DOP853 (scaled from ' + str(n_sp) + ' tp)':<40}{SCIPY_TOL:>8.0e}{W['scipy_wall_s_scaled']:>12.3f}"
          f"{W['scipy_strobe_err_max']:>12.2e}{W['scipy_tp_per_s_per_core']:>12.1f}{1:>7}")
    for label in ("matched", "matched_1thread", "same_tol_1e-10"):
        w = dict(work[label])
        w.setdefault("strobe_err_max", work["matched"]["strobe_err_max"])
        print(f"{'contactvib Taylor ensemble (' + label + ')':<40}{w['tol']:>8.0e}{w['wall_s']:>12.3f}"
              f"{w['strobe_err_max']:>12.2e}{w['tp_per_s_per_core']:>12.1f}{w['threads']:>7}")
    wd = R["contactvib_dop853"]["ensemble"]["matched"]
    print(f"{'contactvib DOP853 ensemble (matched)':<40}{wd['tol']:>8.0e}{wd['wall_s']:>12.3f}"
          f"{wd['strobe_err_max']:>12.2e}{wd['tp_per_s_per_core']:>12.1f}{wd['threads']:>7}")
    print(f"speed-up at equal accuracy: wall {W['speedup_wall']:.0f}x ({n_threads} threads vs 1 core), "
          f"per core {W['speedup_per_core']:.0f}x, 1 thread vs 1 core {W['speedup_1thread_vs_scipy']:.0f}x")
    print("scipy ms per period by orbit: " + ", ".join(f"{1e3 * t:.1f}" for t in R["scipy"]["s_per_period_by_orbit"])
          + f"; nfev/period {R['scipy']['nfev_per_period']:.0f}, events/period {R['scipy']['events_per_period']:.1f}")
    print(line)
    print(f"Newton, 4 orbits to closure 1e-8 (rtol 1e-10): {t_newton * 1e3:.1f} ms, "
          f"err vs ref {err_n.max():.1e}")
    s = R["settle_many"]
    print(f"settle_many, {s['starts']} starts (transient+detect+Newton 1e-8): {t_sm:.3f} s, "
          f"period-1 found {s['period1_found']}/{s['starts']}, err vs ref {s['err_vs_reference_max']}")
    print(line)
    print("Compile (first call vs second call):")
    for k_, v_ in comp.items():
        print(f"  warm cache  {k_:<26}{v_:10.4f} s")
    for k_, v_ in R.get("compile_cold", {}).items():
        if isinstance(v_, float):
            print(f"  cold cache  {k_:<26}{v_:10.4f} s")
    print(line)
    c = R["cli"]
    if c["available"]:
        print(f"CLI end-to-end (new process): first {c['wall_first_s']:.2f} s, second {c['wall_second_s']:.2f} s, "
              f"{c['n_attractors']} attractors, periods {c['periods']}; python start+import alone "
              f"{c['python_start_and_import_s']:.2f} s")
    else:
        print("CLI end-to-end: skipped - " + c["message"])
    print(f"one scipy DOP853 {a.scipy_long}-period trajectory: {t_long:.2f} s"
          + (f"  (ratio scipy/CLI = {t_long / c['wall_second_s']:.1f})" if c["available"] else ""))
    print(line)
    R["args"] = vars(a)
    Path(a.out).write_text(json.dumps(R, indent=1))
    print(f"results written to {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
