"""contactvib explore with a dataset, in headless Chromium: the level's resonance graph, and a
click on it moves f_e to the clicked grid frequency; the table is then the CLI's search there
(to 1e-6) and the attractor nearest the clicked A_pp is selected. Screenshot in a tmp folder
(docs/explore_dataset.png was taken the same way on the 8-level paper.nc)."""

from __future__ import annotations

import math

import pytest
from test_explore_browser import CHROMIUM, _cli_json, _same, _table, _wait_done, browser, served  # noqa: F401

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]

#: Screen position of a data point (f_e [Hz], A_pp [µm]) on the resonance graph (Bokeh's scales).
XY = """([fe, app]) => {
  for (const v of Bokeh.index.all_views()) {
    if (v.model.type === 'Figure' && v.model.title && v.model.title.text.startsWith('Resonance graph')) {
      const r = v.canvas_view.el.getBoundingClientRect();
      return [r.left + v.frame.x_scale.compute(fe), r.top + v.frame.y_scale.compute(app)];
    }
  }
  return null;
}"""


def click_graph(page, fe: float, app: float, grid_fe: str):
    """Click the resonance graph at (``fe`` [Hz], ``app`` [µm]): f_e moves to the grid frequency
    ``grid_fe``, the table is the CLI's search there (to 1e-6), and the attractor whose A_pp is
    nearest the click (log) is selected."""
    xy = page.evaluate(XY, [fe, app])
    assert xy is not None
    page.mouse.click(*xy)
    page.wait_for_function(f"() => location.search.includes('fe={grid_fe}')", timeout=30_000)
    _wait_done(page, grid_fe)
    assert page.locator(".field-fe input").input_value() == grid_fe
    cli = _cli_json("--fe", grid_fe)
    _same(_table(page), cli)
    apps = [a["app_um"] for a in cli["attractors"]]
    nearest = min(range(len(apps)), key=lambda i: abs(math.log(apps[i] / app)))
    assert page.locator(".attractor-select select").evaluate("s => s.selectedIndex") == nearest  # the clicked one


@pytest.fixture(scope="module")
def dataset_server(small_dataset):
    with served(str(small_dataset)) as url:
        yield url


def test_click_on_the_resonance_graph_moves_fe(dataset_server, browser, tmp_path):  # noqa: F811
    page = browser.new_page(viewport={"width": 1150, "height": 1400})
    page.goto(dataset_server)
    _wait_done(page)
    _same(_table(page), _cli_json())  # 0.65 Q, 360 Hz
    page.wait_for_function("() => Bokeh.index.all_views().some(v => v.model.title && "
                           "v.model.title.text && v.model.title.text.startsWith('Resonance graph'))")
    page.screenshot(path=str(tmp_path / "explore_dataset_360.png"), full_page=True)
    click_graph(page, 371.3, 0.2, "372")  # between grid points 370 and 372 Hz, near the 1/4
    page.screenshot(path=str(tmp_path / "explore_dataset_372.png"), full_page=True)
