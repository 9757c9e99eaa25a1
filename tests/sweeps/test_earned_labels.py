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
