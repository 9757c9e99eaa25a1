"""The continuation button in headless Chromium: the selected orbit's branch in f_e appears,
with the CLI command that reproduces it; a screenshot in a tmp folder."""

from __future__ import annotations

import pytest
from test_explore_browser import CHROMIUM, _table, _wait_done, browser, server  # noqa: F401

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]


def test_continuation_button_draws_the_branch(server, browser, tmp_path):  # noqa: F811
    page = browser.new_page(viewport={"width": 1150, "height": 1700})
    page.goto(server)
    _wait_done(page)
    assert len(_table(page)) == 5  # the table (and its selector) of this request
    page.locator(".attractor-select select option").nth(4).wait_for(state="attached")
    page.locator(".attractor-select select").select_option(index=4)  # the 1/4 (in contact)
    page.wait_for_timeout(500)
    page.locator(".continue button").first.click()
    done = page.locator(".cont-status .cont-done")
    done.wait_for(timeout=120_000)
    text = done.inner_text()
    assert "points" in text and "fold" in text
    assert "contactvib continue --pa 0.65 --from-fe 360 --attractor 4 --no-switch" in \
        page.locator(".cont-status code").inner_text()
    page.wait_for_function("() => Bokeh.index.all_views().some(v => v.model.title && v.model.title.text "
                           "&& v.model.title.text.startsWith('Continuation of the period-1 orbit'))")
    page.screenshot(path=str(tmp_path / "explore_continuation.png"), full_page=True)
