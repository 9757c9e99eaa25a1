"""Resonance sweeps and the paper's Section 3–4 story, checked on the dataset (issue: resonance graphs).

The module fixture runs ``reproduce_paper`` on the paper's eight levels over 30–2000 Hz at a
4 Hz step (the default test grid; the 1 Hz run is the ``slow`` test at the end). Facts are read
with :func:`contactvib.sweeps.facts.resonance_facts`; numbers are checked against the scipy reference
orbits in ``tests/data/reference.json`` (DOP853, rtol 1e-12, made by ``make_reference.py``).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from contactvib.cli import main
from contactvib.labels import dominant_ratio, resonance_label
from contactvib.model import ContactModel, ParameterError
from contactvib.sweeps.dataset import check_consistency
from contactvib.sweeps.facts import coexisting_resonances, resonance_facts
from contactvib.sweeps.paper import PAPER_LEVELS, reproduce_paper
from contactvib.sweeps.settings import fill_in_indices
from contactvib.sweeps.stored import attractors_at
from contactvib.sweeps.sweep import SweepSettings, frequency_grid, multistart_indices, trace_level

REF = json.loads((Path(__file__).parents[1] / "data" / "reference.json").read_text())
Y0_UM = REF["model"]["y0"] * 1e6
STAGES = ["absent", "grows", "bent", "period doubling", "chaos", "divided"]
CONTRACT = {"period", "minima_per_period", "app_um", "ymin_um", "ymax_um", "loses_contact",
            "contact_loss_fraction", "basin_fraction"}


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    return reproduce_paper(out=out, settings=SweepSettings(df_hz=4.0), workers=2, progress=False)


@pytest.fixture(scope="module")
def ds(paper):
    return paper.dataset


def _overlaps(intervals, lo, hi):
    return any(a <= hi and b >= lo for a, b in intervals)


# ------------------------------------------------------------------ outputs of `paper`

def test_paper_writes_one_dataset_chunks_figures_and_index(paper):
    out = paper.out
    assert sorted(p.name for p in out.glob("*.nc")) == ["paper.nc"]
    assert len(list((out / ".chunks").glob("level_pa*.nc"))) == len(PAPER_LEVELS)
    for letter, pa in zip("abcdefgh", PAPER_LEVELS):
        for fig in (2, 3):
            p = out / f"fig{fig}{letter}_pa{pa:.2f}.png"
            assert p.is_file() and p.stat().st_size > 10_000, p
    assert sorted(int(p.name[3]) for p in out.glob("fig[4-9]_*.png")) == [4, 5, 6, 7, 8, 9]
    index = (out / "index.md").read_text()
    assert "four resonances can be excited at one frequency" in index  # statements shipped
    for sid in [f"S3.{i}" for i in range(1, 10)] + [f"S4.{i}" for i in range(1, 8)]:
        assert sid in index, sid
    for name in __import__("re").findall(r"!\[\]\(([^)]+)\)", index):
        assert (out / name).is_file(), name
    on_disk = xr.open_dataset(out / "paper.nc")
    assert on_disk.sizes["point"] == paper.dataset.sizes["point"]
    on_disk.close()


def test_every_variable_states_its_unit_or_meaning(ds):
    for name, var in ds.data_vars.items():
        assert "units" in var.attrs or "comment" in var.attrs or var.dtype == object \
            or name.endswith(("_start", "_count", "_index", "_direction", "_period", "_minima",
                              "_npoints", "_id")), name


def test_no_row_contradicts_itself(ds):
    """Issue 13: app_um = ymax_um − ymin_um and loses_contact ⇔ ymin_um < 0 ⇔
    contact_loss_fraction > 0 on every row of all eight levels (contact-losing rows included)."""
    from contactvib.sweeps.dataset import check_consistency

    assert bool(ds.loses_contact.any()) and not bool(ds.loses_contact.all())
    assert check_consistency(ds) == []


# ------------------------------------------------------------------ against the scipy reference

@pytest.mark.parametrize("orbit", [o for o in REF["orbits"]
                                   if ((o["f_e"] - 30.0) / 4.0).is_integer()],
                         ids=lambda o: f"{o['pa_over_q']}Q-{o['f_e']:g}Hz-{o['label']}")
def test_sweep_points_match_scipy_reference(ds, orbit):
    """Every reference orbit on the grid is in the dataset, A_pp to 1e-6 (scipy DOP853 rtol 1e-12)."""
    res = attractors_at(ds, pa_over_q=orbit["pa_over_q"], fe_hz=orbit["f_e"])
    app_ref = orbit["A_pp"] * Y0_UM
    same = [a for a in res["attractors"] if a["period"] == orbit["period"]
            and a["minima_per_period"] == orbit["minima_per_period"]
            and abs(a["app_um"] - app_ref) <= 1e-6 * app_ref]
    assert len(same) == 1, (app_ref, [(a["period"], a["app_um"]) for a in res["attractors"]])
    want = {"quasistatic": "non-resonant"}.get(orbit["label"], orbit["label"])
    assert same[0]["resonance"] == want


# ------------------------------------------------------------------ Section 3 (Figs. 2-3)

def test_four_resonances_coexist_at_360_hz_065q_and_three_at_234_hz_085q(ds):
    """S3.2/S4.1: main, 1/2, 1/3, 1/4 at 360 Hz, 0.65 Q; S3.6/S4.4: main, 1/5, 1/6 at 234 Hz."""
    assert coexisting_resonances(ds, 0.65, 360.0) == [1, 2, 3, 4]
    assert coexisting_resonances(ds, 0.85, 234.0) == [1, 5, 6]


def test_1_4_and_1_5_never_coexist_at_065q(ds):
    """S3.2: the 1/4 peak has not bent yet, so 1/4 and 1/5 cannot coexist at one frequency."""
    sel = (np.abs(ds["pa_over_q"].values - 0.65) < 1e-9) & (ds["period"].values == 1)
    lab = ds["resonance"].values[sel]
    fe = ds["fe_hz"].values[sel]
    f4 = set(fe[lab == "1/4"])
    f5 = set(fe[lab == "1/5"])
    assert f4 and f5 and not (f4 & f5)
    assert not resonance_facts(ds, 0.65, 4).bent and resonance_facts(ds, 0.65, 3).bent


def test_superharmonic_peaks_lie_near_fn0_over_m_and_bend_left_as_pa_grows(ds):
    """S2.3 / Eq. 2.6 and S3.8: small peaks at 0.9–1.0 f_n0/m; their frequency falls with P_a."""
    for m in (3, 4):
        f = resonance_facts(ds, 0.50, m)
        assert 0.9 * f.fn0_over_m_hz <= f.peak_fe_hz <= f.fn0_over_m_hz + 4.0, (m, f.peak_fe_hz)
    for m in (2, 3, 4, 5):  # until the branch divides (then the upper part leaves the grid)
        facts = [resonance_facts(ds, p, m) for p in PAPER_LEVELS]
        peaks = [f.peak_fe_hz for f in facts if f.present and f.stage() != "divided"]
        assert len(peaks) >= 3, m
        assert all(b <= a + 4.0 for a, b in zip(peaks, peaks[1:])), (m, peaks)
        assert peaks[-1] < 0.9 * facts[0].fn0_over_m_hz, (m, peaks)


def test_period_doubling_of_the_1_2_resonance_appears_at_070q(ds):
    """S3.3, S4.3: no doubling of the 1/2 at 0.65 Q; period 2 at 0.70 Q (4 minima at 470 Hz)."""
    assert resonance_facts(ds, 0.65, 2).period_doubled == {}
    assert 2 in resonance_facts(ds, 0.70, 2).period_doubled
    res = attractors_at(ds, pa_over_q=0.70, fe_hz=470.0)
    pd = [a for a in res["attractors"] if a["resonance"] == "1/2 period-2"]
    assert len(pd) == 1 and pd[0]["period"] == 2 and pd[0]["minima_per_period"] == 4
    assert pd[0]["loses_contact"]


def test_1_2_branch_is_divided_with_parts_no_sweep_reaches(ds):
    """S3.4–S3.7: from 0.75 Q the 1/2 is divided; its part near 100 Hz (0.75 Q), near 50 Hz
    (0.80 Q) and near 800 Hz (0.80–0.90 Q) is found only by the seeds; 1/3 near 500 Hz at 0.9 Q."""
    for p in (0.75, 0.80, 0.85, 0.90):
        assert resonance_facts(ds, p, 2).stage() == "divided", p
    assert _overlaps(resonance_facts(ds, 0.75, 2).isolated_hz, 80, 120)
    assert _overlaps(resonance_facts(ds, 0.80, 2).isolated_hz, 30, 60)
    for p in (0.80, 0.85, 0.90):
        assert _overlaps(resonance_facts(ds, p, 2).isolated_hz, 700, 816), p
    assert _overlaps(resonance_facts(ds, 0.90, 3).isolated_hz, 440, 544)
    iso = ds["branch_reached_by_sweep"].values == 0
    found = ds["found_by"].values[np.isin(ds["branch_index"].values, np.nonzero(iso)[0])]
    assert set(found) <= {"perturbation seed", "multi-start", "continuation"}  # never "sweep"


def test_stages_follow_the_papers_sequence(ds):
    """S3.8: stages never go back as P_a grows, and the 1/2 divides first, then 1/3, 1/4, 1/5."""
    first = {}
    for m in (2, 3, 4, 5, 6):
        st = [STAGES.index(resonance_facts(ds, p, m).stage()) for p in PAPER_LEVELS]
        assert st == sorted(st), (m, st)
        div = [p for p, s in zip(PAPER_LEVELS, st) if s == STAGES.index("divided")]
        first[m] = div[0] if div else np.inf
    assert first[2] < first[3] < first[4] < first[5], first


def test_open_primary_branch_runs_over_the_whole_grid_without_a_jump(ds):
    """S3.9 and the open upper branch: the main resonance is traced from 30 to 2000 Hz on one
    branch whose A_pp falls monotonically with f_e up to 800 Hz."""
    for p in PAPER_LEVELS:
        r = attractors_at(ds, pa_over_q=p, fe_hz=30.0)
        main = [a for a in r["attractors"] if a["resonance"] == "main"]
        assert len(main) == 1 and main[0]["app_um"] > 1000.0
        b = [i for i, bid in enumerate(ds["branch_id"].values) if bid == main[0]["branch"]][0]
        f_end = frequency_grid(SweepSettings(df_hz=4.0))[-1]
        assert ds["branch_fmin_hz"].values[b] == 30.0 and ds["branch_fmax_hz"].values[b] == f_end
        sel = ds["branch_index"].values == b
        order = np.argsort(ds["fe_hz"].values[sel])
        fe = ds["fe_hz"].values[sel][order]
        app = ds["app_um"].values[sel][order]
        assert np.all(np.diff(fe) == 4.0)
        low = fe <= 800
        assert np.all(np.diff(app[low]) < 0)


def _branch_points(ds, att):
    b = [i for i, bid in enumerate(ds["branch_id"].values) if bid == att["branch"]][0]
    sel = ds["branch_index"].values == b
    order = np.argsort(ds["fe_hz"].values[sel])
    return ds["fe_hz"].values[sel][order], ds["app_um"].values[sel][order]


def test_sweep_branches_coincide_with_continuation_and_jump_at_the_fold(ds):
    """Stable continued branches (pseudo-arclength, rtol 1e-12) pass through the sweep's points
    (A_pp to 1e-5 via a cubic spline through the continuation points, log-log on the
    open branch), and the up-sweep leaves
    the lower primary branch within one grid step below its fold (0.65 Q)."""
    from scipy.interpolate import CubicSpline

    from contactvib import ContinuationSettings, continue_orbit

    model = ContactModel()
    y_um, v_mm_s = model.y0 * 1e6, model.y0 * model.omega_n0 * 1e3

    def state(a):
        p = a["strobe_points"][0]
        return np.array([p["y_um"] / y_um, p["ydot_mm_s"] / v_mm_s])

    # the open upper primary branch, 1202 Hz down to 300 Hz
    up = [a for a in attractors_at(ds, pa_over_q=0.65, fe_hz=1202.0)["attractors"] if a["resonance"] == "main"]
    assert len(up) == 1
    b = continue_orbit(model.excitation(0.65, 1202.0), state(up[0]), 1, direction="down",
                       settings=ContinuationSettings(fmin_hz=290.0, fmax_hz=1300.0))
    assert np.all(b.stable) and np.all(np.diff(b.fe_hz) < 0)  # no fold: open branch
    spline = CubicSpline(np.log(b.fe_hz[::-1]), np.log(b.app_um[::-1]))  # A_pp ~ power of f_e
    fe, app = _branch_points(ds, up[0])
    inside = (fe >= 300.0) & (fe <= 1200.0)
    assert inside.sum() > 200
    assert np.max(np.abs(np.exp(spline(np.log(fe[inside]))) / app[inside] - 1.0)) < 1e-5
    # the lower branch through its fold: the sweep's last point lies within one step of it
    low = min((a for a in attractors_at(ds, pa_over_q=0.65, fe_hz=902.0)["attractors"] if a["resonance"] == "main"),
              key=lambda a: a["app_um"])
    b = continue_orbit(model.excitation(0.65, 902.0), state(low), 1, direction="up",
                       settings=ContinuationSettings(fmin_hz=800.0, fmax_hz=1100.0, ds=0.002, ds_max=0.004,
                                                               max_points=2000))
    folds = [sp.fe_hz for sp in b.special if sp.type == "fold"]
    assert len(folds) == 1
    fe, app = _branch_points(ds, low)
    assert fe.max() <= folds[0] < fe.max() + 4.0, (fe.max(), folds[0])
    turn = int(np.argmax(np.diff(b.fe_hz) <= 0)) + 1  # points up to the fold, along the arclength
    before = np.arange(len(b.fe_hz)) < turn
    assert np.all(b.stable[before][:-1])
    spline = CubicSpline(b.fe_hz[before], b.app_um[before])
    inside = (fe >= b.fe_hz[before].min()) & (fe <= fe.max() - 8.0)
    assert inside.sum() > 10
    assert np.max(np.abs(spline(fe[inside]) / app[inside] - 1.0)) < 1e-5


def test_perturbation_series_lies_on_the_small_amplitude_orbits(ds):
    """Issue 5 overlay: where the series is valid it equals a stored period-1 orbit (1e-3)."""
    from contactvib.frequency.perturbation import perturbation_curve

    model = ContactModel()
    f = np.arange(30.0, 1998.0, 40.0)
    fe, app, ok = perturbation_curve(model, pa_over_q=0.65, fe_hz=f)
    assert 20 <= ok.sum() < len(f)  # valid below and between the resonances, not everywhere
    for fv, av in zip(fe[ok], app[ok]):
        stored = [a["app_um"] for a in attractors_at(ds, pa_over_q=0.65, fe_hz=fv)["attractors"] if a["period"] == 1]
        assert min(abs(s / av - 1.0) for s in stored) < 1e-3, fv


def test_chaos_inside_the_1_2_resonance_at_075q():
    """S3.4: two opposing cascades of the 1/2 at 0.75 Q lead to chaos (λ > 0 between them)."""
    model = ContactModel()
    st = SweepSettings(fmin_hz=560.0, fmax_hz=640.0, df_hz=1.0, multistart_per_octave=16)
    from contactvib.sweeps.dataset import level_dataset

    d = level_dataset(model, trace_level(model, pa_over_q=0.75, settings=st), st.to_dict())
    lab = d["resonance"].values
    for k in (2, 4, 8):
        assert f"1/2 period-{k}" in set(lab), k
    chaos = (lab == "non-periodic (1/2)") & (d["attractor_type"].values == "chaotic")
    assert chaos.any()
    assert np.all(d["lyapunov_per_period"].values[chaos] > 0.02)
    f_c = d["fe_hz"].values[chaos]
    f_p8 = d["fe_hz"].values[lab == "1/2 period-8"]
    assert np.min(np.abs(f_c[:, None] - f_p8[None, :])) <= 3.0  # chaos next to the cascade


def test_isolated_part_is_not_found_by_the_sweeps_alone(ds):
    """The special procedure of Sec. 3: without seeds no 1/2 orbit exists near 100 Hz at 0.75 Q."""
    model = ContactModel()
    st = SweepSettings(fmin_hz=30.0, fmax_hz=2000.0, df_hz=4.0, multistart_per_octave=0)
    lv = trace_level(model, pa_over_q=0.75, settings=st)
    from contactvib.sweeps.dataset import level_dataset

    d = level_dataset(model, lv, st.to_dict())
    near = (d["fe_hz"].values >= 80) & (d["fe_hz"].values <= 120)
    assert not any(str(x).startswith("1/2") for x in d["resonance"].values[near])
    assert any(str(a["resonance"]).startswith("1/2")
               for a in attractors_at(ds, pa_over_q=0.75, fe_hz=102.0)["attractors"])


@pytest.mark.parametrize("pa", PAPER_LEVELS)
def test_basin_fractions_sum_to_one_where_measured(ds, pa):
    """At every multi-start and fill-in frequency of every level each box start is counted for
    at most one stored attractor, the fractions are measured there only, and they sum to 1 (to
    round-off) except where whole starts reached no stored attractor (an orbit of period above
    kmax that the verdict does not keep: the sum is 1 − j/n_starts for an integer j)."""
    sel = np.abs(ds["pa_over_q"].values - pa) < 1e-9
    fe = ds["fe_hz"].values[sel]
    bf = ds["basin_fraction"].values[sel]
    measured = np.unique(fe[np.isfinite(bf)])
    st = SweepSettings(df_hz=4.0)
    grid = frequency_grid(st)
    assert fill_in_indices(st).size > 100
    assert set(measured) == set(grid[multistart_indices(st)]) | set(grid[fill_in_indices(st)])
    n_starts = np.where(np.isin(measured, grid[multistart_indices(st)]), st.n_starts, st.fill_in_starts)
    sums = np.array([bf[(fe == f) & np.isfinite(bf)].sum() for f in measured])
    assert len(sums) > 30
    assert np.all(sums <= 1.0 + 1e-12)
    uncounted = (1.0 - sums) * n_starts
    np.testing.assert_allclose(uncounted, np.round(uncounted), rtol=0, atol=1e-9)
    assert np.mean(np.abs(sums - 1.0) < 1e-12) >= 0.95
    assert np.all(bf[np.isfinite(bf)] >= 0.0)


# ------------------------------------------------------------------ labels

def test_labels_use_the_dominant_amplified_harmonic():
    """The early 1/5 has 2 minima but its 5th harmonic dominates the acceleration."""
    h = np.zeros(64)
    h[0], h[1], h[4] = 1.0, 0.2, 0.05  # |Y1|, |Y2|, |Y5|: accelerations 1, 0.8, 1.25
    nu = dominant_ratio(1, 2, h, False, 287.0, 1485.0)
    assert nu == 5 and resonance_label(0, 1, nu, 2, False, 287.0, 1485.0) == "1/5"
    h[4] = 0.01
    assert dominant_ratio(1, 2, h, False, 287.0, 1485.0) == 1
    assert resonance_label(0, 1, dominant_ratio(1, 1, h, False, 287.0, 1485.0), 1, False, 287.0,
                           1485.0) == "non-resonant"
    # harmonics above 1.1 f_n0 are never the resonance (Eq. 2.6: superharmonics lie below f_n0)
    h2 = np.zeros(64)
    h2[0], h2[5] = 1.0, 0.1
    assert dominant_ratio(1, 1, h2, False, 300.0, 1485.0) == 1
    # contact lost: minima per period over the period
    from fractions import Fraction

    assert resonance_label(0, 2, Fraction(4, 2), 4, True, 470.0, 1485.0) == "1/2 period-2"
    assert resonance_label(0, 2, Fraction(1, 2), 1, True, 470.0, 1485.0) == "subharmonic 1/2 bouncing"
    assert resonance_label(0, 4, Fraction(3, 4), 3, True, 1400.0, 1485.0) == "ultrasubharmonic 3/4 bouncing"
    assert resonance_label(1, 0, Fraction(64, 32), -1, True, 570.0, 1485.0) == "non-periodic (1/2)"


# ------------------------------------------------------------------ query

def test_query_json_follows_the_attractors_contract(paper, capsys):
    path = str(paper.out / "paper.nc")
    assert main(["query", path, "--pa", "0.85", "--fe", "235.9", "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["pa_over_q"] == 0.85 and res["fe_hz"] == 234.0
    assert res["requested"] == {"pa_over_q": 0.85, "fe_hz": 235.9}
    assert abs(res["fn0_hz"] - REF["model"]["f_n0"]) < 1e-6 and abs(res["y0_um"] - Y0_UM) < 1e-9
    apps = [a["app_um"] for a in res["attractors"]]
    assert apps == sorted(apps, reverse=True)
    for a in res["attractors"]:
        assert CONTRACT <= set(a) and {"branch", "branch_label", "resonance"} <= set(a)
        assert isinstance(a["period"], int) and isinstance(a["loses_contact"], bool)
    # each attractor once, merged across up-, down-sweep and seeds
    keys = [(a["period"], round(a["app_um"], 9)) for a in res["attractors"]]
    assert len(keys) == len(set(keys))


# ------------------------------------------------------------------ resume and interruption

def _small(**kw):
    base = dict(fmin_hz=340.0, fmax_hz=380.0, df_hz=2.0, multistart_per_octave=0)
    base.update(kw)
    return SweepSettings(**base)


def test_resume_recomputes_only_missing_levels(tmp_path, monkeypatch):
    import contactvib.sweeps.sweep as sweep
    from contactvib.sweeps.resonance import chunk_path, resonance_dataset

    model = ContactModel()
    first = resonance_dataset(model, levels=[0.6, 0.65], settings=_small(), out=tmp_path, workers=1, progress=False)
    kept = chunk_path(tmp_path, 0.6)
    mtime = kept.stat().st_mtime_ns
    chunk_path(tmp_path, 0.65).unlink()
    calls = []
    real = sweep.trace_level
    monkeypatch.setattr(sweep, "trace_level",
                        lambda m, *, pa_over_q, settings: calls.append(pa_over_q) or real(m, pa_over_q=pa_over_q,
                                                                                           settings=settings))
    again = resonance_dataset(model, levels=[0.6, 0.65], settings=_small(), out=tmp_path, resume=True, workers=1,
                              progress=False)
    assert calls == [0.65] and kept.stat().st_mtime_ns == mtime
    for name in ("fe_hz", "app_um", "period", "resonance", "branch_index"):
        np.testing.assert_array_equal(first[name].values, again[name].values)
    # other settings: the chunks are not reused, the resume is refused before computing
    # (tests/sweeps/test_resume_safety.py); without resume they are recomputed
    calls.clear()
    with pytest.raises(ParameterError, match="seed"):
        resonance_dataset(model, levels=[0.6, 0.65], settings=_small(seed=1), out=tmp_path, resume=True, workers=1,
                          progress=False)
    assert calls == []
    resonance_dataset(model, levels=[0.6, 0.65], settings=_small(seed=1), out=tmp_path, workers=1, progress=False)
    assert sorted(calls) == [0.6, 0.65]


def test_interrupted_run_keeps_finished_levels(tmp_path, monkeypatch):
    """An interrupt while the second level is sweeping loses only that level."""
    import contactvib.sweeps.sweep as sweep
    from contactvib.sweeps.resonance import chunk_path, resonance_dataset

    real = sweep.trace_level
    calls = []

    def interrupted(m, *, pa_over_q, settings):
        pa = pa_over_q
        calls.append(pa)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(m, pa_over_q=pa, settings=settings)

    monkeypatch.setattr(sweep, "trace_level", interrupted)
    model = ContactModel()
    with pytest.raises(KeyboardInterrupt):
        resonance_dataset(model, levels=[0.6, 0.65], settings=_small(), out=tmp_path, workers=1, progress=False)
    assert chunk_path(tmp_path, 0.6).is_file() and not chunk_path(tmp_path, 0.65).exists()
    assert not (tmp_path / "resonance.nc").exists()
    assert not list(tmp_path.rglob("*.tmp*"))
    monkeypatch.setattr(sweep, "trace_level",
                        lambda m, *, pa_over_q, settings: calls.append(pa_over_q) or real(m, pa_over_q=pa_over_q,
                                                                                           settings=settings))
    calls.clear()
    resonance_dataset(model, levels=[0.6, 0.65], settings=_small(), out=tmp_path, resume=True, workers=1,
                      progress=False)
    assert calls == [0.65] and (tmp_path / "resonance.nc").is_file()


def test_resonance_cli_writes_dataset_and_figures(tmp_path, capsys):
    out = tmp_path / "res"
    assert main(["resonance", "--pa", "0.6", "0.65", "--fmin", "340", "--fmax", "380", "--df", "2",
                 "--multistart-per-octave", "0", "--workers", "1", "--no-progress",
                 "--out", str(out)]) == 0
    assert "2 levels" in capsys.readouterr().out
    d = xr.open_dataset(out / "resonance.nc")
    assert sorted(np.unique(d["pa_over_q"].values)) == [0.6, 0.65]
    d.close()
    for p in (0.6, 0.65):
        assert (out / f"resonance_pa{p:.2f}.png").is_file() and (out / f"extrema_pa{p:.2f}.png").is_file()
    # resume: nothing recomputed, same file
    assert main(["resonance", "--pa", "0.6", "0.65", "--fmin", "340", "--fmax", "380", "--df", "2",
                 "--multistart-per-octave", "0", "--workers", "1", "--no-progress", "--resume",
                 "--out", str(out)]) == 0


def test_sweep_settings_validate():
    with pytest.raises(ParameterError, match="f_max"):
        SweepSettings(fmin_hz=100.0, fmax_hz=50.0)
    with pytest.raises(ParameterError, match="kmax"):
        SweepSettings(kmax=0)
    assert len(frequency_grid(SweepSettings())) == 1971
    idx = multistart_indices(SweepSettings())
    assert idx[0] == 0 and np.all(np.diff(idx) > 0) and len(idx) == 49


# ------------------------------------------------------------------ the full run (slow)

@pytest.mark.slow
def test_full_paper_run(tmp_path):
    """`contactvib paper` at 1 Hz: every reference orbit, the 1/5 with two minima at 287 Hz."""
    res = reproduce_paper(out=tmp_path, workers=2, progress=False)
    d = res.dataset
    assert check_consistency(d) == []  # no row contradicts itself (issue 13)
    for orbit in REF["orbits"]:
        test_sweep_points_match_scipy_reference(d, orbit)
    fives = [a for a in attractors_at(d, pa_over_q=0.65, fe_hz=287.0)["attractors"] if a["resonance"] == "1/5"]
    assert len(fives) == 1 and fives[0]["minima_per_period"] == 2 and not fives[0]["loses_contact"]
    test_four_resonances_coexist_at_360_hz_065q_and_three_at_234_hz_085q(d)
    test_1_2_branch_is_divided_with_parts_no_sweep_reaches(d)
    test_stages_follow_the_papers_sequence(d)
    assert resonance_facts(d, 0.75, 2).nonperiodic_fe_hz


def test_continuation_overlay_on_the_resonance_graph(paper, tmp_path, capsys):
    """`continue --dataset` draws the continued branches over the sweep's resonance graph."""
    nc = str(paper.out / "paper.nc")
    assert main(["continue", "--pa", "0.66", "--from-fe", "1930", "--dataset", nc,
                 "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--pa (P_a/Q) = 0.66: not in --dataset" in err
    assert not (tmp_path / "x").exists()
    assert main(["continue", "--pa", "0.65", "--from-fe", "1930", "--attractor", "0",
                 "--fmin", "1700", "--fmax", "2000", "--dataset", nc, "--out", str(tmp_path / "b")]) == 0
    assert (tmp_path / "b" / "overlay_pa0.65_fe1930.png").stat().st_size > 20_000


def test_label_flickers_along_a_branch_are_smoothed():
    """A short run of other labels inside one continued branch (≤ 3 % of f_e, the same label on
    both sides, minima matching the sides and not the run) takes the surrounding label; long
    runs, runs whose minima match their own label, runs at a branch end and runs across two
    branches are left alone."""
    from contactvib.labels import smooth_labels

    fe = np.arange(226.0, 240.0)
    six = np.full(fe.size, 6)
    one = np.zeros(fe.size, int)
    lab = np.array(["1/6"] * 4 + ["1/7"] * 4 + ["1/5"] + ["1/6"] * 5, dtype=object)
    assert list(smooth_labels(lab, fe, six, one, 1.0)) == ["1/6"] * fe.size
    long_run = np.array(["1/6"] * 3 + ["1/5"] * 8 + ["1/6"] * 3, dtype=object)  # 8 Hz > 3 %
    assert list(smooth_labels(long_run, fe, six, one, 1.0)) == list(long_run)
    own = np.array(["1/5"] * 6 + ["1/6"] * 2 + ["1/5"] * 6, dtype=object)  # a small 1/6 peak
    minima = np.array([5] * 6 + [6] * 2 + [5] * 6)
    assert list(smooth_labels(own, fe, minima, one, 1.0)) == list(own)
    at_end = np.array(["1/6"] * 12 + ["1/5"] * 2, dtype=object)
    assert list(smooth_labels(at_end, fe, six, one, 1.0)) == list(at_end)
    two_chains = np.repeat([0, 1], 7)  # the flicker sits at the junction of two branches
    lab2 = np.array(["1/6"] * 6 + ["1/5"] * 2 + ["1/6"] * 6, dtype=object)
    assert list(smooth_labels(lab2, fe, six, two_chains, 1.0)) == list(lab2)


def test_one_sixth_at_090q_bends_and_is_not_divided(ds):
    """S3.7: at 0.90 Q the 1/6 grows and bends (one part; its labels no longer flicker)."""
    facts = resonance_facts(ds, 0.90, 6)
    assert facts.present and facts.bent
    assert facts.stage() == "bent", facts
