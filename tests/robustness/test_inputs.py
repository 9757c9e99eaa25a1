"""Any input either works or is refused in one line (issue 13, acceptance): property-based tests
(Hypothesis, derandomized) of every command's options and of the model's validation.

The command line is driven in-process with every computation replaced by a stub
(``no_computation``, tests/robustness/conftest.py): an accepted input reaches the stub, a refused
one gives exit status 2 and exactly one stderr line ``contactvib: error: ...`` naming the option;
nothing else may happen (no other exception out of ``main``, no traceback printed). The Python API
(:class:`ContactModel`, :meth:`ContactModel.excitation`, the attractor search's sizes) either
accepts a value or raises :class:`ParameterError` naming the parameter, never TypeError,
ZeroDivisionError, OverflowError or AttributeError.
"""

import math
from decimal import Decimal
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from contactvib.cli import main
from contactvib.model import PAPER_DEFAULTS, ContactModel, ParameterError

#: fixed examples (derandomized: the same cases on every run), a few seconds per property
PROPERTY = settings(max_examples=60, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])

#: Any float written as a user might: repr, str, %e, %.17g (NaN, ±inf, subnormals, huge, -0.0).
FLOAT_TEXT = st.floats().flatmap(lambda x: st.sampled_from(
    [repr(x), str(x), f"{x:e}", f"{x:.17g}", f"{x:f}"[:40]]))
#: Plain numbers near the ranges' ends, integers, and any text at all.
NUMBER_TEXT = st.from_regex(r"\A[+-]?\d{1,4}(\.\d{0,3})?([eE][+-]?\d{1,3})?\Z")
#: Values inside the options' ranges (so that accepted inputs are drawn too).
USUAL = st.one_of(st.floats(min_value=0.0, max_value=3000.0).map(lambda x: f"{x:.6g}"),
                  st.integers(0, 64).map(str),
                  st.sampled_from(["0.5", "0.65", "1", "2", "8", "300", "360", "1500", "1e-12", "1e-8", "pa", "fe",
                                   "pade", "plain"]))
VALUE = st.one_of(FLOAT_TEXT, NUMBER_TEXT, st.integers().map(str), st.text(max_size=16), USUAL)

#: Every option that takes a value, by command, with the other arguments it needs to matter.
#: Kinds: "value" (one value), "levels" (one or more values after --pa), "pair" (two values),
#: "csv" (comma-separated values), "set" (NAME=VALUE).
OPTIONS = {
    "attractors": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set",
                   "--starts": "value", "--seed": "value", "--kmax": "value", "--max-periods": "value"},
    "simulate": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set",
                 "--starts": "value", "--seed": "value", "--kmax": "value", "--max-periods": "value",
                 "--from-state": "pair", "--periods": "value"},
    "resonance": {"--pa": "levels", "--fmin": "value", "--fmax": "value", "--df": "value",
                  "--multistart-per-octave": "value", "--starts": "value", "--seed": "value",
                  "--kmax": "value", "--workers": "value", "--set": "set", "--fill-in-per-octave": "value",
                  "--fill-in-starts": "value"},
    "atlas": {"--pa": "levels", "--pa-min": "value", "--pa-max": "value", "--npa": "value", "--fmin": "value",
              "--fmax": "value", "--df": "value", "--multistart-per-octave": "value", "--starts": "value",
              "--seed": "value", "--kmax": "value", "--workers": "value", "--set": "set",
              "--dask-workers": "value", "--scheduler": "value", "--fill-in-per-octave": "value",
              "--fill-in-starts": "value"},
    "query": {"--pa": "value", "--fe": "value", "--completeness": "value", "--seed": "value"},
    "animate": {"--fps": "value", "--size": "value"},
    "paper": {"--fmin": "value", "--fmax": "value", "--df": "value", "--multistart-per-octave": "value",
              "--starts": "value", "--seed": "value", "--kmax": "value", "--workers": "value",
              "--set": "set", "--fill-in-per-octave": "value", "--fill-in-starts": "value"},
    "continue": {"--pa": "value", "--from-fe": "value", "--attractor": "value", "--parameter": "value",
                 "--pa-min": "value", "--pa-max": "value", "--set": "set", "--fmin": "value",
                 "--fmax": "value", "--max-points": "value", "--app-max": "value", "--rtol": "value"},
    "bifurcations": {"--pa": "levels", "--seed-fe": "csv", "--set": "set", "--fmin": "value",
                     "--fmax": "value", "--max-points": "value", "--app-max": "value", "--rtol": "value",
                     "--cascade-fe": "value", "--cascade-direction": "value", "--system": "value",
                     "--pa-newton": "value", "--coordinate": "value"},
    "evolution": {"--order": "value", "--pa-min": "value", "--pa-max": "value", "--levels": "value",
                  "--set": "set"},
    "hbm": {"--pa": "value", "--set": "set", "--harmonics": "value", "--fmin": "value", "--fmax": "value",
            "--energy-tol": "value", "--system": "value", "--pa-newton": "value", "--n-time": "value",
            "--plot": "value", "--measure": "value"},
    "basins": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set",
               "--grid": "value", "--y-range": "pair", "--ydot-range": "pair", "--kmax": "value",
               "--max-periods": "value", "--starts": "value", "--system": "value", "--slice": "value",
               "--a-range": "pair", "--b-range": "pair", "--through": "pair"},
    "section": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set",
                "--starts": "value", "--seed": "value", "--kmax": "value", "--max-periods": "value",
                "--periods": "value", "--csv": "value", "--attractor": "value"},
    "orbit-diagram": {"--pa": "value", "--fe": "value", "--set": "set", "--vary": "value", "--fe-from": "value",
                      "--fe-to": "value", "--fe-step": "value", "--pa-from": "value", "--pa-to": "value",
                      "--pa-step": "value", "--periods": "value", "--search-every": "value", "--starts": "value",
                      "--kmax": "value", "--measure": "value", "--ylim": "pair", "--csv": "value", "--nc": "value",
                      "--workers": "value"},
    "perturbation": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set",
                     "--terms": "value", "--order": "value", "--summation": "value"},
    "map": {"--orders": "levels", "--curves": "value"},
    "friction": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set", "--starts": "value",
                 "--seed": "value", "--kmax": "value", "--max-periods": "value", "--vd": "value", "--mu": "value",
                 "--kt-ratio": "value", "--kt-law": "value", "--kd": "value", "--cd": "value", "--beta": "value",
                 "--fe-range": "pair", "--df": "value", "--vd-range": "pair", "--nvd": "value", "--drive": "value",
                 "--ft": "value"},
    "fit": {"--static": "value", "--decay": "value", "--frf": "value", "--set": "set", "--fix": "value",
            "--bounds": "value", "--starts": "value", "--seed": "value", "--save-model": "value"},
    "lyapunov": {"--pa": "value", "--pa-newton": "value", "--fe": "value", "--set": "set", "--starts": "value",
                 "--seed": "value", "--kmax": "value", "--max-periods": "value", "--periods": "value",
                 "--batches": "value", "--transient": "value", "--y0-um": "value", "--v0-mm-s": "value",
                 "--from-state": "pair"},
    "explore": {"--system": "value", "--port": "value", "--host": "value", "--time-limit": "value",
                "--graph-fmin": "value",
                "--graph-fmax": "value", "--graph-df": "value", "--graph-time-limit": "value"},
}

#: The contact-law options of every command that builds a model, and the excitation families'
#: options of the commands at one operating point.
LAW = {"--law": "value", "--law-file": "value", "--damping": "value", "--preload": "value", "--model": "value"}
EXCITATION = {"--base-um": "value", "--base-g": "value", "--harmonic": "value"}
for _name in ("attractors", "simulate", "section", "basins", "perturbation", "friction", "lyapunov"):
    OPTIONS[_name].update(LAW, **EXCITATION)
OPTIONS["simulate"].update({"--random-psd": "value", "--band": "pair", "--duration": "value"})
#: A system of several degrees of freedom (`rocking` or a TOML file) at one operating point.
for _name in ("attractors", "simulate", "continue", "lyapunov"):
    OPTIONS[_name]["--system"] = "value"
OPTIONS["continue"].update({"--pa-newton": "value", "--coordinate": "value"})
for _name in ("resonance", "atlas", "paper", "continue", "bifurcations", "evolution", "hbm", "explore",
              "orbit-diagram"):
    OPTIONS[_name].update(LAW)
#: What the levels hold (force, base-um, base-g): the sweeps, the continuation in f_e and hbm.
for _name in ("resonance", "atlas", "paper", "continue", "bifurcations", "hbm"):
    OPTIONS[_name]["--excitation"] = "value"
#: The friction columns of the sweeps (issue 26): NAME=VALUE pairs, or `default`.
for _name in ("resonance", "atlas"):
    OPTIONS[_name]["--friction"] = "value"
#: The sweeps of a system (--system rocking|FILE.toml): its level in N, the coordinate and measure drawn.
for _name in ("resonance", "atlas"):
    OPTIONS[_name].update({"--system": "value", "--pa-newton": "value", "--plot": "value", "--measure": "value"})

#: Arguments an option needs to be read at all (--periods only with --from-state; --pa-min and
#: --pa-max are a range with --parameter pa).
#: contactvib fit needs a data set and the mass M: the example static curve.
_FIT_NEEDS = ["--static", str(Path(__file__).resolve().parents[2] / "examples" / "fit_static.csv"), "--set", "M=0.2106"]
NEEDS = {("simulate", "--periods"): ["--from-state", "0.1", "0"],
         **{("fit", o): _FIT_NEEDS for o in ("--decay", "--frf", "--set", "--fix", "--bounds", "--starts",
                                             "--seed", "--save-model")},
         ("fit", "--static"): ["--set", "M=0.2106"],
         ("continue", "--pa-min"): ["--parameter", "pa"], ("continue", "--pa-max"): ["--parameter", "pa"],
         ("continue", "--pa"): ["--parameter", "pa"],
         ("friction", "--df"): ["--fe-range", "300", "400"], ("friction", "--nvd"): ["--vd-range", "0.01", "1"],
         ("friction", "--ft"): ["--drive", "force"],
         ("lyapunov", "--y0-um"): ["--v0-mm-s", "0"], ("lyapunov", "--v0-mm-s"): ["--y0-um", "0.1"],
         ("lyapunov", "--from-state"): ["--system", "rocking"],
         **{("basins", o): ["--system", "rocking"] for o in ("--slice", "--a-range", "--b-range", "--through")}}

CASES = [pytest.param(c, o, k, id=f"{c}{o}") for c, opts in OPTIONS.items() for o, k in opts.items()]


def test_every_option_is_covered():
    """OPTIONS lists every option of every command that takes a value (flags need none)."""
    from contactvib.cli.main import cli

    assert set(OPTIONS) | {"query"} == set(cli.commands)
    for name, command in cli.commands.items():
        takes_value = {p.opts[-1] for p in command.params
                       if p.param_type_name == "option" and not p.is_flag and p.opts[-1] not in ("--out", "--dataset")}
        assert takes_value == set(OPTIONS[name]), name


def _argv(command, option, kind, value, tmp_path, small_dataset):
    head = [command]
    if command == "query" and option == "--completeness":
        head += [str(small_dataset)]
    elif command == "query" and option == "--seed":  # the seed of --completeness
        head += [str(small_dataset), "--completeness", "1"]
    elif command == "query":
        head += [str(small_dataset), "--pa", "0.65", "--fe", "360"]
    if command == "map":
        head += [str(small_dataset)]
    if command == "animate":  # a dataset and a film file
        head += [str(small_dataset), "--out", str(tmp_path / "film.mp4")]
    elif command in ("section", "orbit-diagram"):  # --out is a figure file
        head += ["--out", str(tmp_path / "out.png")]
        if command == "orbit-diagram":
            head += ["--fe-from", "810", "--fe-to", "811", "--fe-step", "1"]
    elif command not in ("attractors", "query", "explore", "lyapunov"):  # these write nothing
        head += ["--out", str(tmp_path / "out")]
    head += NEEDS.get((command, option), [])
    if kind == "levels":
        return head + [option, *value]
    if kind == "pair":
        return head + [option, *value]
    if kind == "csv":
        return head + [option, ",".join(value)]
    return head + [option, value]


def _outcome(argv, capsys, computation):
    """``main(argv)``: "accepted" (the stubbed computation was reached, or exit 0) or the one
    error line; anything else fails the test."""
    try:
        rc = main(argv)
    except computation:
        rc = None
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err, err
    if rc is None or rc == 0:
        assert not err or all(line.startswith("contactvib: warning: ") for line in err.splitlines()), err
        return "accepted"
    assert rc == 2, (rc, err)
    assert err.count("\n") == 1 and err.startswith("contactvib: error: "), err
    return err


def _names(err, option, kind, value):
    """Whether the error line names the option (or the token the user typed in its place: an
    option-like token in a list of levels is read as an option)."""
    if option in err:
        return True
    tokens = value if isinstance(value, (list, tuple)) else [value]
    return any(t.startswith("-") and t in err for t in tokens)


def _values(kind):
    if kind in ("levels", "csv"):
        return st.lists(VALUE, min_size=0 if kind == "csv" else 1, max_size=4)
    if kind == "pair":
        return st.tuples(VALUE, VALUE)
    return VALUE


@pytest.mark.parametrize("command, option, kind", [c for c in CASES if c.values[2] != "set"])
def test_any_option_value_works_or_is_one_line(command, option, kind, no_computation, capsys, tmp_path,
                                               small_dataset):
    @PROPERTY
    @given(value=_values(kind))
    def check(value):
        argv = _argv(command, option, kind, value, tmp_path, small_dataset)
        err = _outcome(argv, capsys, no_computation)
        if err != "accepted":
            assert _names(err, option, kind, value), (argv, err)

    check()


@pytest.mark.parametrize("command", [c for c, opts in OPTIONS.items() if "--set" in opts])
@pytest.mark.parametrize("name", list(PAPER_DEFAULTS))
def test_any_model_parameter_works_or_is_one_line(command, name, no_computation, capsys, tmp_path):
    """--set NAME=VALUE for every parameter: a refusal names --set NAME, or — for a model whose
    f_n0 puts a frequency option out of reach — the frequency option and the model's f_n0."""
    @PROPERTY
    @given(value=VALUE)
    def check(value):
        argv = _argv(command, "--set", "value", f"{name}={value}", tmp_path, None)
        err = _outcome(argv, capsys, no_computation)
        if err != "accepted":
            assert f"--set {name}" in err or "f_n0" in err, (argv, err)

    check()


@PROPERTY
@given(items=st.lists(st.one_of(st.text(max_size=12),
                                st.tuples(st.sampled_from(list(PAPER_DEFAULTS)), VALUE).map("=".join)),
                      max_size=4))
def test_any_set_list_works_or_is_one_line(items, no_computation, capsys):
    argv = ["attractors"] + [a for item in items for a in ("--set", item)]
    err = _outcome(argv, capsys, no_computation)
    assert err == "accepted" or "--set" in err or "f_n0" in err, (argv, err)


@pytest.mark.parametrize("command", list(OPTIONS))
def test_any_command_line_works_or_is_one_line(command, no_computation, capsys, tmp_path, small_dataset):
    """Any list of the command's option names and any values, in any order: accepted, help
    (exit 0) or one error line."""
    names = sorted(OPTIONS[command]) + ["--json", "--no-seeds", "--resume", "--no-switch", "--"]
    token = st.one_of(st.sampled_from(names), VALUE)

    @PROPERTY
    @given(tokens=st.lists(token, max_size=8))
    def check(tokens):
        head = [command, str(small_dataset)] if command in ("query", "map", "animate") else [command]
        out = str(tmp_path / ("film.mp4" if command == "animate" else "out"))
        _outcome(head + tokens + ["--out", out] * (command not in ("attractors", "query", "explore")),
                 capsys, no_computation)

    check()


# ------------------------------------------------------------------ the Python API

#: Anything a caller might pass as a parameter.
ANY_OBJECT = st.one_of(
    st.floats(), st.integers(), st.booleans(), st.none(), st.text(max_size=8), NUMBER_TEXT,
    st.floats().map(np.float64), st.floats(width=32).map(np.float32), st.integers(-2**63, 2**63 - 1).map(np.int64),
    st.floats(allow_nan=False).map(lambda x: Decimal(repr(x))), st.fractions().map(Fraction),
    st.complex_numbers(max_magnitude=1e3), st.binary(max_size=4),
    st.lists(st.floats(), max_size=2), st.just(object()), st.just(np.array([1.0, 2.0])), st.just({}),
)
#: The API properties are cheap: more examples.
API = settings(PROPERTY, max_examples=200)
#: Values of a parameter near its range (over many decades), to reach the combination checks.
PARAMETER = st.one_of(st.floats(min_value=1e-320, max_value=1e308), st.floats(min_value=0.5, max_value=12))
DERIVED = {"Q", "y0", "f_n0", "zeta"}


def _api_refusal(e, names):
    """A ParameterError of the API names the parameter: its symbol is one of ``names``, or its
    range names one (``f_max = 20: must be > f_min = 30 Hz``), or it is a derived scale whose
    message names every parameter of the model, or — for the damping ratio, which every parameter
    changes — h_n with the largest h_n allowed."""
    assert isinstance(e, ParameterError), repr(e)
    assert "\n" not in str(e)
    if e.symbol in names or set(e.bounds) & set(names):
        return
    if e.symbol == "h_n":
        assert "damping ratio zeta" in str(e) and "i.e. h_n <= " in str(e), str(e)
    else:
        assert e.symbol in DERIVED and all(f"{n} = " in str(e) for n in PAPER_DEFAULTS), str(e)


@API
@given(params=st.dictionaries(st.sampled_from(list(PAPER_DEFAULTS)), st.one_of(ANY_OBJECT, PARAMETER), max_size=7))
def test_contact_model_accepts_or_names_the_parameter(params):
    try:
        model = ContactModel(**params)
    except Exception as e:
        _api_refusal(e, set(params))
        return
    values = model.parameters()
    assert all(isinstance(v, float) and math.isfinite(v) for v in values.values())
    assert all(math.isfinite(x) and x > 0 for x in (model.Q, model.y0, model.f_n0))


@API
@given(pa=st.one_of(ANY_OBJECT, st.floats(min_value=0, max_value=2e3)),
       fe=st.one_of(ANY_OBJECT, st.floats(min_value=1e-3, max_value=1e7)),
       params=st.dictionaries(st.sampled_from(list(PAPER_DEFAULTS)), PARAMETER, max_size=3))
def test_excitation_accepts_or_names_the_parameter(pa, fe, params):
    try:
        model = ContactModel(**params)
    except ParameterError:
        model = ContactModel()
    try:
        exc = model.excitation(pa, fe)
    except Exception as e:
        _api_refusal(e, {"P_a/Q", "f_e"})
        return
    assert math.isfinite(exc.pa_over_q) and 0.0 <= exc.pa_over_q and math.isfinite(exc.r) and exc.r > 0
    assert np.all(np.isfinite(exc.kernel_parameters()))


@API
@given(sizes=st.fixed_dictionaries({k: st.one_of(ANY_OBJECT, st.integers(-5, 10**12))
                                    for k in ("n_starts", "seed", "kmax", "max_periods")}))
def test_search_sizes_accept_or_name_the_parameter(sizes):
    """The attractor search's sizes (find_attractors checks them first)."""
    from contactvib.steady.attractors import check_search

    try:
        n_starts, seed, kmax, max_periods = check_search(**sizes)
    except Exception as e:
        _api_refusal(e, set(sizes))
        return
    assert all(isinstance(v, int) for v in (n_starts, seed, kmax, max_periods))


#: Values of sizes, tolerances and frequencies of the settings objects.
SETTING = st.one_of(ANY_OBJECT, st.integers(-5, 10**7), st.floats(min_value=1e-20, max_value=1e7))


@API
@given(kw=st.dictionaries(st.sampled_from(["fmin_hz", "fmax_hz", "df_hz", "kmax", "max_periods",
                                           "multistart_per_octave", "n_starts", "seed", "tol"]),
                          SETTING, max_size=4))
def test_sweep_settings_accept_or_name_the_parameter(kw):
    from contactvib.sweeps.sweep import SweepSettings

    symbols = {"fmin_hz": "f_min", "fmax_hz": "f_max", "df_hz": "df"}
    try:
        SweepSettings(**kw)
    except Exception as e:
        _api_refusal(e, {symbols.get(k, k) for k in kw})


@API
@given(kw=st.dictionaries(st.sampled_from(["fmin_hz", "fmax_hz", "pa_min", "pa_max", "max_points", "app_max_um",
                                           "rtol", "tol", "ds", "ds_min", "ds_max"]),
                          SETTING, max_size=4))
def test_continuation_settings_accept_or_name_the_parameter(kw):
    from contactvib.continuation.shooting import ContinuationSettings

    symbols = {"fmin_hz": "f_min", "fmax_hz": "f_max"}
    try:
        ContinuationSettings(**kw)
    except Exception as e:
        _api_refusal(e, set(kw) | {symbols.get(k, k) for k in kw})


@API
@given(y=st.one_of(ANY_OBJECT, st.floats()), ydot=st.one_of(ANY_OBJECT, st.floats()),
       n=st.one_of(ANY_OBJECT, st.integers(-5, 10**9)), samples=st.one_of(ANY_OBJECT, st.integers(-5, 10**6)))
def test_simulation_start_accepts_or_names_the_parameter(y, ydot, n, samples):
    from contactvib.steady.simulate import check_start

    try:
        check_start(ContactModel(), y, ydot, n, samples)
    except Exception as e:
        _api_refusal(e, {"y", "ydot", "n_periods", "samples_per_period"})


@API
@given(kw=st.dictionaries(st.sampled_from(["ds", "ds_min", "ds_max", "df_max_hz", "max_points", "energy_tol", "tol"]),
                          SETTING, max_size=4))
def test_harmonic_balance_settings_accept_or_name_the_parameter(kw):
    from contactvib.frequency.harmonic_balance import HBSettings

    try:
        HBSettings(**kw)
    except Exception as e:
        _api_refusal(e, set(kw))


def test_settings_store_their_checked_values():
    """Numbers given as text are stored as floats, counts as ints (they used to be stored as given,
    and text raised TypeError in the next comparison); a fractional count is refused."""
    from contactvib.continuation.shooting import ContinuationSettings
    from contactvib.frequency.harmonic_balance import HBSettings
    from contactvib.sweeps.sweep import SweepSettings

    s = SweepSettings(fmin_hz="30", fmax_hz=Decimal("400"), df_hz="5", kmax=3.0, n_starts="8")
    assert (s.fmin_hz, s.fmax_hz, s.df_hz, s.kmax, s.n_starts) == (30.0, 400.0, 5.0, 3, 8)
    assert type(s.fmax_hz) is float and type(s.kmax) is int and type(s.n_starts) is int
    c = ContinuationSettings(fmin_hz="30", pa_min="0.1", ds_min="1e-7", max_points=16.0)
    assert (c.fmin_hz, c.pa_min, c.ds_min, c.max_points) == (30.0, 0.1, 1e-7, 16) and type(c.max_points) is int
    h = HBSettings(ds_min="1e-6", max_points="10")
    assert (h.ds_min, h.max_points) == (1e-6, 10)
    for make, symbol in ((lambda: ContinuationSettings(max_points=16.7), "max_points"),
                         (lambda: ContinuationSettings(fmin_hz=100, fmax_hz=50), "fmax_hz"),
                         (lambda: HBSettings(ds=1.0, ds_min=1.0, ds_max=0.5), "ds_max")):
        with pytest.raises(ParameterError) as e:
            make()
        assert e.value.symbol == symbol
    assert SweepSettings() == SweepSettings(fmin_hz=30, fmax_hz=2000, df_hz=1)


def _api_calls():
    from contactvib import continue_orbit, hb_continuation, hb_solve, simulate

    model = ContactModel()
    exc = model.excitation(0.65, 360)
    return {  # values that raised TypeError, ValueError, ZeroDivisionError or AttributeError
        "simulate rtol text": (lambda: simulate(exc, rtol="a"), "rtol"),
        "simulate rtol 0": (lambda: simulate(exc, rtol=0), "rtol"),
        "hb_solve start text": (lambda: hb_solve(exc, harmonics=4, start="abc"), "start"),
        "hb_solve start nan": (lambda: hb_solve(exc, harmonics=4, start=[np.nan, 0.0]), "start"),
        "hb_solve tol text": (lambda: hb_solve(exc, harmonics=4, tol="x"), "tol"),
        "hb_solve max_iter text": (lambda: hb_solve(exc, harmonics=4, max_iter="x"), "max_iter"),
        "hb_continuation settings": (lambda: hb_continuation(model, pa_over_q=0.65, fmin_hz=300, fmax_hz=400,
                                                             settings="x"), "settings"),
        "continue_orbit state text": (lambda: continue_orbit(exc, "ab", 1), "state"),
        "continue_orbit settings": (lambda: continue_orbit(exc, [1.0, 0.0], 1, settings="x"), "settings"),
    }


@pytest.mark.parametrize("case", list(_api_calls()))
def test_api_refuses_wrong_values_by_name(case):
    call, symbol = _api_calls()[case]
    with pytest.raises(ParameterError) as e:
        call()
    assert e.value.symbol == symbol
