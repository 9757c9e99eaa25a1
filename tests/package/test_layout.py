"""The package's shape: the limits of the redesign (ARCHITECTURE.md) hold, so that no module
grows into a monolith again. Modules at most ~500 lines, functions at most ~80 lines of code
(their docstring not counted: a numpydoc docstring is welcome, not a reason to split), at most 12
parameters outside the kernels (kernels take arrays of parameters), matplotlib only in plotting/,
and no module reaches into the CLI."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "contactvib"
MODULES = sorted(SRC.rglob("*.py"))
#: generous by a little over the issue's "~": beyond these a module or function must be split
MAX_MODULE_LINES = 520
MAX_FUNCTION_LINES = 85
MAX_PARAMETERS = 12


def _rel(path: Path) -> str:
    return str(path.relative_to(SRC))


def _functions(tree):
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            yield node


@pytest.mark.parametrize("path", MODULES, ids=_rel)
def test_module_and_function_sizes(path):
    text = path.read_text()
    assert len(text.splitlines()) <= MAX_MODULE_LINES, f"{_rel(path)}: split the module"
    tree = ast.parse(text)
    for fn in _functions(tree):
        n = fn.end_lineno - fn.lineno + 1
        first = fn.body[0]
        if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) \
                and isinstance(first.value.value, str):
            n -= first.end_lineno - first.lineno + 1
        assert n <= MAX_FUNCTION_LINES, f"{_rel(path)}:{fn.lineno} {fn.name} has {n} lines"
        if "_kernels" not in path.parts:
            a = fn.args
            n_par = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs)
            n_par -= int(bool(a.args) and a.args[0].arg in ("self", "cls"))
            assert n_par <= MAX_PARAMETERS, f"{_rel(path)}:{fn.lineno} {fn.name}: {n_par} parameters"


def _imports(path: Path):
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module:
            yield node.module


@pytest.mark.parametrize("path", MODULES, ids=_rel)
def test_who_may_use_whom(path):
    rel = _rel(path)
    mods = set(_imports(path))
    if not rel.startswith("plotting"):
        assert not any(m.split(".")[0] == "matplotlib" for m in mods), f"{rel} imports matplotlib"
    if not rel.startswith("cli") and rel != "__main__.py":
        assert not any(m.startswith("contactvib.cli") for m in mods), f"{rel} uses the CLI"
    if rel.startswith("_kernels"):
        assert not any(m.startswith("contactvib.") and not m.startswith("contactvib._kernels")
                       for m in mods), f"{rel}: kernels use only kernels"
        assert not {"xarray", "click", "tqdm"} & {m.split(".")[0] for m in mods}
    if rel.startswith("plotting"):
        assert not any(m.startswith("contactvib._kernels") for m in mods), f"{rel} uses kernels"
    if rel.startswith("cli"):
        assert not any(m.startswith("contactvib._kernels") for m in mods), f"{rel} uses kernels"


def test_the_public_api_exports_every_verb_and_result_type():
    import contactvib

    for name in contactvib.__all__:
        assert getattr(contactvib, name) is not None, name
    from contactvib import simulate

    assert callable(simulate) and simulate.__module__ == "contactvib.steady.simulate"
