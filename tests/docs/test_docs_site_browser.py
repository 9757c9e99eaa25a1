"""The built documentation opens in headless Chromium: every page loads with its title and main
content, no internal link points at a missing page or anchor, and the gallery's images (drawn by
the package at build time) are present and decoded."""

from __future__ import annotations

import shutil
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = [pytest.mark.browser, pytest.mark.docs,
              pytest.mark.skipif(CHROMIUM is None, reason="no chromium binary (apt-get install chromium)")]
playwright = pytest.importorskip("playwright.sync_api", reason="playwright is in the test extra")

#: what a page reports: its title, whether it has the theme's main content, every link's
#: resolved href, and per image (src, decoded width)
_PAGE = """() => ({
  title: document.title,
  main: !!document.querySelector('main article, main .bd-article'),
  links: [...document.querySelectorAll('a[href]')].map(a => a.href),
  ids: [...document.querySelectorAll('[id]')].map(e => e.id),
  images: [...document.images].map(i => [i.getAttribute('src'), i.complete ? i.naturalWidth : 0]),
})"""


def _pages(site: Path) -> list[Path]:
    skip = {"_sources", "_static", "_downloads", "_images", "_modules"}
    return sorted(p for p in site.rglob("*.html") if not skip & set(p.relative_to(site).parts))


@pytest.fixture(scope="module")
def visited(docs_site):
    """page -> what Chromium reports on it, for every page of the site."""
    out = {}
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        page = browser.new_page()
        for path in _pages(docs_site):
            response = page.goto(path.as_uri(), wait_until="load")
            assert response is None or response.ok, path
            out[path] = page.evaluate(_PAGE)
        browser.close()
    return out


def test_every_page_loads(docs_site, visited):
    names = {p.relative_to(docs_site).as_posix() for p in visited}
    assert {"index.html", "getting-started.html", "cli.html", "formats.html", "physics.html",
            "benchmarks.html", "api/index.html", "gallery/index.html"} <= names
    assert len([n for n in names if n.startswith("tutorials/")]) >= 9
    for path, info in visited.items():
        assert info["title"] and "contactvib" in info["title"], path
        if path.name not in ("genindex.html", "search.html", "py-modindex.html"):
            assert info["main"], f"{path}: no main content"


def test_no_internal_link_is_broken(docs_site, visited):
    ids = {p.resolve(): set(info["ids"]) for p, info in visited.items()}
    broken, checked = [], 0
    for path, info in visited.items():
        for href in info["links"]:
            url = urlsplit(href)
            if url.scheme != "file":
                continue
            checked += 1
            target = Path(unquote(url.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.is_file():
                broken.append(f"{path.name} -> {href}")
            elif url.fragment and target in ids and unquote(url.fragment) not in ids[target]:
                broken.append(f"{path.name} -> {href} (no such anchor)")
    assert checked > 20 * len(visited)  # the theme's navigation links every page to every section
    assert not broken, "broken internal links:\n" + "\n".join(sorted(set(broken)))


def test_gallery_images_are_present(docs_site, visited):
    examples = sorted((docs_site / "gallery").glob("plot_*.html"))
    assert len(examples) >= 4
    for path in examples:
        images = [(src, w) for src, w in visited[path]["images"] if "sphx_glr_" in src]
        assert images, f"{path.name}: no figure"
        assert all(w > 0 for _, w in images), f"{path.name}: an image did not load: {images}"
    thumbs = [(s, w) for s, w in visited[docs_site / "gallery" / "index.html"]["images"] if "thumb" in s]
    assert len(thumbs) == len(examples) and all(w > 0 for _, w in thumbs)
