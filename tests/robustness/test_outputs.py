"""Every command that writes checks its output folder before computing (issue 13, class 4): an
unwritable ``--out`` (a folder that cannot be created, a path under a regular file) is refused in
under 2 s with one ``contactvib: error:`` line naming ``--out``, exit status 2, and nothing is
computed (the computations are replaced by stubs, tests/robustness/conftest.py)."""

import time
from pathlib import Path

import pytest

from contactvib.cli import main


def _writes_nothing(command):
    return pytest.param(command, [], marks=pytest.mark.skip(reason=f"{command} writes nothing (no --out)"),
                        id=f"{command}-writes-nothing")


EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: Every command of `contactvib --help`, with options that keep it otherwise valid.
COMMANDS = [
    pytest.param("simulate", [], id="simulate"),
    pytest.param("simulate", ["--from-state", "0.1", "0", "--periods", "5"], id="simulate-from-state"),
    pytest.param("resonance", ["--pa", "0.5", "0.65", "--df", "5"], id="resonance"),
    pytest.param("resonance", ["--resume", "--workers", "1"], id="resonance-resume"),
    pytest.param("paper", [], id="paper"),
    pytest.param("atlas", ["--npa", "3", "--df", "5"], id="atlas"),
    pytest.param("atlas", ["--pa", "0.5", "0.6", "--dask-workers", "2"], id="atlas-dask"),
    pytest.param("atlas", ["--scheduler", "tcp://127.0.0.1:8786", "--resume"], id="atlas-scheduler"),
    pytest.param("continue", [], id="continue"),
    pytest.param("continue", ["--parameter", "pa", "--pa-min", "0.3", "--pa-max", "0.9"], id="continue-in-pa"),
    pytest.param("bifurcations", ["--pa", "0.6", "0.7"], id="bifurcations"),
    pytest.param("evolution", [], id="evolution"),
    pytest.param("hbm", [], id="hbm"),
    pytest.param("section", [], id="section"),
    pytest.param("section", ["--impacts", "--json"], id="section-json"),
    pytest.param("orbit-diagram", ["--fe-from", "810", "--fe-to", "811", "--fe-step", "1"], id="orbit-diagram"),
    pytest.param("basins", ["--grid", "10x10"], id="basins"),
    pytest.param("basins", ["--grid", "10x10", "--json"], id="basins-json"),
    pytest.param("perturbation", [], id="perturbation"),
    pytest.param("perturbation", ["--json"], id="perturbation-json"),
    pytest.param("map", ["DATASET"], id="map"),  # DATASET: the small_dataset fixture
    # animate's --out is a file (evolution.mp4); the dataset is read after --out is checked
    pytest.param("animate", ["no_such_dataset.nc"], id="animate"),
    pytest.param("friction", [], id="friction"),
    pytest.param("friction", ["--fe-range", "300", "400", "--df", "50"], id="friction-fe-range"),
    pytest.param("friction", ["--vd-range", "0.01", "1", "--nvd", "3", "--json"], id="friction-vd-range"),
    pytest.param("fit", ["--static", str(EXAMPLES / "fit_static.csv"), "--set", "M=0.2106"], id="fit"),
    _writes_nothing("attractors"),
    _writes_nothing("query"),
    _writes_nothing("explore"),  # a server: it writes no file
]


def test_every_command_is_listed():
    from contactvib.cli.main import cli

    listed = {p.values[0] for p in COMMANDS}
    assert listed == set(cli.commands)


def _dataset(args, small_dataset):
    """``args`` with the placeholder DATASET replaced by the small_dataset fixture's file (a
    session fixture: built before the computations are stubbed)."""
    return [str(small_dataset) if a == "DATASET" else a for a in args]


def _unwritable(kind, tmp_path):
    if kind == "proc":
        return "/proc/contactvib_robustness/x"
    blocker = tmp_path / "a_file"
    blocker.write_text("not a folder")
    return str(blocker / "x")


@pytest.mark.timing
@pytest.mark.parametrize("kind", ["proc", "under-a-file"])
@pytest.mark.parametrize("command, args", COMMANDS)
def test_unwritable_out_refused_before_computing(no_computation, capsys, tmp_path, command, args, kind,
                                                  small_dataset):
    args = _dataset(args, small_dataset)
    out = _unwritable(kind, tmp_path)
    t0 = time.perf_counter()
    rc = main([command, *args, "--out", out])
    elapsed = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith(f"contactvib: error: --out = {out}: cannot create"), err
    assert elapsed < 2.0, f"{elapsed:.2f} s"


@pytest.mark.parametrize("command, args", [p for p in COMMANDS if not p.marks])
def test_out_that_is_a_file_refused_before_computing(no_computation, capsys, tmp_path, command, args,
                                                     small_dataset):
    args = _dataset(args, small_dataset)
    out = tmp_path / "a_file"
    out.write_text("kept")
    assert main([command, *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("contactvib: error: ") and "--out" in err and str(out) in err, err
    assert out.read_text() == "kept"


#: Commands whose --out is a file of a given suffix (checked by their own controls).
_FILE_OUT = ("animate", "section", "orbit-diagram")


@pytest.mark.parametrize("command, args", [p for p in COMMANDS if not p.marks and p.values[0] not in _FILE_OUT])
def test_a_writable_out_reaches_the_computation(no_computation, tmp_path, command, args, small_dataset):
    """The control: with a writable --out each command gets past its checks to a stubbed
    computation (so the stubs are the ones the commands call)."""
    args = _dataset(args, small_dataset)
    with pytest.raises(no_computation):
        main([command, *args, "--out", str(tmp_path / "out")])


def test_animate_with_a_writable_out_reaches_the_computation(no_computation, tmp_path, small_dataset):
    """The control for animate, whose --out is a film file and whose DATASET must exist."""
    with pytest.raises(no_computation):
        main(["animate", str(small_dataset), "--out", str(tmp_path / "out" / "film.mp4")])
    assert (tmp_path / "out").is_dir()


@pytest.mark.parametrize("command, args", [p for p in COMMANDS if p.values[0] in ("section", "orbit-diagram")])
def test_figure_file_out_reaches_the_computation(no_computation, tmp_path, command, args):
    """The control for the commands whose --out is a figure file (its folder is created)."""
    with pytest.raises(no_computation):
        main([command, *args, "--out", str(tmp_path / "out" / "figure.png")])
    assert (tmp_path / "out").is_dir()
