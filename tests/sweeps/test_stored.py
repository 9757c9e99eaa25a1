"""The one accessor of a stored resonance dataset (:class:`contactvib.sweeps.stored.ResonanceData`,
opened by :func:`~contactvib.sweeps.stored.open_resonance`): its levels, the points of a level
matched by the one rule (the nearest stored level within ``LEVEL_TOL``), the error that names the
stored levels, and ``attractors_at`` equal to what ``contactvib query --json`` prints and to the
dataset's own rows."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest
import xarray as xr

import contactvib
from contactvib.cli import main
from contactvib.sweeps.dataset import merge_levels
from contactvib.sweeps.stored import (
    LEVEL_TOL,
    DatasetError,
    MissingLevel,
    ResonanceData,
    attractors_at,
    matching_level,
    open_resonance,
)


def test_matching_level_is_the_nearest_within_the_tolerance():
    levels = (0.5, 0.65, 0.7)
    assert LEVEL_TOL == 1e-6
    assert matching_level(levels, 0.65) == 0.65
    assert matching_level(levels, 0.65 + 0.9e-6) == 0.65 and matching_level(levels, 0.7 - 1e-7) == 0.7
    assert matching_level(levels, 0.65 + 1.1e-6) is None and matching_level(levels, 0.6) is None
    assert matching_level((), 0.65) is None and matching_level(levels, float("nan")) is None
    assert matching_level((0.65, 0.6500004), 0.6500003) == 0.6500004  # the nearest one


def test_levels_and_points_of_a_level(small_dataset):
    with open_resonance(small_dataset.parent) as data:  # the folder: its resonance.nc
        assert isinstance(data, contactvib.ResonanceData) and data.path == small_dataset
        assert data.levels == (0.65,) and data.kind == "force"
        assert (data.level_symbol, data.level_unit) == ("P_a/Q", "Q")
        pa = data.ds["pa_over_q"].values
        idx = data.points(0.65 + 5e-7)
        assert np.array_equal(idx, np.flatnonzero(pa == 0.65)) and idx.size == pa.size
        one = data.level(0.65)
        assert one.sizes["point"] == idx.size and one.sizes["extremum"] == data.ds.sizes["extremum"]
        assert np.array_equal(one["app_um"].values, data.ds["app_um"].values[idx])
        assert data.match(0.65 - 1e-7) == 0.65 and data.match(0.66) is None


def test_a_missing_level_names_the_stored_ones(small_dataset):
    data = open_resonance(small_dataset, load=True)
    for call in (data.level, data.points, data.stored_level):
        with pytest.raises(MissingLevel, match=r"^P_a = 0.66 Q is not a level of resonance.nc \(levels: 0.65 Q\)$"):
            call(0.66)
    with pytest.raises(MissingLevel) as e:
        ResonanceData(data.ds).level(0.65 + 2e-6)
    assert str(e.value) == "P_a = 0.650002 Q is not a level of the dataset (levels: 0.65 Q)"
    assert e.value.levels == (0.65,) and e.value.level == pytest.approx(0.650002)
    # a DatasetError (the one dataset error), a LookupError and a ValueError, and it survives a pool
    assert isinstance(e.value, DatasetError) and isinstance(e.value, LookupError) and isinstance(e.value, ValueError)
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is MissingLevel and str(back) == str(e.value) and back.levels == (0.65,)
    base = ResonanceData(data.ds.assign_attrs(excitation="base-um", level_symbol="U", level_unit="um"))
    assert (base.kind, base.level_symbol, base.level_unit) == ("base-um", "U", "um")
    with pytest.raises(MissingLevel, match=r"^U = 0.7 µm is not a level of the dataset \(levels: 0.65 µm\)$"):
        base.level(0.7)


def test_levels_closer_than_the_tolerance_stay_apart(small_dataset):
    ds = xr.load_dataset(small_dataset)
    twin = ds.copy(deep=True)
    for v in ("pa_over_q", "branch_pa_over_q", "trace_pa_over_q"):
        twin[v] = xr.full_like(twin[v], 0.65 + 4e-7)
    data = ResonanceData(merge_levels([ds, twin]))
    assert data.levels == (0.65, 0.65 + 4e-7)
    n = ds.sizes["point"]
    assert np.array_equal(data.points(0.65 - 1e-7), np.arange(n))
    assert np.array_equal(data.points(0.65 + 3e-7), np.arange(n, 2 * n))
    assert np.array_equal(data.level(0.6500004)["app_um"].values, ds["app_um"].values)


def test_attractors_at_is_what_query_prints(small_dataset, capsys):
    data = open_resonance(small_dataset)
    with data:
        got = data.attractors_at(0.65, 360.4)
    assert got == attractors_at(xr.load_dataset(small_dataset), pa_over_q=0.65, fe_hz=360.4)
    assert main(["query", str(small_dataset), "--pa", "0.65", "--fe", "360.4", "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == json.loads(json.dumps(got).replace("NaN", "null"))
    # the rows are the dataset's own: the points of 0.65 Q at the grid frequency 360 Hz
    ds = xr.load_dataset(small_dataset)
    at = np.flatnonzero((ds["pa_over_q"].values == 0.65) & (ds["fe_hz"].values == 360.0))
    assert got["pa_over_q"] == 0.65 and got["fe_hz"] == 360.0
    assert got["requested"] == {"pa_over_q": 0.65, "fe_hz": 360.4}
    assert sorted(a["app_um"] for a in got["attractors"]) == sorted(ds["app_um"].values[at].tolist())
    assert [a["app_um"] for a in got["attractors"]] == sorted((a["app_um"] for a in got["attractors"]),
                                                              reverse=True)
    with pytest.raises(MissingLevel, match=r"^--pa \(P_a/Q\) = 0.66: not in the dataset; stored levels: 0.65$"):
        ResonanceData(ds).attractors_at(0.66, 360.0)
    with pytest.raises(LookupError, match=r"^--fe \(f_e\) = 500: no grid point within half a step"):
        ResonanceData(ds).attractors_at(0.65, 500.0)
