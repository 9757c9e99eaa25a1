"""``SweepSettings.level_seeds`` (:mod:`contactvib.sweeps.level_seeds`): a level that lacks an
orbit of period ≤ 4 a neighbouring level holds is swept again from that orbit walked in P_a.

At 0.75 Q over 1370–1400 Hz (5 Hz) the multi-start finds the period-4 orbit with 3 minima per
period (1380–1385 Hz); at 0.80 Q it finds none, though the orbit exists there (the brute-force
search of ``query --completeness`` lists it as missing from the paper's dataset at 0.80 Q, 1300
and 1400 Hz). With the switch on, 0.80 Q holds it, checked against an independent 256-start
search at 1400 Hz (same period and minima, A_pp within 1e-3, |Floquet multiplier| < 1), and
nothing else changes. Off (the default), the sweep and its record are what they were."""

from __future__ import annotations

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib.model import ParameterError
from contactvib.sweeps.level_seeds import LEVEL_STEP, level_seeds, walk_orbit
from contactvib.sweeps.resonance import resonance_dataset
from contactvib.sweeps.stored import ResonanceData
from contactvib.sweeps.sweep import SweepSettings

GRID = dict(fmin_hz=1370.0, fmax_hz=1400.0, df_hz=5.0)
LEVELS = [0.75, 0.8]


def _sweep(on: bool):
    st = SweepSettings(**GRID, level_seeds=on)
    return ResonanceData(resonance_dataset(ContactModel(), levels=LEVELS, settings=st, out=None, workers=1,
                                           progress=False))


@pytest.fixture(scope="module")
def off():
    return _sweep(False)


@pytest.fixture(scope="module")
def on():
    return _sweep(True)


def _points(data, p, k=None, m=None):
    one = data.level(p)
    keep = np.ones(one.sizes["point"], bool) if k is None else \
        (one["period"].values == k) & (one["minima_per_period"].values == m)
    return one.isel(point=np.flatnonzero(keep))


def test_off_the_level_lacks_the_orbit_and_the_record_is_unchanged(off):
    assert _points(off, 0.75, 4, 3).sizes["point"] >= 1
    assert _points(off, 0.8, 4, 3).sizes["point"] == 0
    assert "level_seeds" not in off.ds.attrs["settings"]
    assert "level seed" not in set(off.ds["found_by"].values)


def test_on_the_level_holds_the_orbit_of_the_brute_force_search(on):
    got = _points(on, 0.8, 4, 3)
    assert got.sizes["point"] >= 1 and set(got["found_by"].values) == {"level seed"}
    assert np.all(got["floquet_abs_max"].values < 1.0)
    at = np.flatnonzero(got["fe_hz"].values == 1400.0)
    assert at.size == 1
    ref = find_attractors(ContactModel().excitation(0.8, 1400.0), n_starts=256, seed=0)
    same = [a for a in ref.attractors if a.period == 4 and a.minima_per_period == 3]
    assert len(same) == 1
    assert got["app_um"].values[at[0]] == pytest.approx(same[0].app_um, rel=1e-3)


def test_on_adds_attractors_only(off, on):
    def rows(data, p):
        one = data.level(p)
        return {(float(f), int(k), int(m), round(float(a), 6)) for f, k, m, a in zip(
            one["fe_hz"].values, one["period"].values, one["minima_per_period"].values, one["app_um"].values)}

    assert rows(off, 0.75) == rows(on, 0.75)  # a level that lacks nothing is not swept again
    assert rows(off, 0.8) < rows(on, 0.8)
    assert {r[1:3] for r in rows(on, 0.8) - rows(off, 0.8)} == {(4, 3)}


def test_a_level_swept_with_its_seeds_has_none_left(on):
    st = SweepSettings(**GRID, level_seeds=True)
    assert level_seeds(ContactModel(), {p: on.level(p) for p in LEVELS}, st) == {}


def test_the_walk_needs_its_steps():
    """A single Newton solve from the 0.75 Q orbit at 0.80 Q does not reach the orbit: the walk
    in steps of LEVEL_STEP does."""
    from contactvib._kernels.shooting import newton_orbit
    from contactvib._kernels.status import STATUS_OK

    m = ContactModel()
    st = SweepSettings(**GRID)
    ref = find_attractors(m.excitation(0.75, 1385.0), n_starts=256, seed=0)
    (a,) = [a for a in ref.attractors if a.period == 4 and a.minima_per_period == 3]
    got = walk_orbit(m, st, a.state, 4, 1385.0, 0.75, 0.8)
    assert got is not None and got[1] == 4
    oz, oM = np.empty(2), np.empty((2, 2))
    s, _res = newton_orbit(np.array(a.state, float), 4, m.excitation(0.8, 1385.0).kernel_parameters(),
                           st.rtol, st.rtol, st.tol, 20, oz, oM)
    assert s != STATUS_OK or np.max(np.abs(oz - got[0])) > 1e-6
    assert LEVEL_STEP == 0.0025


def test_the_switch_is_a_bool():
    with pytest.raises(ParameterError, match="level_seeds"):
        SweepSettings(level_seeds="yes")


def test_an_orbit_a_level_gained_reaches_the_next():
    """Over 770–820 Hz (2 Hz) the multi-start finds the period-2 orbit with 3 minima at 0.70 Q
    only; walked from 0.70 Q it reaches 0.75 Q (788–814 Hz), and from there, in the next pass,
    0.80 Q (from 804 Hz): the full sweep of ``contactvib paper`` holds it at 0.75 Q over 788–814
    Hz and at 0.80 Q over 804–830 Hz. Checked at 0.80 Q, 810 Hz against a 256-start search."""
    grid = dict(fmin_hz=770.0, fmax_hz=820.0, df_hz=2.0)
    sweeps = {on: ResonanceData(resonance_dataset(ContactModel(), levels=[0.7, 0.75, 0.8],
                                                  settings=SweepSettings(**grid, level_seeds=on), out=None,
                                                  workers=1, progress=False)) for on in (False, True)}

    def window(data, p):
        fe = _points(data, p, 2, 3)["fe_hz"].values
        return (fe.min(), fe.max()) if fe.size else None

    assert window(sweeps[False], 0.7) == window(sweeps[True], 0.7) == (770.0, 794.0)
    assert window(sweeps[False], 0.75) is None and window(sweeps[False], 0.8) is None
    assert window(sweeps[True], 0.75) == (788.0, 814.0)
    assert window(sweeps[True], 0.8)[0] == 804.0
    got = _points(sweeps[True], 0.8, 2, 3)
    assert set(got["found_by"].values) == {"level seed"}
    at = np.flatnonzero(got["fe_hz"].values == 810.0)
    ref = find_attractors(ContactModel().excitation(0.8, 810.0), n_starts=256, seed=0)
    (same,) = [a for a in ref.attractors if a.period == 2 and a.minima_per_period == 3]
    assert got["app_um"].values[at[0]] == pytest.approx(same.app_um, rel=1e-3)
