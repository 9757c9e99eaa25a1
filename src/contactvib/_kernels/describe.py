"""Description of one attractor point of the sweep tracer (compiled, pure).

One row of the tracer's output record :class:`TraceRows` holds, for an attractor point at one
grid frequency: the orbit range and contact loss (:func:`.orbit.measure_orbit`), the extrema,
the stroboscopic points, the amplitudes of the harmonics ``j f_e/k`` (direct DFT of uniform
samples of the dense output) and, for a non-periodic attractor, the largest Lyapunov exponent of
the stroboscopic map. :func:`describe_point` measures a point from one tight-tolerance record of
``k`` periods (periodic) or :data:`NP_RECORD` periods (non-periodic).

Units: nondimensional as in :mod:`.flow` (x = y/y0, τ = ω_n0 t, T = 2π/r).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from .orbit import RECORD_CAP_MAX, measure_orbit, record_steps, sample_records
from .shooting import strobe_map
from .status import STATUS_OK

#: Stored extrema per attractor point (periodic orbits need 2 × minima; clouds are truncated).
EXT_MAX = 256
#: Stored stroboscopic points per attractor point (period k ≤ kmax; clouds: the last ones).
STROBE_MAX = 32
#: Harmonic amplitudes stored per point, at frequencies j·f_e/k, j = 1..HARM_MAX.
HARM_MAX = 64
#: Samples per excitation period for the harmonic analysis (Nyquist: 64 f_e).
N_SAMPLES = 128
#: Periods recorded to describe a non-periodic attractor.
NP_RECORD = 32
#: Periods used for the largest Lyapunov exponent of the stroboscopic map.
NP_LYAPUNOV = 64

#: Per-row output of the tracer (one row per attractor point), a record of arrays with a
#: leading row axis: ``i`` grid index; ``kind`` (0 periodic, 1 non-periodic); ``k`` period
#: (0: non-periodic); ``z`` orbit point (x, x') at phase 0; ``mu_re``, ``mu_im`` Floquet
#: multipliers (NaN: non-periodic); ``closure`` relative closure (inf: non-periodic); ``xmin``,
#: ``xmax`` range of x [y0]; ``flight`` fraction of the time with x ≤ 0; ``n_min`` minima over
#: the recorded periods; ``n_ext``, ``ext_t`` [τ], ``ext_x`` [y0], ``ext_min`` the first
#: :data:`EXT_MAX` extrema; ``n_strobe``, ``strobe`` the stroboscopic points; ``harm`` one-sided
#: amplitudes [y0] at ``j f_e/k``; ``lyap`` largest Lyapunov exponent [1/period] (NaN:
#: periodic); ``origin`` how the point was reached (:data:`.status.ORIGIN_NEWTON`, …).
TraceRows = namedtuple("TraceRows", [
    "i", "kind", "k", "z", "mu_re", "mu_im", "closure", "xmin", "xmax", "flight", "n_min",
    "n_ext", "ext_t", "ext_x", "ext_min", "strobe", "n_strobe", "harm", "lyap", "origin"])


def new_rows(cap: int) -> TraceRows:
    """A zeroed :class:`TraceRows` with room for ``cap`` rows."""
    return TraceRows(
        i=np.zeros(cap, np.int64), kind=np.zeros(cap, np.int64), k=np.zeros(cap, np.int64),
        z=np.zeros((cap, 2)), mu_re=np.zeros((cap, 2)), mu_im=np.zeros((cap, 2)),
        closure=np.zeros(cap), xmin=np.zeros(cap), xmax=np.zeros(cap), flight=np.zeros(cap),
        n_min=np.zeros(cap, np.int64), n_ext=np.zeros(cap, np.int64),
        ext_t=np.zeros((cap, EXT_MAX)), ext_x=np.zeros((cap, EXT_MAX)),
        ext_min=np.zeros((cap, EXT_MAX), np.bool_), strobe=np.zeros((cap, STROBE_MAX, 2)),
        n_strobe=np.zeros(cap, np.int64), harm=np.zeros((cap, HARM_MAX)),
        lyap=np.zeros(cap), origin=np.zeros(cap, np.int64),
    )


@njit(cache=True)
def lyapunov_strobe(z, par, rtol, n_periods):
    """Largest Lyapunov exponent of the stroboscopic map [1/excitation period] from ``z``.

    Tangent vector propagated by the monodromy of each period and renormalised (Benettin et al.
    1980): λ = (1/n) Σ ln |M_j w_j|; NaN if the integration fails.
    """
    cur = z.copy()
    nxt = np.empty(2)
    M = np.empty((2, 2))
    w0 = 1.0 / math.sqrt(2.0)
    w1 = w0
    acc = 0.0
    for _ in range(n_periods):
        if strobe_map(cur, np.int64(1), par, rtol, rtol, nxt, M) != STATUS_OK:
            return math.nan
        a = M[0, 0] * w0 + M[0, 1] * w1
        b = M[1, 0] * w0 + M[1, 1] * w1
        nrm = math.sqrt(a * a + b * b)
        if not (nrm > 0.0 and math.isfinite(nrm)):
            return math.nan
        acc += math.log(nrm)
        w0 = a / nrm
        w1 = b / nrm
        cur[0] = nxt[0]
        cur[1] = nxt[1]
    return acc / n_periods


@njit(cache=True, inline='always')
def floquet_pair(M, out_re, out_im):
    """Eigenvalues of the 2×2 monodromy ``M``: μ = tr/2 ± sqrt(tr²/4 − det) into (re, im)."""
    tr = M[0, 0] + M[1, 1]
    det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
    disc = 0.25 * tr * tr - det
    if disc >= 0.0:
        s = math.sqrt(disc)
        out_re[0] = 0.5 * tr + s
        out_re[1] = 0.5 * tr - s
        out_im[0] = 0.0
        out_im[1] = 0.0
    else:
        s = math.sqrt(-disc)
        out_re[0] = 0.5 * tr
        out_re[1] = 0.5 * tr
        out_im[0] = s
        out_im[1] = -s


@njit(cache=True, inline='always')
def strobe_from_record(rec, n_per, T, out):
    """The last ``min(n_per, STROBE_MAX)`` stroboscopic points (x, x') at τ = jT of a record of
    ``n_per`` periods into ``out`` (rows); returns their number."""
    n_s = min(n_per, STROBE_MAX)
    ts = np.empty(n_s)
    for j in range(n_s):
        ts[j] = (n_per - n_s + j) * T
    xs, vs, _cs = sample_records(rec, ts)
    for j in range(n_s):
        out[j, 0] = xs[j]
        out[j, 1] = vs[j]
    return n_s


@njit(cache=True, inline='always')
def harmonic_amplitudes(rec, n_per, T, out):
    """One-sided amplitudes |X_j| [y0] at ``j f_e / n_per``, j = 1..len(out), into ``out``.

    Direct DFT of N = N_SAMPLES · n_per uniform samples x_q of the record over ``n_per T``:
    ``|X_j| = (2/N) |Σ_q x_q e^{−2πi jq/N}|``; NaN above the Nyquist limit (j > N/2 − 1).
    """
    N = N_SAMPLES * n_per
    tt = np.empty(N)
    for q in range(N):
        tt[q] = q * (n_per * T) / N
    xq, _v, _c = sample_records(rec, tt)
    cos_q = np.empty(N)
    sin_q = np.empty(N)
    for q in range(N):
        cos_q[q] = math.cos(2.0 * math.pi * q / N)
        sin_q[q] = math.sin(2.0 * math.pi * q / N)
    for j in range(1, out.shape[0] + 1):
        if j > N // 2 - 1:
            out[j - 1] = math.nan
            continue
        re = 0.0
        im = 0.0
        iq = 0
        for q in range(N):
            re += xq[q] * cos_q[iq]
            im -= xq[q] * sin_q[iq]
            iq += j
            if iq >= N:
                iq -= N
        out[j - 1] = 2.0 * math.sqrt(re * re + im * im) / N


@njit(cache=True)
def describe_point(z, n_per, par, rtol, rows, row, o_end):
    """Measure ``n_per`` periods from ``z`` at phase 0 into row ``row`` of ``rows``.

    Writes the range, contact loss, minima and extrema (:func:`.orbit.measure_orbit`), the
    stroboscopic points and the harmonics of :class:`TraceRows`, and the end state
    ``P^n_per(z)`` into ``o_end``; returns a :mod:`.flow` status.
    """
    T = 2.0 * math.pi / par[4]
    rec, z_end, t_flight, _n_events, st = record_steps(z, 0.0, n_per, par, rtol, 256 * n_per,
                                                       RECORD_CAP_MAX)
    if st != STATUS_OK:
        return st
    o_end[0] = z_end[0]
    o_end[1] = z_end[1]
    xmin, xmax, flight, n_min, t_e, x_e, m_e = measure_orbit(rec, t_flight, n_per, par[4])
    rows.xmin[row] = xmin
    rows.xmax[row] = xmax
    rows.flight[row] = flight
    rows.n_min[row] = n_min
    n_keep = min(t_e.shape[0], EXT_MAX)
    rows.n_ext[row] = n_keep
    for j in range(n_keep):
        rows.ext_t[row, j] = t_e[j]
        rows.ext_x[row, j] = x_e[j]
        rows.ext_min[row, j] = m_e[j]
    rows.n_strobe[row] = strobe_from_record(rec, n_per, T, rows.strobe[row])
    harmonic_amplitudes(rec, n_per, T, rows.harm[row])
    return STATUS_OK
