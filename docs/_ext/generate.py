"""Pages written when the documentation is built (called from ``docs/conf.py``).

- ``api/generated/<package>.rst``: one autodoc entry per name of the package's ``__all__``, so a
  new public name appears by itself and a removed one disappears;
- ``generated/paper_statements.md``: the paper's statements S2.1–S4.7, where ``contactvib paper``
  shows each and which tests and modules name it;
- ``benchmarks.md``: one table per committed ``benchmarks/results_*.json``, flattened to
  (quantity, value) rows — the current numbers, not a dated log.
"""

from __future__ import annotations

import importlib
import inspect
import json
from pathlib import Path

#: the public packages, in the order of the API reference; a name documented under an earlier
#: package (``contactvib`` first) is only listed under a later one
API_PACKAGES = ("contactvib", "contactvib.model", "contactvib.plotting", "contactvib.fitting",
                "contactvib.friction", "contactvib.cli", "contactvib.testing")


def _directive(module: str, name: str, obj) -> str:
    if inspect.isclass(obj):
        return f".. autoclass:: {module}.{name}\n   :members:\n"
    if callable(obj):
        return f".. autofunction:: {module}.{name}\n"
    return f".. autodata:: {module}.{name}\n   :no-value:\n"


def api_entries() -> dict[str, list[tuple[str, str | None]]]:
    """package -> [(name, None) for names documented there, (name, home) for names documented
    under an earlier package ``home``]."""
    seen: dict[int, str] = {}
    out: dict[str, list[tuple[str, str | None]]] = {}
    for package in API_PACKAGES:
        mod = importlib.import_module(package)
        rows = []
        for name in mod.__all__:
            if name.startswith("__"):
                continue
            obj = getattr(mod, name)
            key = id(obj) if (inspect.isclass(obj) or callable(obj)) else id((package, name))
            rows.append((name, seen.get(key)))
            seen.setdefault(key, package)
        out[package] = rows
    return out


def write_api_pages(folder: Path) -> list[Path]:
    gen = folder / "generated"
    gen.mkdir(parents=True, exist_ok=True)
    written = []
    for package, rows in api_entries().items():
        mod = importlib.import_module(package)
        title = f"``{package}``"
        lines = [title, "=" * len(title), "", f".. module:: {package}", "   :no-index:", ""]
        doc = inspect.getdoc(mod) or ""
        lines += [doc.split("\n\n", 1)[0], ""]
        again = [(n, home) for n, home in rows if home is not None]
        if again:
            lines += ["Also importable from here: "
                      + ", ".join(f":py:obj:`{n} <{home}.{n}>`" for n, home in again) + ".", ""]
        for name, home in rows:
            if home is None:
                lines.append(_directive(package, name, getattr(mod, name)))
        path = gen / f"{package}.rst"
        text = "\n".join(lines) + "\n"
        if not path.is_file() or path.read_text() != text:  # unchanged pages keep Sphinx's cache
            path.write_text(text)
        written.append(path)
    return written


def _flatten(value, prefix: str = ""):
    """(dotted key, value) rows of a JSON value; lists of numbers or strings stay one row."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _flatten(v, f"{prefix}.{k}" if prefix else str(k))
    elif isinstance(value, list) and any(isinstance(v, (dict, list)) for v in value):
        for i, v in enumerate(value):
            yield from _flatten(v, f"{prefix}[{i}]")
    else:
        yield prefix, value


def _cell(value) -> str:
    if isinstance(value, list):
        text = ", ".join(_cell(v) for v in value[:12]) + (f", … ({len(value)} values)" if len(value) > 12 else "")
    elif isinstance(value, float):
        text = f"{value:.6g}"
    else:
        text = str(value)
    return text.replace("|", "\\|").replace("\n", " ")


def benchmarks_markdown(folder: Path) -> str:
    files = sorted(folder.glob("results_*.json"))
    out = ["# Benchmarks", "",
           "The current result of each benchmark, read from the result files committed in "
           "`benchmarks/` when this page was built (one table per file; nested keys are joined "
           "with dots). Each file is written by the benchmark script of the same name; the "
           "machine and load are in the file when the script records them.", "",
           (Path(__file__).parent / "benchmarks_intro.md").read_text(), ""]
    for f in files:
        name = f.stem.removeprefix("results_")
        out += [f"## `{name}`", "", f"`benchmarks/{f.name}`", "", "| quantity | value |", "|---|---|"]
        out += [f"| `{k}` | {_cell(v)} |" for k, v in _flatten(json.loads(f.read_text()))]
        out.append("")
    return "\n".join(out)


def write_benchmarks_page(folder: Path, page: Path) -> Path:
    text = benchmarks_markdown(folder)
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)
    return page


def statements(path: Path) -> dict[str, str]:
    """The paper's statements by id (``"S3.2"`` → text) from ``data/paper_statements.md``."""
    out: dict[str, str] = {}
    current = None
    for line in path.read_text().splitlines():
        if line.startswith("- S"):
            current, text = line[2:].split(" ", 1)
            out[current] = text
        elif current and line.startswith("  ") and line.strip():
            out[current] += " " + line.strip()
        else:
            current = None
    return out


def _where_shown(sid: str, text: str) -> str:
    """Where ``contactvib paper`` shows statement ``sid``: ``index.md`` always, and the figures
    of its level (S3) or its figure number (S4)."""
    import re

    if sid.startswith("S4."):
        m = re.match(r"\(Fig\. (\d+)", text)
        return f"`fig{m.group(1)}_*.png`, `index.md`" if m else "`index.md`"
    if sid in ("S3.8", "S3.9"):
        return "`fig2*.png`, `fig3*.png` (all levels), `index.md`"
    if sid.startswith("S3."):
        return "`fig2*`/`fig3*` of the level(s) named, `index.md`"
    return "`index.md` (model line)"


def statements_markdown(src: Path, tests: Path) -> str:
    """A table of the paper's statements S2.1–S4.7, where ``contactvib paper`` shows each and
    which test files and modules name it (found by searching the sources for its id)."""
    files = sorted([*tests.rglob("*.py"), *src.rglob("*.py")])
    texts = {f: f.read_text(encoding="utf-8") for f in files}
    rows = ["| id | the paper says | shown in `paper/` | named by |", "|---|---|---|---|"]
    for sid, text in statements(src / "data" / "paper_statements.md").items():
        named = [f.relative_to(src.parents[1]).as_posix() for f in files if sid in texts[f]]
        cell = ", ".join(f"`{n}`" for n in named) or "—"
        rows.append(f"| {sid} | {_cell(text)} | {_where_shown(sid, text)} | {cell} |")
    return "\n".join(rows) + "\n"


def write_statements_page(root: Path, page: Path) -> Path:
    page.parent.mkdir(parents=True, exist_ok=True)
    text = statements_markdown(root / "src" / "contactvib", root / "tests")
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)
    return page


def dataset_variables_markdown() -> str:
    """The variables of a resonance dataset (``paper.nc``, ``resonance.nc``, ``atlas.nc``) with
    their dimensions, type, units and description, read from a small dataset computed here (one
    level, three frequencies), so the table is the one the code writes."""
    from contactvib import ContactModel, SweepSettings, resonance_dataset

    settings = SweepSettings(fmin_hz=355.0, fmax_hz=365.0, df_hz=5.0, multistart_per_octave=0)
    ds = resonance_dataset(ContactModel(), [0.65], settings, workers=1, progress=False)
    rows = ["| variable | dimensions | type | units | description |", "|---|---|---|---|---|"]
    for name, var in ds.variables.items():
        text = " ".join(str(var.attrs[k]) for k in ("long_name", "comment") if k in var.attrs)
        rows.append(f"| `{name}` | {', '.join(var.dims)} | {var.dtype} | {_cell(var.attrs.get('units', ''))} "
                    f"| {_cell(text)} |")
    rows += ["", "Attributes of the dataset: " + ", ".join(f"`{k}`" for k in ds.attrs) + "."]
    return "\n".join(rows) + "\n"


def write_dataset_page(page: Path) -> Path:
    page.parent.mkdir(parents=True, exist_ok=True)
    text = dataset_variables_markdown()
    if not page.is_file() or page.read_text() != text:
        page.write_text(text)
    return page
