#!/usr/bin/env python
"""The cost of the verdict in a system's sweep: ``sweep_system_level`` with and without ``nonperiodic``.

Run from the repository root::

    python -m benchmarks system_sweep_verdict            # both cases (about 2 minutes)
    python -m benchmarks system_sweep_verdict --quick    # the two-DOF case only

Cases (the grids of ``contactvib resonance --system``, a search every 10 points, 6 starts):

* ``two_dof_stop``: ``examples/two_dof_stop.toml`` at P_a = 0.1 N, 0.09–0.1 Hz, Δf = 0.0005 Hz
  (chaos at 0.0955–0.0975 Hz, orbits of period 10 and 35 above kmax = 8);
* ``rocking``: the rocking unit at 0.65 Q over its default grid 297–3215 Hz, Δf = 50 Hz.

For each, in one process after a warm-up (compile cache): the wall time of the sweep with
``SystemSweepSettings(nonperiodic=False)`` (periodic attractors only) and with the verdict (the
default), their ratio, the rows of each and the non-periodic rows; and whether the periodic rows
without the verdict are the first rows with it, bit for bit (period, state, multipliers, measures).
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time
from pathlib import Path

import numpy as np

from benchmarks import result_path

ROOT = Path(__file__).resolve().parents[1]


def _cases(quick: bool) -> dict:
    from contactvib import ContactModel
    from contactvib.model.rocking import rocking_system
    from contactvib.model.system_file import load_system

    cases = {"two_dof_stop": (load_system(ROOT / "examples" / "two_dof_stop.toml"), 0.1, (0.09, 0.1, 0.0005))}
    if not quick:
        model = ContactModel()
        cases["rocking"] = (rocking_system(model), 0.65 * model.Q, (297.0, 3215.0, 50.0))
    return cases


def _same(a: dict, b: dict) -> bool:
    keys = ("i", "k", "z", "mu", "closure", "origin", "found_by", "basin", "strobe", "minima")
    return all(np.array_equal(np.asarray(a[k]), np.asarray(b[k]), equal_nan=np.asarray(a[k]).dtype.kind in "fc")
               for k in keys) and all(np.array_equal(np.asarray(a["columns"][k]), np.asarray(b["columns"][k]))
                                      for k in a["columns"])


def run_case(system, pa: float, grid: tuple) -> dict:
    from contactvib.sweeps.system_sweep import SystemSweepSettings, sweep_system_level

    out, levels = {}, {}
    for nonperiodic in (False, True):
        st = SystemSweepSettings(*grid, search_every=10, n_starts=6, nonperiodic=nonperiodic)
        t0 = time.perf_counter()
        levels[nonperiodic] = lv = sweep_system_level(system, pa, st)
        out["verdict" if nonperiodic else "periodic_only"] = {
            "wall_s": time.perf_counter() - t0, "rows": len(lv.rows),
            "nonperiodic_rows": sum(r["k"] == 0 for r in lv.rows),
            "above_kmax_rows": sum(r["k"] > st.kmax for r in lv.rows)}
    old, new = levels[False].rows, levels[True].rows
    out["ratio_verdict_over_periodic_only"] = out["verdict"]["wall_s"] / out["periodic_only"]["wall_s"]
    out["periodic_rows_unchanged"] = len(new) >= len(old) and all(_same(a, b) for a, b in zip(old, new))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="the two-DOF case only")
    p.add_argument("--out", default=str(result_path(__name__)))
    a = p.parse_args(argv)
    import numba

    from contactvib.sweeps.system_sweep import SystemSweepSettings, sweep_system_level

    cases = _cases(a.quick)
    system, pa, _grid = cases["two_dof_stop"]
    sweep_system_level(system, pa, SystemSweepSettings(0.095, 0.0955, 0.0005, search_every=1, n_starts=1))  # compile
    R = {"environment": {"python": platform.python_version(), "numpy": np.__version__, "numba": numba.__version__,
                         "threads": numba.get_num_threads()},
         "command": "python -m benchmarks system_sweep_verdict" + (" --quick" if a.quick else ""), "cases": {}}
    for name, (system, pa, grid) in cases.items():
        R["cases"][name] = r = run_case(system, pa, grid)
        print(f"{name}: {r['periodic_only']['wall_s']:.1f} s periodic only ({r['periodic_only']['rows']} rows), "
              f"{r['verdict']['wall_s']:.1f} s with the verdict ({r['verdict']['rows']} rows, "
              f"{r['verdict']['nonperiodic_rows']} non-periodic, {r['verdict']['above_kmax_rows']} above kmax): "
              f"ratio {r['ratio_verdict_over_periodic_only']:.2f}; periodic rows unchanged: "
              f"{r['periodic_rows_unchanged']}", flush=True)
    Path(a.out).write_text(json.dumps(R, indent=1) + "\n")
    return 0 if all(r["periodic_rows_unchanged"] for r in R["cases"].values()) else 1


if __name__ == "__main__":
    sys.exit(main())
