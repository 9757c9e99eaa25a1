"""The resonance graph computed in the background (no dataset), in headless Chromium: the button
shows the sweep's progress, a new P_a stops the run, a bad P_a is the resonance command's
message, the finished graph is drawn as with a dataset, and a click on it moves f_e (the table is
then the CLI's search there). Screenshots in a tmp folder (docs/explore_level_graph.png: the
same page with the default grid, 30-2000 Hz, 1 Hz)."""

from __future__ import annotations

import re
import time

import pytest
from test_explore_browser import CHROMIUM, _cli_json, _same, _set_field, _table, _wait_done, browser, served  # noqa: F401
from test_explore_dataset_browser import click_graph

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]

GRAPH = "() => Bokeh.index.all_views().some(v => v.model.title && v.model.title.text && " \
        "v.model.title.text.startsWith('Resonance graph'))"


@pytest.fixture(scope="module")
def graph_server():
    with served("--graph-fmin", "250", "--graph-fmax", "450", "--graph-df", "1") as url:
        yield url


def test_background_graph_progress_stop_and_click(graph_server, browser, tmp_path):  # noqa: F811
    page = browser.new_page(viewport={"width": 1150, "height": 1500})
    page.goto(graph_server)
    _wait_done(page)
    button = page.locator(".graph-compute button")
    assert button.is_visible() and not page.evaluate(GRAPH)

    button.click()  # a new P_a stops the run: no graph, the button back
    busy = page.locator(".graph-status .graph-busy")
    busy.wait_for(timeout=30_000)
    assert re.fullmatch(r"P_a = 0\.65 Q: \d+/201 f_e points, \d+ s", busy.inner_text())
    _set_field(page, "pa", "0.7")
    busy.wait_for(state="detached", timeout=30_000)
    page.wait_for_function("() => location.search.includes('pa=0.7')", timeout=30_000)
    page.locator(".status .done").wait_for(timeout=120_000)
    assert page.locator(".graph-status span, .graph-status b").count() == 0  # no progress, no message
    assert not page.locator(".graph-progress progress").is_visible()
    assert button.is_visible() and button.is_enabled() and not page.evaluate(GRAPH)

    _set_field(page, "pa", "-1")  # a bad P_a: the resonance command's message, no run
    page.locator(".message .error").wait_for(timeout=30_000)
    button.click()
    error = page.locator(".graph-status .graph-error")
    error.wait_for(timeout=30_000)
    assert error.inner_text() == "contactvib: error: --pa (P_a/Q) = -1: must be > 0 (multiple of Q = M g)"
    assert not page.locator(".graph-progress progress").is_visible()

    _set_field(page, "pa", "0.65")
    page.locator(".status .done").wait_for(timeout=120_000)
    assert error.count() == 0
    button.click()
    busy.wait_for(timeout=30_000)
    assert page.locator(".graph-progress progress").is_visible()  # the progress bar
    seen = {busy.inner_text()}
    done = page.locator(".graph-status .graph-done")
    deadline = time.monotonic() + 120
    while not done.count():
        assert time.monotonic() < deadline, "the background graph did not finish within 120 s"
        seen.update(busy.all_text_contents())  # no wait: the run may end between a count and a read
        page.wait_for_timeout(100)
    assert all(re.fullmatch(r"P_a = 0\.65 Q: \d+/201 f_e points, \d+ s", t) for t in seen if t)
    assert done.inner_text().startswith("201/201 f_e points, ")
    assert page.locator(".graph-status code").inner_text() == \
        "contactvib resonance --pa 0.65 --fmin 250 --fmax 450 --df 1"
    page.wait_for_function(GRAPH, timeout=30_000)
    assert not button.is_visible()
    page.screenshot(path=str(tmp_path / "explore_level_graph_360.png"), full_page=True)

    click_graph(page, 371.3, 0.2, "371")  # between grid points 371 and 372 Hz, near the 1/4
    page.wait_for_function(GRAPH, timeout=30_000)  # the graph stays for a new f_e
    page.screenshot(path=str(tmp_path / "explore_level_graph_371.png"), full_page=True)
    print("screenshots in", tmp_path)
