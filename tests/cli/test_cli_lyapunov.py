"""``contactvib lyapunov``: the spectrum of every attractor at a point or of one trajectory, its
JSON, and its refusals (one line, exit 2, before any computation)."""

import json

import pytest

from contactvib.cli import main

CHAOS = ["--pa", "0.75", "--fe", "816.5", "--y0-um", "-0.20081059854145153", "--v0-mm-s", "-4.106686232024136",
         "--transient", "0"]


def test_trajectory_json_is_chaotic_with_its_error_bars(capsys):
    rc = main(["lyapunov", *CHAOS, "--periods", "4000", "--json"])
    d = json.loads(capsys.readouterr().out)
    assert rc == 0 and d["units"] == {"lyapunov": "1/s"} and len(d["spectra"]) == 1
    s = d["spectra"][0]
    assert s["attractor_type"] == "chaotic" and s["method"] == "benettin" and s["periods"] == 4000
    lam, se = s["lyapunov_per_s"], s["lyapunov_stderr_per_s"]
    assert lam[0] > 3 * se[0] and lam[0] > lam[1]
    assert s["sum_per_s"] == pytest.approx(s["damping_average_per_s"], rel=1e-6)
    assert 2.0 < s["kaplan_yorke_dimension"] < 3.0


def test_every_attractor_table(capsys):
    rc = main(["lyapunov", "--pa", "0.75", "--fe", "816.5", "--periods", "2000"])
    out = capsys.readouterr().out.splitlines()
    assert rc == 0 and "exponents [1/s]" in out[0]
    rows = out[1:]
    assert sum("chaotic" in r and "benettin" in r for r in rows) == 1
    assert sum("periodic" in r and "floquet" in r for r in rows) == len(rows) - 1 >= 3


@pytest.mark.parametrize("args, words", [
    (["--periods", "50"], "--periods"),                       # fewer than 10 batches x 10 periods
    (["--periods", "1000", "--batches", "5"], "--batches"),   # fewer than 10 batches
    (["--periods", "x"], "--periods"),
    (["--transient", "-1"], "--transient"),
    (["--y0-um", "1"], "--v0-mm-s"),
    (["--y0-um", "1e30", "--v0-mm-s", "0"], "--y0-um"),
    (["--from-state", "1,2", "3,4"], "--from-state"),
])
def test_refusals_are_one_line(args, words, capsys):
    rc = main(["lyapunov", "--pa", "0.75", "--fe", "816.5", *args])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith("contactvib: error: ") and words in err, err
