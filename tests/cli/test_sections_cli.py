"""`contactvib section` and `contactvib orbit-diagram`: their outputs (JSON, CSV, NetCDF, figure)."""

import json

import numpy as np
import xarray as xr

from contactvib.cli import main
from figure_files import assert_figure_file


def test_section_json_points_and_units(tmp_path, capsys):
    rc = main(["section", "--pa", "0.65", "--fe", "360", "--starts", "32", "--periods", "20", "--impacts", "--json",
               "--out", str(tmp_path / "s.svg")])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["units"]["y_um"] == "um" and d["units"]["v_loss_mm_s"] == "mm/s"
    assert d["attractors"] and all(len(a["y_um"]) == a["period"] for a in d["attractors"])
    assert all(len(a["phase_rad"]) == len(a["v_loss_mm_s"]) for a in d["attractors"])
    assert (tmp_path / "s.svg").read_text().lstrip().startswith("<?xml")


def test_orbit_diagram_writes_figure_csv_and_netcdf(tmp_path, capsys):
    rc = main(["orbit-diagram", "--pa", "0.65", "--fe-from", "359", "--fe-to", "360", "--fe-step", "1",
               "--periods", "8", "--starts", "32", "--measure", "v-loss", "--out", str(tmp_path / "d.png"),
               "--csv", str(tmp_path / "d.csv"), "--nc", str(tmp_path / "d.nc")])
    assert rc == 0
    out = capsys.readouterr().out
    assert "2 grid points" in out
    assert_figure_file(tmp_path / "d.png")
    with xr.open_dataset(tmp_path / "d.nc") as ds:
        n_loss = ds.sizes["loss"]
        assert ds["v_loss_mm_s"].attrs["units"] == "mm/s" and np.all(ds["v_loss_mm_s"].values <= 0)
        assert set(np.unique(ds["fe_hz"].values)) == {359.0, 360.0}
    lines = (tmp_path / "d.csv").read_text().splitlines()
    assert lines[2] == "fe_hz,pa_over_q,attractor,kind,period,phase_frac,v_loss_mm_s,lambda1"
    assert len(lines) == 3 + n_loss
