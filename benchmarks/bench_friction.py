"""Benchmark of the friction columns of a resonance sweep (the target: a 1 Hz sweep of
one level with friction costs no more than 1.5x the same sweep without).

Runs ``contactvib resonance --pa 0.65 --df 1 --workers 1`` (30-2000 Hz, warm numba cache) with and
without ``--friction default``, alternately, ``--repeats`` times each, and reports the wall and CPU
seconds of each run (CPU: user + system of the finished child, also valid on a shared machine)
and the ratios with/without of the medians, measured within this one run.

Run from the repository root::

    python -m benchmarks friction               # writes benchmarks/results_friction.json
    python -m benchmarks friction --fmax 700    # a shorter grid
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


def _run(args) -> dict:
    """Wall and CPU seconds of one CLI run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([sys.executable, "-m", "contactvib", *args], check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return {"wall_s": round(wall, 2), "cpu_s": round(cpu, 2)}


def _points(path: Path) -> dict:
    import xarray as xr

    with xr.open_dataset(path) as ds:
        out = {"points": int(ds.sizes["point"]), "periodic": int((ds["period"].values > 0).sum())}
        if "friction_ratio" in ds:
            fr = ds["friction_ratio"].values
            out.update(friction_computed=int(np.isfinite(fr).sum()),
                       friction_settled=int((ds["friction_settled"].values == 1).sum()),
                       friction_ratio_min=float(np.nanmin(fr)), friction_ratio_max=float(np.nanmax(fr)))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pa", default="0.65")
    ap.add_argument("--fmin", default="30")
    ap.add_argument("--fmax", default="2000")
    ap.add_argument("--friction", default="default", help="the --friction value of the run with friction")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--out", default=str(result_path(__name__)))
    a = ap.parse_args(argv)
    base = ["resonance", "--pa", a.pa, "--fmin", a.fmin, "--fmax", a.fmax, "--df", "1", "--workers", "1",
            "--no-progress"]
    runs = {"without": [], "with": []}
    info = {}
    with tempfile.TemporaryDirectory() as tmp:
        _run([*base, "--fmax", str(float(a.fmin) + 20), "--friction", a.friction, "--out", f"{tmp}/warm"])  # compile
        for r in range(a.repeats):
            for name, extra in (("without", []), ("with", ["--friction", a.friction])):
                out = Path(tmp) / f"{name}{r}"
                runs[name].append(_run([*base, *extra, "--out", str(out)]))
                info[name] = _points(out / "resonance.nc")
                print(name, runs[name][-1], flush=True)
    med = {k: {m: float(np.median([x[m] for x in v])) for m in ("wall_s", "cpu_s")} for k, v in runs.items()}
    result = {
        "command": "contactvib resonance " + " ".join(base[1:]) + f" [--friction {a.friction}]",
        "runs": runs, "median": med,
        "ratio_cpu": round(med["with"]["cpu_s"] / med["without"]["cpu_s"], 3),
        "ratio_wall": round(med["with"]["wall_s"] / med["without"]["wall_s"], 3),
        "datasets": info,
        "machine": {"python": platform.python_version(), "cpus": os.cpu_count(),
                    "load_avg_1min": os.getloadavg()[0]},
        "note": "CPU seconds include the interpreter start, the kernels' cache load and the two figures of "
                "each run; the ratios are of the medians within this one run",
    }
    Path(a.out).write_text(json.dumps(result, indent=1) + "\n")
    print(json.dumps({k: result[k] for k in ("median", "ratio_cpu", "ratio_wall")}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
