"""Issue 13, classes 1 and 2: no spurious attractors, no hangs on legal input.

A start that finds no period is a non-periodic attractor only when its strobe cloud is
recurrent and its Lyapunov exponent is not negative; otherwise it is counted as unsettled. The
references are independent: a 20,000-period integration (the issue's test), maps whose
Lyapunov exponent and recurrence are known (Hénon, an irrational rotation, a drift), the
closed-form free flight, and the linear decay time.
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib.cli.main import main
from contactvib.model import ParameterError
from contactvib.steady.attractors import UnsettledWarning
from contactvib.steady.orbits import describe_orbit
from contactvib.steady.transients import (
    MIN_TRANSIENT_PERIODS,
    WINDOW,
    WORK_MAX_STEPS,
    check_work,
    cloud_verdict,
    transient_periods,
)

MODEL = ContactModel()


def _signature(result):
    """What a search reports, to compare searches: (period, minima, A_pp rounded) per attractor."""
    return sorted((a.period or 0, a.minima_per_period or 0, round(a.app_um, 4)) for a in result)


def _quiet_search(exc, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsettledWarning)
        return find_attractors(exc, **kw)


# --- the operating points against a 20,000-period integration -----------------------

@pytest.mark.parametrize("fe", [3000.0, 10000.0])
def test_default_search_reports_only_what_20000_periods_confirm(fe):
    """3000 Hz: period 3 and period 2 only (3 spurious 'non-periodic' groups before);
    10000 Hz: the period-1 orbit over the whole box (22 spurious groups and the real one missed
    before, with a fixed 400-period limit)."""
    exc = MODEL.excitation(0.65, fe)
    long = find_attractors(exc, max_periods=20000)
    assert long.n_unsettled == 0 and long.n_failed == 0
    assert all(a.period is not None for a in long)
    default = _quiet_search(exc)
    assert _signature(default) == _signature(long)
    assert all(a.kind == "periodic" for a in default)
    # basin shares: the long search's, less what the default leaves unsettled (tolerance 1 %)
    for a, b in zip(sorted(default, key=lambda a: a.app_um), sorted(long, key=lambda a: a.app_um)):
        assert b.basin_fraction - default.unsettled_fraction - 0.01 <= a.basin_fraction <= b.basin_fraction + 0.01
    if fe == 10000.0:
        assert len(default) == 1 and default[0].period == 1
        assert default[0].basin_fraction == pytest.approx(1.0)
        assert default.settings["max_periods"] == 1361  # the damping-derived limit (README)


def test_too_short_a_limit_reports_unsettled_not_attractors():
    """64 box starts and the ballistic seeds (every start behaves alike here: 512 add only time)."""
    exc = MODEL.excitation(0.65, 10000.0)
    with pytest.warns(UnsettledWarning, match=r"did not settle within 400 periods.*--max-periods"):
        res = find_attractors(exc, n_starts=64, max_periods=400)
    assert len(res) == 0
    assert res.n_unsettled == res.n_box + res.n_seeds
    assert res.unsettled_fraction == 1.0
    assert res.to_dict()["n_unsettled"] == res.n_unsettled
    # every start is still spiralling into the period-1 focus (|mu| = 0.983 per period)
    assert res.to_dict()["unsettled_reasons"] == {"still converging": res.n_unsettled}


def test_cli_exits_nonzero_when_nothing_settles(capsys):
    rc = main(["attractors", "--pa", "0.65", "--fe", "10000", "--max-periods", "400", "--starts", "64"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 1
    assert [e for e in err if e.startswith("contactvib: error:")] == [
        "contactvib: error: no attractor: none of the 88 starts settled within 400 periods "
        "(88 unsettled, 0 failed); raise --max-periods"]  # 64 box starts + 24 ballistic seeds
    assert all(e.startswith("contactvib: ") for e in err)


def test_chaotic_attractor_is_kept_and_confirmed():
    """0.65 Q, 232 Hz: the chaotic piece of the paper's dataset (λ ≈ 0.14 there) is found,
    classified chaotic, and stays on its cloud over 2,000 more periods."""
    exc = MODEL.excitation(0.65, 232.0)
    res = _quiet_search(exc)
    chaos = [a for a in res if a.period is None]
    assert len(chaos) == 1
    a = chaos[0]
    assert a.kind == "chaotic" and a.lyapunov_per_period > 0.05
    assert 0.02 < a.basin_fraction < 0.10
    from contactvib._kernels.describe import lyapunov_strobe

    lam = lyapunov_strobe(a.state.copy(), exc.kernel_parameters(), 1e-10, 2000)
    assert lam > 0.05  # an independent, 30× longer estimate at a tighter tolerance
    d = a.to_dict()
    assert d["kind"] == "chaotic" and d["lyapunov_per_period"] == pytest.approx(a.lyapunov_per_period)


# --- the verdict on model clouds ------------------------------------------------------------

def _henon(n, burn=1000):
    x, y = 0.1, 0.1
    pts = []
    for i in range(burn + n):
        x, y = 1 - 1.4 * x * x + y, 0.3 * x
        if i >= burn:
            pts.append((x, y))
    return np.array(pts)


def test_cloud_verdict_on_maps_with_known_answers():
    n = 2 * WINDOW
    assert cloud_verdict(_henon(n), 0.42) == (True, "chaotic")  # Hénon: λ = 0.42
    th = 2 * np.pi * (np.sqrt(5) - 1) / 2 * np.arange(n)  # irrational rotation: a torus, λ = 0
    circle = np.column_stack([np.cos(th), np.sin(th)])
    assert cloud_verdict(circle, 0.0) == (True, "quasi-periodic")
    drift = np.column_stack([np.linspace(0, 1, n), np.zeros(n)])  # a slow transient
    assert cloud_verdict(drift, 0.0) == (False, "strobe cloud still drifting")
    two = np.tile([[0.0, 0.0], [1.0, 1.0]], (WINDOW, 1))  # a period-2 orbit past kmax
    assert cloud_verdict(two, -0.1) == (False, "still converging")
    r = 0.99 ** np.arange(n)  # a spiral into a focus, |μ| = 0.99
    assert cloud_verdict(circle * r[:, None], math.log(0.99))[0] is False
    assert cloud_verdict(circle[:WINDOW], 0.0) == (False, "too few strobe points")
    bad = circle.copy()
    bad[3] = np.nan
    assert cloud_verdict(bad, 0.0)[0] is False
    assert cloud_verdict(circle, math.nan)[0] is False


# --- transient length and work ----------------------------------------------------------------

def test_transient_periods_is_twice_the_decay_time_of_the_orbit():
    """Independent reference: the 10 kHz orbit's own Floquet multiplier (shooting's monodromy)
    gives the periods a start 9.5 y0 away needs to come within 1e-4, ln(9.5/1e-4)/(−ln|μ|max);
    the limit from ζ and r (no orbit computed) is twice that, within 5 %."""
    exc = MODEL.excitation(0.65, 10000.0)
    orbit = _quiet_search(exc, n_starts=16, seeds=False)[0]
    needed = math.log(9.5 / 1e-4) / -math.log(orbit.floquet_abs_max)
    assert transient_periods(exc, 1e-4, 9.5) / needed == pytest.approx(2.0, rel=0.05)
    assert transient_periods(MODEL.excitation(0.65, 360.0), 1e-4, 9.5) == MIN_TRANSIENT_PERIODS
    undamped = MODEL.replace(h_n=0.0)
    assert transient_periods(undamped.excitation(0.65, 360.0), 1e-4, 9.5) == MIN_TRANSIENT_PERIODS


def test_work_beyond_reach_is_refused_naming_f_n0():
    stiff = ContactModel(m2=1.0)  # f_n0 = 2.2 MHz with the paper's c_n
    with pytest.raises(ParameterError, match=r"f_n0 = 2\.21198e\+06 Hz") as e:
        find_attractors(stiff.excitation(0.65, 360.0))
    assert e.value.symbol == "f_e"
    exc = MODEL.excitation(0.65, 360.0)
    assert check_work(exc, 536, 400) < WORK_MAX_STEPS
    with pytest.raises(ParameterError, match="--periods"):
        check_work(exc, 1, int(WORK_MAX_STEPS), "the periods (n_periods, --periods)")


@pytest.mark.timing
def test_cli_refuses_unreachable_work_at_once(capsys):
    t0 = time.perf_counter()
    rc = main(["attractors", "--set", "m2=1"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and time.perf_counter() - t0 < 5.0
    assert len(err) == 1 and err[0].startswith("contactvib: error: --set m2 = 1: gives f_n0 = 2.21198e+06 Hz")
    assert "--fe (f_e) = 360 Hz: needs 1.8e+16" in err[0] and "--starts" in err[0] and "needs m2 >= 1.466" in err[0]


#: A search that is long by construction: at 3000 Hz the attractors have periods 2 and 3 (and a
#: torus), so with --kmax 1 no start can stop early: all 64 run the whole 2,000,000-period limit
#: (about 3e9 integration steps, minutes).
LONG_SEARCH = ["attractors", "--pa", "0.65", "--fe", "3000", "--kmax", "1", "--max-periods", "2000000",
               "--starts", "64", "--no-seeds"]


def _sigint_free_child():
    """The child's SIGINT at its default (a shell's background job, or a CI runner, may have
    it ignored, and Python would keep ignoring it)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _first_line(p, timeout: float) -> str:
    """The first line of ``p``'s stdout, or fail after ``timeout`` [s] (a cold kernel cache
    takes about a minute)."""
    import select

    ready, _, _ = select.select([p.stdout], [], [], timeout)
    assert ready, "the search did not start"
    return p.stdout.readline()


def _cpu_seconds(pid: int) -> float:
    """CPU seconds (user + system) the process ``pid`` has used so far (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


@pytest.mark.timing
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads the child's CPU time in /proc")
@pytest.mark.parametrize("into_search", [0.0, 2.0])
def test_sigint_interrupts_a_long_search_within_a_second(into_search):
    """SIGINT when the search starts (its header line), and once the search's kernels have
    worked ``into_search`` CPU seconds after it (an event, whatever the machine's speed), ends
    the run within about a second, with one line and exit 130."""
    p = subprocess.Popen([sys.executable, "-m", "contactvib", *LONG_SEARCH], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, preexec_fn=_sigint_free_child)
    try:
        header = _first_line(p, 300.0)
        assert header.startswith("P_a = 0.65 Q") and "64 box starts + 0 seeds" in header
        worked = _cpu_seconds(p.pid) + into_search
        deadline = time.monotonic() + 120
        while _cpu_seconds(p.pid) < worked:
            assert p.poll() is None and time.monotonic() < deadline, "the search ended or stalled"
            time.sleep(0.05)
        assert p.poll() is None
        t0 = time.perf_counter()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=30)
        waited = time.perf_counter() - t0
    finally:
        if p.poll() is None:
            p.kill()
            p.communicate()
    assert p.returncode == 130
    # the search is long: its progress bar (once drawn) is cleared before the line (text mode
    # reads the bar's carriage returns as line ends)
    lines = err.splitlines()
    assert lines[-1] == "contactvib: interrupted" and err.endswith("\n")
    assert all("attractor search, at most" in line or not line.strip() for line in lines[:-1]), err
    assert out == ""  # no table
    assert waited < 1.5


def test_sigint_in_the_nonperiodic_verdict_ends_the_run(monkeypatch, capsys):
    """SIGINT while the chaotic starts' Lyapunov spectra are computed (after the starts'
    kernel has returned) is not lost: one line, exit 130, no table."""
    import contactvib.steady.attractors as search

    calls = []

    def verdict(*args):
        calls.append(1)
        signal.raise_signal(signal.SIGINT)
        return real(*args)

    real = search.search_verdict
    monkeypatch.setattr(search, "search_verdict", verdict)
    rc = main(["attractors", "--pa", "0.65", "--fe", "232", "--starts", "64", "--no-seeds"])
    out, err = capsys.readouterr()
    assert calls == [1]
    assert rc == 130 and err == "contactvib: interrupted\n"
    assert "period" not in out  # the header, not the table


def test_sigint_outside_the_computation_is_one_line(monkeypatch, capsys):
    """Ctrl-C while the options are read (outside the search) gives the same line, without the
    empty line click prints for an Abort."""
    import contactvib.cli.steady as steady

    def interrupted(_settings):
        raise KeyboardInterrupt

    monkeypatch.setattr(steady, "parse_model", interrupted)
    assert main(["attractors"]) == 130
    assert capsys.readouterr().err == "contactvib: interrupted\n"


def test_sigint_while_the_commands_load_is_one_line():
    """Ctrl-C while the console script imports the commands (``import contactvib`` before it is
    light): the same line and exit 130, no traceback."""
    code = ("import sys\n"
            "class Interrupt:\n"
            "    def find_spec(self, name, path=None, target=None):\n"
            "        if name == 'contactvib.cli.main':\n"
            "            raise KeyboardInterrupt\n"
            "sys.meta_path.insert(0, Interrupt())\n"
            "from contactvib.__main__ import main\n"
            "sys.exit(main(['attractors']))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert (r.returncode, r.stderr, r.stdout) == (130, "contactvib: interrupted\n", "")


# --- undamped models and self-consistent rows -------------------------------------------------

def test_undamped_model_is_refused_for_attractors_but_simulates(capsys, tmp_path):
    undamped = MODEL.replace(h_n=0.0)
    with pytest.raises(ParameterError, match="conservative") as e:
        find_attractors(undamped.excitation(0.65, 360.0))
    assert e.value.symbol == "h_n"
    for argv in (["attractors", "--set", "h_n=0"],
                 ["resonance", "--set", "h_n=0", "--pa", "0.5", "--out", str(tmp_path / "r")]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--set h_n" in err[0] and "simulate works" in err[0]
    assert main(["simulate", "--set", "h_n=0", "--from-state", "0.3", "0", "--periods", "3",
                 "--out", str(tmp_path / "s")]) == 0


def test_rows_never_contradict_themselves_even_far_from_rest():
    """--pa 50 used to give app_um 0, loses_contact false with contact_loss_fraction 0.9996:
    a record in free flight for longer than its span had its range from one extremum only."""
    exc = MODEL.excitation(50.0, 360.0)
    res = _quiet_search(exc, n_starts=128)
    for a in res:
        assert a.app_um == pytest.approx(a.ymax_um - a.ymin_um, rel=1e-12, abs=1e-12)
        assert a.loses_contact == (a.ymin_um < 0) == (a.contact_loss_fraction > 0)
    # the closed-form flight: x'' = 1/m2 in flight, so from x0 < 0 going up (x' < 0) the apex is
    # x0 − m2 x'0²/2 (at τ = −m2 x'0, inside the span), and the top of the range is the end
    # point, below x0: the record is a flight longer than its span
    x0, v0 = -2.0e6, -200.0
    rest = MODEL.excitation(0.0, 360.0)  # no harmonic force: gravity alone in flight
    span = 32 * rest.tau_period
    a = describe_orbit(rest, np.array([x0, v0]), None)
    m2 = MODEL.m2
    apex = x0 - m2 * v0 ** 2 / 2
    end = x0 + v0 * span + span ** 2 / (2 * m2)
    y0 = MODEL.units.y_um
    assert a.ymin_um == pytest.approx(apex * y0, rel=1e-9)
    assert -m2 * v0 < span and end > x0
    assert a.ymax_um == pytest.approx(end * y0, rel=1e-9)
    assert a.loses_contact and a.contact_loss_fraction == pytest.approx(1.0)
