"""The sweep stores no unsettled transient as a non-periodic attractor (the search's verdict)."""

from __future__ import annotations

import numpy as np
import pytest

from contactvib._kernels.table import KIND_NONPERIODIC
from contactvib.model import ContactModel
from contactvib.steady.transients import LYAPUNOV_ZERO
from contactvib.sweeps import verdict
from contactvib.sweeps.sweep import SweepSettings, trace_level

#: 0.75 Q over 540–820 Hz at 4 Hz with periods up to 8 detected: without the verdict the sweep
#: stores 14 non-periodic points there, 9 of them with λ < −0.02 per period (transients still
#: converging, most towards the period-10 orbits near 700–740 Hz that kmax = 16 detects).
REDUCED = dict(fmin_hz=540.0, fmax_hz=820.0, df_hz=4.0, kmax=8, fill_in_per_octave=0.0)


@pytest.fixture(scope="module")
def level():
    return trace_level(ContactModel(), pa_over_q=0.75, settings=SweepSettings(**REDUCED))


@pytest.fixture(scope="module")
def level_without_verdict():
    mp = pytest.MonkeyPatch()
    mp.setattr(verdict, "drop_unsettled", lambda lt, *a: lt)
    try:
        return trace_level(ContactModel(), pa_over_q=0.75, settings=SweepSettings(**REDUCED))
    finally:
        mp.undo()


def test_no_stored_nonperiodic_point_is_still_converging(level, level_without_verdict):
    raw = level_without_verdict.rows
    assert np.sum((raw.kind == KIND_NONPERIODIC) & (raw.lyap < -LYAPUNOV_ZERO)) >= 5  # the test bites
    rows = level.rows
    nonp = rows.kind == KIND_NONPERIODIC
    assert not np.any(rows.lyap[nonp] < -LYAPUNOV_ZERO)
    assert level.n_rows < level_without_verdict.n_rows


def test_every_kept_nonperiodic_point_passes_the_search_verdict(level):
    m = ContactModel()
    rows = level.rows
    for j in np.flatnonzero(rows.kind == KIND_NONPERIODIC):
        assert verdict.settled_nonperiodic(m, 0.75, float(level.f_hz[rows.i[j]]), rows.z[j],
                                           rows.lyap[j], 1e-8, 300)


def test_links_and_basins_stay_consistent_after_the_drop(level):
    n = level.n_rows
    for v in level.rows:
        assert v.shape[0] == n
    assert level.found_by.shape == (n,) and level.basin.shape == (n,)
    links = level.links
    assert np.all((links.a >= 0) & (links.a < n) & (links.b >= 0) & (links.b < n))
    # a Newton link joins neighbouring grid points of one kind
    newton = links.jump == 0
    di = np.abs(level.rows.i[links.b[newton]] - level.rows.i[links.a[newton]])
    assert np.all(di == 1)


def test_a_spiral_into_a_periodic_orbit_is_rejected():
    """A point on the way to a stable period-1 orbit (a transient) is not a non-periodic
    attractor, whatever λ is claimed for it, even after settling longer."""
    m = ContactModel()
    rows = trace_level(m, pa_over_q=0.75, settings=SweepSettings(fmin_hz=600.0, fmax_hz=604.0, df_hz=4.0)).rows
    per = np.flatnonzero((rows.kind == 0) & (rows.k == 1))[0]
    z = rows.z[per] * (1.0 + 1e-2)
    assert not verdict.settled_nonperiodic(m, 0.75, 600.0, z, 0.0, 1e-8, 0)
    assert not verdict.settled_nonperiodic(m, 0.75, 600.0, z, -1.0, 1e-8, 300)


def _in_level(lt, f_hz, attractor, rtol=1e-6):
    """Whether a periodic attractor of the full search is a row of the level at ``f_hz``."""
    m = ContactModel()
    r = lt.rows
    app = (r.xmax - r.xmin) * m.units.y_um
    at = (lt.f_hz[r.i] == f_hz) & (r.kind == 0) & (r.k == attractor.period)
    return bool(np.any(at & (np.abs(app - attractor.app_um) <= rtol * attractor.app_um)))


def test_period2_newton_seeds_find_the_ultrasubharmonic_isola():
    """0.60 Q, 500 Hz: the full search finds a period-2 orbit with 3 minima (A_pp 2.109 µm, basin
    0.2 % of the box), on an isola (stable 472.5–555.3 Hz) that no sweep meets and the 24 box
    starts miss; the period-2 Newton seeds find it, and every attractor of the search is traced."""
    import warnings

    from contactvib.steady.attractors import find_attractors
    from contactvib.sweeps import newton_seeds

    m = ContactModel()
    st = SweepSettings(fmin_hz=460.0, fmax_hz=560.0, df_hz=4.0)  # multi-start at 460, 500, 548 Hz
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = find_attractors(m.excitation(0.60, 500.0))
    iso = [a for a in full.attractors if a.period == 2 and a.minima_per_period == 3]
    assert len(iso) == 1 and iso[0].basin_fraction < 0.01
    lt = trace_level(m, pa_over_q=0.60, settings=st)
    for a in full.attractors:
        assert _in_level(lt, 500.0, a), (a.period, a.minima_per_period, a.app_um)
    r = lt.rows
    on_isola = (r.k == 2) & (r.n_min == 3)
    assert lt.f_hz[r.i[on_isola]].min() <= 476.0 and lt.f_hz[r.i[on_isola]].max() >= 552.0
    mp = pytest.MonkeyPatch()  # without the period-2 seeds (the period-3–5 ones still run)
    mp.setattr(newton_seeds, "NEWTON_SEEDS", tuple(e for e in newton_seeds.NEWTON_SEEDS if e[0] != 2))
    try:
        assert not _in_level(trace_level(m, pa_over_q=0.60, settings=st), 500.0, iso[0])  # the test bites
    finally:
        mp.undo()


def test_period5_newton_seeds_find_the_bouncing_orbit():
    """0.85 Q, 1700 Hz: the full search finds bouncing orbits of periods 1–5; the period-5 one
    (A_pp 10.16 µm, basin 0.8 % of the box) lies on a branch (1589–2000 Hz) that no sweep meets
    and the 24 box starts miss; the period-3–5 Newton seeds (stage 1, after the multi-start) find
    it from the multi-start at 1600 Hz, and every attractor of the search is traced."""
    import warnings

    from contactvib.steady.attractors import find_attractors
    from contactvib.sweeps import newton_seeds

    m = ContactModel()
    st = SweepSettings(fmin_hz=1600.0, fmax_hz=1720.0, df_hz=4.0)  # multi-start at 1600 Hz only
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        full = find_attractors(m.excitation(0.85, 1700.0))
    p5 = [a for a in full.attractors if a.period == 5]
    assert len(p5) == 1 and p5[0].basin_fraction < 0.01
    lt = trace_level(m, pa_over_q=0.85, settings=st)
    for a in full.attractors:
        assert _in_level(lt, 1700.0, a), (a.period, a.minima_per_period, a.app_um)
    f5 = lt.f_hz[lt.rows.i[lt.rows.k == 5]]
    assert f5.min() == 1600.0 and f5.max() == 1720.0
    mp = pytest.MonkeyPatch()  # with the period-2 seeds only
    mp.setattr(newton_seeds, "NEWTON_SEEDS", tuple(e for e in newton_seeds.NEWTON_SEEDS if e[0] == 2))
    try:
        assert not _in_level(trace_level(m, pa_over_q=0.85, settings=st), 1700.0, p5[0])  # the test bites
    finally:
        mp.undo()


# ------------------------------------------------------------------ the full run (slow)

#: Attractors of the full search below this basin fraction may still be missed by the sweep's
#: 24-start multi-start, unless they are periodic of period 1–5 (:data:`NEWTON_KINDS`). At the 41
#: points of benchmarks/bench_sweep_completeness.py two are (measured on the dataset of
#: `contactvib paper`): the period-9 orbit with 6 minima at 0.70 Q/800 Hz (A_pp 4.889 µm, basin
#: 0.78 %) and the period-24 orbit with 16 minima at 0.80 Q/1700 Hz (A_pp 0.886 µm, basin 0.20 %),
#: both beyond the sweep's kmax = 8, which the search's long-period verdict reports with their
#: true period. (The search's former "chaotic attractor" at 0.80 Q/360 Hz, transient chaos, is
#: no longer reported: its verdict now runs 2000 periods.)
SMALL_BASIN = 0.01
#: Misses allowed at those points (each below SMALL_BASIN and not of period 1–5).
MISSES_MAX = 2
#: Periods the sweep must hold whatever their basin: the period-2 Newton seeds find the
#: ultrasubharmonic isolas (period 2 with 3 minima at 0.60 Q/500 Hz and 0.75 Q/800 Hz, basins
#: 0.2 and 0.4 %) and tracing on finds their doublings (period 4 with 6 minima at 0.80 Q/800 Hz,
#: 0.6 %); the period-3–5 ones the period-5 bouncing orbit at 0.85 Q/1700 Hz (0.8 %); a
#: period-1 orbit is what a Newton start reduces to.
NEWTON_KINDS = (1, 2, 3, 4, 5)


@pytest.mark.slow
def test_every_attractor_of_the_full_search_with_a_basin_over_1_percent_or_of_period_1_to_5_is_in_the_paper_dataset(
        tmp_path):
    import json

    from benchmarks.bench_sweep_completeness import default_points, missing_at

    from contactvib.sweeps.paper import PAPER_LEVELS
    from contactvib.sweeps.resonance import resonance_dataset

    m = ContactModel()
    import xarray as xr

    resonance_dataset(m, levels=PAPER_LEVELS, settings=SweepSettings(), out=tmp_path, name="paper", workers=2,
                      progress=False)
    ds = xr.open_dataset(tmp_path / "paper.nc").load()
    nonp = ds["kind"].values != "periodic"
    assert not np.any(ds["lyapunov_per_period"].values[nonp] < -LYAPUNOV_ZERO)
    points = default_points(json.loads(ds.attrs["levels_pa_over_q"])) + [(0.6, 500.0)]
    assert len(points) >= 40
    found = missed = 0
    for pa, fe in points:
        r = missing_at(ds, m, pa, fe)
        found += len(r["attractors"])
        missed += len(r["missing"])
        assert [a for a in r["missing"] if a["basin"] >= SMALL_BASIN
                or (a["kind"] == "periodic" and a["period"] in NEWTON_KINDS)] == [], (pa, fe, r["missing"])
    assert found >= 150 and missed <= MISSES_MAX
