"""The shortcuts of the attractor search and of the sweep tracer give what the long way gives.

* Second-wave capture (``find_attractors(capture_tol=...)``) against every start run to the end
  (``capture_tol=0``): the same attractors, and basin fractions within 2 % of the box.
* The tracer's sub-step bridge (``trace.bridge_orbit``) over a grid step where the 1/6 branch at
  0.90 Q bends fast: its predictor converges to the scipy reference orbit at 170 Hz (DOP853,
  rtol 1e-12, ``tests/data/reference.json``) where a zero-order predictor does not; and it
  refuses to cross the end of that branch (near 167 Hz).
"""
import json
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib._kernels.shooting import newton_orbit
from contactvib._kernels.status import STATUS_NEWTON_DIVERGED, STATUS_NEWTON_MAXITER, STATUS_NEWTON_SINGULAR
from contactvib._kernels.trace import bridge_orbit
from contactvib.model import ParameterError

MODEL = ContactModel()
REFERENCE = json.loads((Path(__file__).parents[1] / "data" / "reference.json").read_text())


def _key(a):
    return (a.period, a.minima_per_period, round(a.app_um, 6))


@pytest.mark.parametrize("pa,fe", [(0.65, 360.0), (0.85, 234.0)])
def test_capture_finds_the_same_attractors_and_basins(pa, fe):
    exc = MODEL.excitation(pa, fe)
    full = find_attractors(exc, n_starts=256, capture_tol=0.0)
    fast = find_attractors(exc, n_starts=256)
    assert fast.settings["capture_tol"] > 0 and fast.settings["first_wave"] == 64
    assert sorted(_key(a) for a in fast) == sorted(_key(a) for a in full)
    basin_full = {_key(a): a.basin_fraction for a in full}
    for a in fast:
        assert abs(a.basin_fraction - basin_full[_key(a)]) <= 0.02, (_key(a), a.basin_fraction)
    assert sum(a.basin_fraction for a in fast) == pytest.approx(1.0 - fast.n_failed / 256)


@pytest.mark.parametrize("bad", [-1e-3, 0.5, float("nan")])
def test_capture_tol_out_of_range_is_refused(bad):
    with pytest.raises(ParameterError, match="capture_tol"):
        find_attractors(MODEL.excitation(0.65, 360.0), capture_tol=bad)


def _orbit(f_e, z):
    par = MODEL.excitation(0.90, f_e).kernel_parameters()
    oz, oM = np.empty(2), np.empty((2, 2))
    status, _res = newton_orbit(np.asarray(z, float), 1, par, 1e-12, 1e-12, 1e-10, 12, oz, oM)
    return status, oz, par


def test_bridge_follows_a_fast_bend_and_stops_at_the_branch_end():
    ref = next(o for o in REFERENCE["orbits"]
               if o["pa_over_q"] == 0.9 and o["f_e"] == 170.0 and o["label"] == "1/6")
    def r(f_e):
        return f_e / MODEL.f_n0

    st, z174, par174 = _orbit(174.0, (2.3755, 0.5571))
    assert st == 0
    # one grid step (4 Hz) with a zero-order predictor does not converge ...
    st, _z, _par = _orbit(170.0, z174)
    assert st in (STATUS_NEWTON_DIVERGED, STATUS_NEWTON_SINGULAR, STATUS_NEWTON_MAXITER)
    # ... the bridge's predictor does, to the reference orbit
    zg, zb = np.empty(2), np.empty(2)
    assert bridge_orbit(z174, r(174.0), z174, 0.0, False, r(170.0), 1, par174, 1e-12, 1e-10, zg,
                        zb) == 2
    st, z170, _par = _orbit(170.0, zg)
    assert st == 0
    assert np.max(np.abs(z170 - ref["strobe"])) < 1e-8
    # the branch ends between 168 and 166 Hz: no bridge across 170 -> 162 Hz
    assert bridge_orbit(z170, r(170.0), z174, r(174.0), True, r(162.0), 1, par174, 1e-12,
                        1e-10, zg, zb) == 0
