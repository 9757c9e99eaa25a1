"""The built documentation's text, as a reader copies it: command-line options keep their two
hyphens (``--pa``, never an en dash "–pa" made by typographic replacements), and the pages speak
to users (no references to the project's issue tracker such as "issue 26")."""

from __future__ import annotations

import html
import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.docs

#: an en or em dash at the start of a word followed by a lower-case letter: what ``--pa`` or
#: ``---set`` become under smart quotes ("2a–h" or "0.5 – 1" are left alone)
DASHED_OPTION = re.compile(r"(?:^|[\s(\[>\"'`])[–—]+[a-z]")
ISSUE = re.compile(r"\bissues? ?#?\d+", re.I)


def _text(path: Path) -> str:
    """The page's text without its scripts, styles and tags (entities decoded)."""
    t = path.read_text(encoding="utf-8")
    t = re.sub(r"<(script|style)\b.*?</\1>", " ", t, flags=re.S | re.I)
    return html.unescape(re.sub(r"<[^>]+>", "", t))


def _pages(site: Path) -> list[Path]:
    skip = {"_sources", "_static", "_downloads", "_images", "_modules"}
    return sorted(p for p in site.rglob("*.html") if not skip & set(p.relative_to(site).parts))


def test_options_keep_their_hyphens(docs_site):
    cli = _text(docs_site / "cli.html")
    assert "--pa" in cli and "--fe" in cli and "--set" in cli
    bad = []
    for path in _pages(docs_site):
        for line in _text(path).splitlines():
            m = DASHED_OPTION.search(line)
            if m:
                bad.append(f"{path.relative_to(docs_site)}: …{line[max(0, m.start() - 40):m.end() + 20].strip()}…")
    assert not bad, "a dash where -- was meant:\n" + "\n".join(bad[:30])


def test_no_issue_numbers_on_user_pages(docs_site):
    bad = [f"{path.relative_to(docs_site)}: {m.group(0)}" for path in _pages(docs_site)
           for m in ISSUE.finditer(_text(path))]
    assert not bad, "developer references on the site:\n" + "\n".join(bad[:30])


def test_the_sections_have_a_navigation(docs_site):
    """Each tutorial and reference page shows the pages of its section in the left sidebar."""
    for page, sibling in [("tutorials/attractors.html", "resonance.html"), ("cli.html", "formats.html"),
                          ("api/generated/steady.html", "continuation.html"), ("physics.html", "benchmarks.html")]:
        t = (docs_site / page).read_text(encoding="utf-8")
        nav = t[t.index("bd-docs-nav"):]
        nav = nav[:nav.index("</nav>")]
        assert f'href="{sibling}"' in nav or f'href="../../{sibling}"' in nav, page


def test_equations_are_typeset(docs_site):
    """The equations are MathJax math, not monospace code."""
    t = (docs_site / "physics.html").read_text(encoding="utf-8")
    assert 'class="math' in t and "mathjax" in t.lower()
    assert r"\ddot y" in t and "<pre>M ÿ" not in t
