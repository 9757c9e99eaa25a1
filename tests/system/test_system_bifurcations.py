"""``contactvib bifurcations --system``: every branch through the attractors at the seed
frequencies, each followed once (an attractor on a branch already followed is not continued
again), with the period-2 branches of the doublings; its special points are those of ``continue
--system`` (themselves checked against scipy in test_system_continuation.py)."""

from __future__ import annotations

import json

import pytest

from contactvib.cli import main

STOP = "examples/two_dof_stop.toml"


def test_all_branches_of_the_stop_system(tmp_path, capsys):
    out = tmp_path / "bif"
    assert main(["bifurcations", "--system", STOP, "--pa-newton", "0.1", "--fmin", "0.08", "--fmax", "0.14",
                 "--seed-fe", "0.09,0.11", "--out", str(out), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["system"] == STOP and d["cascades"] == []
    branches = {s["branch"] for s in d["special_points"]}
    # the two attractors at 0.11 Hz (upper and lower branch) lie on the branch followed from 0.09 Hz
    assert branches == {"b0", "b0.pd1"}
    sp = sorted((s["type"], round(s["fe_hz"], 5)) for s in d["special_points"] if s["branch"] == "b0")
    assert sp == [("fold", 0.104), ("fold", 0.12026), ("neimark-sacker", 0.09261), ("neimark-sacker", 0.09845),
                  ("period-doubling", 0.11758), ("period-doubling", 0.12026)]
    assert (out / "bifurcations.json").exists() and (out / "branches_two_dof_stop_pa0.1N.png").exists()


@pytest.mark.parametrize("args, needle", [
    (["--system", STOP, "--pa-newton", "0.1", "--fmin", "0.08", "--fmax", "0.14", "--cascade-fe", "0.1"],
     "--cascade-fe"),
    (["--system", STOP, "--pa-newton", "0.1", "--fmin", "0.08", "--fmax", "0.14", "--seed-fe", "0.2"], "--seed-fe"),
    (["--system", STOP, "--pa", "0.5", "--fmin", "0.08", "--fmax", "0.14"], "defines no Q"),
    (["--system", STOP, "--pa-newton", "0.1", "--coordinate", "q7"], "--coordinate q7"),
    (["--pa-newton", "0.1"], "--pa-newton: an option of --system only"),
])
def test_bad_input(args, needle, tmp_path, capsys):
    assert main(["bifurcations", *args, "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0] and len(err[0]) <= 400
