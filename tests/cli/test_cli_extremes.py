"""Extreme inputs (issue 13, item 4): an unwritable output folder, a sweep grid of one frequency,
overflowing numbers and sizes whose arrays would not fit in memory. Each is refused before any
computation with exactly one stderr line ``contactvib: error: ...`` and exit status 2, never a
traceback; the library raises ParameterError (not OverflowError, ZeroDivisionError, ...)."""
import subprocess
import sys
import time

import pytest

from contactvib.cli import main
from contactvib.model import ContactModel, Excitation, ParameterError
from contactvib.model.checks import MEMORY_MAX, PA_MAX, R_RANGE, check_pa_level
from contactvib.steady.attractors import check_search, find_attractors
from contactvib.steady.simulate import check_start, simulate
from contactvib.sweeps.sweep import SweepSettings

CMD = [sys.executable, "-m", "contactvib"]


def _one_line_error(capsys, args) -> str:
    """Run ``main(args)``: exit 2 and one stderr line ``contactvib: error: ...``; return it."""
    assert main(args) == 2
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("contactvib: error: ")
    assert "Traceback" not in captured.err + captured.out
    return lines[0]


# ------------------------------------------------------------------ unwritable --out

OUT_COMMANDS = [
    ["simulate"],
    ["simulate", "--from-state", "0", "0"],
    ["resonance", "--fmin", "300", "--fmax", "310", "--df", "5", "--no-progress"],
    ["paper", "--no-progress"],
    ["continue"],
    ["bifurcations"],
    ["evolution"],
    ["hbm"],
    ["perturbation"],
]


@pytest.mark.timing
@pytest.mark.parametrize("args", OUT_COMMANDS, ids=lambda a: a[0])
def test_unwritable_out_refused_before_computing(args):
    """--out /proc/x (a folder that cannot be created): one line, exit 2, before any work."""
    t0 = time.perf_counter()
    p = subprocess.run(CMD + args + ["--out", "/proc/contactvib_x"], capture_output=True, text=True,
                       timeout=20)
    elapsed = time.perf_counter() - t0
    assert p.returncode == 2, p.stderr
    lines = p.stderr.splitlines()
    assert len(lines) == 1, p.stderr
    assert lines[0].startswith("contactvib: error: --out = /proc/contactvib_x: cannot create")
    assert "Traceback" not in p.stderr
    assert elapsed < 10.0  # interpreter start-up and imports only: nothing was computed


def test_out_that_is_a_file_refused(tmp_path, capsys):
    f = tmp_path / "a_file"
    f.write_text("")
    line = _one_line_error(capsys, ["hbm", "--out", str(f)])
    assert "--out" in line and str(f) in line
    from contactvib.cli.common import InputError, checked_output_folder

    with pytest.raises(InputError, match="not a folder"):
        checked_output_folder(f)


def test_writable_out_is_created(tmp_path):
    """The helper creates the folder and leaves no probe file in it."""
    from contactvib.cli.common import checked_output_folder

    p = checked_output_folder(tmp_path / "a" / "b")
    assert p.is_dir() and list(p.iterdir()) == []


# ------------------------------------------------------------------ a grid of one frequency

def test_df_larger_than_range_refused(capsys):
    line = _one_line_error(capsys, ["resonance", "--fmin", "300", "--fmax", "400", "--df", "1000",
                                    "--out", "/proc/contactvib_x"])
    assert line == ("contactvib: error: --df (df) = 1000: must be <= --fmax - --fmin = 100 Hz "
                    "(the grid needs at least two frequencies)")


def test_sweep_settings_refuse_a_grid_of_one_frequency():
    with pytest.raises(ParameterError) as e:
        SweepSettings(fmin_hz=300.0, fmax_hz=400.0, df_hz=1000.0)
    assert e.value.symbol == "df"
    SweepSettings(fmin_hz=300.0, fmax_hz=400.0, df_hz=100.0)  # two frequencies: accepted


# ------------------------------------------------------------------ extreme numbers

EXTREME = [
    (["--pa", "1e308"], "--pa (P_a/Q) = 1e+308: must be <= 1000"),
    (["--pa-newton", "1e308"], "--pa-newton (P_a) = 1e+308: must be <= 2065.99 N (P_a/Q <= 1000)"),
    (["--fe", "1e308"], "--fe (f_e) = 1e+308: must lie in [0.0001 f_n0, 1000 f_n0]"),
    (["--fe", "5e-324"], "--fe (f_e) = 4.94066e-324: must lie in [0.0001 f_n0, 1000 f_n0]"),
    (["--set", "m2=1e308"], "--set m2 (m2) = 1e+308: must be <= 10"),
    (["--set", "l=1e308"], "--set l (l) = 1e+308: must be <= 10"),
    (["--set", "c_n=1e300"], "--set c_n=1e+300 (y0) = 4.79118e-149: must be in [1e-100, 1e+100] m"),
    (["--set", "c_n=5e-324"], "--set c_n=4.94066e-324 (y0) = inf: must be in [1e-100, 1e+100] m"),
    (["--set", "M=1e308"], "--set M=1e+308 (Q) = inf: must be in [1e-100, 1e+100] N"),
]


@pytest.mark.parametrize("command", ["attractors", "simulate"])
@pytest.mark.parametrize("args, message", EXTREME)
def test_extreme_numbers_one_line(capsys, command, args, message):
    extra = ["--out", "/proc/contactvib_x"] if command == "simulate" else []
    line = _one_line_error(capsys, [command, *args, *extra])
    assert line.startswith("contactvib: error: " + message), line


@pytest.mark.parametrize("command", ["perturbation", "hbm", "continue"])
@pytest.mark.parametrize("args, message", [
    (["--pa", "1e308"], "--pa (P_a/Q) = 1e+308: must be <= 1000"),
    (["--fe", "1e308"], "--fe (f_e) = 1e+308: must lie in"),
    (["--fe", "5e-324"], "--fe (f_e) = 4.94066e-324: must lie in"),
])
def test_extreme_operating_point_other_commands(capsys, command, args, message):
    if command == "hbm" and args[0] == "--fe":
        args, message = ["--fmax", args[1]], message.replace("--fe", "--fmax")
        if args[1] == "5e-324":
            args, message = ["--fmin", "5e-324"], "--fmin (f_e) = 4.94066e-324: must lie in"
    if command == "continue" and args[0] == "--fe":
        args, message = ["--from-fe", args[1]], message.replace("--fe", "--from-fe")
    line = _one_line_error(capsys, [command, *args, "--out", "/proc/contactvib_x"])
    assert line.startswith("contactvib: error: " + message), line


@pytest.mark.parametrize("args, message", [
    (["--from-state", "1e308", "0"], "--from-state (y) = 1e+308: must be in [-225358, 225358] um"),
    (["--from-state", "0", "1e308"], "--from-state (ydot) = 1e+308: must be in"),
    (["--from-state", "-1e7", "0"], "--from-state (y) = -1e+7: must be in"),
])
def test_extreme_initial_state(capsys, args, message):
    line = _one_line_error(capsys, ["simulate", *args, "--out", "/proc/contactvib_x"])
    assert line.startswith("contactvib: error: " + message), line


@pytest.mark.parametrize("args, message", [
    (["resonance", "--fmax", "1e8", "--df", "1e6"], "--fmax (f_e) = 1e+8: must lie in"),
    (["bifurcations", "--fmax", "1e8"], "--fmax (f_e) = 1e+8: must lie in"),
    (["continue", "--fmin", "1e-300"], "--fmin (f_e) = 1e-300: must lie in [0.0001 f_n0, 1000 f_n0]"),
    (["evolution", "--pa-max", "1e308"], "--pa-max (P_a/Q) = 1e+308: must be <= 1000"),
    (["resonance", "--pa", "0.5", "1e308"], "--pa (P_a/Q) = 1e+308: must be <= 1000"),
])
def test_extreme_ranges_of_sweeps_and_continuation(capsys, args, message):
    line = _one_line_error(capsys, [*args, "--out", "/proc/contactvib_x"])
    assert line.startswith("contactvib: error: " + message), line


# ------------------------------------------------------------------ memory

@pytest.mark.timing
@pytest.mark.parametrize("args, message", [
    (["attractors", "--starts", "1e9"], "--starts (n_starts) = 1e+9: must be <= "),
    (["attractors", "--max-periods", "1e9"], "--max-periods (max_periods) = 1e+9: must be <= "),
    (["simulate", "--starts", "1e9", "--out", "/proc/contactvib_x"], "--starts (n_starts) = 1e+9: must be <= "),
    (["simulate", "--max-periods", "1e9", "--out", "/proc/contactvib_x"],
     "--max-periods (max_periods) = 1e+9: must be <= "),
    (["simulate", "--from-state", "0", "0", "--periods", "100000", "--out", "/proc/contactvib_x"],
     "--periods (n_periods) = 100000: must be <= "),
    (["resonance", "--starts", "1e9", "--out", "/proc/contactvib_x"],
     "--starts (n_starts) = 1e+9: must be <= 524288"),
    (["paper", "--starts", "1e9", "--out", "/proc/contactvib_x"],
     "--starts (n_starts) = 1e+9: must be <= 524288"),
])
def test_memory_refused_before_allocating(capsys, args, message):
    t0 = time.perf_counter()
    line = _one_line_error(capsys, args)
    assert time.perf_counter() - t0 < 5.0
    assert line.startswith("contactvib: error: " + message), line
    assert "GB of memory" in line


# ------------------------------------------------------------------ the library

@pytest.mark.parametrize("kw, symbol", [
    ({"m2": 1e308}, "m2"), ({"l": 1e308}, "l"), ({"c_n": 1e300}, "y0"), ({"c_n": 5e-324}, "y0"),
    ({"M": 1e308}, "Q"), ({"S": 1e-300}, "y0"), ({"g": 1e308}, "Q"),
])
def test_model_refuses_overflowing_parameters(kw, symbol):
    with pytest.raises(ParameterError) as e:
        ContactModel(**kw)
    assert e.value.symbol == symbol


def test_lower_bounds_keep_their_messages():
    with pytest.raises(ParameterError, match=r"m2 = 0.5: must be >= 1$"):
        ContactModel(m2=0.5)
    with pytest.raises(ParameterError, match=r"P_a/Q = -1: must be >= 0"):
        Excitation(ContactModel(), -1.0, 360.0)
    with pytest.raises(ParameterError, match=r"P_a/Q = 0: must be > 0"):
        check_pa_level(0.0)


@pytest.mark.parametrize("pa, fe, symbol", [
    (1e308, 360.0, "P_a/Q"), (PA_MAX * 1.01, 360.0, "P_a/Q"), (0.65, 1e308, "f_e"),
    (0.65, 5e-324, "f_e"), (0.65, 1e-3, "f_e"),
])
def test_excitation_refuses_extremes(pa, fe, symbol):
    with pytest.raises(ParameterError) as e:
        Excitation(ContactModel(), pa, fe)
    assert e.value.symbol == symbol


def test_excitation_range_ends_are_accepted():
    m = ContactModel()
    lo, hi = R_RANGE
    assert Excitation(m, PA_MAX, lo * m.f_n0).pa_over_q == PA_MAX
    Excitation(m, 0.65, hi * m.f_n0)
    with pytest.raises(ParameterError) as e:
        Excitation.from_newtons(m, 1e308, 360.0)
    assert e.value.symbol == "P_a"
    with pytest.raises(ParameterError):
        check_pa_level(1e308)


def test_library_search_and_simulation_refuse_extremes():
    m = ContactModel()
    exc = m.excitation(0.65, 360.0)
    for kw, symbol in [({"n_starts": 10**9}, "n_starts"), ({"max_periods": 10**9}, "max_periods")]:
        with pytest.raises(ParameterError) as e:
            find_attractors(exc, **kw)
        assert e.value.symbol == symbol and "GB of memory" in e.value.allowed
    with pytest.raises(ParameterError) as e:
        simulate(exc, y_um=1e308, ydot_mm_s=0.0)
    assert e.value.symbol == "y"
    with pytest.raises(ParameterError) as e:
        simulate(exc, y_um=0.0, ydot_mm_s=-1e308)
    assert e.value.symbol == "ydot"
    with pytest.raises(ParameterError) as e:
        simulate(exc, y_um=0.0, ydot_mm_s=0.0, n_periods=100000)
    assert e.value.symbol == "n_periods"
    # the largest values named in the messages are accepted by the checks
    n = int(str(e.value.allowed).split("<= ")[1].split(" ")[0])
    assert check_start(m, 0.0, 0.0, n)[2] == n
    assert check_search(512, 0, 8, 400) == (512, 0, 8, 400)
    assert MEMORY_MAX == 2 * 1024**3
