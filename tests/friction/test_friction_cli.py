"""`contactvib friction`: the table, the JSON contract, the grids against f_e and v_d with their
files, and bad input in one line (exit 2)."""

import json

import pytest

from contactvib.cli import main
from contactvib.friction import MINDLIN_RATIO
from figure_files import assert_figure_file


def test_one_point_table(capsys):
    assert main(["friction", "--pa", "0.65", "--fe", "360", "--starts", "32"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("P_a = 0.65 Q") and "v_d = 0.1 mm/s" in out[0] and "mu = 0.3" in out[0]
    assert out[1].split()[:6] == ["#", "period", "A_pp", "[um]", "gap", "ratio"]
    rows = [line.split() for line in out[2:]]
    assert len(rows) == 5  # the paper's five attractors at 0.65 Q, 360 Hz
    assert all(0.0 < float(r[4]) < 1.0 for r in rows)


def test_json_contract(capsys):
    assert main(["friction", "--pa", "0.65", "--fe", "360", "--starts", "32", "--json", "--kt-law", "constant",
                 "--mu", "0.2", "--vd", "1", "--beta", "0.8"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["friction"] == {"mu": 0.2, "kt_ratio": MINDLIN_RATIO, "kt_law": "constant", "kd": 1e5, "cd": 30.0,
                             "vd": 1.0, "beta": 0.8, "drive": "velocity", "ft": 0.0}
    assert {"fn0_hz", "y0_um", "pa_over_q", "fe_hz", "model", "attractors"} <= set(d)
    for a in d["attractors"]:
        assert {"period", "app_um", "contact_loss_fraction", "friction_ratio", "friction_reduction",
                "stick_fraction", "slip_fraction", "free_fraction", "tangential_app_um", "limit_mean",
                "energy_residual", "settled", "tangential_period"} <= set(a)
        assert a["friction_ratio"] == pytest.approx(1.0 - a["friction_reduction"])
        assert abs(a["energy_residual"]) < 1e-8


def test_frequency_grid_writes_csv_and_figure(tmp_path, capsys):
    out = tmp_path / "fr"
    assert main(["friction", "--pa", "0.65", "--fe-range", "340", "380", "--df", "40", "--starts", "16",
                 "--out", str(out)]) == 0
    text = capsys.readouterr().out
    lines = (out / "friction_fe.csv").read_text().splitlines()
    assert lines[0].startswith("fe_hz,vd_mm_s,attractor,period")
    assert {float(line.split(",")[0]) for line in lines[1:]} == {340.0, 380.0}
    assert_figure_file(out / "friction_fe.png")
    assert "friction_fe.png" in text


def test_velocity_grid_json(capsys):
    assert main(["friction", "--pa", "0.65", "--fe", "360", "--starts", "16", "--vd-range", "0.01", "10",
                 "--nvd", "3", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    vds = sorted({p["vd_mm_s"] for p in d["points"]})
    assert vds == pytest.approx([0.01, 0.316227766, 10.0])
    # a faster drive slips more: the friction ratio of each attractor rises with v_d
    for k in {p["attractor"] for p in d["points"]}:
        r = [p["friction_ratio"] for p in sorted(d["points"], key=lambda p: p["vd_mm_s"]) if p["attractor"] == k]
        assert all(b >= a - 1e-9 for a, b in zip(r, r[1:]))


def test_one_point_out_writes_histories(tmp_path, capsys):
    out = tmp_path / "one"
    assert main(["friction", "--pa", "0.65", "--fe", "360", "--starts", "16", "--out", str(out), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["attractors"]  # stdout stays one JSON object
    pngs = sorted(out.glob("friction_*.png"))
    assert pngs and all(assert_figure_file(p) is None for p in pngs)
    assert len(json.loads((out / "friction.json").read_text())) == len(pngs)


@pytest.mark.parametrize("args, message", [
    (["--mu", "-0.1"], "--mu (mu) = -0.1: must be in (0, 100]"),
    (["--kt-ratio", "0"], "--kt-ratio (kt_ratio) = 0: must be in (0, 1e+6]"),
    (["--kd", "0"], "--kd (k_d) = 0: must be > 0 N/m: the drive velocity v_d acts through a drive spring"),
    (["--kd", "1e16"], "--kd (k_d) = 1e+16: must be <= 1e+15 N/m"),
    (["--vd", "-1"], "--vd (v_d) = -1: must be in [0, 1e+6] mm/s"),
    (["--cd", "-1"], "--cd (c_d) = -1: must be in [0, 1e+12] N s/m"),
    (["--beta", "1.5"], "--beta (beta) = 1.5: must be in (0, 1]"),
    (["--fe-range", "400", "300"], "--fe-range FMAX (f_max) = 300: must be > --fe-range FMIN = 400 Hz"),
    (["--fe-range", "300", "400", "--vd-range", "0.1", "1"], "--fe-range and --vd-range: give one of them"),
    (["--df", "5"], "--df: belongs to --fe-range"),
    (["--vd-range", "1", "0.1"], "--vd-range VMAX (v_max) = 0.1"),
    (["--fe-range", "300", "400", "--df", "0"], "--df (df) = 0: must be > 0 Hz"),
    (["--fe-range", "1", "1e12"], "--df = 20: 50000000000 frequencies over --fe-range; at most 10000"),
    (["--kt-law", "mindlin"], "--kt-law"),
    (["--drive", "force"], "--drive force: needs the tangential force --ft N"),
    (["--ft", "1"], "--ft: belongs to --drive force"),
    (["--drive", "force", "--ft", "0"], "--ft (F_T) = 0: must be in (0, 1e+12] N"),
    (["--drive", "force", "--ft", "1", "--vd-range", "0.1", "1"], "--vd-range: belongs to the velocity drive"),
])
def test_bad_input_one_line(args, message, capsys):
    assert main(["friction", *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("contactvib: error: ") and message in err, err


def test_force_drive_table(capsys):
    assert main(["friction", "--pa", "0.65", "--fe", "360", "--starts", "16", "--drive", "force", "--ft", "0.3"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert "F_T = 0.3 N" in out[0] and out[1].split()[-3:] == ["v", "[mm/s]", "T_t"]
    assert all(float(line.split()[-2]) > 0.0 for line in out[2:])  # every attractor creeps
