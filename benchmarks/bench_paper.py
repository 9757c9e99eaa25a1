"""Benchmark of ``contactvib paper``: wall time on this machine, growth with the number of
frequencies, and the numba compile time measured separately.

Run from the repository root after ``pip install .``::

    python benchmarks/bench_paper.py            # writes benchmarks/results_paper.json

* compile time: the same small sweep (one level, 300–340 Hz, 1 Hz, multi-start on) run once with
  an empty numba cache directory (cold: every kernel compiled) and once more (warm); the difference
  is the compile time, reported apart from the runs below;
* ``contactvib paper`` at Δf = 4, 2 and 1 Hz (493, 986 and 1971 frequencies per level, 8 levels,
  both sweep directions, seeds and multi-start), each on a warm cache, into a fresh folder —
  the 1 Hz run is the command of the README. Points and branches come from the dataset.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks import result_path

HERE = Path(__file__).resolve().parent


def _run(args, env=None) -> float:
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "contactvib", *args], check=True, env=env,
                   stdout=subprocess.DEVNULL)
    return time.perf_counter() - t


def main(argv=None) -> None:
    import xarray as xr

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)

    small = ["resonance", "--pa", "0.65", "--fmin", "300", "--fmax", "340", "--df", "1",
             "--workers", "1", "--no-progress"]
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(tmp) / "numba-cache"))
        cold = _run([*small, "--out", str(Path(tmp) / "cold")], env)
        warm = _run([*small, "--out", str(Path(tmp) / "warm")], env)
        runs = []
        for df in (4.0, 2.0, 1.0):
            out = Path(tmp) / f"paper_df{df:g}"
            _run(["paper", "--df", f"{df:g}", "--no-progress", "--out", str(out)])  # warm-up
            wall = _run(["paper", "--df", f"{df:g}", "--no-progress", "--out", str(out) + "_2"])
            with xr.open_dataset(out.parent / (out.name + "_2") / "paper.nc") as ds:
                n_f = int(round((2000.0 - 30.0) / df)) + 1
                runs.append({"df_hz": df, "frequencies_per_level": n_f, "levels": 8,
                             "wall_s": round(wall, 2), "points": int(ds.sizes["point"]),
                             "branches": int(ds.sizes["branch"]),
                             "ms_per_point": round(1e3 * wall / ds.sizes["point"], 3)})
            print(runs[-1], flush=True)
    res = {
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
        "compile_s": round(cold - warm, 2),
        "small_sweep_cold_s": round(cold, 2),
        "small_sweep_warm_s": round(warm, 2),
        "paper_runs": runs,
        "growth_1hz_over_4hz": round(runs[-1]["wall_s"] / runs[0]["wall_s"], 3),
        "target_s": 60.0,
    }
    Path(args.out).write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
