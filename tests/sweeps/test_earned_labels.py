"""The sweep's rows judged by the attractor search's rule (sweeps/verdict.py: judge_rows): a
non-periodic row that is a long-period orbit becomes "periodic" with its true period (checked by
plain iteration of the map, an independent method), a chaotic one keeps λ1 > 3 stderr, a free
flight or a converging transient is removed, and periodic rows get ln|μ|/T."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors, orbit_period
from contactvib._kernels import trace as tk
from contactvib._kernels.describe import new_rows
from contactvib._kernels.table import KIND_NONPERIODIC
from contactvib.steady.orbits import strobe_points
from contactvib.sweeps.level_state import LevelTrace
from contactvib.sweeps.verdict import judge_rows

PA = 0.75
GRID = np.array([812.0, 816.5])


@pytest.fixture(scope="module")
def level():
    """Four rows: the period-1 orbit and the period-10 orbit (found by the sweep as non-periodic:
    its period exceeds kmax = 8) at 812 Hz, the chaotic attractor at 816.5 Hz, and a start still
    converging onto the period-1 orbit at 812 Hz."""
    model = ContactModel()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a812 = find_attractors(model.excitation(PA, 812.0))
        a816 = find_attractors(model.excitation(PA, 816.5))
    p1 = next(a for a in a812 if a.period == 1 and a.app_um > 1.0)
    long = next(a for a in a812 if a.period is None or a.period > 8)
    chaos = next(a for a in a816 if a.period is None)
    rows = new_rows(4)
    exc812 = model.excitation(PA, 812.0)
    for j, (i, z, kind, k) in enumerate([(0, p1.state, 0, 1), (0, long.state, KIND_NONPERIODIC, 0),
                                         (1, chaos.state, KIND_NONPERIODIC, 0),
                                         (0, p1.state + np.array([0.3, 0.0]), KIND_NONPERIODIC, 0)]):
        rows.i[j], rows.kind[j], rows.k[j] = i, kind, k
        rows.z[j] = z
        exc = model.excitation(PA, float(GRID[i]))
        pts = strobe_points(exc, z, 32, 1e-10)
        rows.strobe[j, :32] = pts
        rows.n_strobe[j] = 32
    mu = p1.floquet_multipliers
    rows.mu_re[0], rows.mu_im[0] = mu.real, mu.imag
    lt = LevelTrace(rows=rows, found_by=np.zeros(4, np.int64), basin=np.full(4, np.nan), links=tk.new_links(0),
                    f_hz=GRID, stops=[], pa_over_q=PA)
    return model, exc812, p1, lt, judge_rows(lt, model, 1e-8, 8)


def test_periodic_rows_get_their_floquet_exponents(level):
    _model, _exc, p1, _lt, judged = level
    v = judged.verdicts
    want = np.sort(np.log(np.abs(p1.floquet_multipliers)) * 812.0)[::-1]
    np.testing.assert_allclose(v["lyapunov_per_s"][0], want, rtol=1e-14)
    assert v["attractor_type"][0] == "periodic" and v["true_period"][0] == 1


def test_long_period_chaos_and_the_unsettled_start(level):
    model, exc, _p1, lt, judged = level
    v = judged.verdicts
    assert judged.n_rows == 3  # the converging start is removed
    assert list(v["attractor_type"]) == ["periodic", "periodic", "chaotic"]
    k, _z = orbit_period(exc, state=lt.rows.z[1])  # plain iteration of the map
    assert v["true_period"][1] == k == 10
    lam, se = v["lyapunov_per_s"][2], v["lyapunov_stderr_per_s"][2]
    assert lam[0] > 3 * se[0] > 0 and lam[1] < 0
    assert np.all(v["lyapunov_per_s"][1] < 0)  # a stable orbit: both exponents negative


def _judge_row_by_row(lt, model, rtol, kmax):
    """judge_rows as one search_verdict per non-periodic row and one np.sort per periodic row (the
    reference of the batched form: one compiled Benettin call, the periodic rows as arrays)."""
    from contactvib.steady.transients import search_verdict

    rows, n = lt.rows, lt.n_rows
    types = np.array(["periodic"] * n, dtype=object)
    true_period = np.where(rows.kind == KIND_NONPERIODIC, 0, rows.k).astype(np.int64)
    lam, se, keep = np.full((n, 2), np.nan), np.zeros((n, 2)), np.ones(n, bool)
    fe = lt.f_hz[rows.i]
    with np.errstate(divide="ignore"):
        mu = np.log(np.hypot(rows.mu_re, rows.mu_im))
    for j in range(n):
        if rows.kind[j] != KIND_NONPERIODIC:
            lam[j] = np.sort(mu[j] * fe[j] / rows.k[j])[::-1]
            continue
        v = search_verdict(model.excitation(lt.pa_over_q, float(fe[j])), rows.strobe[j, :rows.n_strobe[j]], rtol, kmax)
        types[j], keep[j] = v.kind, v.kind != "unsettled"
        if v.kind == "periodic":
            true_period[j] = v.period
            lam[j] = np.sort(np.log(np.abs(np.linalg.eigvals(v.monodromy))) * fe[j] / v.period)[::-1]
        elif v.spectrum is not None:
            lam[j], se[j] = v.spectrum.exponents_per_s, v.spectrum.stderr_per_s
    return keep, {"attractor_type": types[keep], "true_period": true_period[keep], "lyapunov_per_s": lam[keep],
                  "lyapunov_stderr_per_s": se[keep]}


def test_batched_verdicts_are_bit_identical_to_one_call_per_row(level):
    """The batched judge (one compiled Benettin call over the rows, the periodic rows' exponents
    as arrays) gives exactly (bit for bit) what a search_verdict per row and an np.sort per row
    give, the special multipliers included (0: −inf, NaN, a complex pair, equal moduli)."""
    model, _exc, _p1, lt, judged = level
    rows = new_rows(lt.n_rows + 4)
    for name in rows._fields:
        getattr(rows, name)[:lt.n_rows] = getattr(lt.rows, name)
    for j, (re, im) in enumerate([((0.0, 0.5), (0.0, 0.0)), ((np.nan, 0.2), (0.0, 0.0)),
                                  ((0.3, 0.3), (0.4, -0.4)), ((-0.5, 0.5), (0.0, -0.0))], lt.n_rows):
        rows.i[j], rows.kind[j], rows.k[j] = 0, 0, 1 + j % 3
        rows.mu_re[j], rows.mu_im[j] = re, im
    lt2 = LevelTrace(rows=rows, found_by=np.zeros(rows.i.size, np.int64), basin=np.full(rows.i.size, np.nan),
                     links=tk.new_links(0), f_hz=GRID, stops=[], pa_over_q=PA)
    keep, want = _judge_row_by_row(lt2, model, 1e-8, 8)
    got = judge_rows(lt2, model, 1e-8, 8)
    assert got.n_rows == keep.sum() == judged.n_rows + 4
    for key, w in want.items():
        g = got.verdicts[key]
        assert g.dtype == w.dtype and g.shape == w.shape
        if w.dtype == object:
            assert list(g) == list(w)
        else:  # the same bits: NaN where NaN, the sign of ±inf and of 0
            assert np.array_equal(g.view(np.int64) if g.dtype == float else g,
                                  w.view(np.int64) if w.dtype == float else w), key
    for key in judged.verdicts:  # the fixture's own judgement is the first rows of this one
        a, b = got.verdicts[key][:judged.n_rows], judged.verdicts[key]
        assert list(a) == list(b) if a.dtype == object else np.array_equal(a, b, equal_nan=True)


def test_spectrum_rows_on_threads_and_serial_equal_one_call_per_row(level):
    """The compiled rows of Benettin runs (lyapunov.spectrum_map_rows), on the threads and in a
    plain loop, fill every row exactly as one spectrum_map call from that row does."""
    from contactvib._kernels import lyapunov as lk

    model, _exc, _p1, lt, _judged = level
    Z = np.ascontiguousarray(lt.rows.strobe[:, 31])
    PAR = np.stack([model.excitation(PA, float(GRID[i])).kernel_parameters() for i in lt.rows.i])
    n, nb, per, m = Z.shape[0], 10, 20, 64
    want = [np.zeros((n, nb, 2)), np.zeros((n, nb)), np.zeros((n, 3)), np.zeros((n, m, 2)), np.zeros(n, np.int64)]
    for q in range(n):
        want[4][q] = lk.spectrum_map(Z[q].copy(), PAR[q], 1e-8, 0, nb, per, False, want[0][q], want[1][q],
                                     want[2][q], want[3][q], np.zeros(1, np.int64))
    assert np.all(want[4] == 0)
    for kernel in (lk._spectrum_rows_threads, lk._spectrum_rows_serial):
        got = [np.zeros_like(a) for a in want]
        kernel(Z, PAR, 1e-8, np.int64(nb), np.int64(per), *got, np.zeros(1, np.int64))
        for g, w in zip(got, want):
            assert np.array_equal(g, w, equal_nan=True)


def _refine_reference(z, k, par, rtol, tol):
    """refine_stable_orbit with one strobe_map run per proper divisor (its former form)."""
    from contactvib._kernels.shooting import MINIMAL_PERIOD_TOL, newton_orbit, stable_monodromy, strobe_map

    oz, oM = np.empty(2), np.zeros((2, 2))
    st, res = newton_orbit(z.copy(), k, par, rtol, rtol, tol, np.int64(12), oz, oM)
    if st != 0 or not stable_monodromy(oM):
        return False, k, res, oz, oM
    pz, sc = np.empty(2), max(1.0, abs(oz[0]), abs(oz[1]))
    for d in range(1, k):
        if k % d:
            continue
        if strobe_map(oz, d, par, rtol, rtol, pz, np.empty((0, 0))) != 0:
            return False, k, res, oz, oM
        if max(abs(pz[0] - oz[0]), abs(pz[1] - oz[1])) / sc < MINIMAL_PERIOD_TOL:
            st, res = newton_orbit(oz.copy(), d, par, rtol, rtol, tol, np.int64(12), oz, oM)
            if st != 0 or not stable_monodromy(oM):
                return False, k, res, oz, oM
            return True, d, res, oz, oM
    return True, k, res, oz, oM


@pytest.mark.parametrize("row, k", [(0, 1), (0, 6), (1, 10), (1, 20), (1, 30), (1, 7)])
def test_minimal_period_from_one_run_equals_one_run_per_divisor(level, row, k):
    """refine_stable_orbit reduces k to the minimal period from one run over the proper divisors;
    its result (ok, period, residual, orbit point, monodromy) is bit-identical to one strobe_map
    run per divisor: the period-1 orbit given k = 1 and 6, the period-10 orbit given 10, 20, 30
    (reduced to 10) and 7 (no orbit of period 7: refused)."""
    from contactvib._kernels.settle import refine_stable_orbit
    from contactvib.steady.orbits import CLOSE_TOL, RTOL_REFINE

    _model, exc, _p1, lt, _judged = level
    par, z = exc.kernel_parameters(), lt.rows.strobe[row, 31].copy()
    oz, oM = np.empty(2), np.zeros((2, 2))
    ok, kk, res = refine_stable_orbit(z.copy(), k, par, RTOL_REFINE, CLOSE_TOL, oz, oM)
    ok0, kk0, res0, oz0, oM0 = _refine_reference(z, k, par, RTOL_REFINE, CLOSE_TOL)
    assert (ok, kk) == (ok0, kk0) and (res == res0 or (np.isnan(res) and np.isnan(res0)))
    assert np.array_equal(oz, oz0) and np.array_equal(oM, oM0)
    if row == 1 and k % 10 == 0:
        assert ok and kk == 10


def test_a_set_stop_flag_ends_the_batched_runs_as_one_run_per_row(level):
    """Under a stop flag already set (``contactvib explore``'s time limit) every row's run returns
    within one period, and the batched verdicts are what one search_verdict per row gives:
    unsettled, the integration not finished."""
    from contactvib.interrupts import stop_scope
    from contactvib.steady.transients import search_verdict, search_verdicts

    model, _exc, _p1, lt, _judged = level
    excs = [model.excitation(PA, float(GRID[i])) for i in lt.rows.i]
    tails = [lt.rows.strobe[j, :32] for j in range(lt.n_rows)]
    with stop_scope(np.ones(1, np.int64)):
        got = search_verdicts(excs, tails, 1e-8, 8)
        want = [search_verdict(e, t, 1e-8, 8) for e, t in zip(excs, tails)]
    assert [(v.kind, v.reason) for v in got] == [(v.kind, v.reason) for v in want]
    assert all(v.kind == "unsettled" and v.reason == "integration failed" for v in got)
