"""Every command that reads a resonance dataset (``query``, ``map``, ``animate``, ``explore``)
finds and opens it in one place (:func:`contactvib.sweeps.stored.open_resonance`): they accept the
same files and folders, and refuse the same inputs with the same one-line message."""

from __future__ import annotations

import shutil
import socket

import numpy as np
import pytest
import xarray as xr

from contactvib.cli.main import main
from contactvib.sweeps.dataset import FORMAT
from contactvib.sweeps.stored import DATASET_NAMES, DatasetError, find_dataset, open_resonance


def _argv(command: str, dataset: str, tmp_path) -> list:
    """A command line of ``command`` on ``dataset`` that ends soon after opening it."""
    if command == "query":
        return ["query", dataset, "--pa", "0.65", "--fe", "360"]
    if command == "map":
        return ["map", dataset, "--out", str(tmp_path / "map")]
    if command == "animate":  # a small GIF
        return ["animate", dataset, "--out", str(tmp_path / "film.gif"), "--gif", "--size", "64x64"]
    return ["explore", dataset, "--no-browser", "--port", str(_TAKEN.getsockname()[1])]  # refused after opening


COMMANDS = ("query", "map", "animate", "explore")
#: A port this process listens on: ``explore`` cannot serve there, and says so after opening its dataset
_TAKEN = socket.create_server(("127.0.0.1", 0))


def _bad_inputs(tmp_path, small_dataset) -> dict:
    """name -> (path, the message after ``DATASET = ``)."""
    empty = tmp_path / "empty"
    empty.mkdir()
    text = tmp_path / "text.nc"
    text.write_text("not netcdf")
    foreign = tmp_path / "foreign.nc"
    xr.Dataset({"x": ("a", np.arange(3.0))}).to_netcdf(foreign)
    with xr.open_dataset(small_dataset) as ds:
        ds = ds.load()
    old = tmp_path / "old.nc"
    ds.assign_attrs(format="contactvib-resonance-0").to_netcdf(old)
    damaged = tmp_path / "damaged.nc"
    ds.drop_vars("extremum_y_um").to_netcdf(damaged)
    missing = tmp_path / "missing.nc"
    return {
        "missing": (missing, f"{missing}: no such file or folder"),
        "empty folder": (empty, f"{empty}: a folder without atlas.nc, paper.nc or resonance.nc"),
        "not NetCDF": (text, f"{text}: not a readable NetCDF dataset (ValueError)"),
        "foreign": (foreign, f"{foreign}: not a contactvib resonance dataset (made by paper, resonance or atlas)"),
        "old": (old, f"{old}: written by another contactvib version (format 'contactvib-resonance-0', "
                     f"not {FORMAT!r}): recompute it"),
        "damaged": (damaged, f"{damaged}: damaged: variable 'extremum_y_um' is missing: recompute it"),
    }


def test_every_command_refuses_the_same_inputs_with_the_same_line(tmp_path, small_dataset, capsys):
    for name, (path, why) in _bad_inputs(tmp_path, small_dataset).items():
        with pytest.raises(DatasetError) as e:
            open_resonance(path)
        assert str(e.value) == why, name
        for command in COMMANDS:
            assert main(_argv(command, str(path), tmp_path)) == 2, (name, command)
            out, err = capsys.readouterr()
            assert err == f"contactvib: error: DATASET = {why}\n", (name, command)


def test_every_command_accepts_a_dataset_file_and_its_folder(tmp_path, small_dataset, capsys):
    folder = tmp_path / "paper_and_atlas"
    folder.mkdir()
    for name in ("paper.nc", "atlas.nc"):  # the atlas first, as every command looks
        shutil.copy(small_dataset, folder / name)
    assert find_dataset(folder) == folder / "atlas.nc" and DATASET_NAMES[0] == "atlas.nc"
    for dataset in (small_dataset, folder):
        for command in COMMANDS:
            rc = main(_argv(command, str(dataset), tmp_path))
            out, err = capsys.readouterr()
            if command != "explore":
                assert rc == 0 and err == "", (command, err)
            else:  # refused after the dataset was opened, by the port
                assert rc == 2 and "DATASET" not in err and "cannot listen" in err, (command, err)
