"""The explore page's contact-law chooser without a browser: the law fields (law, damping, preload,
c_e, lam, alpha) in the URL, the model they build against the model built directly with
:class:`~contactvib.ContactModel` (an independent path: no CLI, no text), the page's search
against :func:`~contactvib.steady.attractors.find_attractors` on that model, the CLI's one-line
messages for bad values, and the commands the page prints, run through the CLI."""

from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel, Excitation
from contactvib.cli import main
from contactvib.cli.explore import _check, _find, _graph_grid, _level_inputs
from contactvib.explore.dataset_view import DatasetLevels
from contactvib.explore.level_graph import LevelRun, sweep_level
from contactvib.explore.state import DEFAULTS, BadInput, Point, derived, search, table_rows
from contactvib.model.laws import TableLaw, law_names
from contactvib.steady.attractors import find_attractors
from contactvib.sweeps.stored import open_resonance

ROOT = Path(__file__).resolve().parents[2]
TABLE = ROOT / "examples" / "power_law_table.csv"
#: An exponential law with Hunt–Crossley damping and a preload, every value off its default.
LAW = {"law": "exponential", "c_e": "700", "lam": "1.2e-7", "damping": "hunt-crossley", "alpha": "30",
       "preload": "0.5"}


def _direct() -> ContactModel:
    return ContactModel(law="exponential", c_e=700.0, lam=1.2e-7, damping="hunt-crossley", alpha=30.0,
                        preload=0.5)


def test_law_fields_in_the_url_round_trip():
    p = Point.from_query({**{k: [v] for k, v in LAW.items()}, "fe": ["900"]})
    assert p.fields == {**DEFAULTS, **LAW, "fe": "900"}
    assert p.query() == {**LAW, "fe": "900"}
    assert Point.from_query(p.query()).fields == p.fields
    # a law or damping the page does not offer is ignored: the table without a server's file
    assert Point.from_query({"law": ["table"], "damping": ["viscous"]}).fields == DEFAULTS
    start = Point(law_file=str(TABLE))
    assert Point.from_query({"law": ["table"]}, start).fields["law"] == "table"
    assert Point.from_query({"law": ["table"]}, start).law_file == str(TABLE)


def test_only_the_chosen_families_parameters_are_passed():
    p = Point({**DEFAULTS, **LAW, "c_n": "1", "h_n": "-1", "M": "0.3"})  # c_n, h_n hidden
    assert p.active() == ("M", "g", "S", "c_e", "lam", "alpha")
    assert p.settings() == ("M=0.3", "c_e=700", "lam=1.2e-7", "alpha=30")
    assert p.command_options() == (" --law exponential --damping hunt-crossley --preload 0.5 --set M=0.3 "
                                   "--set c_e=700 --set lam=1.2e-7 --set alpha=30")
    assert Point().command_options() == ""
    q = Point({**DEFAULTS, "alpha": "-1", "c_e": "x", "lam": "-1"})  # the power families: all hidden
    assert q.active() == ("M", "g", "S", "c_n", "m2", "h_n", "l") and q.settings() == ()
    model, _exc = _check(q)
    assert model == ContactModel()
    table = Point({**DEFAULTS, "law": "table"}, law_file="my table.csv")
    assert table.command_options() == " --law table --law-file 'my table.csv'"


def test_page_model_equals_the_model_built_directly():
    model, exc = _check(Point({**DEFAULTS, **LAW, "pa": "0.3", "fe": "900"}))
    ref = _direct()
    assert model == ref and model.parameters() == ref.parameters()
    got, want = derived(model), {"f_n0": ref.f_n0, "y0": ref.y0 * 1e6, "zeta": ref.zeta}
    for k in want:
        assert got[k] == pytest.approx(want[k], rel=1e-12), k
    assert got["f_n0"] != pytest.approx(derived(ContactModel())["f_n0"], rel=1e-3)  # the law changed it
    assert exc == Excitation(ref, 0.3, 900.0)
    table, _ = _check(Point({**DEFAULTS, "law": "table"}, law_file=str(TABLE)))
    ref = ContactModel(law="table", table=TableLaw.from_csv(str(TABLE)))
    assert table.law == "table" and table.parameters() == ref.parameters()
    assert table.f_n0 == pytest.approx(ref.f_n0, rel=1e-12)


def test_page_search_equals_find_attractors_on_the_direct_model():
    model, exc = _check(Point({**DEFAULTS, **LAW, "pa": "0.3", "fe": "900"}))
    result, _seconds = search(_find, model, exc)
    ref = find_attractors(Excitation(_direct(), 0.3, 900.0), n_starts=512, seed=0, kmax=8)
    rows, want = table_rows(result), table_rows(ref)
    assert len(rows) == len(want) == 2
    assert rows == want  # every number of the table, bit for bit
    assert rows != table_rows(search(_find, *_check(Point({**DEFAULTS, "pa": "0.3", "fe": "900"})))[0])


@pytest.mark.parametrize(("fields", "message"), [
    ({"law": "exponential", "lam": "-1"}, r"--set lam \(lam\) = -1: must be > 0 m"),
    ({"law": "exponential", "c_e": "abc"}, r"--set c_e \(c_e\) = abc: must be a finite number"),
    ({"damping": "hunt-crossley", "alpha": "-1"}, r"--set alpha \(alpha\) = -1: must be >= 0 s/m"),
    ({"preload": "3000"}, r"--preload \(F_pre\) = 3000: must be <= 2065.99 N \(at most 1000 Q = 2066 N\)"),
    ({"preload": "-1"}, r"--preload \(F_pre\) = -1: must be >= 0 N"),
    ({"law": "table"}, r"--law table: needs --law-file FILE.csv"),
])
def test_bad_law_values_give_the_cli_message(fields, message):
    with pytest.raises(BadInput, match=rf"^contactvib: error: {message}"):
        _check(Point({**DEFAULTS, **fields}))


def test_background_level_with_the_law_equals_the_resonance_command(tmp_path, capsys):
    point = Point({**DEFAULTS, **LAW, "pa": "0.3"})
    run = LevelRun(*_level_inputs(point, _graph_grid("896", "904", "4")))
    assert run.command == ("contactvib resonance --pa 0.3 --fmin 896 --fmax 904 --df 4 --law exponential "
                           "--damping hunt-crossley --preload 0.5 --set c_e=700 --set lam=1.2e-7 --set alpha=30")
    assert run.model == _direct()
    kind, (got, _seconds) = sweep_level(run)
    assert kind == "ok"
    args = shlex.split(run.command)[1:] + ["--workers", "1", "--no-progress", "--out", str(tmp_path)]
    assert main(args) == 0
    capsys.readouterr()
    stored = DatasetLevels(open_resonance(tmp_path)).level(0.3)
    assert got.fe_hz.size >= 3
    for name in ("fe_hz", "app_um", "branch", "kind", "resonance"):
        assert np.array_equal(getattr(got, name), getattr(stored, name)), name


def test_continuation_with_the_law_equals_the_printed_command(tmp_path, capsys):
    import xarray as xr

    from contactvib.cli.explore import _continue

    point = Point({**DEFAULTS, **LAW, "pa": "0.3", "fe": "900"})
    model, exc = _check(point)
    result = _find(model, exc)
    branch, command = _continue(point, model, exc, result, 1)
    assert command.endswith(" --law exponential --damping hunt-crossley --preload 0.5 --set c_e=700 "
                            "--set lam=1.2e-7 --set alpha=30")
    assert main(shlex.split(command)[1:] + ["--out", str(tmp_path)]) == 0
    capsys.readouterr()
    cli = xr.load_dataset(next(tmp_path.glob("branch_*_b0.nc")))
    assert cli.sizes["point"] == len(branch) > 10
    for name in ("fe_hz", "app_um"):
        np.testing.assert_allclose(getattr(branch, name), cli[name].values, rtol=1e-9)


def test_explore_command_starts_the_page_with_its_law_options(monkeypatch, capsys):
    import contactvib.explore.server as server

    seen = {}
    monkeypatch.setattr(server, "serve", lambda *args, **kw: seen.update(start=args[-1]))
    assert main(["explore", "--law", "exponential", "--preload", "2", "--no-browser"]) == 0  # the README's
    start = seen["start"]
    assert start.fields == {**DEFAULTS, "law": "exponential", "preload": "2"}
    # every registered law but the table (which needs --law-file)
    assert start.law_choices() == tuple(n for n in law_names() if n != "table")
    assert start.law_choices()[:2] == ("power", "exponential")
    assert _check(start)[0] == ContactModel(law="exponential", preload=2.0)
    assert main(["explore", "--damping", "hunt-crossley", "--no-browser"]) == 0
    assert seen["start"].fields == {**DEFAULTS, "damping": "hunt-crossley"}
    assert Point.from_query({"damping": ["power"]}, seen["start"]).fields == DEFAULTS
    assert main(["explore", "--law", "table", "--law-file", str(TABLE), "--no-browser"]) == 0
    assert seen["start"].fields["law"] == "table" and "table" in seen["start"].law_choices()
    assert _check(seen["start"])[0].law == "table"
    for args, message in ((["--preload", "1e9"], "--preload (F_pre) = 1e+9: must be <= 2065.99 N"),
                          (["--law", "table"], "--law table: needs --law-file FILE.csv"),
                          (["--law-file", str(TABLE)], "a table file belongs to --law table")):
        seen.clear()
        assert main(["explore", *args, "--no-browser"]) == 2
        assert message in capsys.readouterr().err and not seen


def test_explore_starts_from_a_saved_model(monkeypatch, capsys, tmp_path):
    """``contactvib explore --model F`` (a ``contactvib fit --save-model`` file): the page's first
    point is that model (equal to it, built from the page's fields); a table law's file is refused."""
    import json

    import contactvib.explore.server as server

    seen = {}
    monkeypatch.setattr(server, "serve", lambda *args, **kw: seen.update(start=args[-1]))
    for model in (_direct(), ContactModel(m2=1.9, c_n=3.1e16, l=0.7)):
        path = tmp_path / "model.json"
        path.write_text(json.dumps(model.parameters()))
        assert main(["explore", "--model", str(path), "--no-browser"]) == 0
        assert _check(seen["start"])[0] == model
    path.write_text(json.dumps(ContactModel(law=TableLaw.from_csv(TABLE)).parameters()))
    seen.clear()
    assert main(["explore", "--model", str(path), "--no-browser"]) == 2
    assert "a table law's model" in capsys.readouterr().err and not seen
