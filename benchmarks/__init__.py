"""contactvib's benchmarks: one module ``bench_<name>.py`` per benchmark, run by
``python -m benchmarks NAME [NAME ...] [ARGS ...]`` from the repository root (with contactvib
importable: ``pip install -e .`` or ``PYTHONPATH=src``).

Each benchmark writes one current result file, ``benchmarks/results_<name>.json`` (its ``--out``
option chooses another path), and takes its own options after the names; ``python -m benchmarks``
alone lists the benchmarks. ``compare_datasets.py`` is a tool, not a benchmark.
"""

from __future__ import annotations

import importlib
from pathlib import Path

HERE = Path(__file__).resolve().parent

__all__ = ["HERE", "load", "names", "result_path", "summary"]


def names() -> list[str]:
    """The benchmarks' names: the files ``bench_<name>.py`` of this folder, sorted."""
    return sorted(p.stem.removeprefix("bench_") for p in HERE.glob("bench_*.py"))


def result_path(module: str) -> Path:
    """``benchmarks/results_<name>.json`` of a benchmark module (``__name__`` or its name)."""
    return HERE / f"results_{module.rsplit('.', 1)[-1].removeprefix('bench_')}.json"


def load(name: str):
    """The module of benchmark ``name``."""
    return importlib.import_module(f"benchmarks.bench_{name}")


def summary(name: str) -> str:
    """The first line of benchmark ``name``'s docstring, read without importing it."""
    import ast

    doc = ast.get_docstring(ast.parse((HERE / f"bench_{name}.py").read_text(encoding="utf-8"))) or ""
    return doc.strip().splitlines()[0] if doc.strip() else ""
