"""A dataset swept with friction shown by ``map`` (the friction-ratio maps over (f_e, P_a)) and by
``explore``'s dataset view (the friction ratio of the level's branches below its resonance
graph); datasets without friction columns show neither (issue 26)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from contactvib.cli import main
from contactvib.explore.dataset_view import DatasetLevels, friction_figure, graph_figure
from contactvib.friction import FrictionModel
from contactvib.model import ContactModel
from contactvib.sweeps.regimes import FRICTION_MAPS, regime_maps
from contactvib.sweeps.resonance import resonance_dataset
from contactvib.sweeps.stored import open_resonance
from contactvib.sweeps.sweep import SweepSettings
from figure_files import assert_figure_file


@pytest.fixture(scope="module")
def friction_dataset(tmp_path_factory):
    """Two levels (0.5, 0.65 Q) over 340–380 Hz at 4 Hz, with friction columns."""
    out = tmp_path_factory.mktemp("fr_views")
    st = SweepSettings(fmin_hz=340.0, fmax_hz=380.0, df_hz=4.0, multistart_per_octave=0,
                       friction=FrictionModel(vd=0.5))
    resonance_dataset(ContactModel(), levels=[0.5, 0.65], settings=st, out=out, workers=1, progress=False)
    return out / "resonance.nc"


def test_maps_hold_the_extremes_of_the_friction_ratio(friction_dataset):
    ds = xr.load_dataset(friction_dataset)
    maps = regime_maps(ds)
    assert set(FRICTION_MAPS) <= set(maps) and maps["friction_ratio_min"].attrs["units"] == "1"
    assert maps.attrs["friction"] == ds.attrs["friction"]
    lo, hi = maps["friction_ratio_min"].values, maps["friction_ratio_max"].values
    assert np.all(np.isfinite(lo)) and np.all(lo <= hi) and np.all((lo > 0.0) & (hi <= 1.0 + 1e-9))
    j = int(np.nanargmin(ds["friction_ratio"].values))  # the lowest ratio is the map's at its cell
    cell = maps["friction_ratio_min"].sel(pa_over_q=float(ds["pa_over_q"].values[j]),
                                          fe_hz=float(ds["fe_hz"].values[j]))
    assert float(cell) == ds["friction_ratio"].values[j]


def test_map_command_draws_the_friction_maps(friction_dataset, tmp_path, capsys):
    out = tmp_path / "map"
    assert main(["map", str(friction_dataset), "--out", str(out)]) == 0
    assert "and 8 figures map_*.png" in capsys.readouterr().out
    for name in FRICTION_MAPS:
        assert_figure_file(out / f"map_{name}.png")
    assert set(FRICTION_MAPS) <= set(xr.load_dataset(out / "map.nc").variables)


def test_map_without_friction_has_no_friction_maps(small_dataset, tmp_path):
    assert not set(FRICTION_MAPS) & set(regime_maps(xr.load_dataset(small_dataset)))


def test_explore_dataset_view_shows_the_friction_ratio(friction_dataset, small_dataset):
    lv = DatasetLevels(open_resonance(friction_dataset)).level(0.65)
    ds = xr.load_dataset(friction_dataset)
    sel = np.abs(ds["pa_over_q"].values - 0.65) <= 1e-6
    assert np.array_equal(lv.friction_ratio, ds["friction_ratio"].values[sel], equal_nan=True)
    graph, _current = graph_figure(lv)
    fig = friction_figure(lv, graph.x_range)
    assert fig.x_range is graph.x_range and "friction ratio" in fig.yaxis[0].axis_label
    ys = [y for r in fig.renderers if r.glyph.__class__.__name__ == "MultiLine"
          for seg in r.data_source.data["ys"] for y in seg]
    periodic = lv.kind == "periodic"
    assert sorted(ys) == sorted(lv.friction_ratio[periodic])  # every periodic point drawn once
    plain = DatasetLevels(open_resonance(small_dataset)).level(0.65)
    assert plain.friction_ratio is None and friction_figure(plain) is None
