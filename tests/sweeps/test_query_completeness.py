"""``contactvib query DATASET --completeness N``: random grid points of a stored dataset searched
again by brute force (:func:`contactvib.sweeps.completeness.check_completeness`). A dataset whose
sweep found everything reports nothing missing; the same dataset with one attractor's point
deleted reports exactly that attractor (its level, f_e, period, minima and A_pp), so the check
is compared with the dataset's own refined orbits, an independent computation of the same
attractors (the sweep's continuation and multi-start against a fresh random search)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from contactvib.cli.main import cli, main
from contactvib.sweeps.completeness import (
    APP_RTOL,
    check_completeness,
    completeness_points,
    same_attractor,
)
from contactvib.sweeps.stored import open_resonance

#: Two levels × 3 grid points (350, 360, 370 Hz) in the 1/1 – 1/2 coexistence region of the paper's
#: model: up to 5 (0.65 Q) and 6 (0.7 Q) coexisting attractors per point.
SETTINGS = dict(fmin_hz=350.0, fmax_hz=370.0, df_hz=10.0, multistart_per_octave=8, n_starts=64)
LEVELS = [0.65, 0.7]
N_GRID = 6


@pytest.fixture(scope="module")
def two_levels(tmp_path_factory):
    from contactvib import ContactModel
    from contactvib.sweeps.resonance import resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    out = tmp_path_factory.mktemp("completeness")
    resonance_dataset(ContactModel(), levels=LEVELS, settings=SweepSettings(**SETTINGS), out=out,
                      workers=1, progress=False)
    return out / "resonance.nc"


def _query(path, *args):
    res = CliRunner().invoke(cli, ["query", str(path), *args])
    assert res.exit_code == 0, res.output
    return res.output


def test_the_points_are_distinct_grid_points_drawn_by_the_seed(two_levels):
    with open_resonance(two_levels) as data:
        pts = completeness_points(data, 4, 3)
        assert pts == completeness_points(data, 4, 3) and len(set(pts)) == 4
        assert all(p in LEVELS and f in (350.0, 360.0, 370.0) for p, f in pts)
        assert sorted(completeness_points(data, 100, 0)) == sorted(
            (p, f) for p in LEVELS for f in (350.0, 360.0, 370.0))  # capped at the grid


def test_sameness_rule():
    strobe = np.array([[1.0, 20.0], [-3.0, 5.0]])
    a = {"period": 2, "minima_per_period": 1, "app_um": 37.39, "strobe": strobe}
    assert same_attractor(a, {**a, "strobe": strobe[::-1]})  # the other cyclic order
    assert same_attractor(a, {**a, "app_um": 37.39 * (1 + 0.5 * APP_RTOL)})
    assert not same_attractor(a, {**a, "app_um": 37.39 * (1 + 2 * APP_RTOL)})
    assert not same_attractor(a, {**a, "minima_per_period": 3})
    assert not same_attractor(a, {**a, "strobe": strobe + [[0.5, 0.0], [0.0, 0.0]]})
    nonp = {"period": None, "minima_per_period": None, "app_um": 5.0, "strobe": np.zeros((0, 2))}
    assert same_attractor(nonp, {**nonp, "app_um": 9.0}) and not same_attractor(a, nonp)


def test_a_complete_dataset_reports_nothing_missing(two_levels):
    out = json.loads(_query(two_levels, "--completeness", str(N_GRID), "--seed", "2", "--json"))
    rep = out["completeness"]
    assert rep["points_checked"] == N_GRID and rep["seed"] == 2
    assert rep["missing"] == [] and rep["found_fraction"] == 1.0


def test_a_deleted_attractor_is_reported_exactly(two_levels, tmp_path):
    with open_resonance(two_levels, load=True) as data:
        one = data.level(0.7)
        at = np.flatnonzero(one["fe_hz"].values == 360.0)
        # the period-2 orbit with one minimum per period (the 1/2 resonance, A_pp ≈ 37 µm)
        j = at[(one["period"].values[at] == 2) & (one["minima_per_period"].values[at] == 1)]
        assert j.size == 1
        gone = int(data.points(0.7)[j[0]])
        app = float(data.ds["app_um"].values[gone])
        ds = data.ds.isel(point=np.delete(np.arange(data.ds.sizes["point"]), gone))
    damaged = tmp_path / "resonance.nc"
    ds.to_netcdf(damaged)
    rep = json.loads(_query(damaged, "--completeness", str(N_GRID), "--json"))["completeness"]
    assert len(rep["missing"]) == 1
    m = rep["missing"][0]
    assert (m["level"], m["fe_hz"], m["period"], m["minima_per_period"]) == (0.7, 360.0, 2, 1)
    assert m["app_um"] == pytest.approx(app, rel=APP_RTOL)
    assert 0.0 < m["basin_fraction"] <= 1.0
    assert rep["found_fraction"] < 1.0
    # the table names it too
    text = _query(damaged, "--completeness", str(N_GRID), "--no-progress")
    assert "1 missing attractor" in text and "0.7       360      2      1" in text


def test_the_library_call_reports_progress(two_levels):
    calls = []
    with open_resonance(two_levels) as data:
        rep = check_completeness(data, n_points=2, seed=5, n_starts=32, progress=lambda d, t: calls.append((d, t)))
    assert calls == [(0, 2), (1, 2), (2, 2)] and rep["n_starts"] == 32


def test_bad_input_is_one_line(two_levels, capsys):
    for args, word in ((["--completeness", "0"], "--completeness"), (["--completeness", "2", "--pa", "0.7"], "--pa"),
                       (["--pa", "0.7"], "--fe")):
        assert main(["query", str(two_levels), *args]) == 2
        err = capsys.readouterr().err
        assert word in err and len(err.strip().splitlines()) == 1
