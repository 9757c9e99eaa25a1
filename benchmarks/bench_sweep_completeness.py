"""Does the sweep miss attractors? Compare a full attractor search with a resonance dataset.

At grid points (P_a/Q, f_e) of a ``paper.nc``/``resonance.nc`` dataset, run
:func:`contactvib.steady.attractors.find_attractors` (512 box starts + ballistic seeds) and check
that every attractor it lists is a row of the dataset at that point: a periodic one by the same
period and A_pp to ``--rtol`` relative, a non-periodic one by any non-periodic row there.
Writes a JSON with every point's attractors and the missing ones::

    python -m benchmarks sweep_completeness /work/base_paper/paper.nc

The default points: 5 per level of the paper (8 levels × 5 = 40 points), spread over 30–2000 Hz
geometrically, plus 0.60 Q / 500 Hz.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings

import numpy as np
import xarray as xr

from benchmarks import result_path
from contactvib.model import ContactModel
from contactvib.steady.attractors import UnsettledWarning, find_attractors

#: Frequencies [Hz] checked at every level (geometric, 30–2000 Hz, on the 1 Hz grid).
DEFAULT_F = (60.0, 150.0, 360.0, 800.0, 1700.0)


def default_points(levels) -> list[tuple[float, float]]:
    """(P_a/Q, f_e) pairs: every level × :data:`DEFAULT_F` (8 × 5 = 40 for the paper)."""
    return [(float(pa), f) for pa in levels for f in DEFAULT_F]


def missing_at(ds: xr.Dataset, model: ContactModel, pa: float, fe: float, n_starts: int = 512,
               rtol: float = 1e-6) -> dict:
    """The full search's attractors at (pa, fe) and those the dataset lacks."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsettledWarning)
        res = find_attractors(model.excitation(pa, fe), n_starts=n_starts)
    sel = (np.abs(ds["pa_over_q"].values - pa) < 1e-12) & (np.abs(ds["fe_hz"].values - fe) < 1e-9)
    kind = ds["kind"].values[sel]
    period = ds["period"].values[sel]
    app = ds["app_um"].values[sel]
    out = {"pa_over_q": pa, "fe_hz": fe, "attractors": [], "missing": [],
           "dataset_rows": int(sel.sum()), "dataset_nonperiodic": int(np.sum(kind != "periodic"))}
    for a in res.attractors:
        d = {"period": a.period, "minima_per_period": a.minima_per_period, "app_um": a.app_um,
             "basin": a.basin_fraction, "kind": a.kind}
        out["attractors"].append(d)
        if a.period is not None and a.kind == "periodic":
            hit = np.any((kind == "periodic") & (period == a.period)
                         & (np.abs(app - a.app_um) <= rtol * max(abs(a.app_um), 1e-300)))
        else:
            hit = np.any(kind != "periodic")
        if not hit:
            out["missing"].append(d)
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("dataset")
    p.add_argument("--out", default=str(result_path(__name__)))
    p.add_argument("--starts", type=int, default=512)
    p.add_argument("--points", default=None, help="PA:FE,PA:FE,... (default: levels × DEFAULT_F + 0.6:500)")
    a = p.parse_args(argv)
    ds = xr.open_dataset(a.dataset)
    model = ContactModel(**json.loads(ds.attrs["model"]))
    if a.points:
        pts = [tuple(float(x) for x in s.split(":")) for s in a.points.split(",")]
    else:
        pts = default_points(json.loads(ds.attrs["levels_pa_over_q"]) if isinstance(
            ds.attrs["levels_pa_over_q"], str) else ds.attrs["levels_pa_over_q"])
        if (0.6, 500.0) not in pts:
            pts.append((0.6, 500.0))
    t0 = time.process_time()
    results = []
    for pa, fe in pts:
        r = missing_at(ds, model, pa, fe, a.starts)
        results.append(r)
        for m in r["missing"]:
            print(f"missing at {pa:g} Q, {fe:g} Hz: period {m['period']}, {m['minima_per_period']} minima, "
                  f"A_pp {m['app_um']:.4g} um, basin {m['basin']:.3%} ({m['kind']})", flush=True)
    n_att = sum(len(r["attractors"]) for r in results)
    n_miss = sum(len(r["missing"]) for r in results)
    summary = {"dataset": a.dataset, "points": len(results), "attractors": n_att, "missing": n_miss,
               "cpu_s": time.process_time() - t0, "results": results}
    with open(a.out, "w") as fh:
        json.dump(summary, fh, indent=1, default=float)
    print(f"{len(results)} points, {n_att} attractors, {n_miss} missing from the dataset")
    return 0 if n_miss == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
