"""The explore page's resonance graph without a dataset, without a browser: the level swept in
the background equals the level ``contactvib resonance`` writes with the command the page shows
(read back by the dataset mode's reader), its progress is the sweep's own, it stops when told or
at its time limit, and a bad input is the resonance command's one-line message; the page's
button draws it, a new f_e keeps it, a new P_a or model drops it and stops a run under way."""

from __future__ import annotations

import asyncio
import threading
import time
from functools import partial

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.cli.explore import _graph_grid, _level_inputs
from contactvib.explore.app import Page
from contactvib.explore.dataset_view import DatasetLevels
from contactvib.explore.level_graph import LevelRun, sweep_level
from contactvib.explore.state import BadInput, Point
from contactvib.sweeps.stored import open_resonance

SMALL = ("340", "380", "2")  # the grid of the small_dataset fixture (21 frequencies)


def _run(fields=None, grid=SMALL) -> LevelRun:
    point = Point()
    point.fields.update(fields or {})
    return LevelRun(*_level_inputs(point, _graph_grid(*grid)))


def test_background_level_equals_the_resonance_command(tmp_path):
    """One level on 350–370 Hz at 2 Hz (11 frequencies): the background run and the command agree."""
    run = _run({"pa": "0.65", "h_n": "0.7"}, grid=("350", "370", "2"))
    assert run.command == "contactvib resonance --pa 0.65 --fmin 350 --fmax 370 --df 2 --set h_n=0.7"
    kind, (got, seconds) = sweep_level(run)
    assert kind == "ok" and seconds > 0
    assert 0 < run.points <= run.total == 11  # the sweep's own reports
    args = run.command.split()[1:] + ["--workers", "1", "--no-progress", "--out", str(tmp_path)]
    assert main(args) == 0
    stored = DatasetLevels(open_resonance(tmp_path)).level(0.65)
    assert got.pa_over_q == stored.pa_over_q and got.fe_hz.size > 11
    for name in ("fe_hz", "app_um", "branch", "kind", "resonance", "isolated"):
        assert np.array_equal(getattr(got, name), getattr(stored, name)), name


@pytest.mark.timing
def test_a_stopped_level_ends_at_once_and_the_time_limit_stops_it():
    run = _run(grid=("30", "2000", "1"))
    box = {}
    worker = threading.Thread(target=lambda: box.update(out=sweep_level(run)))
    worker.start()
    for _ in range(600):  # until the sweep has reported progress
        if run.points:
            break
        time.sleep(0.05)
    assert 0 < run.points < run.total
    t0 = time.perf_counter()
    run.stop()
    worker.join(10)
    assert not worker.is_alive() and time.perf_counter() - t0 < 5
    assert box["out"] == ("stopped", "stopped")
    t0 = time.perf_counter()
    assert sweep_level(_run(grid=("30", "2000", "1")), 0.5) == ("stopped", "stopped after 0.5 s")
    assert time.perf_counter() - t0 < 5
    stopped = _run()
    stopped.stop()  # stopped while queued: never starts
    assert sweep_level(stopped) == ("stopped", "stopped")


@pytest.mark.parametrize("fields, args", [
    ({"pa": "-1"}, ["--pa", "-1"]),
    ({"pa": "abc"}, ["--pa", "abc"]),
    ({"h_n": "0"}, ["--pa", "0.65", "--set", "h_n=0"]),
    ({"m2": "x"}, ["--pa", "0.65", "--set", "m2=x"]),
])
def test_bad_input_is_the_resonance_commands_message(tmp_path, capsys, fields, args):
    with pytest.raises(BadInput) as e:
        _run(fields)
    assert main(["resonance", *args, "--fmin", "340", "--fmax", "380", "--df", "2",
                 "--out", str(tmp_path)]) == 2
    assert str(e.value) == capsys.readouterr().err.strip()


@pytest.mark.parametrize("args, message", [
    (["--graph-df", "100", "--graph-fmin", "340", "--graph-fmax", "380"],
     "--graph-df (df) = 100: must be <= --graph-fmax - --graph-fmin = 40 Hz"),
    (["--graph-fmin", "0"], "--graph-fmin (f_min) = 0: must be > 0 Hz"),
    (["--graph-fmax", "20"], "--graph-fmax (f_max) = 20: must be > --graph-fmin = 30 Hz"),
    (["--graph-time-limit", "-1"], "--graph-time-limit (time_limit) = -1: must be > 0 s"),
])
def test_bad_graph_options_are_one_line_before_serving(capsys, args, message):
    assert main(["explore", *args, "--no-browser", "--port", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"contactvib: error: {message}") and len(err.strip().splitlines()) == 1


def _no_search(point):
    raise BadInput("contactvib: error: (no search in this test)")


async def _until(condition, timeout=30.0):
    """Return once ``condition()`` holds (checked every 20 ms), fail after ``timeout`` s."""
    for _ in range(int(timeout / 0.02)):
        if condition():
            return
        await asyncio.sleep(0.02)
    pytest.fail("the page did not reach the expected state")


@pytest.mark.timing
def test_page_button_draws_the_level_and_a_new_pa_or_model_stops_it():
    page = Page(Point(), (_no_search, None, None, partial(_level_inputs, grid=_graph_grid(*SMALL))))
    assert page.graph_button.visible and not page.graph[:]

    async def scenario():
        await page._graph_clicked()
        fig = page.graph[0].object
        assert fig.title.text.startswith("Resonance graph, P_a = 0.65 Q")
        assert 'class="graph-done"' in page.graph_status.object and not page.graph_button.visible
        assert page.graph_progress.value == page.graph_progress.max == 21
        page.fields["fe"].value = "372"  # a new f_e keeps the graph
        await asyncio.sleep(0.3)  # nothing to wait for: the graph must still be there after a while
        assert page.graph_level is not None and page.graph[:]
        page.fields["pa"].value = "0.7"  # a new P_a drops it
        await _until(lambda: page.graph_level is None)
        assert not page.graph[:] and page.graph_button.visible
        clicked = asyncio.ensure_future(page._graph_clicked())
        await _until(lambda: page.graph_run is not None)
        run = page.graph_run
        assert run.pa_over_q == 0.7 and not run.flag[0]
        page.fields["h_n"].value = "3e11"  # a new model stops the run under way
        await _until(lambda: page.graph_run is None)
        assert run.flag[0] == 1
        await clicked
        assert page.graph_level is None and not page.graph[:] and page.graph_status.object == ""

    asyncio.run(scenario())


def test_a_failing_sweep_is_one_line(monkeypatch):
    import contactvib.sweeps.resonance as resonance

    def broken(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr(resonance, "resonance_dataset", broken)
    assert sweep_level(_run()) == ("error", "contactvib: the sweep failed: RuntimeError: disk full")
