"""The documentation's build-time pages (docs/_ext/generate.py): every public name gets an API
entry, every committed benchmark result a table, every paper statement a row."""

from __future__ import annotations

import importlib
import importlib.util
import json
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "docs" / "_ext"))
generate = importlib.import_module("generate")


def test_every_public_name_is_documented_once():
    entries = generate.api_entries()
    assert list(entries) == list(generate.API_PACKAGES)
    for package, rows in entries.items():
        public = [n for n in importlib.import_module(package).__all__ if not n.startswith("__")]
        assert [n for n, _ in rows] == public, package
        for _name, home in rows:  # a name documented elsewhere points at an earlier package
            assert home is None or generate.API_PACKAGES.index(home) < generate.API_PACKAGES.index(package)
    top = dict(entries["contactvib"])
    assert top and all(home is None for home in top.values())
    # a name importable from contactvib and from its package is documented under contactvib
    assert dict(entries["contactvib.model"])["ContactModel"] == "contactvib"
    assert dict(entries["contactvib.model"])["PowerLaw"] is None


def test_api_pages_hold_a_directive_per_name(tmp_path):
    pages = generate.write_api_pages(tmp_path)
    text = {p.stem: p.read_text() for p in pages}
    assert list(text) == [t[0] for t in generate.API_TOPICS]
    assert ".. autofunction:: contactvib.find_attractors" in text["steady"]
    assert ".. autoclass:: contactvib.ContactModel" in text["model"]
    assert ".. autoclass:: contactvib.model.PowerLaw" in text["model"]
    assert ":py:obj:`ContactModel <contactvib.ContactModel>`" in text["model"]
    assert ".. autofunction:: contactvib.continue_orbit" in text["continuation"]
    assert ".. autofunction:: contactvib.hb_solve" in text["frequency"]
    assert ".. autofunction:: contactvib.resonance_dataset" in text["sweeps"]
    assert ".. autoclass:: contactvib.ContactvibError" in text["errors"]
    # every documented name is on exactly one page
    directives = [line.split("::")[1].split()[0] for t in text.values() for line in t.splitlines()
                  if line.startswith(".. auto")]
    expected = [f"{package}.{name}" for package, rows in generate.api_entries().items()
                for name, home in rows if home is None]
    assert sorted(directives) == sorted(expected)


def test_api_index_lists_every_topic_page():
    index = (ROOT / "docs" / "api" / "index.md").read_text()
    listed = [line.strip().removeprefix("generated/") for line in index.splitlines()
              if line.strip().startswith("generated/")]
    assert listed == [t[0] for t in generate.API_TOPICS]


def test_benchmarks_page_has_one_table_per_result_file():
    files = sorted((ROOT / "benchmarks").glob("results_*.json"))
    text = generate.benchmarks_markdown(ROOT / "benchmarks")
    assert text.count("\n## `") == len(files) >= 1
    f = files[0]
    key, value = next(generate._flatten(json.loads(f.read_text())))
    assert f"| `{key}` | {generate._cell(value)} |" in text


@pytest.mark.parametrize("value, cell", [(1.23456789, "1.23457"), ([1, 2], "1, 2"), ("a|b", "a\\|b"),
                                         (list(range(20)), "0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, … (20 values)")])
def test_benchmark_cells(value, cell):
    assert generate._cell(value) == cell


def test_statements_table_has_every_statement():
    src = ROOT / "src" / "contactvib"
    ids = list(generate.statements(src / "data" / "paper_statements.md"))
    assert ids[0] == "S2.1" and ids[-1] == "S4.7" and len(ids) == 20
    table = generate.statements_markdown(src, ROOT / "tests")
    rows = [r for r in table.splitlines() if r.startswith("| S")]
    assert [r.split(" | ")[0][2:] for r in rows] == ids
    fig4 = next(r for r in rows if r.startswith("| S4.1 "))
    assert "`fig4_*.png`" in fig4 and "tests/steady/test_attractors_paper.py" in fig4


def test_dataset_table_lists_every_variable_with_its_units():
    text = generate.dataset_variables_markdown()
    for name, units in [("pa_over_q", "Q"), ("fe_hz", "Hz"), ("app_um", "um"), ("strobe_ydot_mm_s", "mm/s"),
                        ("branch_reached_by_sweep", "1"), ("trace_stop", "")]:
        assert any(r.startswith(f"| `{name}` |") and r.split(" | ")[3] == units for r in text.splitlines()), name
    assert "`levels_pa_over_q`" in text and "`model`" in text


def test_tutorial_figures_are_small_and_shown():
    """The committed figures of docs/make_tutorial_figures.py: each made by a command of its table,
    shown by a tutorial page, under 200 KB (3 MB together)."""
    spec = importlib.util.spec_from_file_location("make_tutorial_figures", ROOT / "docs" / "make_tutorial_figures.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    made = {target for _, figures in script.FIGURES.values() for target in figures.values()}
    files = {p.name: p.stat().st_size for p in (ROOT / "docs" / "_static" / "tutorials").glob("*.png")}
    assert set(files) == made
    assert all(size < 200_000 for size in files.values()) and sum(files.values()) < 3_000_000
    pages = "".join(p.read_text() for p in (ROOT / "docs" / "tutorials").glob("*.md"))
    assert all(f"_static/tutorials/{name}" in pages for name in files), sorted(n for n in files if n not in pages)
