"""The pages whose commands and printed outputs the tests run: the README, the documentation's
getting-started page and its tutorials (docs/tutorials/*.md), so that a command or a table moved
between them stays tested."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
#: every page whose ```bash command lines must run (tests/cli/test_readme_commands.py)
PAGES = [README, DOCS / "getting-started.md", *sorted((DOCS / "tutorials").glob("*.md"))]


def block_after(heading: str, page: Path | None = None) -> str:
    """The first fenced block after ``heading`` on ``page`` (default: the one page of
    :data:`PAGES` that holds the heading; it must be exactly one)."""
    if page is None:
        holders = [p for p in PAGES if heading in p.read_text()]
        assert len(holders) == 1, (heading, [p.name for p in holders])
        page = holders[0]
    text = page.read_text()
    i = text.index(heading)
    return re.search(r"```\n(.*?)```", text[i:], re.S).group(1)
