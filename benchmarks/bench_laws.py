"""Integration rate per contact law: contactvib's compiled flow against scipy on the same work.

For each law (the paper's power law, a preload and Hunt-Crossley damping on the power spring, the
exponential spring, all on the Taylor flow; the 301-row table on the Taylor flow interval by
interval, each row an event) the same starts are integrated over the same periods at 0.65 Q,
360 Hz at one tolerance (1e-8) by

* contactvib: ``_kernels.taylor.advance_state`` (the attractor search's transient integrator),
* scipy: ``solve_ivp(method="DOP853")`` on the same nondimensional right-hand side (the package's
  own ``flow.acceleration``, compiled, so that only the integrator differs), one segment per
  contact/flight mode with the switching instants located by ``events``.

Each time is the best of three passes (both sides; the machine may be shared). Both end states
are compared with a tight scipy run (rtol 1e-12) so that the ratio is at equal accuracy; the
ratio is reported per law and the attractor search's time (``find_attractors`` with 64 starts)
beside it. Run::

    python benchmarks/bench_laws.py [--out benchmarks/results_laws.json]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import time

import numba
import numpy as np
from numba import njit, prange

from benchmarks import result_path
from contactvib import ContactModel, ExponentialLaw, TableLaw, find_attractors
from contactvib._kernels.flow import acceleration
from contactvib._kernels.taylor import advance_state
from contactvib.testing import integrate_modes


def laws():
    power = ContactModel()
    table = TableLaw.from_function(lambda y: 0.0009 * 4.52e16 * y**2, 3e-6, 301, source="power law, 301 rows")
    return {"power (Taylor)": power,
            "exponential (Taylor)": ContactModel(law=ExponentialLaw()),
            "table (301 rows, Taylor)": ContactModel(law=table),
            "power + Hunt-Crossley (Taylor)": ContactModel(damping="hunt-crossley"),
            "power + preload 1 N (Taylor)": ContactModel(preload=1.0)}


def scipy_flow(z, t0, t1, par, rtol):
    """(x, x') at t1 from z at t0: scipy DOP853 per mode, switching at located crossings of x = 0
    (:func:`contactvib.testing.integrate_modes` on the kernels' acceleration of each law)."""
    def f(contact):
        return lambda tt, s: [s[1], acceleration(contact, tt, s[0], s[1], par)]

    y = np.array(z, float)
    return integrate_modes(f(True), f(False), y, t0, t1, contact=bool(y[0] > 0.0), rtol=rtol, atol=rtol).y


@njit(parallel=True, cache=True)
def _advance_many(Z, t_end, par, tol):
    """The starts of ``Z`` (rows, in place) advanced to ``t_end`` in parallel: one start per
    thread at a time (numba threads, the attractor search's kind of parallelism); total steps."""
    steps = np.zeros(Z.shape[0], np.int64)
    for i in prange(Z.shape[0]):
        y = Z[i].copy()
        _c, _h, ns, _tf, _ne, _st = advance_state(y, 0.0, t_end, y[0] > 0, 0.01, par, tol, 10**8)
        Z[i] = y
        steps[i] = ns
    return steps.sum()


def bench(model, n_starts=16, periods=20, tol=1e-8, seed=0, passes=3):
    exc = model.excitation(0.65, 360.0)
    par = exc.kernel_parameters()
    T = exc.tau_period
    rng = np.random.default_rng(seed)
    Z = np.column_stack([rng.uniform(0.2, 2.0, n_starts), rng.uniform(-2.0, 2.0, n_starts)])
    advance_state(Z[0].copy(), 0.0, T, Z[0, 0] > 0, 0.01, par, tol, 10**7)  # compile
    t_cv = math.inf
    for _ in range(passes):
        t = time.perf_counter()
        ends = []
        for z in Z:
            y = z.copy()
            advance_state(y, 0.0, periods * T, y[0] > 0, 0.01, par, tol, 10**8)
            ends.append(y)
        t_cv = min(t_cv, time.perf_counter() - t)
    # the same starts on every core (numba threads), the work repeated 4 times so that each
    # thread has several starts (the ratio is per start-period, as the 1-thread one)
    _advance_many(Z[:2].copy(), T, par, tol)  # compile
    t_cv_threads = math.inf
    for _ in range(passes):
        Zp = np.tile(Z, (4, 1))
        t = time.perf_counter()
        n_steps = _advance_many(Zp, periods * T, par, tol)
        t_cv_threads = min(t_cv_threads, (time.perf_counter() - t) / 4)
    k = max(2, n_starts // 8)
    t_sp = math.inf
    for _ in range(passes):
        t = time.perf_counter()
        sp = [scipy_flow(z, 0.0, periods * T, par, tol) for z in Z[:k]]
        t_sp = min(t_sp, (time.perf_counter() - t) * n_starts / k)
    ref = [scipy_flow(z, 0.0, periods * T, par, 1e-12) for z in Z[:k]]

    def err(a):
        return max(float(np.max(np.abs(x - r)) / max(1.0, float(np.max(np.abs(r))))) for x, r in zip(a, ref))

    t = time.perf_counter()
    found = find_attractors(exc, n_starts=64)
    t_search = time.perf_counter() - t
    return {"f_n0_hz": model.f_n0, "contactvib_s": t_cv, "scipy_s": t_sp, "ratio": t_sp / t_cv,
            "threads": numba.get_num_threads(), "contactvib_threads_s": t_cv_threads,
            "ratio_threads": t_sp / t_cv_threads, "steps_per_period": n_steps / (4 * n_starts * periods),
            "error_contactvib": err(ends[:k]), "error_scipy": err(sp),
            "search_64_starts_s": t_search, "attractors": [round(a.app_um, 5) for a in found],
            "load_average_1min": os.getloadavg()[0],
            "trajectory_periods": n_starts * periods}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    rows = {}
    for name, model in laws().items():
        rows[name] = r = bench(model)
        print(f"{name:30s} contactvib {r['contactvib_s']:.3f} s  scipy {r['scipy_s']:.2f} s  ratio "
              f"{r['ratio']:.0f}x ({r['threads']} threads: {r['ratio_threads']:.0f}x, "
              f"{r['steps_per_period']:.0f} steps/period)  "
              f"error {r['error_contactvib']:.1e} vs {r['error_scipy']:.1e}  "
              f"search(64) {r['search_64_starts_s']:.2f} s  load {r['load_average_1min']:.1f}", flush=True)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump({"benchmark": "bench_laws", "operating_point": "0.65 Q, 360 Hz", "tol": 1e-8,
                       "laws": rows, "note": "ratio = scipy time / contactvib time on the same starts and "
                                             "periods (scipy's scaled from a subset), one thread, each "
                                             "the best of 3 passes; "
                                             "ratio_threads: contactvib on all numba threads (cores)"}, fh, indent=1,
                      default=lambda x: None if isinstance(x, float) and not math.isfinite(x) else x)


if __name__ == "__main__":
    main()
