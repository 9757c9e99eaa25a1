"""Benchmark: pseudo-arclength continuation of the primary resonance at 0.65 Q.

1. Upper (open) branch from 1930 Hz down to 297 Hz (f_e/f_n0 from 1.3 to 0.2) with Floquet
   multipliers and special points at every point; A_pp accuracy against a rerun of every point at
   rtol = 1e-14.
2. Lower branch from 297 Hz up through the jump-up fold (and back down its unstable part to
   297 Hz); the fold frequency's convergence with the integrator tolerance.

AUTO-07p reference: about 7 s on one core for part 1 (orthogonal collocation,
300 mesh intervals). Usage::

    PYTHONPATH=src python benchmarks/bench_continuation.py [--repeat 5] [--out FILE]
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from benchmarks import result_path  # noqa: E402
from contactvib import ContactModel, ContinuationSettings, continue_orbit, find_attractors  # noqa: E402  # noqa: E402
from contactvib._kernels.continuation import orbit_range  # noqa: E402
from contactvib.steady.orbits import refine_orbit  # noqa: E402

AUTO_SECONDS = 7.0


def timed(fn, repeat):
    ts, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return out, min(ts), float(np.median(ts))


def app_reference(model, branch, rtol=1e-14):
    """A_pp of every point re-solved at fixed f_e with a tighter tolerance."""
    ref = np.empty(len(branch))
    y_um = model.y0 * 1e6
    for i in range(len(branch)):
        exc = model.excitation(branch.pa_over_q[i], branch.fe_hz[i])
        z, _M, _r = refine_orbit(exc, branch.state[i], branch.period, tol=1e-12, rtol=rtol)
        xmin, xmax, _f, _n, st = orbit_range(z, branch.period, exc.kernel_parameters(), rtol)
        assert st == 0
        ref[i] = (xmax - xmin) * y_um
    return ref


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    model = ContactModel()
    fn0 = model.f_n0
    res = {"machine": f"{platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}",
           "threads": os.environ.get("NUMBA_NUM_THREADS")}

    # seeds (not timed: AUTO also starts from a computed solution)
    e_hi = model.excitation(0.65, 1930.0)
    seed_hi = [a for a in find_attractors(e_hi) if a.period == 1][0]
    e_lo = model.excitation(0.65, 297.0)
    lows = [a for a in find_attractors(e_lo) if a.period == 1]

    # ---------------------------------------------------------------- 1. upper branch
    res["upper"] = {}
    for rtol in (1e-10, 1e-12):
        s = ContinuationSettings(fmin_hz=297.0, fmax_hz=2000.0, rtol=rtol, tol=max(100 * rtol, 1e-11))
        run = lambda s=s: continue_orbit(e_hi, seed_hi.state, 1, direction="down", settings=s)  # noqa: E731
        run()  # compile / warm
        b, tmin, tmed = timed(run, args.repeat)
        ref = app_reference(model, b)
        err = float(np.max(np.abs(b.app_um - ref) / ref))
        res["upper"][f"{rtol:g}"] = {
            "time_s_min": tmin, "time_s_median": tmed, "points": len(b),
            "fe_range_hz": [float(b.fe_hz.min()), float(b.fe_hz.max())],
            "app_range_um": [float(b.app_um.min()), float(b.app_um.max())],
            "all_stable": bool(b.stable.all()), "app_max_rel_error_vs_rtol1e-14": err,
            "stops": [st.reason for st in b.stops],
            "special": [(sp.type, float(sp.fe_hz)) for sp in b.special],
            "speedup_vs_auto": AUTO_SECONDS / tmin}
        print(f"upper branch rtol={rtol:g}: {tmin * 1e3:.1f} ms (median {tmed * 1e3:.1f}), {len(b)} points, "
              f"A_pp {b.app_um.min():.4g}..{b.app_um.max():.4g} um, max rel A_pp error {err:.2e}, "
              f"{AUTO_SECONDS / tmin:.0f}x AUTO; stops {[st.reason for st in b.stops]}")

    # ---------------------------------------------------------------- 2. lower branch + fold
    res["lower"] = {}
    seed_lo = None
    for a in sorted(lows, key=lambda a: a.app_um):
        b = continue_orbit(e_lo, a.state, 1, direction="up",
                           settings=ContinuationSettings(fmin_hz=297.0, fmax_hz=2000.0))
        if any(sp.type == "fold" and sp.fe_hz > 900 for sp in b.special):
            seed_lo = a
            break
    assert seed_lo is not None, "lower branch with the jump-up fold not found"
    rows = []
    ref_fold = None
    for rtol in (1e-14, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13):
        s = ContinuationSettings(fmin_hz=297.0, fmax_hz=2000.0, rtol=rtol, tol=max(100 * rtol, 1e-12))
        run = lambda s=s: continue_orbit(e_lo, seed_lo.state, 1, direction="up", settings=s)  # noqa: E731
        b, tmin, tmed = timed(run, 1 if rtol == 1e-14 else args.repeat)
        folds = [sp for sp in b.special if sp.type == "fold" and sp.fe_hz > 900]
        f = folds[0].fe_hz
        if rtol == 1e-14:
            ref_fold = f
            continue
        rows.append({"rtol": rtol, "fold_hz": f, "fold_r": f / fn0, "err_r": abs(f - ref_fold) / fn0,
                     "time_s_min": tmin, "points": len(b),
                     "n_special": len(b.special), "stops": [st.reason for st in b.stops]})
        print(f"lower branch rtol={rtol:g}: {tmin * 1e3:.1f} ms, {len(b)} points, fold {f:.9f} Hz "
              f"(r = {f / fn0:.12f}), |dr| vs 1e-14 = {abs(f - ref_fold) / fn0:.1e}; "
              f"specials {[(sp.type, round(sp.fe_hz, 3)) for sp in b.special]}")
    res["lower"] = {"fold_ref_hz_rtol1e-14": ref_fold, "table": rows}
    Path(args.out).write_text(json.dumps(res, indent=1))
    print("wrote", args.out)


if __name__ == "__main__":
    sys.exit(main())
