"""Compare two resonance datasets (``paper.nc`` / ``resonance.nc``) variable by variable.

It shows whether a refactoring leaves ``contactvib paper`` unchanged::

    python benchmarks/compare_datasets.py BEFORE/paper.nc AFTER/paper.nc [--rtol 1e-10]

Every variable of the first must be in the second, with the same dimensions and sizes (the second
may add variables and dimensions: new results; they are listed, not counted as differences);
numeric values must agree to ``rtol``
relative (or to 1e-14 of the variable's largest magnitude for values that are zero up to
round-off; NaN equals NaN, inf equals inf), strings and integers exactly. The model, settings,
format and levels attributes must be equal. Prints one line per variable that differs and a
summary; exit status 1 if anything differs.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import xarray as xr

ATTRS = ("format", "model", "settings", "levels_pa_over_q", "fn0_hz", "y0_um")


def compare(a: xr.Dataset, b: xr.Dataset, rtol: float = 1e-10) -> list[str]:
    """Differences between datasets ``a`` and ``b`` (empty list: equal to ``rtol``)."""
    diffs = []
    if any(b.sizes.get(dim) != n for dim, n in a.sizes.items()):
        diffs.append(f"sizes differ: {dict(a.sizes)} vs {dict(b.sizes)}")
        return diffs
    for name in ATTRS:
        if a.attrs.get(name) != b.attrs.get(name):
            diffs.append(f"attribute {name}: {a.attrs.get(name)!r} vs {b.attrs.get(name)!r}")
    for name in sorted(a.variables):
        if name not in b.variables:
            diffs.append(f"{name}: only in the first")
            continue
        if a[name].dims != b[name].dims:
            diffs.append(f"{name}: dimensions {a[name].dims} vs {b[name].dims}")
            continue
        x, y = a[name].values, b[name].values
        if x.dtype.kind in "fc":
            fin = np.isfinite(x) & np.isfinite(y)
            scale = float(np.max(np.abs(x[fin]))) if fin.any() else 0.0
            d = np.abs(np.where(fin, x, 0.0) - np.where(fin, y, 0.0))
            close = d <= np.maximum(rtol * np.maximum(np.abs(x), np.abs(y)), 1e-14 * scale)
            same = (x == y) | (np.isnan(x) & np.isnan(y))
            bad = ~(same | (fin & close))
            if bad.any():
                with np.errstate(invalid="ignore", divide="ignore"):
                    rel = np.nanmax(d[bad] / np.maximum(np.abs(x[bad]), 1e-300))
                diffs.append(f"{name}: {int(bad.sum())} values differ (largest relative {rel:.3g})")
        elif not np.array_equal(x, y):
            diffs.append(f"{name}: {int(np.sum(x != y))} values differ")
    return diffs


def added(a: xr.Dataset, b: xr.Dataset) -> list[str]:
    """Variables of ``b`` that ``a`` does not have (results added since ``a`` was written)."""
    return sorted(set(b.variables) - set(a.variables))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("first")
    ap.add_argument("second")
    ap.add_argument("--rtol", type=float, default=1e-10)
    args = ap.parse_args(argv)
    with xr.open_dataset(args.first) as a, xr.open_dataset(args.second) as b:
        diffs = compare(a, b, args.rtol)
        new = added(a, b)
        n = a.sizes.get("point", 0)
        nb = a.sizes.get("branch", 0)
    for d in diffs:
        print(d)
    if new:
        print(f"added in the second (not compared): {', '.join(new)}")
    print(f"{'DIFFERENT' if diffs else 'equal'}: {n} points, {nb} branches, rtol {args.rtol:g}")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main())
