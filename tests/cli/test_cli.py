"""The command line: JSON contract, figures (input errors: test_cli_errors.py)."""
import json

import pytest

from contactvib.cli import main
from figure_files import assert_figure_file


def test_attractors_json_contract(capsys):
    """JSON at 360 Hz, 0.65 Q: sorted by A_pp, integer periods, the documented keys."""
    assert main(["attractors", "--pa", "0.65", "--fe", "360", "--json", "--starts", "256"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["fe_hz"] == 360.0 and d["pa_over_q"] == 0.65
    assert d["fn0_hz"] == pytest.approx(1485.0, abs=0.05)
    assert d["y0_um"] == pytest.approx(0.2254, abs=5e-5)
    atts = d["attractors"]
    assert [a["app_um"] for a in atts] == sorted((a["app_um"] for a in atts), reverse=True)
    keys = {"period", "minima_per_period", "app_um", "ymin_um", "ymax_um", "loses_contact",
            "contact_loss_fraction", "basin_fraction", "floquet_abs_max", "strobe_points"}
    for a in atts:
        assert keys <= set(a)
        assert a["app_um"] == pytest.approx(a["ymax_um"] - a["ymin_um"], rel=1e-12)
        assert a["loses_contact"] == (a["ymin_um"] < 0)
        assert 0.0 <= a["contact_loss_fraction"] < 1.0
        assert isinstance(a["period"], int) and len(a["strobe_points"]) == a["period"]
        assert a["floquet_abs_max"] < 1.0
    period1 = {a["minima_per_period"] for a in atts if a["period"] == 1}
    assert {1, 2, 3, 4} <= period1


def test_pa_newton_equals_pa(capsys):
    from contactvib import ContactModel

    q = ContactModel().Q
    main(["attractors", "--pa-newton", str(0.5 * q), "--fe", "1000", "--json", "--starts", "64"])
    a = json.loads(capsys.readouterr().out)
    main(["attractors", "--pa", "0.5", "--fe", "1000", "--json", "--starts", "64"])
    b = json.loads(capsys.readouterr().out)
    assert a["pa_over_q"] == pytest.approx(0.5, rel=1e-12)
    assert [x["app_um"] for x in a["attractors"]] == pytest.approx([x["app_um"] for x in b["attractors"]], rel=1e-9)


def test_simulate_writes_figures(tmp_path, capsys):
    out = tmp_path / "fig"
    assert main(["simulate", "--pa", "0.9", "--fe", "50", "--out", str(out), "--starts", "32"]) == 0
    pngs = sorted(out.glob("*.png"))
    assert len(pngs) >= 2
    for p in pngs:
        assert_figure_file(p)
    d = json.loads((out / "attractors.json").read_text())
    assert len(d["attractors"]) == len(pngs)
    assert main(["simulate", "--pa", "0.9", "--fe", "50", "--from-state", "0.3", "0",
                 "--periods", "3", "--out", str(out)]) == 0
    assert (out / "trajectory_pa0.9_fe50.png").exists()
