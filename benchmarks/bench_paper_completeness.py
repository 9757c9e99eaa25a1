"""How many attractors a resonance dataset lacks at random grid points (``query --completeness``).

For each dataset given, :func:`contactvib.sweeps.completeness.check_completeness` searches
``--points`` random grid points again by brute force (256 box starts + ballistic seeds, up to
the dataset's kmax, longer periods by the search's verdict), once per ``--seeds`` value, and the
result lists per seed the attractors the dataset lacks, how many of them have a basin of at least
0.5 % of the box (issue 34's bar), and the fraction of the search's attractors the dataset holds::

    python -m benchmarks paper_completeness --datasets OLD/paper.nc paper/paper.nc

Each dataset is labelled by its file and its ``settings`` record (kmax, fill-in).
"""

from __future__ import annotations

import argparse
import json
import time

from benchmarks import result_path

#: The basin fraction [1] from which a missing attractor counts against the dataset.
BASIN_BAR = 0.005


def check(path: str, seeds, n_points: int) -> dict:
    """The completeness reports of one dataset, one per seed, with their counts."""
    from contactvib.sweeps.completeness import check_completeness
    from contactvib.sweeps.stored import open_resonance

    data = open_resonance(path)
    settings = json.loads(data.ds.attrs["settings"])
    runs = []
    for seed in seeds:
        t0 = time.process_time()
        rep = check_completeness(data, n_points=n_points, seed=seed)
        runs.append({"seed": seed, "points": rep["points_checked"], "missing": len(rep["missing"]),
                     "missing_basin_ge_0.5pct": sum(m["basin_fraction"] >= BASIN_BAR for m in rep["missing"]),
                     "found_fraction": round(rep["found_fraction"], 4),
                     "cpu_s": round(time.process_time() - t0, 1), "missing_list": rep["missing"]})
    return {"dataset": path, "points": int(data.ds.sizes["point"]),
            "kmax": settings.get("kmax"), "fill_in_per_octave": settings.get("fill_in_per_octave", 0.0),
            "runs": runs}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--datasets", nargs="+", default=["paper/paper.nc"], help="paper.nc / resonance.nc files")
    ap.add_argument("--seeds", default="1,2,3", help="comma-separated seeds of the random points")
    ap.add_argument("--points", type=int, default=200, help="grid points per seed")
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    seeds = [int(s) for s in args.seeds.split(",")]
    results = []
    for path in args.datasets:
        res = check(path, seeds, args.points)
        results.append(res)
        for r in res["runs"]:
            print(f"{path} (kmax {res['kmax']}, fill-in {res['fill_in_per_octave']}/octave): seed {r['seed']}: "
                  f"{r['missing']} missing, {r['missing_basin_ge_0.5pct']} with basin >= 0.5 %, "
                  f"found fraction {r['found_fraction']}", flush=True)
    with open(args.out, "w") as fh:
        json.dump({"basin_bar": BASIN_BAR, "datasets": results}, fh, indent=1)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
