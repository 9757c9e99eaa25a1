"""Storage size of the atlas (the target: the 96-level atlas stays under ~400 MB).

A standalone script, not a test. It reads finished level files (the ``.chunks/level_pa*.nc`` of
``paper`` for its eight levels and of an atlas of a few low levels), writes each level with three
NetCDF4 encodings and reports bytes per attractor point and MB per level, then extrapolates to the
96 levels 0.05–1.0 Q from the measured points per level (linear between measured levels)::

    PYTHONPATH=src python benchmarks/bench_atlas_size.py paper/.chunks/*.nc low/.chunks/*.nc
    # writes benchmarks/results_atlas_size.json

Encodings: ``vlen strings`` (zlib 4 + shuffle, strings as NetCDF variable-length strings, which
NetCDF4 cannot compress), ``char strings`` (the strings as UTF-8 character arrays: the encoding
of :func:`contactvib.sweeps.dataset.compressed_encoding`; lossless) and
``char strings + float32 harmonics`` (harmonics_um rounded to float32: not used, see README).
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
from pathlib import Path

import numpy as np

from benchmarks import result_path

HERE = Path(__file__).resolve().parent


def _encodings(ds):
    from contactvib.sweeps.dataset import compressed_encoding

    now = compressed_encoding(ds)
    vlen = {k: {a: b for a, b in v.items() if a != "dtype"} for k, v in now.items()}
    f32 = {k: dict(v) for k, v in now.items()}
    f32["harmonics_um"]["dtype"] = "float32"
    return {"vlen strings": vlen, "char strings": now, "char strings + float32 harmonics": f32}


def _size(ds, enc, folder) -> int:
    path = Path(folder) / "level.nc"
    ds.to_netcdf(path, engine="netcdf4", format="NETCDF4", encoding=enc)
    return os.path.getsize(path)


def _levels(paths):
    """Every level file (an atlas's or paper's ``.chunks/level_pa*.nc``), one dataset each."""
    import xarray as xr

    for p in paths:
        ds = xr.load_dataset(p)
        yield float(ds["pa_over_q"].values[0]), ds


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="+", help="level files (.chunks/level_pa*.nc)")
    ap.add_argument("--out", default=str(result_path(__name__)))
    args = ap.parse_args(argv)
    paths = args.paths
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for pa, lvl in _levels(paths):
            sizes = {name: _size(lvl, enc, tmp) for name, enc in _encodings(lvl).items()}
            rows.append({"pa_over_q": pa, "points": int(lvl.sizes["point"]), "bytes": sizes})
            print(f"P_a {pa:5.3f} Q: {lvl.sizes['point']:6d} points  "
                  + "  ".join(f"{k}: {v / 1e6:5.2f} MB" for k, v in sizes.items()), flush=True)
    rows.sort(key=lambda r: r["pa_over_q"])
    pa = np.array([r["pa_over_q"] for r in rows])
    pts = np.array([r["points"] for r in rows], dtype=float)
    grid = np.linspace(0.05, 1.0, 96)
    points96 = float(np.interp(grid, pa, pts).sum())
    result = {"levels": rows, "points_96_levels": points96, "extrapolated_96_levels_mb": {}}
    for name in rows[0]["bytes"]:
        per_point = sum(r["bytes"][name] for r in rows) / pts.sum()
        mb = points96 * per_point / 1e6
        result["extrapolated_96_levels_mb"][name] = round(mb, 1)
        print(f"{name}: {per_point:.0f} B/point, 96 levels ≈ {mb:.0f} MB")
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n")


if __name__ == "__main__":
    main()
