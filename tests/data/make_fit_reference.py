"""Noise-free synthetic measurements for the tests of ``contactvib fit``, made independently of
the package's kernels: scipy ``solve_ivp`` (DOP853) with located contact events
(:func:`contactvib.testing.integrate_contact`) on the SI equation

    M ÿ = M g − S c_n y^m2 [y > 0] − S h_n y^l ẏ [y > 0] + P_a cos(2π f_e t)

Regenerate with ``python tests/data/make_fit_reference.py [SET ...]`` (writes ``fit_<set>_frf.csv``
and ``fit_<set>_decay.csv`` next to this file; about a minute per set). Nothing from
``contactvib`` but its kernel-free :mod:`contactvib.testing` is imported: the parameter sets are
given by (m2, l, y0, ζ) and turned into c_n, h_n here with M, g, S the paper's.

Stepped sine: each step starts from the state the previous step ended on (the first from the
static point at rest), integrates 5 periods at a time until two successive stroboscopic points
agree to ``SETTLED`` (relative to the state scale; at most ``MAX_PERIODS``), then one more period
whose y range (turning points located as events, and the ends) gives A_pp. Up and down sweeps at
two force levels, P_a = 0.3 Q and 0.65 Q, one process per sweep.

Free decay: P_a = 0 from y(0) = y0 + a y0, ẏ(0) = 0, sampled at ``N_DECAY`` instants over
``DECAY_CYCLES`` linear periods; the file holds y − y0 [µm].
"""

from __future__ import annotations

import csv
import math
import sys
from pathlib import Path

import numpy as np

from contactvib.testing import ContactODE, integrate_contact

HERE = Path(__file__).resolve().parent

# The files were made (2026-11) with every mode switch started 1e-15 m inside the new mode;
# integrate_contact now does so only where a grazing switch needs it (the event's root at the
# start itself). The difference (1e-15 m ~ 1e-8 y0 at a switch) is far below the files' digits.
M, G, S = 0.2106, 9.81, 0.0009
Q = M * G
MAX_PERIODS = 1000
#: solve_ivp tolerance of the sweeps, and the change of the stroboscopic point (relative to the
#: state scale) over one period below which a step has settled: far below 1 % reading noise.
RTOL_SWEEP = 1e-9
SETTLED = 1e-8
SETTLED_LATE = 1e-6
DECAY_CYCLES = 25
N_DECAY = 1000

#: name -> (m2, l, y0 [m], zeta, points per sweep, decay start a [y0])
SETS = {
    "paper": (2.0, 1.0, None, None, 25, 1.2),
    "a": (1.5, 0.5, 0.30e-6, 0.030, 14, 1.5),
    "b": (2.5, 1.5, 0.15e-6, 0.012, 14, 0.8),
    "c": (1.3, 0.0, 0.40e-6, 0.020, 14, 0.8),
}
#: level [Q] -> range of f_e / f_n0 swept
LEVELS = {0.3: (0.64, 1.04), 0.65: (0.54, 1.0)}


def parameters(m2, l, y0, zeta):
    """c_n, h_n (SI) of a set given by (m2, l, y0, ζ); None, None: the paper's."""
    if y0 is None:
        return 4.52e16, 3.5e11
    Sc = Q / y0**m2
    k = m2 * Q / y0
    c_lin = 2.0 * zeta * math.sqrt(k * M)
    return Sc / S, c_lin / y0**l / S


def scales(c_n, m2, h_n, l):
    y0 = (Q / (S * c_n)) ** (1.0 / m2)
    k = m2 * Q / y0
    return y0, math.sqrt(k / M) / (2.0 * math.pi), S * h_n * y0**l / (2.0 * math.sqrt(k * M))


def ode(c_n, m2, h_n, l, pa, fe):
    Sc, Sh, w = S * c_n, S * h_n, 2.0 * math.pi * fe

    def force(y, v):
        ya = abs(y)
        return math.copysign(Sc * ya**m2, y) + math.copysign(Sh * ya**l, y if l else 1.0) * v

    def rate(y):
        return Sh * abs(y) ** l
    return ContactODE(M, Q, force, lambda t: pa * Q * math.cos(w * t), rate)


def stepped_sine(c_n, m2, h_n, l, pa, freqs, y0):
    """A_pp [m] at each frequency of ``freqs`` (in the sweep's order)."""
    y, v = y0, 0.0
    out = []
    for fe in freqs:
        od = ode(c_n, m2, h_n, l, pa, fe)
        T = 1.0 / fe
        n = 0
        while n < MAX_PERIODS:
            tr = integrate_contact(od, y, v, 0.0, 5 * T, rtol=RTOL_SWEEP, y_scale=y0, v_scale=y0 * 2 * math.pi * fe)
            pts = tr.sample(np.arange(1, 6) * T * (1 - 1e-12))
            y, v = tr.y, tr.ydot
            n += 5
            sc = max(abs(pts[0, -1]), abs(pts[1, -1]) / (2 * math.pi * fe), y0)
            d = max(abs(pts[0, -1] - pts[0, -2]), abs(pts[1, -1] - pts[1, -2]) / (2 * math.pi * fe)) / sc
            if d < SETTLED or (n >= 100 and d < SETTLED_LATE):  # at grazing the points jitter ~1e-8
                break
        tr = integrate_contact(od, y, v, 0.0, T, rtol=RTOL_SWEEP, y_scale=y0, v_scale=y0 * 2 * math.pi * fe)
        y, v = tr.y, tr.ydot
        out.append(tr.ymax - tr.ymin)
    return np.array(out)


def make(name, frf=True):
    m2, l, y0_set, zeta, npts, a = SETS[name]
    c_n, h_n = parameters(m2, l, y0_set, zeta)
    y0, fn0, z = scales(c_n, m2, h_n, l)
    print(f"{name}: c_n = {c_n:.6g}, h_n = {h_n:.6g}, y0 = {y0 * 1e6:.4f} um, f_n0 = {fn0:.2f} Hz, zeta = {z:.4f}")
    head = f"# set {name}: M={M} g={G} S={S} c_n={c_n!r} m2={m2} h_n={h_n!r} l={l}\n"
    make_decay(name, head, c_n, m2, h_n, l, y0, fn0, a)
    if frf:
        make_frf(name, head, c_n, m2, h_n, l, y0, fn0, npts)


def _sweep(job):
    c_n, m2, h_n, l, pa, freqs, y0 = job
    return stepped_sine(c_n, m2, h_n, l, pa, freqs, y0)


def make_frf(name, head, c_n, m2, h_n, l, y0, fn0, npts):
    """The four sweeps (two levels, up and down), one process each."""
    from multiprocessing import Pool

    jobs, keys = [], []
    for pa, (r0, r1) in LEVELS.items():
        f = np.round(np.linspace(r0 * fn0, r1 * fn0, npts), 2)
        for direction, freqs in (("up", f), ("down", f[::-1])):
            jobs.append((c_n, m2, h_n, l, pa, freqs, y0))
            keys.append((pa, direction, freqs))
    with Pool(len(jobs)) as pool:
        results = pool.map(_sweep, jobs)
    rows = []
    for (pa, direction, freqs), app in zip(keys, results):
        rows += [(fe, pa * Q, A * 1e6, direction) for fe, A in zip(freqs, app)]
        print(f"  {pa} Q {direction}: A_pp {app.min() * 1e6:.3f} .. {app.max() * 1e6:.3f} um")
    with open(HERE / f"fit_{name}_frf.csv", "w", newline="") as fh:
        fh.write(head)
        w = csv.writer(fh)
        w.writerow(["fe_hz", "force_amplitude_n", "app_um", "direction"])
        for fe, F, A, d in rows:
            w.writerow([f"{fe:.2f}", f"{F:.10g}", f"{A:.10g}", d])


def make_decay(name, head, c_n, m2, h_n, l, y0, fn0, a):
    T_end = DECAY_CYCLES / fn0
    t = np.linspace(0.0, T_end, N_DECAY)
    tr = integrate_contact(ode(c_n, m2, h_n, l, 0.0, 1.0), y0 * (1 + a), 0.0, 0.0, T_end, rtol=1e-11,
                           y_scale=y0, v_scale=y0 * 2 * math.pi * fn0)
    ys = tr.sample(t)[0]
    with open(HERE / f"fit_{name}_decay.csv", "w", newline="") as fh:
        fh.write(head)
        w = csv.writer(fh)
        w.writerow(["t_ms", "y_um"])
        for ti, yi in zip(t, ys):
            w.writerow([f"{ti * 1e3:.8g}", f"{(yi - y0) * 1e6:.10g}"])


if __name__ == "__main__":
    names = [n for n in sys.argv[1:] if n != "--decay-only"]
    for name in names or SETS:
        make(name, frf="--decay-only" not in sys.argv)
