"""A finished ``resonance`` / ``paper`` run leaves its dataset and figures, not its resume data:
the chunks of its levels are removed once the dataset and figures are written (kept with
``--keep-chunks``, and by an interrupted run), the lock file ``OUT/.lock`` when the lock is
released. Progress texts state their time estimates for what they are: no time left while the
kernels compile, the attractor search's work estimate as an upper bound."""

from __future__ import annotations

import pytest

from contactvib.cli.main import main
from contactvib.sweeps.resonance import (
    COMPILING_MESSAGE,
    OutputLocked,
    chunk_path,
    output_lock,
    remove_chunks,
    sweep_bar_format,
)

SMALL = ["--pa", "0.65", "--fmin", "340", "--fmax", "360", "--df", "10", "--multistart-per-octave", "0",
         "--workers", "1", "--no-progress"]


def test_a_finished_resonance_run_removes_its_chunks_and_lock(tmp_path):
    out = tmp_path / "res"
    assert main(["resonance", *SMALL, "--out", str(out)]) == 0
    assert (out / "resonance.nc").is_file() and (out / "resonance_pa0.65.png").is_file()
    assert not (out / ".chunks").exists() and not (out / ".lock").exists()
    assert sorted(p.name for p in out.iterdir()) == ["extrema_pa0.65.png", "resonance.nc", "resonance_pa0.65.png"]


def test_keep_chunks_keeps_them(tmp_path):
    out = tmp_path / "res"
    assert main(["resonance", *SMALL, "--out", str(out), "--keep-chunks"]) == 0
    assert chunk_path(out, 0.65).is_file() and not (out / ".lock").exists()


def test_remove_chunks_leaves_other_levels(tmp_path):
    for pa in (0.5, 0.6):
        chunk_path(tmp_path, pa).parent.mkdir(exist_ok=True)
        chunk_path(tmp_path, pa).write_bytes(b"x")
    assert remove_chunks(tmp_path, [0.6, 0.7]) == 1
    assert chunk_path(tmp_path, 0.5).is_file() and not chunk_path(tmp_path, 0.6).exists()
    assert remove_chunks(tmp_path, [0.5]) == 1 and not (tmp_path / ".chunks").exists()


def test_the_lock_file_lives_as_long_as_the_lock(tmp_path):
    with output_lock(tmp_path):
        assert (tmp_path / ".lock").is_file()
        with output_lock(tmp_path):  # re-entrant: the inner exit keeps it
            pass
        assert (tmp_path / ".lock").is_file()
    assert not (tmp_path / ".lock").exists()
    with output_lock(tmp_path):  # and it can be taken again
        assert (tmp_path / ".lock").is_file()


def test_a_held_lock_still_refuses_a_second_holder(tmp_path):
    import fcntl

    tmp_path.mkdir(exist_ok=True)
    with open(tmp_path / ".lock", "a+") as f:
        fcntl.flock(f.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        with pytest.raises(OutputLocked):
            with output_lock(tmp_path):
                pass
        assert (tmp_path / ".lock").is_file()  # the refused run removes nothing


def test_no_time_left_is_shown_while_the_kernels_compile():
    assert "{remaining}" not in sweep_bar_format(True) and "{elapsed}" in sweep_bar_format(True)
    assert sweep_bar_format(False) is None  # tqdm's default: time left from the measured rate
    assert "first run only" in COMPILING_MESSAGE
    # one figure for the compilation: the message says what the README says
    import re
    from pathlib import Path

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    said = re.search(r"about (\d+) s more", COMPILING_MESSAGE).group(1)
    assert f"compiles the kernels, about {said} s more" in " ".join(readme.split())


def test_the_search_estimate_is_stated_as_an_upper_bound(capsys):
    """Every start run to 500000 periods would take minutes; the starts settle in seconds (at 360 Hz,
    five periodic attractors: ~0.1 s of search)."""
    assert main(["attractors", "--pa", "0.65", "--fe", "360", "--max-periods", "500000", "--starts", "64",
                 "--no-seeds"]) == 0
    err = capsys.readouterr().err
    assert "attractor search, at most " in err and "estimated" not in err
