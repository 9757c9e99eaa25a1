"""The explore page's dataset mode without a browser: the lazy level reader, the graph's lines
(every stored point drawn once, coloured as the paper's figures) and the DATASET argument's
one-line errors (before anything is served)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from contactvib.cli import main
from contactvib.explore.dataset_view import DatasetError, DatasetLevels, graph_figure
from contactvib.labels import label_family
from contactvib.plotting.style import order_colour
from contactvib.sweeps.stored import open_resonance


def test_levels_read_lazily_equal_the_file(small_dataset):
    levels = DatasetLevels(open_resonance(small_dataset))
    ds = xr.load_dataset(small_dataset)
    assert levels.levels == (0.65,)
    lv = levels.level(0.65 + 1e-9)
    sel = np.abs(ds["pa_over_q"].values - 0.65) <= 1e-6
    assert np.array_equal(lv.fe_hz, ds["fe_hz"].values[sel])
    assert np.array_equal(lv.app_um, ds["app_um"].values[sel])
    assert levels.level(0.65) is lv  # read once
    assert lv.snap(371.3) == 372.0 and lv.snap(339.0) == 340.0  # the 2 Hz grid of the fixture
    assert levels.nearest_level(0.7) is None
    with pytest.raises(DatasetError, match=r"P_a = 0.7 Q is not a level of resonance.nc \(levels: 0.65 Q\)"):
        levels.level(0.7)


def test_graph_draws_every_stored_point_once_in_the_papers_colours(small_dataset):
    lv = DatasetLevels(open_resonance(small_dataset)).level(0.65)
    fig, current = graph_figure(lv)
    periodic = lv.kind == "periodic"
    drawn, colours = 0, set()
    for r in fig.renderers:
        if r.glyph.__class__.__name__ == "MultiLine" and r.glyph.line_color != "gold":
            drawn += sum(len(x) for x in r.data_source.data["xs"])
            colours.add(r.glyph.line_color)
    assert drawn == periodic.sum() > 0
    expected = {order_colour(label_family(x)[0]) for x in lv.resonance[periodic] if label_family(x)[0]}
    assert expected <= colours
    assert fig.y_scale.__class__.__name__ == "LogScale" and "f_e [Hz]" in fig.xaxis[0].axis_label
    assert current.data == {"fe_hz": [], "app_um": [], "name": []}


@pytest.mark.parametrize("arg, why", [
    ("{tmp}/none.nc", "no such file or folder"),
    ("{tmp}/text.nc", "not a readable NetCDF dataset"),
    ("{tmp}", "a folder without atlas.nc, paper.nc or resonance.nc"),
])
def test_bad_dataset_is_one_line_before_serving(tmp_path, capsys, arg, why):
    (tmp_path / "text.nc").write_text("not netcdf")
    path = arg.format(tmp=tmp_path)
    assert main(["explore", path, "--no-browser", "--port", "1"]) == 2
    out, err = capsys.readouterr()
    assert err.startswith(f"contactvib: error: DATASET = {path}: ") and why in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_a_dataset_of_another_kind_is_refused(tmp_path, capsys):
    xr.Dataset({"x": ("t", np.arange(3.0))}).to_netcdf(tmp_path / "paper.nc")
    assert main(["explore", str(tmp_path), "--no-browser"]) == 2
    assert "not a contactvib resonance dataset" in capsys.readouterr().err


def test_an_atlas_folder_is_opened_by_its_dataset(small_dataset, tmp_path):
    import shutil

    shutil.copy(small_dataset, tmp_path / "atlas.nc")
    levels = DatasetLevels(open_resonance(tmp_path))
    assert levels.path == tmp_path / "atlas.nc" and levels.levels == (0.65,)
    assert levels.level(0.65).fe_hz.size == DatasetLevels(open_resonance(small_dataset)).level(0.65).fe_hz.size
