"""Stable parts that only continuation reaches (sweeps/unstable_parts.py): the 1/5 at 0.90 Q.

Its period-1 branch loses stability by period doubling near 250 Hz going down, regains it through
a second doubling at 113.27 Hz and stays stable down to a fold at 101.76 Hz (continuation,
tests/continuation/test_second_part.py). No sweep lands there; the post-pass must store it."""

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib.sweeps import unstable_parts
from contactvib.sweeps.dataset import level_dataset
from contactvib.sweeps.facts import level_stages
from contactvib.sweeps.sweep import TRACE_ROOTS, SweepSettings, trace_level

PD_HZ, FOLD_HZ = 113.27, 101.76  # tests/continuation/test_second_part.py
DF = 5.0


@pytest.fixture(scope="module")
def level():
    model = ContactModel()
    st = SweepSettings(fmin_hz=95.0, fmax_hz=260.0, df_hz=DF, multistart_per_octave=0)
    return model, level_dataset(model, trace_level(model, pa_over_q=0.9, settings=st), st.to_dict())


def test_continuation_is_a_trace_root():
    assert "continuation" in TRACE_ROOTS and len(set(TRACE_ROOTS)) == len(TRACE_ROOTS)


def test_the_second_part_of_the_1_5_is_stored(level):
    model, d = level
    found_by = d["found_by"].values.astype(str)
    sel = ((found_by == "continuation") & (d["period"].values == 1)
           & (d["minima_per_period"].values == 5))
    fe = d["fe_hz"].values[sel]
    assert fe.size >= 2
    assert np.all(d["floquet_abs_max"].values[sel] < 1.0)
    # between the fold and the doubling, each end within one grid step
    assert FOLD_HZ <= fe.min() < FOLD_HZ + DF and PD_HZ - DF < fe.max() <= PD_HZ
    # no row of that orbit was there before: every 5-minima period-1 row in the window is new
    window = (d["fe_hz"].values > FOLD_HZ) & (d["fe_hz"].values < PD_HZ)
    five = window & (d["period"].values == 1) & (d["minima_per_period"].values == 5)
    assert np.array_equal(five, sel & window)
    # the same orbit as the multi-start search finds
    p = int(np.flatnonzero(sel & (d["fe_hz"].values == 110.0))[0])
    att = [a for a in find_attractors(model.excitation(0.9, 110.0))
           if a.period == 1 and a.minima_per_period == 5]
    assert len(att) == 1
    assert float(d["app_um"].values[p]) == pytest.approx(att[0].app_um, rel=1e-6)


def test_the_stage_table_says_divided(level):
    _model, d = level
    assert level_stages(d, 0.9)[5] == "divided"


def test_no_stable_part_means_no_new_trace():
    """A branch whose continuation never becomes stable again starts nothing."""

    class Branch:
        stable = np.array([True, True, False, False, False])

    assert unstable_parts._stable_again(Branch()) == []
    Branch.stable = np.array([True, False, False, True, True, False, True])
    assert unstable_parts._stable_again(Branch()) == [(3, 4), (6, 6)]
