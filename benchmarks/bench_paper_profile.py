"""Where ``contactvib paper``'s time goes: wall and CPU seconds per level and per stage.

Run from the repository root (contactvib importable)::

    python -m benchmarks paper_profile      # writes benchmarks/results_paper_profile.json

The paper's eight levels are run in this process, one after the other (``workers=1``), on a warm
numba cache (a first small run compiles), with every stage the sweep marks
(``contactvib.sweeps.stage_times``) timed exclusively: the settling of the grid's ends, the
compiled tracer, the multi-start probes (box starts settled against the known attractors), their
perturbation seeds and Newton seeds, the late Newton seeds, the unstable parts' continuation, the
non-periodic verdict, the level's dataset (descriptions, Lyapunov exponents), the perturbation
overlay, the figures, the merge, the NetCDF write and the index page. ``other`` is the run's wall
time that no stage claims. The real ``contactvib paper`` runs the levels in two processes, so
its wall time is about half the sum here; the shares are what this benchmark is for.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import tempfile
import time
from pathlib import Path

from benchmarks import result_path


def main(argv=None) -> None:
    from contactvib import ContactModel
    from contactvib.sweeps.paper import reproduce_paper
    from contactvib.sweeps.settings import SweepSettings
    from contactvib.sweeps.stage_times import recording

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(result_path(__name__)))
    ap.add_argument("--df", type=float, default=1.0, help="frequency step [Hz] (the paper's: 1)")
    args = ap.parse_args(argv)

    model = ContactModel()
    with tempfile.TemporaryDirectory() as tmp:
        reproduce_paper(model, out=Path(tmp) / "warm", levels=(0.65,), workers=1, progress=False,
                        settings=SweepSettings(fmin_hz=300.0, fmax_hz=340.0))  # compile / load the cache
        t0, c0 = time.perf_counter(), time.process_time()
        with recording() as times:
            reproduce_paper(model, out=Path(tmp) / "paper", workers=1, progress=False,
                            settings=SweepSettings(df_hz=args.df))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    stages: dict = {}
    levels: dict = {}
    for (level, name), v in times.items():
        s = stages.setdefault(name, {"wall_s": 0.0, "cpu_s": 0.0, "calls": 0})
        for key in s:
            s[key] += v[key]
        if level is not None:
            levels.setdefault(f"{level:g}", {})[name] = round(v["wall_s"], 3)
    claimed = sum(s["wall_s"] for s in stages.values())
    stages["other"] = {"wall_s": wall - claimed, "cpu_s": cpu - sum(s["cpu_s"] for s in stages.values()),
                       "calls": 0}
    order = sorted(stages, key=lambda n: -stages[n]["wall_s"])
    res = {
        "machine": f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores",
        "df_hz": args.df,
        "workers": 1,
        "wall_s": round(wall, 2),
        "cpu_s": round(cpu, 2),
        "stages": {n: {"wall_s": round(stages[n]["wall_s"], 3), "cpu_s": round(stages[n]["cpu_s"], 3),
                       "share": round(stages[n]["wall_s"] / wall, 4), "calls": stages[n]["calls"]}
                   for n in order},
        "per_level_wall_s": {p: dict(sorted(v.items(), key=lambda kv: -kv[1]))
                             for p, v in sorted(levels.items(), key=lambda kv: float(kv[0]))},
    }
    Path(args.out).write_text(json.dumps(res, indent=1, ensure_ascii=False) + "\n")
    print(json.dumps(res, indent=1, ensure_ascii=False))


if __name__ == "__main__":
    main()
