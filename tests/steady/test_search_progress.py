"""A long attractor search shows its progress: a legal model whose search takes minutes
(``--set m2=1.5``: f_n0 ≈ 16.5 kHz, ζ ≈ 1e-5) draws a bar on stderr with the starts done and the
time left, a short search draws none, the refusal states its threshold as a time, and the
chunked search of a long estimate finds what the one-call search finds."""

import os
import select
import signal
import subprocess
import sys
import time

import pytest

from contactvib import ContactModel, find_attractors
from contactvib.steady import attractors as search
from contactvib.steady.transients import duration_text


def _stderr_until(p, text: str, timeout: float) -> str:
    """``p``'s stderr read until ``text`` appears (or fail after ``timeout`` s)."""
    seen, end = "", time.monotonic() + timeout
    fd = p.stderr.fileno()
    while text not in seen:
        left = end - time.monotonic()
        assert left > 0 and p.poll() is None, f"no {text!r} on stderr: {seen!r}"
        if select.select([fd], [], [], left)[0]:
            seen += os.read(fd, 4096).decode(errors="replace")
    return seen


def test_a_long_search_draws_a_progress_bar_on_stderr():
    p = subprocess.Popen([sys.executable, "-m", "contactvib", "attractors", "--set", "m2=1.5"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        err = _stderr_until(p, "start", 300.0)  # the bar's unit; a cold kernel cache takes ~1 min
    finally:
        p.send_signal(signal.SIGKILL)
        p.communicate()
    assert "attractor search, at most " in err and " min" in err and "0/536" in err


def test_a_short_search_draws_none():
    r = subprocess.run([sys.executable, "-m", "contactvib", "attractors", "--pa", "0.65", "--fe", "360",
                        "--starts", "16"], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0 and r.stderr == "" and "A_pp" in r.stdout


def test_the_refusal_states_the_threshold_in_time(capsys):
    from contactvib.cli.main import main

    assert main(["attractors", "--set", "m2=1"]) == 2
    err = capsys.readouterr().err
    assert "years here; at most 1e+10 steps (about " in err and " min) are allowed" in err


def test_duration_text():
    assert [duration_text(s) for s in (0.2, 40, 119, 490, 9000, 3e5, 1e9)] == \
        ["1 s", "40 s", "119 s", "8.2 min", "2.5 h", "3.5 days", "32 years"]


@pytest.mark.parametrize("long", [False, True])
def test_a_chunked_search_finds_what_one_call_finds(monkeypatch, long):
    """Above LONG_SEARCH_S the starts run in chunks, each reported: the same attractors."""
    exc = ContactModel().excitation(0.65, 360.0)
    plain = find_attractors(exc, n_starts=64)
    calls = []
    monkeypatch.setattr(search, "LONG_SEARCH_S", 0.0 if long else 1e9)
    chunked = find_attractors(exc, n_starts=64, progress=lambda d, t: calls.append((d, t)))
    assert chunked.to_json() == plain.to_json()
    n = 64 + chunked.n_seeds
    assert calls[0] == (0, n) and calls[-1] == (n, n)
    assert (len(calls) > 3) == long and [d for d, _ in calls] == sorted(d for d, _ in calls)
