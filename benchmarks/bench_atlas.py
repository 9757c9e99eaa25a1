"""Benchmark of ``contactvib atlas``, measured in one run:

* a slice of the 96-level atlas (``--levels`` levels spread evenly over 0.05–1.0 Q, 30–2000 Hz
  at 1 Hz, warm numba cache) on the local pool with 2 workers: wall time, CPU seconds per level
  (this process's children, so also valid on a shared machine), levels per minute, and the
  96-level time extrapolated from the CPU seconds per level on 2 cores;
* the same slice on a Dask ``LocalCluster`` with 1 and with 2 workers: parallel efficiency
  t(1) / (2 t(2));
* ``contactvib paper`` with an empty numba cache (``NUMBA_CACHE_DIR`` set to a new temporary
  folder: the package then leaves numba's cache folder alone, see ``_kernels/__init__.py``) and
  again warm;
* ``contactvib basins --pa 0.65 --fe 360 --grid 400x400``.

Run from the repository root::

    python -m benchmarks atlas             # writes benchmarks/results_atlas.json
    python -m benchmarks atlas --levels 4  # a smaller slice
    python -m benchmarks atlas --full-atlas --paper-runs 3  # also the whole 96-level atlas (~6 min), paper cold 3x

``--full-atlas`` runs the reference atlas's command, ``contactvib atlas --pa-min 0.05 --pa-max 1.0
--npa 96 --fmin 30 --fmax 2000 --df 1`` (local pool, 2 workers, warm cache): its wall time is the
96-level figure, measured rather than extrapolated from the slice. ``--paper-runs N`` repeats the
cold and warm ``contactvib paper`` pair N times (each cold run with a new empty cache folder): on
a shared 2-core machine one run varies by a few seconds.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks import result_path

HERE = Path(__file__).resolve().parent


def _run(args, env=None) -> dict:
    """Wall and CPU seconds (user + system of the finished children) of one CLI run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "contactvib", *args], check=True, env=env,
                   stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall_s": round(wall, 2), "cpu_s": round(cpu, 2)}


def _atlas(levels, tmp, name, backend) -> dict:
    out = Path(tmp) / name
    r = _run(["atlas", "--pa", *levels, "--no-progress", *backend, "--out", str(out)])
    r["levels"] = len(levels)
    r["levels_per_min"] = round(60 * len(levels) / r["wall_s"], 2)
    r["cpu_s_per_level"] = round(r["cpu_s"] / len(levels), 2)
    r["atlas_mb"] = round((out / "atlas.nc").stat().st_size / 1e6, 2)
    print(name, r, flush=True)
    return r


def _full_atlas(tmp) -> dict:
    """The reference 96-level atlas, 30–2000 Hz at 1 Hz, local pool with 2 workers."""
    out = Path(tmp) / "atlas96"
    r = _run(["atlas", "--pa-min", "0.05", "--pa-max", "1.0", "--npa", "96", "--fmin", "30",
              "--fmax", "2000", "--df", "1", "--workers", "2", "--no-progress", "--out", str(out)])
    r["levels"] = 96
    r["wall_min"] = round(r["wall_s"] / 60, 2)
    r["levels_per_min"] = round(60 * 96 / r["wall_s"], 2)
    r["cpu_s_per_level"] = round(r["cpu_s"] / 96, 2)
    r["atlas_mb"] = round((out / "atlas.nc").stat().st_size / 1e6, 1)
    print("atlas96", r, flush=True)
    return r


def main(argv=None) -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--levels", type=int, default=12)
    ap.add_argument("--no-dask", action="store_true")
    ap.add_argument("--full-atlas", action="store_true", help="also the 96-level atlas")
    ap.add_argument("--paper-runs", type=int, default=1)
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    levels = [f"{p:.4g}" for p in np.linspace(0.05, 1.0, args.levels)]
    res = {"machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
           "load_average_at_start": os.getloadavg(), "slice_pa_over_q": levels}
    with tempfile.TemporaryDirectory() as tmp:
        _run(["atlas", "--pa", "0.5", "--fmin", "300", "--fmax", "320", "--no-progress",
              "--out", str(Path(tmp) / "warmup")])  # the cache warm
        pool = res["pool_2_workers"] = _atlas(levels, tmp, "pool2", ["--workers", "2"])
        res["extrapolated_96_levels_min_2_cores"] = round(96 * pool["cpu_s_per_level"] / 2 / 60, 2)
        if not args.no_dask:
            d1 = res["dask_1_worker"] = _atlas(levels, tmp, "dask1", ["--dask-workers", "1"])
            d2 = res["dask_2_workers"] = _atlas(levels, tmp, "dask2", ["--dask-workers", "2"])
            res["dask_parallel_efficiency"] = round(d1["wall_s"] / (2 * d2["wall_s"]), 3)
        if args.full_atlas:
            res["atlas_96_levels"] = _full_atlas(tmp)
        runs = []
        for j in range(args.paper_runs):
            env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(tmp) / f"numba-cold{j}"))
            cold = _run(["paper", "--no-progress", "--out", str(Path(tmp) / f"p_cold{j}")], env)
            warm = _run(["paper", "--no-progress", "--out", str(Path(tmp) / f"p_warm{j}")], env)
            print("paper", cold, warm, flush=True)
            runs.append((cold, warm))
        res["paper_first_run"], res["paper_warm"] = runs[0]
        if len(runs) > 1:
            res["paper_runs"] = [{"first_run": c, "warm": w} for c, w in runs]
            res["paper_first_run_median_s"] = float(np.median([c["wall_s"] for c, _ in runs]))
            res["paper_warm_median_s"] = float(np.median([w["wall_s"] for _, w in runs]))
        res["basins_400x400"] = _run(["basins", "--pa", "0.65", "--fe", "360", "--grid", "400x400",
                                      "--out", str(Path(tmp) / "basins")])
        print("basins", res["basins_400x400"], flush=True)
    res["targets"] = {"atlas_96_levels_min": 6.0, "dask_efficiency": 0.9, "paper_first_run_s": 60.0,
                      "basins_400_s": 30.0}
    Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
