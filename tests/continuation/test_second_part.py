"""The 1/5 resonance at 0.90 Q is divided (paper S3.7): its period-1 branch, continued below the
period doubling at 249.76 Hz, becomes stable again through a second doubling near 113 Hz and
stays stable down to a fold near 102 Hz, five minima per period (README, "paper" section).
Independent check: the multi-start search finds that stable orbit between the two points."""

import json

import pytest

from contactvib import ContactModel, find_attractors
from contactvib.cli.main import main


def test_the_1_5_at_090q_has_a_second_stable_part(tmp_path, capsys):
    rc = main(["continue", "--pa", "0.9", "--from-fe", "252", "--attractor", "4", "--fmin", "90",
               "--fmax", "300", "--no-switch", "--out", str(tmp_path / "c"), "--json"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    points = {(p["type"], round(p["fe_hz"], 2)): p for p in d["special_points"]}
    pd_low = points[("period-doubling", 113.27)]
    fold_low = points[("fold", 101.76)]
    assert ("period-doubling", 249.76) in points
    assert pd_low["app_um"] == pytest.approx(5.44, abs=0.01)
    assert fold_low["app_um"] == pytest.approx(6.90, abs=0.01)
    model = ContactModel()
    found = find_attractors(model.excitation(0.9, 108.0))
    five = [a for a in found if a.period == 1 and a.minima_per_period == 5]
    assert len(five) == 1
    assert pd_low["app_um"] < five[0].app_um < fold_low["app_um"]
    assert five[0].floquet_abs_max < 1.0 and 0.005 < five[0].basin_fraction < 0.05
