"""`contactvib fit` on the command line: outputs, the saved model read back by --model, and every
bad input as one line on stderr with exit 2 (a fit that does not converge: exit 1)."""

import json
from pathlib import Path

import numpy as np
import pytest

from contactvib.cli import main
from figure_files import assert_figure_file

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
STATIC = str(EXAMPLES / "fit_static.csv")


def _run(argv, capsys):
    capsys.readouterr()
    rc = main(argv)
    return rc, *capsys.readouterr()


def test_static_fit_json_files_and_model_round_trip(tmp_path, capsys):
    model = tmp_path / "m.json"
    rc, out, err = _run(["fit", "--static", STATIC, "--set", "M=0.2106", "--json", "--save-model", str(model),
                         "--out", str(tmp_path / "out")], capsys)
    assert rc == 0, err
    d = json.loads(out)
    assert set(d["parameters"]) == {"S_c_n", "m2", "f_n0_hz", "y0_um"} and d["converged"]
    assert d["parameters"]["f_n0_hz"]["derived"] and "derived" not in d["parameters"]["m2"]
    assert {"value", "stderr", "unit"} == set(d["parameters"]["m2"])
    assert d["correlation"]["names"] == ["ln f_n0", "m2"] and len(d["correlation"]["matrix"]) == 2
    assert d["residual_rms"]["static"] > 0 and d["n_forward"] > 0
    assert_figure_file(tmp_path / "out" / "fit_static.png")
    saved = json.loads(model.read_text())
    assert saved["m2"] == d["parameters"]["m2"]["value"] and saved["M"] == 0.2106
    rc, out, err = _run(["attractors", "--model", str(model), "--pa", "0.3", "--fe", "1200", "--starts", "4",
                         "--json"], capsys)
    assert rc == 0, err
    assert json.loads(out)["model"]["m2"] == saved["m2"]


def _write(tmp_path, text, name="d.csv"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


@pytest.mark.parametrize("args, words", [
    (["--set", "M=0.2106"], "give at least one of --static"),
    (["--static", STATIC], "--set M=...: the slider mass M"),
    (["--static", STATIC, "--set", "M=0.2106", "--fix", "c_n=3"], "--fix c_n: unknown name"),
    (["--static", STATIC, "--set", "M=0.2106", "--bounds", "m2=3:2"], "--bounds m2"),
    (["--static", STATIC, "--set", "M=0.2106", "--bounds", "m2=2"], "expected NAME=LOWER:UPPER"),
    (["--static", STATIC, "--set", "M=0.2106", "--starts", "-1"], "--starts"),
    (["--static", "no_such.csv", "--set", "M=0.2106"], "--static (static) = no_such.csv: cannot read"),
    (["--frf", STATIC, "--set", "M=0.2106"], "--frf (frf) = "),
])
def test_bad_options_are_one_line_exit_2(args, words, capsys):
    rc, out, err = _run(["fit", *args], capsys)
    assert rc == 2 and err.count("\n") == 1 and err.startswith("contactvib: error: ") and words in err, err


@pytest.mark.parametrize("text, words", [
    ("load_n,deflection\n0,0\n1,1\n2,2\n", "missing column deflection_um"),
    ("load_n,deflection_um\n0,0\n1,nan\n2,2\n", "not a finite number"),
    ("load_n,deflection_um\n0,0\n-1,1\n2,2\n", "negative load"),
    ("load_n,deflection_um\n0,0\n1,0.1\n", "at least 3"),
    ("load_n,deflection_um\n" + "\n".join(f"{f},{1 - f / 10}" for f in range(10)) + "\n",
     "no parameter set inside the bounds reaches these data"),
])
def test_bad_static_files_exit_2(tmp_path, text, words, capsys):
    rc, out, err = _run(["fit", "--static", _write(tmp_path, text), "--set", "M=0.2106"], capsys)
    assert rc == 2 and err.count("\n") == 1 and words in err and "--static" in err, err


def test_frf_and_decay_file_errors(tmp_path, capsys):
    head = "fe_hz,force_amplitude_n,app_um,direction\n"
    cases = [(head + "100,1,1,up\n90,1,1,up\n120,1,1,up\n", "out of order"),
             (head + "100,1,1,up\n110,1,1,across\n120,1,1,up\n", "must be up or down")]
    for text, words in cases:
        rc, _out, err = _run(["fit", "--frf", _write(tmp_path, text), "--set", "M=0.2106"], capsys)
        assert rc == 2 and words in err and err.count("\n") == 1, err
    t = np.linspace(0, 1, 50)
    text = "t_ms,y_um\n" + "\n".join(f"{a},{np.cos(4 * a)}" for a in t) + "\n"
    rc, _out, err = _run(["fit", "--decay", _write(tmp_path, text), "--set", "M=0.2106"], capsys)
    assert rc == 2 and "at least 3 cycles" in err, err
    few = head + "100,1,1,up\n110,1,1,up\n120,1,1,up\n"
    rc, _out, err = _run(["fit", "--frf", _write(tmp_path, few), "--set", "M=0.2106"], capsys)
    assert rc == 2 and "fewer than the 5 needed" in err, err


def test_a_fit_that_does_not_converge_prints_the_best_point_and_exits_1(capsys, monkeypatch):
    from contactvib.fitting import solver

    real = solver.fit
    monkeypatch.setattr(solver, "fit", lambda **kw: real(**{**kw, "max_nfev": 1}))
    rc, out, err = _run(["fit", "--static", STATIC, "--set", "M=0.2106", "--no-progress"], capsys)
    assert rc == 1 and err.startswith("contactvib: error: the fit did not converge") and "best point" in err, err
    assert "m2" in out and "NOT converged" in out


def test_a_parameter_on_its_bound_is_reported(capsys):
    rc, out, err = _run(["fit", "--static", STATIC, "--set", "M=0.2106", "--bounds", "m2=1.2:1.5", "--json"], capsys)
    assert rc == 0, err
    d = json.loads(out)
    assert d["parameters"]["m2"]["value"] == pytest.approx(1.5)
    assert any(s.startswith("m2 ended on its bound") for s in d["identifiability"])
