"""Every dotted name ``contactvib.…`` written in the package's sources (docstrings, comments,
messages) names a module or attribute that exists, so a reference cannot outlive a move. The
documentation build checks the rendered docstrings' cross-references (sphinx-build -n); this test
covers the rest, private modules included."""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import contactvib
from contactvib.model.laws import ENTRY_POINT_GROUP

SRC = Path(contactvib.__file__).resolve().parent
DOTTED = re.compile(r"(?<![\w./-])contactvib(?:\.[A-Za-z_]\w*)+")


def resolves(name: str) -> bool:
    """Whether ``name`` is an importable module, or an attribute path under the longest
    importable module prefix."""
    parts = name.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attr in parts[k:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def test_resolves():
    assert resolves("contactvib.model.Excitation.kernel_parameters") and resolves("contactvib.find_attractors")
    assert not resolves("contactvib.periodic") and not resolves("contactvib.model.kernel_parameters")


def test_every_dotted_name_in_the_sources_exists():
    stale = []
    for path in sorted(SRC.rglob("*.py")):
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            stale += [f"{path.relative_to(SRC.parent)}:{i}: {m}" for m in DOTTED.findall(line)
                      if not resolves(m) and m != ENTRY_POINT_GROUP]  # the plug-ins' group, a name, not a module
    assert not stale, "names of modules or attributes that do not exist:\n" + "\n".join(stale)
