"""The contact-law chooser in headless Chromium: switching the law to exponential shows its
fields, hides the power law's, changes the derived f_n0 and the attractor table (equal to
find_attractors on the exponential model built directly), keeps the choice in the URL, and a bad
lam gives the CLI's message; a screenshot in a tmp folder."""

from __future__ import annotations

import pytest
from test_explore_browser import CHROMIUM, _table, _wait_done, browser, playwright, server  # noqa: F401

from contactvib import ContactModel, Excitation
from contactvib.steady.attractors import find_attractors

pytestmark = [pytest.mark.browser,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]


def _next_done(page, request: str):
    """Wait for the answer to the request after ``request`` (a finished search or an error)."""
    page.locator(f'.status .done[data-request="{int(request) + 1}"], .message .error').first.wait_for(
        timeout=60_000)


@pytest.mark.filterwarnings("ignore:.*did not settle")
def test_law_chooser_changes_the_model_and_the_table(server, browser, tmp_path):  # noqa: F811
    page = browser.new_page(viewport={"width": 1150, "height": 1400})
    page.goto(server + "?pa=0.3&fe=900")
    _wait_done(page, "900")
    power = _table(page)
    derived = playwright.expect(page.locator(".derived"))
    derived.to_contain_text(f"f_n0 = {ContactModel().f_n0:.1f} Hz")  # 1485.0 Hz
    assert page.locator(".field-c_n input").is_visible() and not page.locator(".field-c_e input").is_visible()

    request = page.locator(".status .done").get_attribute("data-request")
    page.locator(".field-law select").select_option("exponential")
    _next_done(page, request)
    page.wait_for_function("() => location.search.includes('law=exponential')")
    ref = ContactModel(law="exponential")
    assert f"{ref.f_n0:.1f}" != f"{ContactModel().f_n0:.1f}"
    derived.to_contain_text(f"f_n0 = {ref.f_n0:.1f} Hz, y0 = {ref.y0 * 1e6:.4f} µm, ζ = {ref.zeta:.4f}; "
                            "exponential law")
    assert page.locator(".field-c_e input").is_visible() and page.locator(".field-lam input").is_visible()
    assert not page.locator(".field-c_n input").is_visible() and not page.locator(".field-m2 input").is_visible()
    rows = _table(page)
    want = find_attractors(Excitation(ref, 0.3, 900.0))
    assert rows != power and len(rows) == len(want)
    for r, a in zip(rows, want):
        assert r["A_pp [µm]"] == pytest.approx(a.app_um, abs=1e-6)
    page.screenshot(path=str(tmp_path / "explore_law_exponential.png"), full_page=True)

    box = page.locator(".field-lam input")
    box.fill("-1")
    box.press("Enter")
    err = page.locator(".message .error")
    err.wait_for()
    assert err.inner_text() == "contactvib: error: --set lam (lam) = -1: must be > 0 m"
