"""contactvib explore in headless Chromium (Debian's, through Playwright): the page, a new f_e,
a bad value and recovery, the URL; screenshots in a tmp folder (docs/explore.png is
the first, copied by hand)."""

from __future__ import annotations

import functools
import json
import os
import queue
import shutil
import socket
import subprocess
import sys
import threading
from contextlib import contextmanager
from pathlib import Path

import pytest

import contactvib

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]
playwright = pytest.importorskip("playwright.sync_api", reason="playwright is in the test extra")
#: The children import the package these tests import (the installed one in CI: its kernels
#: are then compiled once, in one cache, for the tests and the servers).
PACKAGE_PARENT = str(Path(contactvib.__file__).resolve().parents[1])


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def serving(*args):
    """``contactvib explore ARGS --no-browser`` on a free port, once it prints its address (it
    compiles the first search's kernels before: up to a minute with a cold numba cache):
    (process, URL)."""
    port = _free_port()
    env = {**os.environ, "PYTHONPATH": PACKAGE_PARENT}
    proc = subprocess.Popen([sys.executable, "-m", "contactvib", "explore", *args, "--no-browser", "--port",
                             str(port)], env=env, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    lines = queue.Queue()
    threading.Thread(target=lambda: [*map(lines.put, proc.stdout), lines.put(None)], daemon=True).start()
    line = ""
    while not line.startswith("contactvib explore: http"):  # after Panel's "Launching server at"
        try:
            line = lines.get(timeout=300)
        except queue.Empty:
            proc.kill()
            raise AssertionError(f"contactvib explore {' '.join(args)} printed no address within 300 s") from None
        assert line is not None, f"contactvib explore {' '.join(args)} exited with {proc.wait()}"
    assert f"127.0.0.1:{port}/" in line, line
    return proc, f"http://127.0.0.1:{port}/"


@contextmanager
def served(*args):
    """The URL of ``contactvib explore ARGS`` (:func:`serving`), stopped on exit."""
    proc, url = serving(*args)
    try:
        yield url
    finally:
        proc.terminate()
        proc.wait(10)


@pytest.fixture(scope="module")
def server():
    with served() as url:
        yield url


@pytest.fixture(scope="module")
def browser():
    with playwright.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        yield b
        b.close()


@functools.cache
def _cli_stdout(*args) -> str:
    """The standard output of ``contactvib attractors --json ARGS`` in a fresh process (run once per
    ``args`` in a session: the search is deterministic)."""
    env = {**os.environ, "PYTHONPATH": PACKAGE_PARENT}
    return subprocess.run([sys.executable, "-m", "contactvib", "attractors", "--json", *args], env=env,
                          capture_output=True, text=True, check=True).stdout


def _cli_json(*args) -> dict:
    return json.loads(_cli_stdout(*args))


def _wait_done(page, fe: str | None = None, timeout=120_000):
    """Wait for the answer to the current request: the status of a finished search (of
    f_e = ``fe`` when given) or the CLI's error message."""
    done = ".status .done" + (f'[data-fe="{fe}"]' if fe is not None else "")
    page.locator(f"{done}, .message .error").first.wait_for(timeout=timeout)


def _table(page) -> list[dict]:
    """The attractor table of the finished request the status line names (the browser may draw
    the status before the table): full-precision values of each row."""
    errors = page.locator(".message .error")
    assert errors.count() == 0, errors.first.inner_text()
    done = page.locator(".status .done")
    done.wait_for()
    request, n = done.get_attribute("data-request"), int(done.get_attribute("data-n"))
    table = page.locator(f'#attractors[data-request="{request}"]')
    table.wait_for()
    rows = table.locator("tr.attractor")
    assert rows.count() == n, (done.inner_text(), rows.count())
    out = []
    for i in range(rows.count()):
        cells = rows.nth(i).locator("td[data-v]")
        out.append({cells.nth(j).get_attribute("data-k"): float(cells.nth(j).get_attribute("data-v"))
                    for j in range(cells.count())})
    return out


def _same(rows, cli):
    assert len(rows) == len(cli["attractors"])
    for r, a in zip(rows, cli["attractors"]):
        for key, name in (("A_pp [µm]", "app_um"), ("y_min [µm]", "ymin_um"), ("y_max [µm]", "ymax_um"),
                          ("gap [frac]", "contact_loss_fraction"), ("basin", "basin_fraction")):
            assert r[key] == pytest.approx(a[name], abs=1e-6), (key, r, a)


def _set_field(page, name, value):
    box = page.locator(f".field-{name} input")
    box.fill(value)
    box.press("Enter")


def test_page_attractors_bad_value_and_url(server, browser, tmp_path):
    shots = tmp_path / "shots"
    shots.mkdir()
    page = browser.new_page(viewport={"width": 1100, "height": 1300})
    page.goto(server)
    _wait_done(page)
    rows = _table(page)
    _same(rows, _cli_json())
    assert len(rows) == 5
    playwright.expect(page.locator(".series-note")).to_contain_text("not drawn: the series has not converged")
    page.screenshot(path=str(shots / "explore_065Q_360Hz.png"), full_page=True)
    with page.expect_download() as info:  # the attractors as JSON: the CLI's contract
        page.locator(".download-json").first.click()
    got = json.loads(Path(info.value.path()).read_text())
    cli = _cli_json()
    assert set(got) == set(cli) and len(got["attractors"]) == 5
    for a, b in zip(got["attractors"], cli["attractors"]):
        assert a["period"] == b["period"] and a["app_um"] == pytest.approx(b["app_um"], abs=1e-6)

    _set_field(page, "fe", "287")
    page.wait_for_function("() => location.search.includes('fe=287')")
    _wait_done(page, "287")
    rows287 = _table(page)
    _same(rows287, _cli_json("--fe", "287"))
    assert rows287 != rows
    # the perturbation series, on the in-contact period-1 orbit
    playwright.expect(page.locator(".series-note")).to_contain_text("drawn on attractor #4")
    page.locator(".attractor-select select").select_option(index=4)
    page.wait_for_function("() => Array.from(Bokeh.index.all_views()).some(v => v.model.title && "
                           "v.model.title.text === 'Time history' && v.model.renderers.some(r => r.glyph && "
                           "JSON.stringify(r.glyph.line_color).includes('#c00000')))", timeout=30_000)
    page.screenshot(path=str(shots / "explore_fe287_series.png"), full_page=True)
    page.screenshot(path=str(shots / "explore_fe287.png"), full_page=True)

    _set_field(page, "fe", "-5")
    err = page.locator(".message .error")
    err.wait_for()
    assert err.inner_text() == "contactvib: error: --fe (f_e) = -5: must be > 0 Hz"
    page.screenshot(path=str(shots / "explore_bad_fe.png"), full_page=True)

    _set_field(page, "fe", "287")
    page.locator('.status .done[data-fe="287"]').wait_for(timeout=120_000)  # the error shows till then
    assert page.locator(".message .error").count() == 0
    _same(_table(page), _cli_json("--fe", "287"))
    url = page.url
    assert "fe=287" in url

    other = browser.new_page(viewport={"width": 1100, "height": 1300})  # a new page at the URL
    other.goto(url)
    _wait_done(other)
    assert other.locator(".field-fe input").input_value() == "287"
    assert _table(other) == _table(page)
    other.screenshot(path=str(shots / "explore_from_url.png"), full_page=True)

    fresh = browser.new_page()  # another tab at the plain address: its own state, not the others'
    fresh.goto(server)
    _wait_done(fresh)
    assert fresh.locator(".field-fe input").input_value() == "360"
    assert _table(fresh) == rows
    assert page.locator(".field-fe input").input_value() == "287"
