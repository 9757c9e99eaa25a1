"""The explore page's figure downloads in headless Chromium: the selected attractor's time
history and phase portrait as PNG and as SVG (the figure `contactvib simulate` writes), named
after the operating point."""

from __future__ import annotations

from pathlib import Path

import pytest
from test_explore_browser import CHROMIUM, _table, _wait_done, browser, server  # noqa: F401

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]


def test_png_and_svg_downloads(server, browser):  # noqa: F811
    page = browser.new_page(viewport={"width": 1100, "height": 1300})
    page.goto(server)
    _wait_done(page)
    assert len(_table(page)) == 5  # the table (and the selected attractor) of this request
    got = {}
    for fmt in ("png", "svg"):
        with page.expect_download() as info:
            page.locator(f".download-{fmt}").first.click()
        got[fmt] = (info.value.suggested_filename, Path(info.value.path()).read_bytes())
    name, png = got["png"]
    assert name == "attractor0_pa0.65_fe360.png"
    assert png.startswith(b"\x89PNG\r\n\x1a\n") and len(png) > 20_000
    name, svg = got["svg"]
    assert name == "attractor0_pa0.65_fe360.svg"
    text = svg.decode("utf-8")
    assert "<svg" in text and "</svg>" in text and "µm" in text  # axes with units
