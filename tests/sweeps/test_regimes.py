"""Regime maps over (f_e, P_a) (issue 14, "Regime maps"): :func:`regime_maps` on a hand-made
dataset with known counts and on the small fixture, the acceptance test (the map's boundaries lie
on the fold curves of ``evolution`` at the 1/2 and the 1/3), the figures, and ``contactvib map``
with its one-line input errors."""

import json
import warnings

import numpy as np
import pytest
import xarray as xr

from contactvib import ContactModel
from contactvib.cli import main
from contactvib.sweeps.dataset import FORMAT
from contactvib.sweeps.regimes import (
    MAP_VARIABLES,
    MapCurve,
    count_changes,
    curve_crossings,
    curves_dataset,
    load_curves,
    regime_maps,
)
from contactvib.sweeps.stored import DatasetError, find_dataset
from figure_files import assert_figure_file

# ------------------------------------------------------------------ a hand-made dataset


def _tiny():
    """Two levels × three frequencies (100, 110, 120 Hz) with known attractors; 0.7 Q, 120 Hz has
    none."""
    rows = [  # (P_a, f_e, label, period, loses contact, λ)
        (0.5, 100.0, "main", 1, 0, np.nan),
        (0.5, 100.0, "1/3", 1, 1, np.nan),
        (0.5, 100.0, "subharmonic 1/2 bouncing", 2, 1, np.nan),
        (0.5, 110.0, "non-resonant", 1, 0, np.nan),
        (0.5, 120.0, "1/2 period-4", 4, 1, np.nan),
        (0.5, 120.0, "non-periodic (1/5)", 0, 1, 0.3),
        (0.7, 100.0, "non-periodic (1/2)", 0, 1, 0.001),  # quasi-periodic: not chaotic
        (0.7, 110.0, "1/6", 1, 0, np.nan),
        (0.7, 110.0, "main period-2", 2, 1, np.nan),
    ]
    pa, fe, lab, per, loses, lyap = (np.array(c) for c in zip(*rows))
    ds = xr.Dataset({"pa_over_q": ("point", pa.astype(float)), "fe_hz": ("point", fe.astype(float)),
                     "resonance": ("point", lab.astype(str)), "period": ("point", per.astype(np.int64)),
                     "loses_contact": ("point", loses.astype(np.int8)),
                     "lyapunov_per_period": ("point", lyap.astype(float))})
    ds.attrs.update(format=FORMAT, fn0_hz=1485.0, model=json.dumps(ContactModel().parameters()),
                    settings=json.dumps({"fmin_hz": 100.0, "fmax_hz": 120.0, "df_hz": 10.0}),
                    levels_pa_over_q=[0.5, 0.7])
    return ds


def test_maps_of_a_hand_made_dataset_are_exact():
    m = regime_maps(_tiny())
    assert m["pa_over_q"].values.tolist() == [0.5, 0.7]
    assert m["fe_hz"].values.tolist() == [100.0, 110.0, 120.0]
    assert m["n_attractors"].values.tolist() == [[3, 1, 2], [1, 2, 0]]
    assert m["max_order"].values.tolist() == [[3, 0, 5], [2, 6, -1]]
    np.testing.assert_array_equal(m["contact_loss_share"].values, [[2 / 3, 0.0, 1.0], [1.0, 0.5, np.nan]])
    assert m["chaotic"].values.tolist() == [[0, 0, 1], [0, 0, 0]]
    assert m["max_period"].values.tolist() == [[2, 1, 4], [0, 2, -1]]
    assert np.all(np.isnan(m["max_lambda1"].values[[0, 0, 1], [0, 1, 2]]))  # no multipliers, no λ there
    assert m["max_lambda1"].values[0, 2] == 0.3 and m["max_lambda1"].values[1, 0] == 0.001
    assert m.attrs["df_hz"] == 10.0
    for name in MAP_VARIABLES:
        assert {"units", "long_name"} <= set(m[name].attrs), name
    assert m["fe_hz"].attrs["units"] == "Hz" and m["pa_over_q"].attrs["units"] == "Q"
    assert count_changes(m, 0.5).tolist() == [105.0, 115.0]
    assert count_changes(m, 0.7).tolist() == [105.0, 115.0]


def test_largest_lyapunov_exponent_map():
    """λ1 of a period-k orbit is ln max|μ| / k, of a non-periodic one its stored estimate; the map
    holds the largest of the grid point's attractors (NaN where none is stored)."""
    ds = _tiny()
    mu = np.array([0.5, 0.9, 0.81, 0.2, 0.3, np.nan, np.nan, 0.6, 0.64])
    ds["floquet_abs_max"] = ("point", mu)
    m = regime_maps(ds)["max_lambda1"].values
    lam = np.where(ds["period"].values == 0, ds["lyapunov_per_period"].values,
                   np.log(mu) / np.maximum(ds["period"].values, 1))
    for il, p in enumerate((0.5, 0.7)):
        for jf, f in enumerate((100.0, 110.0, 120.0)):
            sel = (ds["pa_over_q"].values == p) & (ds["fe_hz"].values == f)
            want = np.max(lam[sel]) if sel.any() else np.nan
            np.testing.assert_allclose(m[il, jf], want, rtol=1e-15)
    assert m[0, 0] == pytest.approx(np.log(0.9)) and m[0, 2] == 0.3


def test_the_grid_comes_from_the_sweep_settings():
    """A frequency of the grid with no attractor at any level is still a column (count 0)."""
    ds = _tiny()
    ds.attrs["settings"] = json.dumps({"fmin_hz": 100.0, "fmax_hz": 130.0, "df_hz": 10.0})
    m = regime_maps(ds)
    assert m["fe_hz"].values.tolist() == [100.0, 110.0, 120.0, 130.0]
    assert m["n_attractors"].values[:, -1].tolist() == [0, 0]


def test_maps_of_the_small_fixture_agree_with_its_rows(small_dataset):
    with xr.open_dataset(small_dataset) as ds:
        m = regime_maps(ds)
        assert m.sizes == {"pa_over_q": 1, "fe_hz": 21}
        for j, f in enumerate(m["fe_hz"].values):
            sel = np.abs(ds["fe_hz"].values - f) < 1e-9
            assert m["n_attractors"].values[0, j] == sel.sum()
            assert m["max_period"].values[0, j] == ds["period"].values[sel].max()
            assert m["contact_loss_share"].values[0, j] == pytest.approx(ds["loses_contact"].values[sel].mean())


@pytest.mark.timing
def test_regime_maps_is_fast_on_a_paper_sized_dataset():
    """72k rows, 8 levels × 1971 frequencies, well under a second (vectorised)."""
    import time

    rng = np.random.default_rng(0)
    n = 72000
    ds = _tiny().isel(point=rng.integers(0, 9, n))
    ds["pa_over_q"] = ("point", rng.choice([0.5, 0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9], n))
    ds["fe_hz"] = ("point", rng.integers(30, 2001, n).astype(float))
    ds.attrs["settings"] = json.dumps({"fmin_hz": 30.0, "fmax_hz": 2000.0, "df_hz": 1.0})
    t0 = time.perf_counter()
    m = regime_maps(ds)
    assert time.perf_counter() - t0 < 2.0
    assert int(m["n_attractors"].sum()) == n


def test_curve_crossings_interpolate_and_the_curves_round_trip(tmp_path):
    c = MapCurve(2, "fold", np.array([600.0, 620.0, 640.0, 700.0]), np.array([0.8, 0.7, 0.6, 0.7]))
    np.testing.assert_allclose(curve_crossings(c, 0.65), [630.0, 670.0])
    assert curve_crossings(c, 0.9).size == 0
    cd = curves_dataset([c, MapCurve(3, "period-doubling", np.array([1.0, 2.0]), np.array([0.1, 0.2]))])
    assert cd["curve_start"].values.tolist() == [0, 4] and cd["curve_count"].values.tolist() == [4, 2]
    assert cd["curve_type"].values.tolist() == ["fold", "period-doubling"]
    assert curves_dataset([]).sizes == {"curve": 0, "curve_point": 0}
    res = {"order": 2, "curves": [{"type": "fold", "fe_hz": c.fe_hz.tolist(), "pa_over_q": c.pa_over_q.tolist()}]}
    (tmp_path / "evolution_order2.json").write_text(json.dumps(res))
    (back,) = load_curves(tmp_path)
    assert back.order == 2 and back.type == "fold" and back.fe_hz.tolist() == c.fe_hz.tolist()


# ------------------------------------------------------------------ acceptance: boundaries on the folds

#: (order m, frequency window [Hz] around the fold of the 1/m at 0.65–0.7 Q)
WINDOWS = {2: (615.0, 650.0), 3: (440.0, 470.0)}
LEVELS = [0.65, 0.7]
DF = 1.0


@pytest.fixture(scope="module")
def fold_cases(tmp_path_factory):
    """Per order: the regime maps of a resonance dataset at LEVELS over the window at 1 Hz, with
    multi-start (a sweep over a narrow window alone starts above the left fold of the 1/3 at
    0.7 Q, 171 Hz, and never reaches the lower branch that ends at its right fold, 452 Hz), and
    the evolution of the 1/m between the levels."""
    from contactvib.continuation.evolution import evolution
    from contactvib.continuation.shooting import ContinuationSettings
    from contactvib.sweeps.resonance import resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    model = ContactModel()
    cases = {}
    for m, (lo, hi) in WINDOWS.items():
        st = SweepSettings(fmin_hz=lo, fmax_hz=hi, df_hz=DF, multistart_per_octave=40)
        ds = resonance_dataset(model, levels=LEVELS, settings=st, out=tmp_path_factory.mktemp(f"fold{m}"), workers=1,
                               progress=False)
        cs = ContinuationSettings(fmin_hz=lo - 60, fmax_hz=hi + 60, max_points=200)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # unsettled starts of the seeds' attractor searches
            res = evolution(model, order=m, pa_min=LEVELS[0], pa_max=LEVELS[-1], n_levels=2,
                            seed_fe=[lo - 30, 0.5 * (lo + hi), hi + 20], settings=cs)
        curves = [MapCurve(m, c.type, c.fe_hz, c.pa_over_q) for c in res.curves if c.fe_hz.size > 1]
        cases[m] = (regime_maps(ds), curves)
    return cases


@pytest.mark.parametrize("order", sorted(WINDOWS))
@pytest.mark.parametrize("level", LEVELS)
def test_count_of_attractors_changes_on_the_fold_curve(fold_cases, order, level):
    """Acceptance: at every level, the frequency where the map's count of coexisting attractors
    changes at a fold of the 1/m lies within one grid step of the evolution's fold curve."""
    maps, curves = fold_cases[order]
    lo, hi = WINDOWS[order]
    folds = [c for c in curves if c.type == "fold"]
    assert folds, f"no fold curve of the 1/{order}"
    crossings = [f for c in folds for f in curve_crossings(c, level) if lo + DF <= f <= hi - DF]
    assert crossings, f"the 1/{order} fold curve does not cross {level} Q inside {lo}-{hi} Hz"
    changes = count_changes(maps, level)
    for f in crossings:
        assert changes.size, f"no change of the count at {level} Q"
        nearest = changes[np.argmin(np.abs(changes - f))]
        assert abs(nearest - f) <= DF, (level, f, changes)
        # the peak bends to lower f_e (softening contact): its stable branch ends at the fold,
        # so the count is larger just below the fold than just above it
        row = maps["n_attractors"].sel(pa_over_q=level).values
        j = int(np.searchsorted(maps["fe_hz"].values, nearest))
        assert row[j - 1] > row[j], (level, nearest, row[j - 1], row[j])


# ------------------------------------------------------------------ figures


def test_panel_has_colour_bar_units_and_curve_legend():
    from contactvib.plotting.regimes import PANEL_TITLES, plot_regime_map, regime_figure

    m = regime_maps(_tiny())
    curves = [MapCurve(2, "fold", np.array([100.0, 120.0]), np.array([0.5, 0.7])),
              MapCurve(2, "period-doubling", np.array([105.0, 115.0]), np.array([0.5, 0.7])),
              MapCurve(3, "fold", np.array([101.0, 119.0]), np.array([0.7, 0.5]))]
    for name in MAP_VARIABLES:
        fig = regime_figure(m, name, curves)
        ax, cax = fig.axes
        assert "[Hz]" in ax.get_xlabel() and "[Q]" in ax.get_ylabel()
        assert cax.get_ylabel() == PANEL_TITLES[name][1]
        texts = [t.get_text() for t in ax.get_legend().get_texts()]
        assert texts == ["1/2 fold", "1/2 period-doubling", "1/3 fold"]
        styles = [line.get_linestyle() for line in ax.get_lines()]
        assert styles[0] == "-" and styles[1] != "-"
        assert ax.get_lines()[0].get_color() != ax.get_lines()[2].get_color()
    ax = plot_regime_map(m, "n_attractors")
    assert ax.get_legend() is None
    assert [float(t) for t in ax.get_yticks()] == [0.5, 0.7]


# ------------------------------------------------------------------ the command


def test_map_command_writes_the_netcdf_and_one_figure_per_map(small_dataset, tmp_path, capsys):
    evo = tmp_path / "evo"
    evo.mkdir()
    (evo / "evolution_order2.json").write_text(json.dumps(
        {"order": 2, "curves": [{"type": "fold", "fe_hz": [350.0, 370.0], "pa_over_q": [0.6, 0.7]}]}))
    out = tmp_path / "map"
    assert main(["map", str(small_dataset.parent), "--curves", str(evo), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    # one attractor everywhere in the fixture: the fold crossing at 0.65 Q is on no boundary
    assert "1 level x 21 frequencies: 1..1 coexisting" in text and "0 of 1 fold crossings" in text
    for name in MAP_VARIABLES:
        assert_figure_file(out / f"map_{name}.png")
    with xr.open_dataset(out / "map.nc") as m, xr.open_dataset(small_dataset) as ds:
        assert set(MAP_VARIABLES) <= set(m.data_vars)
        assert int(m["n_attractors"].sum()) == ds.sizes["point"]
        assert m["curve_fe_hz"].values.tolist() == [350.0, 370.0]
    assert main(["map", str(small_dataset), "--out", str(tmp_path / "plain")]) == 0
    assert "fold crossings" not in capsys.readouterr().out
    with xr.open_dataset(tmp_path / "plain" / "map.nc") as m:
        assert m.sizes["curve"] == 0 and m["n_attractors"].shape == (1, 21)


def test_find_dataset_prefers_the_atlas(tmp_path):
    for name in ("resonance.nc", "paper.nc", "atlas.nc"):
        (tmp_path / name).write_text("x")
        assert find_dataset(tmp_path).name == name
    with pytest.raises(DatasetError, match="no such file or folder"):
        find_dataset(tmp_path / "missing")


def _error(argv, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("contactvib: error: "), err
    return err


def test_map_bad_inputs_are_one_line(small_dataset, tmp_path, capsys):
    out = ["--out", str(tmp_path / "m")]
    assert "no such file or folder" in _error(["map", str(tmp_path / "nothing.nc"), *out], capsys)
    assert "a folder without atlas.nc" in _error(["map", str(tmp_path), *out], capsys)
    junk = tmp_path / "junk.nc"
    junk.write_text("not netcdf")
    assert "not a readable NetCDF" in _error(["map", str(junk), *out], capsys)
    other = tmp_path / "other.nc"
    xr.Dataset({"a": ("x", [1.0])}).to_netcdf(other)
    assert "not a contactvib resonance dataset" in _error(["map", str(other), *out], capsys)
    ds = str(small_dataset)
    assert "--orders" in _error(["map", ds, "--orders", "0", *out], capsys)
    assert "--orders" in _error(["map", ds, "--orders", "x", *out], capsys)
    assert "--orders" in _error(["map", ds, "--orders", *out], capsys)
    assert "one level" in _error(["map", ds, "--orders", "2", *out], capsys)
    assert "either --orders" in _error(["map", ds, "--orders", "2", "--curves", str(tmp_path), *out], capsys)
    assert "no evolution_order" in _error(["map", ds, "--curves", str(tmp_path), *out], capsys)
    (tmp_path / "evolution_order2.json").write_text("{")
    assert "not an evolution result" in _error(["map", ds, "--curves", str(tmp_path), *out], capsys)
    blocker = tmp_path / "a_file"
    blocker.write_text("kept")
    assert "--out" in _error(["map", ds, "--out", str(blocker)], capsys)
    assert blocker.read_text() == "kept"
