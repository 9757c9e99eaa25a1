"""Harmonic balance vs shooting on the same branch (standalone script, not a test).

Branch: P_a = 0.65 Q, the small-amplitude (contact-kept) branch from 300 Hz through the 1/5 and
1/4 superharmonic resonances up to 440 Hz. HB: pseudo-arclength continuation, H harmonics,
stability by one shooting period per point. Shooting: at the same frequencies, Newton shooting
(rtol 1e-12, closure 1e-10) warm-started from the previous orbit, then the A_pp measurement of
``describe_orbit``. Reports wall times (best of 5 runs) and the largest relative A_pp difference.

    PYTHONPATH=src python benchmarks/bench_hbm.py [--harmonics 32]
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from benchmarks import result_path
from contactvib import ContactModel
from contactvib.frequency.harmonic_balance import HBSettings, hb_continuation
from contactvib.steady.orbits import describe_orbit, refine_orbit


def _best(fn, repeats: int = 5):
    """(best wall time [s] of ``repeats`` calls, last result): the machine is shared."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--harmonics", type=int, default=32)
    ap.add_argument("--pa", type=float, default=0.65)
    ap.add_argument("--fmin", type=float, default=300.0)
    ap.add_argument("--fmax", type=float, default=440.0)
    ap.add_argument("--out", default=str(result_path(__name__)))
    a = ap.parse_args(argv)
    model = ContactModel()
    hb_continuation(model, pa_over_q=a.pa, fmin_hz=a.fmin, fmax_hz=a.fmin + 5, harmonics=a.harmonics)  # JIT warm-up
    t_hb, br = _best(lambda: hb_continuation(model, pa_over_q=a.pa, fmin_hz=a.fmin, fmax_hz=a.fmax,
                                             harmonics=a.harmonics))
    t_hb_ns, br_ns = _best(lambda: hb_continuation(model, pa_over_q=a.pa, fmin_hz=a.fmin, fmax_hz=a.fmax,
                                                   harmonics=a.harmonics, settings=HBSettings(stability=False)))
    sol0 = br.solutions[0]
    r0 = sol0.fe_hz / model.f_n0
    X = sol0.coefficients
    k = np.arange(1, a.harmonics + 1)
    z = np.array([X[0] + X[1::2].sum(), r0 * (k * X[2::2]).sum()])

    def shoot(z=z):
        apps = []
        for f in br.fe_hz:
            exc = model.excitation(a.pa, float(f))
            z, M, res = refine_orbit(exc, z, 1)
            apps.append(describe_orbit(exc, z, 1, monodromy=M, closure=res).app_um)
        return apps

    t_sh, apps = _best(shoot)
    dev = np.max(np.abs(np.array(apps) - br.app_um) / np.array(apps))
    n = len(br)
    print(f"branch P_a = {a.pa} Q, {a.fmin:g}..{a.fmax:g} Hz, {n} points, H = {a.harmonics}")
    print(f"  HB continuation + stability : {t_hb:7.3f} s  ({1e3 * t_hb / n:.2f} ms/point)")
    print(f"  HB continuation, no stability: {t_hb_ns:7.3f} s  ({1e3 * t_hb_ns / len(br_ns):.2f} ms/point)")
    print(f"  shooting (Newton + describe)  : {t_sh:7.3f} s  ({1e3 * t_sh / n:.2f} ms/point)")
    print(f"  max relative A_pp difference HB vs shooting: {dev:.2e}")
    res = {"pa_over_q": a.pa, "fmin_hz": a.fmin, "fmax_hz": a.fmax, "harmonics": a.harmonics, "points": n,
           "hb_continuation_stability_s": t_hb, "hb_continuation_no_stability_s": t_hb_ns,
           "shooting_s": t_sh, "max_relative_app_difference": float(dev)}
    Path(a.out).write_text(json.dumps(res, indent=1) + "\n")


if __name__ == "__main__":
    main()
