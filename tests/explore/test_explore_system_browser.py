"""``contactvib explore --system`` in headless Chromium: the page of a structure with contacts
shows the attractors of ``attractors --system`` (the same numbers as its JSON), one row of
figures per coordinate, and a bad value as the CLI's one-line error."""

from __future__ import annotations

import pytest
from test_explore_browser import CHROMIUM, _cli_json, _set_field, _wait_done, browser, served  # noqa: F401

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]

STOP = "examples/two_dof_stop.toml"


def _rows(page) -> list[dict]:
    done = page.locator(".status .done")
    done.wait_for()
    request, n = done.get_attribute("data-request"), int(done.get_attribute("data-n"))
    table = page.locator(f'#system-attractors[data-request="{request}"]')
    table.wait_for()
    rows = table.locator("tr.attractor")
    assert rows.count() == n
    return [{c.get_attribute("data-k"): float(c.get_attribute("data-v")) for c in rows.nth(i).locator("td").all()}
            for i in range(n)]


def _same(rows, cli):
    assert len(rows) == len(cli["attractors"]) >= 1
    for r, a in zip(rows, cli["attractors"]):
        assert r["period"] == a["period"] and r["basin"] == pytest.approx(a["basin_fraction"], abs=1e-12)
        for d in a["dofs"]:
            assert r[f"{d['name']} A_pp [{d['unit'].replace('u', 'µ', 1)}]"] == pytest.approx(d["app"], rel=1e-12)


def test_system_page(browser, tmp_path):  # noqa: F811
    with served("--system", STOP) as url:
        page = browser.new_page(viewport={"width": 1200, "height": 1500})
        page.goto(url)
        _wait_done(page)
        _same(_rows(page), _cli_json("--system", STOP, "--pa-newton", "0.1", "--fe", "0.09836"))
        assert page.locator(".bk-Canvas, canvas").count() >= 1
        _set_field(page, "pa", "2")
        _set_field(page, "fe", "0.2")
        page.locator('.status .done:has-text("f_e = 0.2 Hz")').wait_for(timeout=120_000)
        _same(_rows(page), _cli_json("--system", STOP, "--pa-newton", "2", "--fe", "0.2"))
        page.screenshot(path=str(tmp_path / "system.png"), full_page=True)
        _set_field(page, "fe", "-1")
        err = page.locator(".message .error")
        err.wait_for(timeout=60_000)
        assert err.inner_text().startswith("contactvib: error: --fe") and "\n" not in err.inner_text()
