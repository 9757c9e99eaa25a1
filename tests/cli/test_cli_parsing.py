"""Parsing of the command line's values (issue 13): the levels right after --pa, a value anywhere
else, negative levels, --set given twice, plain ASCII numbers, -0, strict JSON output, the wrong
types in the Python API; and property-based tests: any input either works or is refused with a
ParameterError / one ``contactvib: error:`` line and exit status 2, never another exception."""
import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from contactvib.cli import main
from contactvib.cli.common import InputError, echo_json, one_line, parse_model
from contactvib.model import PAPER_DEFAULTS, ContactModel, ParameterError, check_finite, check_int
from contactvib.model.checks import _NUMBER_TEXT

#: fixed examples (derandomized: the same cases on every run)
FAST = settings(max_examples=100, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture])


def _one_line(capsys, needle=""):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("contactvib: error: ") and needle in err, err
    return err


# ------------------------------------------------------------------ --pa levels and stray values

@pytest.mark.parametrize("args, needle", [
    (["--pa", "0.5", "--fmin", "300", "400", "--fmax", "400", "--df", "5"], "contactvib: error: 400: unexpected value"),
    (["--fmin", "300", "0.7"], "0.7: unexpected value"),
    (["0.7"], "0.7: unexpected value"),
    (["--pa", "0.5", "-0.6"], "--pa (P_a/Q) = -0.6: must be > 0 (multiple of Q = M g)"),
    (["--pa", "-.5"], "--pa (P_a/Q) = -0.5: must be > 0"),
    (["--pa", "-0"], "--pa (P_a/Q) = -0: must be > 0"),
    (["--pa"], "--pa: expected one or more levels"),
    (["--pa=", "0.6"], "--pa (P_a/Q) = : must be a finite number"),
    (["--pa=0.5", "-0.6"], "--pa (P_a/Q) = -0.6: must be > 0"),
    (["--pa", "--df", "1"], "--pa: expected one or more levels"),
    (["--pa", "0.5", "--bogus"], "No such option '--bogus'"),
    (["--pa", "0.5", "0.6", "x"], "--pa (P_a/Q) = x: must be a finite number"),
    (["--pa", "0.5", "0.6", "--df", "0"], "--df (df) = 0: must be > 0 Hz"),
])
def test_resonance_levels(tmp_path, capsys, args, needle):
    assert main(["resonance", *args, "--out", str(tmp_path / "x")]) == 2
    _one_line(capsys, needle)
    assert not (tmp_path / "x").exists()


def test_bifurcations_levels(tmp_path, capsys):
    assert main(["bifurcations", "--pa", "0.5", "0.6", "--fmin", "300", "400", "--out", str(tmp_path)]) == 2
    _one_line(capsys, "400: unexpected value")
    assert main(["bifurcations", "--pa", "0.5", "-0.6", "--out", str(tmp_path)]) == 2
    _one_line(capsys, "--pa (P_a/Q) = -0.6: must be > 0")


def test_levels_reach_the_command(monkeypatch, tmp_path):
    """`--pa 0.5 0.6 0.65` gives three levels, in order; `--pa A --pa B` too."""
    seen = []

    def stop(model, *, levels, **k):
        seen.append(list(levels))
        raise InputError("stop")

    monkeypatch.setattr("contactvib.sweeps.resonance.resonance_dataset", stop)
    assert main(["resonance", "--pa", "0.5", "0.6", "0.65", "--df", "5", "--out", str(tmp_path)]) == 2
    assert main(["resonance", "--pa", "0.5", "--df", "5", "--pa", "0.7", "--out", str(tmp_path)]) == 2
    assert main(["resonance", "--df", "5", "--out", str(tmp_path)]) == 2
    assert main(["resonance", "--pa=0.5", "0.6", "--df", "5", "--out", str(tmp_path)]) == 2
    assert seen == [[0.5, 0.6, 0.65], [0.5, 0.7], [0.65], [0.5, 0.6]]


def test_one_level_commands_refuse_a_second_value(capsys):
    assert main(["attractors", "--pa", "0.5", "0.6"]) == 2
    _one_line(capsys, "0.6")


# ------------------------------------------------------------------ --set, numbers, -0

def test_set_given_twice(capsys):
    assert main(["attractors", "--set", "M=1", "--set", "M=2"]) == 2
    assert _one_line(capsys) == "contactvib: error: --set M given twice\n"
    with pytest.raises(InputError, match="--set M given twice"):
        parse_model(("M=1", " M = 1"))


@pytest.mark.parametrize("text", ["٣٦٠", "3_60", "３６０", "360\u00a0", "0x10", "1e", "--1", "inf", "nan", ""])
def test_only_plain_ascii_numbers(capsys, text):
    assert main(["attractors", "--fe", text]) == 2
    # the value is echoed as typed, invisible characters escaped (one line)
    assert _one_line(capsys) == f"contactvib: error: --fe (f_e) = {one_line(text)}: must be a finite number\n"
    with pytest.raises(ParameterError, match="must be a finite number"):
        check_finite("f_e", text)
    with pytest.raises(ParameterError, match="must be an integer"):
        check_int("kmax", text)


@pytest.mark.parametrize("text, value", [("360", 360.0), (" 3.6e2 ", 360.0), ("+.5", 0.5), ("5.", 5.0),
                                         ("1E-3", 1e-3), ("-0", 0.0), ("-0.0", 0.0)])
def test_plain_numbers_are_read(text, value):
    v = check_finite("x", text)
    assert v == value and math.copysign(1.0, v) == 1.0


def test_minus_zero_is_zero():
    assert math.copysign(1.0, check_finite("x", -0.0)) == 1.0
    exc = ContactModel().excitation("-0", 360)
    assert exc.pa_over_q == 0.0 and math.copysign(1.0, exc.pa_over_q) == 1.0


# ------------------------------------------------------------------ JSON output, datasets

def test_json_output_has_no_bare_nan(capsys):
    echo_json('{"a": NaN, "b": [1.5, Infinity, -Infinity], "c": {"d": NaN}, "e": "NaN"}')
    out = capsys.readouterr().out
    assert json.loads(out, parse_constant=lambda c: pytest.fail(c)) == \
        {"a": None, "b": [1.5, None, None], "c": {"d": None}, "e": "NaN"}
    echo_json({"x": float("nan"), "y": (1, 2.0)})
    assert json.loads(capsys.readouterr().out) == {"x": None, "y": [1, 2.0]}




def _damaged(src, dst, **changes):
    import xarray as xr

    with xr.open_dataset(src) as ds:
        ds = ds.load()
    for name, value in changes.items():
        if name == "settings":
            ds.attrs["settings"] = value
        else:
            ds[name] = ds[name].copy(data=np.full(ds[name].shape, value))
    ds.to_netcdf(dst)
    return dst


def test_query_refuses_nan_values_instead_of_answering_nulls(small_dataset, tmp_path, capsys):
    """NaN where a value must be finite: one line naming the damage (the answer was all nulls)."""
    bad = _damaged(small_dataset, tmp_path / "nan.nc", app_um=np.nan, ymin_um=np.nan, contact_loss_fraction=np.nan)
    assert main(["query", str(bad), "--pa", "0.65", "--fe", "360", "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err == f"contactvib: error: DATASET = {bad}: damaged: app_um is nan at point 0 " \
                                "(P_a = 0.65 Q, f_e = 340 Hz): recompute it\n"


def test_query_json_is_strict_where_values_may_be_missing(small_dataset, capsys):
    """Values that may be missing (the basin fraction, the Lyapunov exponent: NaN in the
    dataset) are null in the JSON, never a bare NaN."""
    assert main(["query", str(small_dataset), "--pa", "0.65", "--fe", "360", "--json"]) == 0
    res = json.loads(capsys.readouterr().out, parse_constant=lambda c: pytest.fail(f"bare {c}"))
    assert res["attractors"] and all(a["basin_fraction"] is None for a in res["attractors"])


@pytest.mark.parametrize("settings_attr", ["{not json", "[]", '{"df_hz": 5}',
                                           '{"df_hz": "x", "fmin_hz": 1, "fmax_hz": 2}'])
def test_query_on_damaged_settings_is_one_line(small_dataset, tmp_path, capsys, settings_attr):
    bad = _damaged(small_dataset, tmp_path / "settings.nc", settings=settings_attr)
    assert main(["query", str(bad), "--pa", "0.65", "--fe", "360"]) == 2
    _one_line(capsys, "dataset attribute 'settings' is missing or damaged")


# ------------------------------------------------------------------ Python API: types

def test_api_refuses_wrong_model_types():
    from contactvib import Excitation, find_attractors, simulate

    model = ContactModel()
    exc = model.excitation(0.65, 360)
    with pytest.raises(ParameterError, match="seed = -1: must be an integer >= 0"):
        find_attractors(exc, seed=-1)
    for call in (lambda: ContactModel.excitation("paper", 0.6, 360), lambda: Excitation("x", 0.6, 360)):
        with pytest.raises(ParameterError, match="model = 'x'|model = 'paper'") as e:
            call()
        assert e.value.symbol == "model" and "must be a ContactModel" in str(e.value)
    with pytest.raises(ParameterError, match="must be an Excitation"):
        simulate("x")
    with pytest.raises(ParameterError, match="model = 'paper'"), pytest.warns(DeprecationWarning):
        find_attractors("paper", exc)  # the deprecated form: its model is checked too


# ------------------------------------------------------------------ equilibrium

def test_rest_state_is_an_equilibrium_without_minima():
    from contactvib.steady.orbits import describe_orbit

    model = ContactModel()
    exc = model.excitation(0.0, 360)
    a = describe_orbit(exc, np.array(model.units.state(model.units.y_um, 0.0)), 1)
    assert a.app_um < 1e-9 * model.units.y_um
    assert a.minima_per_period == 0 and a.extrema_y_um.size == 0 and a.extrema_is_min.size == 0


# ------------------------------------------------------------------ properties

ANY_TEXT = st.text(max_size=12)
NUMBER_TEXT = st.one_of(st.floats(allow_nan=True, allow_infinity=True).map(repr), ANY_TEXT,
                        st.from_regex(r"\A[+-]?\d{1,4}(\.\d{0,3})?([eE][+-]?\d{1,3})?\Z"))


@FAST
@given(value=st.one_of(NUMBER_TEXT, st.floats(), st.integers(), st.none(), st.booleans(),
                       st.lists(st.floats(), max_size=2), st.binary(max_size=4)))
def test_number_parser_property(value):
    try:
        v = check_finite("x", value)
    except ParameterError as e:
        assert e.symbol == "x" and "must be a finite number" in str(e)
        return
    assert isinstance(v, float) and math.isfinite(v)
    assert v != 0.0 or math.copysign(1.0, v) == 1.0  # never -0.0
    if isinstance(value, str):
        assert _NUMBER_TEXT.fullmatch(value) and value.isascii()


@FAST
@given(value=st.one_of(NUMBER_TEXT, st.floats(), st.integers()))
def test_int_parser_property(value):
    try:
        n = check_int("n", value, 0, 64)
    except ParameterError as e:
        assert "must be an integer in 0..64" in str(e)
        return
    assert isinstance(n, int) and 0 <= n <= 64


@FAST
@given(items=st.lists(st.one_of(ANY_TEXT, st.tuples(st.sampled_from(list(PAPER_DEFAULTS)), NUMBER_TEXT)
                                .map(lambda t: f"{t[0]}={t[1]}")), max_size=3))
def test_set_parser_property(items):
    try:
        assert isinstance(parse_model(tuple(items)), ContactModel)
    except InputError as e:
        assert "\n" not in str(e)


@FAST
@given(items=st.lists(st.tuples(st.sampled_from(list(PAPER_DEFAULTS)), NUMBER_TEXT)
                      .map(lambda t: f"{t[0]}={t[1]}"), max_size=2))
def test_set_option_property(capsys, items):
    args = ["attractors"] + [a for item in items for a in ("--set", item)] + ["--fe", "0"]
    assert main(args) == 2
    _one_line(capsys)


@FAST
@given(levels=st.lists(st.one_of(NUMBER_TEXT, ANY_TEXT), min_size=0, max_size=4))
def test_pa_list_property(tmp_path, capsys, levels):
    assume(not any(t in ("-h", "--help") or t.startswith("--h") for t in levels))
    out = tmp_path / "x"
    assert main(["resonance", "--pa", *levels, "--df", "0", "--out", str(out)]) == 2
    _one_line(capsys)
    assert not out.exists()


@FAST
@given(name=st.sampled_from(list(PAPER_DEFAULTS)),
       value=st.one_of(st.floats(), st.integers(), NUMBER_TEXT, st.none(), st.lists(st.floats(), max_size=2)))
def test_contact_model_property(name, value):
    try:
        model = ContactModel(**{name: value})
    except ParameterError as e:
        assert e.symbol
        return
    assert all(math.isfinite(v) for v in model.parameters().values())
