"""First run: a pool's second worker compiles the late kernels while the first starts a level.

The split only pays if the warm-up compiles exactly the specializations a level uses (same
argument types; one specialization per kernel), and it must not change what a run computes."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from contactvib.sweeps.backends import LocalPool, run_levels

SRC = str(Path(__file__).resolve().parents[2] / "src")


def _square(x):
    return x * x


def _record(path):
    Path(path).write_text(str(os.getpid()))
    return "ignored"


def _fails():
    raise RuntimeError("warm-up failed")


def test_warm_up_runs_once_and_its_result_is_dropped(tmp_path):
    got = {}
    flag = tmp_path / "warm"
    run_levels({a: (a,) for a in (1.0, 2.0, 3.0)}, _square, LocalPool(2), got.__setitem__,
               warm_up=(_record, (str(flag),)))
    assert got == {1.0: 1.0, 2.0: 4.0, 3.0: 9.0}  # levels only; the warm-up's value is not a level
    assert flag.read_text().isdigit() and int(flag.read_text()) != os.getpid()  # ran in a worker


def test_a_failing_warm_up_does_not_stop_the_levels():
    got = {}
    run_levels({a: (a,) for a in (1.0, 2.0)}, _square, LocalPool(2), got.__setitem__, warm_up=(_fails, ()))
    assert got == {1.0: 1.0, 2.0: 4.0}


@pytest.mark.slow
def test_warm_up_compiles_only_what_a_level_uses(tmp_path):
    """Cold cache, one process: the warm-up, then a level and its dataset. Every kernel that was
    compiled has one specialization, apart from the flow's small helpers that are specialized on
    purpose (constant component indices and stage counts of DOP853)."""
    script = textwrap.dedent("""
        import dataclasses, importlib, pkgutil, numba
        import contactvib._kernels as K
        from contactvib.model import ContactModel
        from contactvib.sweeps.dataset import level_dataset
        from contactvib.sweeps.sweep import SweepSettings, compile_late_kernels_first, trace_level
        m = ContactModel()
        st = dataclasses.replace(SweepSettings(), fmin_hz=100.0, fmax_hz=130.0, df_hz=1.0)
        compile_late_kernels_first(m, st)
        level_dataset(m, trace_level(m, pa_over_q=0.9, settings=st), dataclasses.asdict(st))
        for info in pkgutil.iter_modules(K.__path__):
            mod = importlib.import_module("contactvib._kernels." + info.name)
            for name, obj in vars(mod).items():
                if isinstance(obj, numba.core.registry.CPUDispatcher) and obj.__module__ == mod.__name__:
                    print(info.name, name, len(obj.signatures))
    """)
    env = dict(os.environ, XDG_CACHE_HOME=str(tmp_path), PYTHONPATH=SRC)
    env.pop("NUMBA_CACHE_DIR", None)
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True,
                         timeout=600, check=True).stdout
    counts = {tuple(line.split()[:2]): int(line.split()[2]) for line in out.splitlines()}
    on_purpose = {("flow", "_stages"), ("dop853", "dense_value"), ("flow", "dense_root"),
                  ("roots", "illinois_update"), ("roots", "illinois_trial"), ("dop853", "step_factor"),
                  ("series_roots", "poly"), ("series_roots", "poly_root")}
    for root in (("settle", "settle"), ("trace", "trace"), ("describe", "describe_point"),
                 ("shooting", "newton_orbit"), ("describe", "lyapunov_strobe"),
                 ("table", "_settle_known_threads")):
        assert counts[root] == 1, root
    assert {k: n for k, n in counts.items() if n > 1 and k not in on_purpose} == {}
