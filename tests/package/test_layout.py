"""The package's shape: the limits of ARCHITECTURE.md hold, so that no module
grows into a monolith again. Modules at most ~500 lines, functions at most ~80 lines of code
(their docstring not counted: a numpydoc docstring is welcome, not a reason to split), at most 12
parameters outside the kernels (kernels take arrays of parameters), matplotlib only in plotting/,
no module reaches into the CLI, and no import circle between modules."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "contactvib"
MODULES = sorted(SRC.rglob("*.py"))
#: generous by a little over ARCHITECTURE.md's "~": beyond these a module or function must be split
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
    if rel in ("errors.py", "testing.py"):
        assert not any(m.startswith("contactvib") for m in mods), f"{rel} uses contactvib"


def test_the_public_api_exports_every_verb_and_result_type():
    import contactvib

    for name in contactvib.__all__:
        assert getattr(contactvib, name) is not None, name
    from contactvib import simulate

    assert callable(simulate) and simulate.__module__ == "contactvib.steady.simulate"


# ------------------------------------------------------------------ import circles
#
# The rule: the modules of src/contactvib and their imports form a graph without a circle (a
# strongly connected component of two or more modules), so that every module can be read, tested
# and imported after the modules it uses. An edge A -> B is any ``import``/``from ... import`` in
# A that names module B, at the top of A or inside one of its functions (an import moved into a
# function to dodge a circle is still a circle). ``from P import x`` names the submodule P.x when
# P.x is a module (``from . import x`` in a package ``__init__`` re-exporting its submodules is an
# edge to the submodule, not to a circle), else the package P itself (its ``__init__``). Imports
# under ``if TYPE_CHECKING:`` count too: a type that two modules both need lives in the module
# beneath them (or is stated there as a Protocol), so the modules still read in one order.


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _import_edges(path: Path, root: Path, known: set) -> set:
    """The contactvib modules that the module at ``path`` imports, at run time or for its types."""
    name = _module_name(path, root)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]

    def owner(dotted):  # the module that defines dotted (a module, or a name in one)
        while dotted and dotted not in known:
            dotted = dotted.rpartition(".")[0]
        return dotted

    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out |= {owner(a.name) for a in node.names if a.name.split(".")[0] == "contactvib"}
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            if base.split(".")[0] == "contactvib":
                out |= {owner(f"{base}.{a.name}") for a in node.names}
    return out - {name, ""}


def import_circles(root: Path) -> list:
    """The circles (strongly connected components of two or more modules, Tarjan's algorithm)
    of the import graph of the modules of the package at ``root``."""
    names = {_module_name(p, root): p for p in sorted(root.rglob("*.py"))}
    graph = {n: sorted(_import_edges(p, root, set(names))) for n, p in names.items()}
    index, low, stack, on_stack, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while not component or component[-1] != v:
                component.append(stack.pop())
                on_stack.discard(component[-1])
            if len(component) > 1:
                circles.append({m: [w for w in graph[m] if w in component] for m in sorted(component)})

    for v in graph:
        if v not in index:
            visit(v)
    return circles


def test_no_import_circle_between_modules():
    circles = import_circles(SRC)
    assert not circles, "import circles (module -> the modules of its circle it imports):\n" + "\n".join(
        "\n".join(f"  {m} -> {', '.join(ws)}" for m, ws in c.items()) for c in circles)


def test_the_circle_finder_sees_function_level_and_type_only_imports(tmp_path):
    pkg = tmp_path / "contactvib"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("from contactvib.sub import a\n")
    (pkg / "sub" / "__init__.py").write_text("from . import a, b\n")
    (pkg / "sub" / "a.py").write_text("def f():\n    from contactvib.sub.b import g\n")
    (pkg / "sub" / "b.py").write_text("def g():\n    pass\n")
    assert import_circles(pkg) == []  # a package re-exporting its modules
    circle = [{"contactvib.sub.a": ["contactvib.sub.b"], "contactvib.sub.b": ["contactvib.sub.a"]}]
    (pkg / "sub" / "b.py").write_text("def g():\n    from .a import f\n")
    assert import_circles(pkg) == circle
    (pkg / "sub" / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                                      "    from contactvib.sub import a\n")
    assert import_circles(pkg) == circle


# ------------------------------------------------------------------ private names stay private
#
# A name that starts with "_" is private to its module: a helper that another module needs is a
# public name of the module that defines it. A module may import a private *module* (the
# ``_kernels`` package, ``_dop853_coefficients``): what counts is the imported symbol, and
# attribute access ``mod._name`` on a contactvib module it imported.


def _private_uses(path: Path):
    """``(line, what)`` of every private name of another contactvib module used by ``path``."""
    name = _module_name(path, SRC)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text())
    aliases = set()  # local names bound to contactvib modules
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            if base.split(".")[0] != "contactvib":
                continue
            for a in node.names:
                target = SRC.parent.joinpath(*f"{base}.{a.name}".split("."))
                if target.with_suffix(".py").is_file() or target.is_dir():
                    aliases.add(a.asname or a.name)
                elif a.name.startswith("_") and not a.name.startswith("__"):
                    yield node.lineno, f"from {base} import {a.name}"
        elif isinstance(node, ast.Import):
            aliases |= {a.asname for a in node.names if a.asname and a.name.startswith("contactvib")}
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id in aliases
                and node.attr.startswith("_") and not node.attr.startswith("__")):
            yield node.lineno, f"{node.value.id}.{node.attr}"


@pytest.mark.parametrize("path", MODULES, ids=_rel)
def test_no_module_uses_another_modules_private_names(path):
    uses = [f"{_rel(path)}:{line}: {what}" for line, what in _private_uses(path)]
    assert not uses, "make these public names of their module:\n" + "\n".join(uses)


# ------------------------------------------------------------------ the code speaks of the software
#
# Docstrings, comments and --help say what the software does, not the history of its making:
# no "issue 26" (the tracker's numbers belong to commit messages and the changelog).

ISSUE_NUMBER = re.compile(r"\bissues?\s*#?\s*\d+", re.IGNORECASE)


@pytest.mark.parametrize("path", MODULES, ids=_rel)
def test_no_issue_numbers_in_the_sources(path):
    hits = [f"{_rel(path)}:{n}: {line.strip()}" for n, line in enumerate(path.read_text().splitlines(), 1)
            if ISSUE_NUMBER.search(line)]
    assert not hits, "say what the code does instead:\n" + "\n".join(hits)


def _commands(group, prefix=("contactvib",)):
    import click

    yield prefix, group
    if isinstance(group, click.Group):
        for name, cmd in sorted(group.commands.items()):
            yield from _commands(cmd, (*prefix, name))


def test_no_issue_numbers_in_any_help_text():
    import click

    from contactvib.cli.main import cli

    hits = []
    for path, cmd in _commands(cli):
        with click.Context(cmd, info_name=" ".join(path)) as ctx:
            text = cmd.get_help(ctx)
        hits += [f"{' '.join(path)} --help: {m.group(0)!r}" for m in ISSUE_NUMBER.finditer(text)]
    assert len(list(_commands(cli))) > 10 and not hits, "\n".join(hits)


def test_the_issue_pattern_finds_what_it_should():
    assert [bool(ISSUE_NUMBER.search(s)) for s in
            ("(issue 26)", "Issue #14: x", "issues 23", "no issue here", "tissue 5 cm")] == \
        [True, True, True, False, False]


# ------------------------------------------------------------------ ARCHITECTURE.md names every module
#
# The map of the package lists every module: by its path (``steady/basins.py``), or by its file
# name in its package's entry of "The parts" (``basins.py`` on the ``steady/`` line), for the
# kernels one per line. A module the map does not name fails here until it is added.

ARCHITECTURE = SRC.parents[1] / "ARCHITECTURE.md"


def _named_in_architecture(rel: Path, text: str) -> bool:
    if str(rel.as_posix()) in text:
        return True
    package = rel.parts[0] if len(rel.parts) > 1 else ""
    block = text.split("\n## The parts\n", 1)[-1].split("```")[1]  # the map's code block
    # the package's entry: from its line "  package/ ..." to the next top-level entry
    entry, inside = [], not package
    for line in block.splitlines():
        head = line[2:].split(" ", 1)[0] if line.startswith("  ") and not line.startswith("   ") else None
        if head is not None:
            inside = (head == f"{package}/") if package else True
        if inside:
            entry.append(line)
    return re.search(rf"(?<![\w/]){re.escape(rel.name)}\b", "\n".join(entry)) is not None


@pytest.mark.parametrize("path", [p for p in MODULES if p.name != "__init__.py"], ids=_rel)
def test_architecture_names_every_module(path):
    assert _named_in_architecture(path.relative_to(SRC), ARCHITECTURE.read_text()), \
        f"ARCHITECTURE.md does not name {_rel(path)}: add it to its package's line in 'The parts'"


def test_the_architecture_check_sees_a_missing_module():
    text = ARCHITECTURE.read_text()
    assert _named_in_architecture(Path("steady/basins.py"), text)
    assert _named_in_architecture(Path("_kernels/series_roots.py"), text)
    assert not _named_in_architecture(Path("sweeps/new_module.py"), text)
    assert not _named_in_architecture(Path("plotting/atlas.py"), text)  # named, but in another package
