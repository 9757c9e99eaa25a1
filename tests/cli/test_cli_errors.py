"""Every command-line input error, in one place: one stderr line naming the option, the library's
symbol, the value and the allowed range (the library's own check and words), exit status 2, no
traceback, nothing written or computed."""
import subprocess
import sys

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.model import (
    KMAX_SEARCH_MAX,
    ContactModel,
    Excitation,
    ParameterError,
    check_frequency_range,
    check_int,
    check_range,
)

CMD = [sys.executable, "-m", "contactvib"]


# ------------------------------------------------------------------ model and operating point

#: attractors options and the start of their one error line
BAD_INPUT = [
    (["--fe", "-5"], "contactvib: error: --fe (f_e) = -5: must be > 0 Hz"),
    (["--fe", "0"], "contactvib: error: --fe (f_e) = 0: must be > 0 Hz"),
    (["--pa", "nan"], "contactvib: error: --pa (P_a/Q) = nan: must be a finite number"),
    (["--fe", "inf"], "contactvib: error: --fe (f_e) = inf: must be a finite number"),
    (["--set", "M=-1"], "contactvib: error: --set M (M) = -1: must be > 0 kg"),
    (["--set", "S=0"], "contactvib: error: --set S (S) = 0: must be > 0 m^2"),
    (["--set", "m2=0.5"], "contactvib: error: --set m2 (m2) = 0.5: must be >= 1"),
    (["--set", "l=-1"], "contactvib: error: --set l (l) = -1: must be >= 0"),
    (["--set", "mass=1"], "contactvib: error: --set mass (mass) = 1: unknown parameter"),
    (["--pa-newton", "-2"], "contactvib: error: --pa-newton (P_a) = -2: must be >= 0 N"),
    (["--set", "l=0"], "contactvib: error: --set l=0 (h_n) = 3.5e+11: gives the damping ratio "
                       "zeta = 8.02e+04 with l = 0: must give zeta <= 100"),
]


@pytest.mark.parametrize("args, message", BAD_INPUT)
def test_bad_input_one_line(args, message):
    """Bad input: one stderr line naming option, symbol, value and range; exit 2; no traceback."""
    r = subprocess.run(CMD + ["attractors", *args], capture_output=True, text=True, timeout=60)
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith(message)


#: attractors options whose refusal the --set values cause: the line's start and a part of it
MODEL_ERRORS = [
    # f_e is ordinary; the --set values move f_n0 out of its reach: they are named, with their range
    (["--set", "m2=1", "--pa", "0.65", "--fe", "360"],
     "contactvib: error: --set m2 = 1: gives f_n0 = 2.21198e+06 Hz", "this f_e needs m2 >= 1.466"),
    (["--set", "c_n=1e25"], "contactvib: error: --set c_n = 1e+25: gives f_n0 = 181112 Hz",
     "this f_e needs c_n <= 2.582e+21"),
    (["--set", "c_n=1e-10", "--set", "h_n=1e-6", "--pa", "0.65", "--fe", "360"],
     "contactvib: error: --set c_n = 1e-10 --set h_n = 1e-6: gives f_n0 = 0.000322069 Hz",
     "this f_e needs c_n >= 156.1"),
    (["--set", "c_n=1e-10", "--pa", "0.65", "--fe", "360"],
     "contactvib: error: --set c_n=1e-10 (h_n) = 3.5e+11: gives the damping ratio zeta = 1.77e+18", "h_n <="),
    # little damping: the automatic transient limit makes the search's work out of reach
    (["--set", "h_n=1e3"], "contactvib: error: --set h_n = 1000: gives f_n0 = 1485.02 Hz, zeta = 5.16e-11",
     "this f_e needs h_n >= 9.473e+07"),
    (["--set", "l=10"], "contactvib: error: --set l = 10: gives f_n0 = 1485.02 Hz, zeta = 2.71e-62",
     "this f_e needs l <= 1.537"),
    # f_e is out of reach of the paper's f_n0 as well: --fe is named
    (["--set", "M=2", "--fe", "1e-9"], "contactvib: error: --fe (f_e) = 1e-9: must lie in", "f_n0 = 845.941 Hz"),
]


@pytest.mark.parametrize("args, start, needle", MODEL_ERRORS)
def test_model_parameter_errors_name_the_parameter(args, start, needle, capsys):
    """An error a --set value causes names that --set (not --fe), one line, exit 2."""
    assert main(["attractors", *args]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(start) and needle in lines[0], err


@pytest.mark.parametrize("command", [["basins"], ["resonance", "--pa", "0.5"], ["continue"], ["bifurcations"]])
def test_model_parameter_errors_name_the_parameter_in_every_command(command, tmp_path, capsys):
    """--set m2=1 (f_n0 = 2.2 MHz) names m2 wherever f_e or the frequency range is refused
    for it (the work of a basin map, --fmin = 30 Hz below 1e-4 f_n0)."""
    out = tmp_path / "out"
    assert main([*command, "--set", "m2=1", "--out", str(out)]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "contactvib: error: --set m2 = 1: gives f_n0 = 2.21198e+06 Hz"), lines
    assert "this f_e needs m2 >= " in lines[0]
    assert not out.exists() or not any(out.iterdir())


#: the longest refusals: many --set values, a basin map's work, every frequency option
LONG_ERRORS = [
    ["attractors", "--set", "m2=1"],
    ["attractors", "--set", "c_n=1e-10", "--set", "h_n=0"],
    ["attractors", "--set", "M=3", "--set", "S=1e-3", "--set", "m2=1", "--set", "h_n=1e-3", "--set", "l=2"],
    ["attractors", "--set", "c_n=1e20", "--set", "m2=1", "--set", "h_n=1", "--set", "l=3"],
    ["basins", "--set", "M=3", "--set", "S=1e-3", "--set", "m2=1", "--set", "h_n=1e-3"],
    ["continue", "--set", "m2=1"],
    ["resonance", "--pa", "0.5", "--set", "m2=1"],
    ["attractors", "--starts", "100000000"],
    ["attractors", "--max-periods", "1000000000"],
]
#: the most an error line may hold: the option, the value, the range and the key numbers
MAX_ERROR_LINE = 400


@pytest.mark.parametrize("args", [["attractors", *a] for a, *_ in BAD_INPUT + MODEL_ERRORS] + LONG_ERRORS,
                         ids=lambda a: " ".join(a))
def test_every_error_is_one_short_line(args, tmp_path, capsys):
    """Exit 2, nothing on stdout, one stderr line of at most MAX_ERROR_LINE characters."""
    out = ["--out", str(tmp_path / "out")] if args[0] != "attractors" else []
    assert main([*args, *out]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    assert len(lines[0]) <= MAX_ERROR_LINE, f"{len(lines[0])} characters: {lines[0]}"


@pytest.mark.parametrize("args, message", [
    (["attractors", "--pa", "-1"],
     "contactvib: error: --pa (P_a/Q) = -1: must be >= 0 (multiple of Q = M g)"),
    (["attractors", "--pa", "0.5", "--pa-newton", "1"],
     "contactvib: error: --pa and --pa-newton: give one of them, not both"),
    (["attractors", "--starts", "16.7"],
     "contactvib: error: --starts (n_starts) = 16.7: must be an integer >= 1"),
    (["attractors", "--starts", "0"],
     "contactvib: error: --starts (n_starts) = 0: must be an integer >= 1"),
    (["attractors", "--kmax", "65"],
     f"contactvib: error: --kmax (kmax) = 65: must be an integer in 1..{KMAX_SEARCH_MAX}"),
    (["attractors", "--kmax", "2.5"],
     f"contactvib: error: --kmax (kmax) = 2.5: must be an integer in 1..{KMAX_SEARCH_MAX}"),
    (["attractors", "--max-periods", "10"],
     "contactvib: error: --max-periods (max_periods) = 10: must be an integer >= 32"),
    (["attractors", "--seed", "-1"], "contactvib: error: --seed (seed) = -1: must be an integer >= 0"),
    (["attractors", "--starts", "abc"], "contactvib: error: --starts (n_starts) = abc: must be a finite number"),
    (["simulate", "--from-state", "0.3", "0", "--periods", "2.5"],
     "contactvib: error: --periods (n_periods) = 2.5: must be an integer >= 1"),
    (["simulate", "--from-state", "0.3", "x"], "contactvib: error: --from-state (ydot) = x: must be a finite number"),
])
def test_steady_state_options(args, message, capsys, tmp_path):
    """Options of `attractors`/`simulate`: find_attractors' own checks, named by option."""
    assert main([*args, *(["--out", str(tmp_path / "x")] if args[0] == "simulate" else [])]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [message]
    assert not (tmp_path / "x").exists()


@pytest.mark.parametrize("args, check", [
    (["--fe", "-5"], lambda: Excitation(ContactModel(), 0.65, -5)),
    (["--pa", "-1"], lambda: Excitation(ContactModel(), -1, 360)),
    (["--pa-newton", "-2"], lambda: Excitation.from_newtons(ContactModel(), -2, 360)),
    (["--set", "m2=0.5"], lambda: ContactModel(m2=0.5)),
])
def test_cli_words_are_the_librarys(args, check, capsys):
    """The CLI adds the option name; symbol, value and range are the library's ParameterError."""
    with pytest.raises(ParameterError) as e:
        check()
    assert main(["attractors", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith(f"({e.value.symbol}) = {str(e.value).split(' = ', 1)[1]}")


# ------------------------------------------------------------------ continuation

@pytest.mark.parametrize("args, message", [
    (["continue", "--from-fe", "-5"], "contactvib: error: --from-fe (f_e) = -5: must be > 0 Hz"),
    (["continue", "--pa", "0"], "contactvib: error: --pa (P_a/Q) = 0: must be > 0"),
    (["continue", "--fmin", "500", "--fmax", "400"], "contactvib: error: --fmax (f_max) = 400: must be > --fmin"),
    (["continue", "--from-fe", "2500"], "contactvib: error: --from-fe (f_e) = 2500: must lie in"),
    (["continue", "--rtol", "1e-3"], "contactvib: error: --rtol (rtol) = 0.001: must be in"),
    (["bifurcations", "--pa", "0.5", "abc"], "contactvib: error: --pa (P_a/Q) = abc: must be a finite number"),
    (["evolution", "--order", "9"], "contactvib: error: --order (order) = 9: must be an integer in 1..8"),
    (["evolution", "--pa-min", "0.8", "--pa-max", "0.5"], "contactvib: error: --pa-max (P_a/Q) = 0.5: must be >"),
])
def test_cli_bad_input(args, message, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(message)


@pytest.mark.parametrize("args,message", [
    # the one message of an ordered pair names the upper option, as --fmax does (it named
    # --pa-min in `continue` and --pa-max in `evolution` before)
    (["continue", "--parameter", "pa", "--pa-min", "0.7", "--pa-max", "0.6"],
     "contactvib: error: --pa-max (P_a/Q) = 0.6: must be > --pa-min = 0.7"),
    (["continue", "--parameter", "pa", "--pa", "0.65", "--pa-max", "0.5"],
     "contactvib: error: --pa (P_a/Q) = 0.65: must lie in [--pa-min, --pa-max] = [0.05, 0.5]"),
    (["continue", "--parameter", "pa", "--pa-min", "-1"],
     "contactvib: error: --pa-min (P_a/Q) = -1: must be > 0"),
    (["continue", "--parameter", "pa", "--dataset", "x.nc"],
     "contactvib: error: --dataset draws over a resonance graph in f_e: not with --parameter pa"),
])
def test_cli_continue_in_pa_bad_input(args, message, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(message)


def test_continue_refuses_an_amplitude_bound_no_branch_can_leave(tmp_path, capsys):
    """--app-max below the A_pp of every start: one line naming it and the smallest A_pp, exit 2,
    nothing written."""
    out = tmp_path / "b"
    assert main(["continue", "--app-max", "0.01", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(
        "contactvib: error: --app-max (app_max_um) = 0.01: must be > 0.8534 µm, the smallest A_pp"), err
    assert not any(out.iterdir())


@pytest.mark.parametrize("args, message", [
    (["continue", "--rtol", "1e-16"], "contactvib: error: --rtol (rtol) = 1e-16: must be in [1e-15, 1e-6]"),
    (["continue", "--app-max", "-1"], "contactvib: error: --app-max (app_max_um) = -1: must be > 0 µm"),
    (["continue", "--max-points", "1"], "contactvib: error: --max-points (max_points) = 1: must be an integer >= 2"),
    (["bifurcations", "--max-points", "0"],
     "contactvib: error: --max-points (max_points) = 0: must be an integer >= 2"),
    (["continue", "--attractor", "1.5"], "contactvib: error: --attractor (attractor) = 1.5: must be an integer >= 0"),
    (["bifurcations", "--seed-fe", "500,2500"],
     "contactvib: error: --seed-fe (f_e) = 2500: must lie in [--fmin, --fmax] = [30, 2000] Hz"),
    (["evolution", "--levels", "1"], "contactvib: error: --levels (n_levels) = 1: must be an integer >= 2"),
])
def test_continuation_options(args, message, capsys):
    assert main(args) == 2
    assert capsys.readouterr().err.strip().splitlines() == [message]


def test_rtol_range_is_the_continuations(capsys):
    """--rtol accepts exactly what ContinuationSettings accepts (it was [1e-14, 1e-6] before)."""
    from contactvib import ContinuationSettings

    for r in (1e-15, 1e-6):
        ContinuationSettings(rtol=r, tol=max(100 * r, 1e-11))
    for r in (1e-16, 1e-5):
        with pytest.raises(ParameterError):
            ContinuationSettings(rtol=r)
        assert main(["continue", "--rtol", str(r)]) == 2
        assert "--rtol (rtol)" in capsys.readouterr().err


# ------------------------------------------------------------------ frequency domain

@pytest.mark.parametrize("args, message", [
    (["perturbation", "--terms", "0"], "contactvib: error: --terms (terms) = 0: must be an integer in 1..400"),
    (["perturbation", "--order", "0"], "contactvib: error: --order (terms) = 0: must be an integer in 1..400"),
    (["perturbation", "--fe", "-1"], "contactvib: error: --fe (f_e) = -1: must be > 0 Hz"),
    (["hbm", "--pa", "-1"], "contactvib: error: --pa (P_a/Q) = -1: must be >= 0 (multiple of Q = M g)"),
    (["hbm", "--harmonics", "2000"],
     "contactvib: error: --harmonics (harmonics) = 2000: must be an integer in 1..1024"),
    (["hbm", "--energy-tol", "0"], "contactvib: error: --energy-tol (energy_tol) = 0: must be > 0"),
    (["hbm", "--fmin", "0"], "contactvib: error: --fmin (f_min) = 0: must be > 0 Hz"),
])
def test_frequency_domain_options(args, message, capsys, tmp_path):
    assert main([*args, "--out", str(tmp_path / "x")]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [message]
    assert not (tmp_path / "x").exists()


# ------------------------------------------------------------------ sweeps

@pytest.mark.parametrize("args, needle", [
    (["resonance", "--df", "0"], "--df (df) = 0: must be > 0 Hz"),
    (["resonance", "--fmin", "300", "--fmax", "200"], "--fmax (f_max) = 200: must be > --fmin = 300 Hz"),
    (["resonance", "--pa", "0.5", "-0.6"], "--pa (P_a/Q) = -0.6: must be > 0"),
    (["resonance", "--workers", "0"], "--workers (workers) = 0: must be an integer in 1..256"),
    (["resonance", "--kmax", "20"], "--kmax (kmax) = 20: must be an integer in 1..16"),
    (["resonance", "--starts", "-2"], "--starts (n_starts) = -2"),
    (["resonance", "--starts", "2.5"], "--starts (n_starts) = 2.5: must be an integer >= 0"),
    (["resonance", "--multistart-per-octave", "-1"], "--multistart-per-octave"),
    (["resonance", "--multistart-per-octave", "2000"], "--multistart-per-octave (multistart_per_octave) = 2000"),
    (["resonance", "--fill-in-per-octave", "-1"], "--fill-in-per-octave (fill_in_per_octave) = -1"),
    (["resonance", "--fill-in-starts", "-3"], "--fill-in-starts (fill_in_starts) = -3"),
    (["paper", "--fill-in-starts", "0.5"], "--fill-in-starts (fill_in_starts) = 0.5: must be an integer >= 0"),
    (["resonance", "--system", "examples/two_dof_stop.toml", "--pa-newton", "0.1", "--fill-in-per-octave", "4"],
     "--system and --fill-in-per-octave"),
    (["resonance", "--fmin", "inf"], "--fmin (f_min) = inf"),
    (["resonance", "--set", "m2=0.5"], "--set m2 (m2) = 0.5"),
    (["resonance", "--pa", "0.5", "--bogus"], "--bogus"),
    (["paper", "--df", "-1"], "--df (df) = -1: must be > 0 Hz"),
    (["paper", "--df", "1e-5"], "--df (df)"),
])
def test_bad_sweep_input_is_one_line(tmp_path, capsys, args, needle):
    assert main([*args, "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("contactvib: error: ") and needle in err, err
    assert not (tmp_path / "x").exists()




@pytest.mark.parametrize("args, needle", [
    (["--pa", "0.66", "--fe", "360"], "--pa (P_a/Q) = 0.66: not in the dataset"),
    (["--pa", "0.65", "--fe", "2003"], "--fe (f_e) = 2003: no grid point within half a step"),
    (["--pa", "0.65", "--fe", "-1"], "--fe (f_e) = -1: must be > 0 Hz"),
    (["--pa", "nan", "--fe", "360"], "--pa (P_a/Q) = nan"),
])
def test_query_errors_are_one_line(small_dataset, capsys, args, needle):
    assert main(["query", str(small_dataset), *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("contactvib: error: ") and needle in err, err


def _damaged(small_dataset, path, damage):
    """A copy of the small dataset at ``path`` with ``damage(ds)`` applied (in memory)."""
    import xarray as xr

    with xr.open_dataset(small_dataset) as ds:
        ds = damage(ds.load())
    ds.to_netcdf(path)
    return path


def _set(name, i, value):
    def damage(ds):
        v = ds[name].values.copy()
        v[i] = value
        return ds.assign({name: (ds[name].dims, v)})
    return damage


@pytest.mark.parametrize("damage, where", [
    (lambda ds: ds.drop_vars("app_um"), "damaged: variable 'app_um' is missing"),
    (lambda ds: ds.drop_vars("strobe_y_um"), "damaged: variable 'strobe_y_um' is missing"),
    (_set("branch_index", 3, 99), "damaged: branch_index = 99 at point 3 (P_a = 0.65 Q, f_e = 346 Hz) "
                                  "refers outside the 2 stored branch entries"),
    (_set("extrema_start", 0, 10 ** 6), "damaged: extrema_start = 1000000, extrema_count = "),
    (_set("fe_hz", 2, np.nan), "damaged: fe_hz is nan at point 2 (P_a = 0.65 Q, f_e = nan Hz)"),
    (_set("pa_over_q", 0, np.nan), "damaged: pa_over_q is nan at point 0"),
    (_set("ymin_um", 5, np.nan), "damaged: ymin_um is nan at point 5 (P_a = 0.65 Q, f_e = 350 Hz)"),
    (_set("strobe_y_um", 4, np.inf), "damaged: strobe_y_um is inf at strobe 4"),
])
def test_query_on_a_damaged_dataset_says_where(small_dataset, tmp_path, capsys, damage, where):
    """A damaged dataset: one line naming the file and the damage, exit 2 (not a library's
    message, not an answer with nulls)."""
    path = _damaged(small_dataset, tmp_path / "damaged.nc", damage)
    assert main(["query", str(path), "--pa", "0.65", "--fe", "360", "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.startswith(f"contactvib: error: DATASET = {path}: {where}"), err
    assert err.rstrip().endswith("recompute it")


def test_query_rejects_missing_and_foreign_files(tmp_path, capsys):
    assert main(["query", str(tmp_path / "none.nc"), "--pa", "0.65", "--fe", "360"]) == 2
    assert "no such file" in capsys.readouterr().err
    bad = tmp_path / "bad.nc"
    bad.write_text("not netcdf")
    assert main(["query", str(bad), "--pa", "0.65", "--fe", "360"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "not a readable NetCDF" in err


def test_checks_used_by_the_cli_are_the_librarys():
    """The CLI's range words come from contactvib.model.checks (no copy of a range here)."""
    with pytest.raises(ParameterError, match=r"f_max = 200: must be > f_min = 300 Hz"):
        check_frequency_range(300, 200)
    with pytest.raises(ParameterError, match=r"must be an integer in 1\.\.16"):
        check_int("kmax", 20, 1, 16)
    with pytest.raises(ParameterError, match=r"must be in \[1e-15, 1e-6\]"):
        check_range("rtol", 1e-3, 1e-15, True, upper=1e-6)


def test_a_failed_computation_is_one_line_exit_1(tmp_path):
    """Harmonic balance from a linear guess at 0.3 Q, 1000 Hz (on the bent main resonance) does not
    converge: one line naming the stage, exit 1 (not a traceback; not exit 2, which is bad input)."""
    r = subprocess.run([sys.executable, "-m", "contactvib", "hbm", "--pa", "0.3", "--fmin", "1000", "--fmax", "1400",
                        "--out", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 1
    assert r.stderr.startswith("contactvib: error: harmonic-balance failed: harmonic-balance Newton did not converge")
    assert len(r.stderr.strip().splitlines()) == 1


# ------------------------------------------------------------------ section, orbit-diagram

_GRID = ["--fe-from", "810", "--fe-to", "812", "--fe-step", "1"]

#: section and orbit-diagram inputs and the start of their one error line
SECTION_BAD_INPUT = [
    (["section", "--periods", "0"], "contactvib: error: --periods (n_periods) = 0: must be an integer >= 1"),
    (["section", "--periods", "2.5"], "contactvib: error: --periods (n_periods) = 2.5: must be an integer"),
    (["section", "--out", "x.txt"], "contactvib: error: --out = x.txt: must end with .png, .svg, .pdf"),
    (["section", "--csv", "x.png"], "contactvib: error: --csv = x.png: must end with .csv"),
    (["orbit-diagram", "--fe-from", "820", "--fe-to", "810", "--fe-step", "1"],
     "contactvib: error: --fe-to (f_to) = 810: must be > --fe-from = 820 Hz"),
    (["orbit-diagram", "--fe-from", "810", "--fe-to", "820", "--fe-step", "0"],
     "contactvib: error: --fe-step (df) = 0: must be > 0 Hz"),
    (["orbit-diagram", "--fe-from", "810", "--fe-to", "820", "--fe-step", "-1"],
     "contactvib: error: --fe-step (df) = -1: must be > 0 Hz"),
    (["orbit-diagram", "--fe-from", "1", "--fe-to", "1000000", "--fe-step", "1"],
     "contactvib: error: --fe-step (df) = 1: gives 1000000 grid points from --fe-from to --fe-to; at most 5000"),
    (["orbit-diagram", "--fe-from", "810", "--fe-to", "820"], "contactvib: error: --fe-step: needed with --vary fe"),
    (["orbit-diagram", *_GRID, "--pa-from", "0.5"], "contactvib: error: --pa-from: belongs to --vary pa"),
    (["orbit-diagram", *_GRID, "--periods", "1"], "contactvib: error: --periods (n_periods) = 1: must be an integer"),
    (["orbit-diagram", *_GRID, "--search-every", "0"], "contactvib: error: --search-every (search_every) = 0"),
    (["orbit-diagram", *_GRID, "--pa", "-1"], "contactvib: error: --pa (P_a/Q) = -1: must be >= 0"),
    (["orbit-diagram", "--vary", "pa", "--pa-from", "0.5", "--pa-to", "0.6", "--pa-step", "0.1"],
     "contactvib: error: --fe: needed with --vary pa"),
    (["orbit-diagram", *_GRID, "--ylim", "1", "0"], "contactvib: error: --ylim 1 0: LO must be < HI"),
]


@pytest.mark.parametrize("args, message", SECTION_BAD_INPUT)
def test_section_and_orbit_diagram_bad_input_one_line(args, message, capsys, tmp_path, monkeypatch):
    """One stderr line naming the option and its range, exit 2, before any computation or file."""
    monkeypatch.chdir(tmp_path)
    assert main(args) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and err.startswith(message), err
    assert not any(tmp_path.iterdir())
