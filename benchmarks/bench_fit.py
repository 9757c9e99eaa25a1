"""Benchmark of ``contactvib fit`` on a stepped-sine FRF at two force levels (the target: ≤ 60 s
on 2 cores for ~150 points).

The data: the paper's contact, up and down sweeps of 38 steps at P_a = 0.3 Q (f_e/f_n0 =
0.64 … 1.04) and 0.65 Q (0.54 … 1.0), 152 points, the grid of ``tests/data/fit_paper_frf.csv``
(which has 25 steps a sweep: the scipy reference is slow to make), computed by the package's own
stepped-sine forward model (it agrees with that reference to the reference's accuracy, tested)
with 2 % reading noise (A_pp × exp(N(0, 0.02)), seed 1). The fit starts from the data alone
(S_c_n, S_h_n, m2, l all free, the model's own values ignored) with the default starts. The
kernels are compiled (or loaded from the cache) by a warm-up forward solve first, which is timed
separately (the warm-up also makes the noise-free data).

    PYTHONPATH=src python benchmarks/bench_fit.py [--out benchmarks/results_fit.json] [--threads 2]

Writes the time, the forward solves, the fitted parameters with their standard errors against the
truth, and the machine's load, to the JSON file.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from benchmarks import result_path

ROOT = Path(__file__).resolve().parents[1]


def _error(name, value, stderr, true):
    """|error| in standard errors; for the products S_c_n, S_h_n in log (their stderr is relative)."""
    if name in ("S_c_n", "S_h_n"):
        return abs(np.log(value / true)) / (stderr / value)
    return abs(value - true) / stderr


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(result_path(__name__)))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--starts", type=int, default=8)
    ap.add_argument("--points", type=int, default=38, help="steps per sweep")
    args = ap.parse_args(argv)
    os.environ.setdefault("NUMBA_NUM_THREADS", str(args.threads))
    import numba

    from contactvib import ContactModel
    from contactvib.fitting import fit, frf_data
    from contactvib.fitting.forward import FrfSet

    numba.set_num_threads(args.threads)
    truth = ContactModel()
    fe, F, direction = [], [], []
    for pa, (r0, r1) in {0.3: (0.64, 1.04), 0.65: (0.54, 1.0)}.items():
        f = np.round(np.linspace(r0 * truth.f_n0, r1 * truth.f_n0, args.points), 2)
        for d, ff in (("up", f), ("down", f[::-1])):
            fe += list(ff)
            F += [pa * truth.Q] * ff.size
            direction += [d] * ff.size
    grid = frf_data(fe, F, np.ones(len(fe)), direction)
    t0 = time.perf_counter()
    clean = FrfSet(grid).predict([{"S_c_n": truth.S * truth.c_n, "m2": 2.0, "S_h_n": truth.S * truth.h_n,
                                   "l": 1.0}], truth)[0]
    warmup = time.perf_counter() - t0
    rng = np.random.default_rng(1)
    data = frf_data(fe, F, clean * np.exp(rng.normal(0.0, 0.02, clean.size)), direction)
    load0 = os.getloadavg()
    r = fit(frf=data, model=truth.replace(c_n=1e16, h_n=1e11), n_starts=args.starts, progress=True)
    true = {"S_c_n": truth.S * truth.c_n, "m2": 2.0, "S_h_n": truth.S * truth.h_n, "l": 1.0,
            "f_n0_hz": truth.f_n0, "zeta": truth.zeta}
    res = {
        "points": int(data.n), "sweeps": len(data.sweeps), "threads": args.threads,
        "cpu_count": os.cpu_count(), "load_average_before": load0, "load_average_after": os.getloadavg(),
        "python": sys.version.split()[0], "machine": platform.machine(),
        "warmup_s": warmup, "fit_s": r.time_s, "budget_s": 60.0, "ratio_to_budget": r.time_s / 60.0,
        "n_forward": r.n_forward, "s_per_forward": r.time_s / r.n_forward, "n_starts": r.n_starts,
        "converged": r.converged, "residual_rms_ln_app": r.residual_rms["frf"],
        "parameters": {k: {"value": r.value(k), "stderr": r.stderr(k), "true": v,
                           "error_in_stderr": _error(k, r.value(k), r.stderr(k), v)} for k, v in true.items()},
    }
    Path(args.out).write_text(json.dumps(res, indent=1))
    print(f"{data.n} points, {len(data.sweeps)} sweeps: fit {r.time_s:.1f} s ({r.time_s / 60:.2f} of the 60 s "
          f"budget), {r.n_forward} forward solves ({r.time_s / r.n_forward:.2f} s each), warm-up {warmup:.1f} s, "
          f"load average {load0[0]:.1f} -> {os.getloadavg()[0]:.1f}")
    for k, v in res["parameters"].items():
        print(f"  {k:8s} {v['value']:.6g} +- {v['stderr']:.3g} (true {v['true']:.6g}, "
              f"{v['error_in_stderr']:.2f} stderr)")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
