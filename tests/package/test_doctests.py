"""The ``>>>`` examples of the package's docstrings run and print what they show (CI runs them
with the rest of the suite)."""

from __future__ import annotations

import doctest
import importlib
from pathlib import Path

import pytest

import contactvib

SRC = Path(contactvib.__file__).resolve().parent


def _modules_with_examples() -> list[str]:
    """Every module of the package whose source holds a ``>>>`` line (found by reading the files,
    so a new example is collected by itself)."""
    names = []
    for path in sorted(SRC.rglob("*.py")):
        if ">>> " in path.read_text(encoding="utf-8"):
            rel = path.relative_to(SRC.parent).with_suffix("")
            parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
            names.append(".".join(parts))
    return names


MODULES = _modules_with_examples()


def test_the_docstring_examples_are_collected():
    assert {"contactvib.model.oscillator", "contactvib.model.contact_law"} <= set(MODULES)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    module = importlib.import_module(name)
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = [t for t in finder.find(module, name) if t.examples]
    assert tests, f"{name} holds '>>> ' but doctest finds no example in its docstrings"
    for t in tests:
        runner.run(t)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {name} failed (output above)"
