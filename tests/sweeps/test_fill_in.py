"""Fill-in multi-starts: the short isolated branches between two multi-start frequencies.

At 0.75 Q a period-3 orbit with 6 minima per period lives over ~662–680 Hz only (an
ultrasubharmonic of the 1/2 window). On the grid 630–700 Hz the multi-start frequencies are 630
and 688 Hz (8 per octave) and neither sweep reaches it; the fill-in frequencies 644, 658 and 672 Hz
(32 per octave, 12 starts each) find it. The reference is the brute-force attractor search at
672 Hz (512 starts), which finds the same orbit.
"""

from __future__ import annotations

import pytest

from contactvib import find_attractors
from contactvib.model import ContactModel, ParameterError
from contactvib.sweeps.settings import fill_in_indices, frequency_grid, multistart_indices
from contactvib.sweeps.sweep import SweepSettings, trace_level

GRID = dict(fmin_hz=630.0, fmax_hz=700.0, df_hz=2.0)


def _period3_rows(lt):
    """Rows of period 3 with 6 minima per period, as (f_e [Hz], A_pp [y0])."""
    r = lt.rows
    sel = (r.kind == 0) & (r.k == 3) & (r.n_min == 6)
    return lt.f_hz[r.i[sel]], (r.xmax - r.xmin)[sel]


@pytest.fixture(scope="module")
def levels():
    m = ContactModel()
    return {fill: trace_level(m, pa_over_q=0.75, settings=SweepSettings(**GRID, fill_in_per_octave=fill))
            for fill in (0.0, 32.0)}


def test_fill_in_frequencies_lie_between_the_multistart_ones():
    st = SweepSettings(**GRID)
    f = frequency_grid(st)
    assert list(f[multistart_indices(st)]) == [630.0, 688.0]
    assert list(f[fill_in_indices(st)]) == [644.0, 658.0, 672.0]
    assert fill_in_indices(SweepSettings(**GRID, multistart_per_octave=0)).size == 0  # sweeps only
    assert fill_in_indices(SweepSettings(**GRID, fill_in_starts=0)).size == 0


def test_the_isolated_branch_is_found_by_the_fill_in_only(levels):
    assert _period3_rows(levels[0.0])[0].size == 0
    f, app = _period3_rows(levels[32.0])
    assert f.size >= 5 and 672.0 in f
    # the brute-force search finds the same orbit at 672 Hz (A_pp to 1e-6: both closed to 1e-9)
    m = ContactModel()
    found = [a for a in find_attractors(m.excitation(0.75, 672.0), n_starts=512)
             if a.period == 3 and a.minima_per_period == 6]
    assert len(found) == 1
    stored = app[f == 672.0][0] * m.y0 * 1e6
    assert stored == pytest.approx(found[0].app_um, rel=1e-6)


def test_the_fill_in_only_adds_rows(levels):
    base, fill = levels[0.0], levels[32.0]
    assert fill.n_rows > base.n_rows
    key = lambda lt: sorted(zip(lt.rows.i.tolist(), lt.rows.k.tolist(), lt.rows.n_min.tolist()))  # noqa: E731
    missing = set(key(base)) - set(key(fill))
    assert not missing


@pytest.mark.parametrize("field, value, words", [
    ("fill_in_per_octave", -1.0, "fill_in_per_octave"),
    ("fill_in_per_octave", "many", "fill_in_per_octave"),
    ("fill_in_starts", -2, "fill_in_starts"),
    ("fill_in_starts", 1.5, "fill_in_starts"),
])
def test_bad_fill_in_settings_are_refused_by_name(field, value, words):
    with pytest.raises(ParameterError, match=words):
        SweepSettings(**{field: value})


def test_kmax_16_is_the_sweep_default_and_bounded():
    assert SweepSettings().kmax == 16
    with pytest.raises(ParameterError, match="kmax"):
        SweepSettings(kmax=17)
