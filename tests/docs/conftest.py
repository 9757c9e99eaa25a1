"""The built documentation site for the tests of tests/docs (marker ``docs``).

``CONTACTVIB_DOCS_HTML`` names a site already built by the CI line
``sphinx-build -W -n -b html docs docs/_build/html`` (so CI builds it once); without it the
fixture builds the site into a temporary folder with the same options."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = [sys.executable, "-m", "sphinx", "-W", "-n", "-b", "html", str(ROOT / "docs")]


@pytest.fixture(scope="session")
def docs_site(tmp_path_factory) -> Path:
    pytest.importorskip("sphinx", reason="the documentation's tools are the 'docs' extra")
    built = os.environ.get("CONTACTVIB_DOCS_HTML")
    if built:
        return Path(built).resolve()
    out = tmp_path_factory.mktemp("html")
    proc = subprocess.run([*BUILD, str(out), "-q"], cwd=ROOT, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-4000:]
    return out
