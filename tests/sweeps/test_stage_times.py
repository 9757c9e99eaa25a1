"""The stage timer of the sweep: exclusive times, per level, off unless recording."""

from __future__ import annotations

import itertools

import pytest

from contactvib.sweeps import stage_times
from contactvib.sweeps.stage_times import for_level, recording, stage


@pytest.fixture
def clock(monkeypatch):
    """A fake clock: every reading advances wall time by 1 s and CPU time by 0.5 s."""
    wall = itertools.count(0.0, 1.0)
    cpu = itertools.count(0.0, 0.5)
    monkeypatch.setattr(stage_times.time, "perf_counter", lambda: next(wall))
    monkeypatch.setattr(stage_times.time, "process_time", lambda: next(cpu))


def test_nested_stages_are_exclusive_and_per_level(clock):
    with recording() as times:
        with for_level(0.65):
            with stage("outer"):          # readings: enter 0, child enter 1, child exit 2, exit 3
                with stage("inner"):
                    pass
        with stage("write"):              # readings 4, 5
            pass
    assert times[(0.65, "outer")] == {"wall_s": 2.0, "cpu_s": 1.0, "calls": 1}
    assert times[(0.65, "inner")] == {"wall_s": 1.0, "cpu_s": 0.5, "calls": 1}
    assert times[(None, "write")] == {"wall_s": 1.0, "cpu_s": 0.5, "calls": 1}


def test_nothing_is_recorded_outside_recording(clock):
    with stage("alone"):
        pass
    with recording() as times:
        pass
    assert times == {}


def test_a_failing_stage_is_still_charged(clock):
    with recording() as times:
        with pytest.raises(ValueError):
            with stage("fails"):
                raise ValueError("boom")
    assert times[(None, "fails")]["calls"] == 1
