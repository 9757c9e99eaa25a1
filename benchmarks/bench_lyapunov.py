"""Lyapunov spectrum of one attractor: the compiled Benettin loop against scipy's on the same work.

The chaotic attractor of the paper's model at 0.75 Q, 816.5 Hz (a point of it at phase 0), its
spectrum over 20 000 excitation periods in 20 batches at rtol 1e-10
(``contactvib.steady.lyapunov.benettin``: one compiled loop, the monodromy of each period, 2 × 2
Gram–Schmidt, the Liouville trace by quadrature on the dense output), one numba thread, warm
numba cache, best of 3 wall times. scipy: ``contactvib.testing.benettin_reference`` (solve_ivp
DOP853 at the same rtol, located switches, variational equation and trace as extra components,
numpy QR per period) on the first ``--scipy-periods`` (default 200) periods of the same start,
scaled to 20 000; both runs' exponents over those periods are compared. Reports the ratio of the
two times (scipy / contactvib) measured in one run.

    PYTHONPATH=src python -m benchmarks lyapunov [--periods 20000] [--scipy-periods 200]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import time
from pathlib import Path

import numpy as np

from benchmarks import HERE, result_path


def _best(fn, repeats: int):
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--periods", type=int, default=20_000)
    ap.add_argument("--scipy-periods", type=int, default=200)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=str(result_path(__name__)))
    a = ap.parse_args(argv)
    import numba

    numba.set_num_threads(1)
    from contactvib import ContactModel
    from contactvib.steady.lyapunov import benettin
    from contactvib.testing import benettin_reference

    model = ContactModel()
    exc = model.excitation(0.75, 816.5)
    z = np.array(model.units.state(-0.20081059854145153, -4.106686232024136))
    rtol = 1e-10
    benettin(exc, z, 200, 10, 0, rtol)  # compile / load
    t_k, spec = _best(lambda: benettin(exc, z, a.periods, 20, 0, rtol), a.repeats)
    short = benettin(exc, z, a.scipy_periods, 10, 0, rtol)
    t0 = time.perf_counter()
    logr, trace, _z = benettin_reference(exc.kernel_parameters(), z, a.scipy_periods, rtol=rtol)
    t_s = time.perf_counter() - t0
    t_s_scaled = t_s * a.periods / a.scipy_periods
    ref = np.sort(logr.mean(axis=0))[::-1]
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=HERE, capture_output=True, text=True)
    res = {
        "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        "load_average_1min": os.getloadavg()[0],
        "git_head": head.stdout.strip(),
        "numba_threads": 1,
        "attractor": {"pa_over_q": 0.75, "fe_hz": 816.5, "y_um": -0.20081059854145153,
                      "ydot_mm_s": -4.106686232024136},
        "rtol": rtol,
        "periods": a.periods,
        "contactvib_s": t_k,
        "contactvib_periods_per_s": a.periods / t_k,
        "scipy_periods": a.scipy_periods,
        "scipy_s": t_s,
        "scipy_s_scaled_to_periods": t_s_scaled,
        "speedup_scipy_over_contactvib": t_s_scaled / t_k,
        "target_under_2_s": bool(t_k < 2.0),
        "lyapunov_per_s": [float(v) for v in spec.exponents_per_s],
        "lyapunov_stderr_per_s": [float(v) for v in spec.stderr_per_s],
        "sum_minus_damping_average_per_s": spec.sum_per_s - spec.damping_average_per_s,
        "kaplan_yorke_dimension": spec.kaplan_yorke_dimension,
        "short_run_max_abs_difference_per_period": float(np.max(np.abs(short.exponents_per_period - ref))),
        "short_run_trace_difference_per_period": float(abs(short.damping_average_per_s / exc.f_e - trace.mean())),
    }
    print(f"spectrum over {a.periods} periods: {t_k:.3f} s ({a.periods / t_k:.0f} periods/s); scipy "
          f"{t_s:.2f} s for {a.scipy_periods} periods -> {t_s_scaled:.0f} s scaled; ratio "
          f"{t_s_scaled / t_k:.0f}x; lambda = {spec.exponents_per_s.round(3)} +- {spec.stderr_per_s.round(3)} 1/s; "
          f"short-run difference {res['short_run_max_abs_difference_per_period']:.1e}/period", flush=True)
    Path(a.out).write_text(json.dumps(res, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
