"""The benchmarks' runner (``python -m benchmarks``): it lists every ``bench_*.py``, each
benchmark takes its options through it and writes one ``results_<name>.json``, and no benchmark
edits ``sys.path`` (contactvib is imported as installed, the benchmarks as a package)."""

import ast
import subprocess
import sys
from pathlib import Path

import benchmarks
from benchmarks import names, result_path

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted((ROOT / "benchmarks").glob("*.py"))


def test_the_runner_lists_every_benchmark_with_its_result_file():
    out = subprocess.run([sys.executable, "-m", "benchmarks"], cwd=ROOT, capture_output=True, text=True,
                         check=True).stdout
    found = sorted(p.stem.removeprefix("bench_") for p in (ROOT / "benchmarks").glob("bench_*.py"))
    assert found and names() == found
    for name in found:
        assert f"  {name} " in out and f"results_{name}.json" in out


def test_an_unknown_benchmark_is_refused_in_one_line():
    r = subprocess.run([sys.executable, "-m", "benchmarks", "nosuch"], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "no benchmark nosuch" in r.stderr


def test_every_benchmark_takes_argv_and_writes_its_one_result_file():
    for name in names():
        tree = ast.parse((ROOT / "benchmarks" / f"bench_{name}.py").read_text(encoding="utf-8"))
        main = next(f for f in tree.body if isinstance(f, ast.FunctionDef) and f.name == "main")
        assert [a.arg for a in main.args.args] == ["argv"], name
        assert "result_path(__name__)" in ast.unparse(main), name
    assert result_path("benchmarks.bench_atlas") == benchmarks.HERE / "results_atlas.json"


def test_result_files_belong_to_a_benchmark():
    stale = [p.name for p in (ROOT / "benchmarks").glob("results_*.json")
             if p.stem.removeprefix("results_") not in names()]
    assert not stale


def test_no_benchmark_touches_sys_path():
    for path in FILES:
        text = path.read_text(encoding="utf-8")
        assert "sys.path" not in text, path.name
