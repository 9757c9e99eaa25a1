"""Regime maps: what a resonance dataset shows over the (f_e, P_a) plane, and the bifurcation curves
that bound its regions.

:func:`regime_maps` turns the attractor rows of a dataset with many P_a levels (``paper.nc``,
``resonance.nc``, the atlas) into images on the grid levels × frequencies:

* ``n_attractors`` — coexisting attractors at the grid point;
* ``max_order`` — the highest m among the 1/m resonance labels present (``"main…"`` = 1;
  :func:`~contactvib.labels.resonance_order`), 0 where every label is non-resonant or
  sub-/ultrasubharmonic;
* ``contact_loss_share`` — the fraction of the attractors that lose contact (y < 0 on the orbit);
* ``chaotic`` — 1 where a non-periodic attractor has λ > ``LYAPUNOV_ZERO`` (a system's dataset:
  where its verdict labels an attractor chaotic, ``attractor_type``);
* ``max_period`` — the largest period [excitation periods] of the periodic attractors (0 where
  only non-periodic ones are stored);
* ``max_lambda1`` — the largest Lyapunov exponent λ1 [1/excitation period] of the attractors at
  the grid point: ln max|μ| / k of a period-k orbit's Floquet multipliers, the stored estimate
  ``lyapunov_per_period`` of a non-periodic one (a system's: ``lyapunov_per_s`` / f_e) (NaN where
  none is stored);
* ``friction_ratio_min``, ``friction_ratio_max`` — for a dataset swept with friction
  (``--friction``, :mod:`contactvib.friction.columns`) only: the lowest and highest friction
  ratio ⟨F_drive⟩/(μ W) of the periodic attractors at the grid point (NaN where none has one):
  the strongest friction reduction there, and its spread over the coexisting attractors.

Grid points without a stored attractor (none reached there) have ``n_attractors`` = 0 and the
others' fill values (−1, NaN). The fold and period-doubling curves of the 1/m resonances
(:func:`contactvib.continuation.evolution.evolution`) are :class:`MapCurve` objects here
(:func:`evolution_curves`, :func:`load_curves`); :func:`curve_crossings` gives the frequencies
where one crosses a level and :func:`count_changes` the frequencies where the map's count of
attractors changes, so that both can be compared (a fold of a stable branch changes the count).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contactvib.labels import LYAPUNOV_ZERO, resonance_order
from contactvib.sweeps.stored import ResonanceData, level_variable

__all__ = ["regime_maps", "MapCurve", "evolution_curves", "load_curves", "curves_dataset", "curve_crossings",
           "count_changes", "MAP_VARIABLES", "FRICTION_MAPS"]

#: The maps, in the order of the figures.
MAP_VARIABLES = ("n_attractors", "max_order", "contact_loss_share", "chaotic", "max_period", "max_lambda1")
#: The maps of a dataset with friction columns (after :data:`MAP_VARIABLES`).
FRICTION_MAPS = ("friction_ratio_min", "friction_ratio_max")

_ATTRS = {
    "n_attractors": {"units": "1", "long_name": "coexisting attractors"},
    "max_order": {"units": "1", "long_name": "highest resonance order m of the 1/m labels present",
                  "comment": "1 = main resonance; 0 = no 1/m label (non-resonant, sub-/ultrasubharmonic); "
                             "-1 = no attractor stored"},
    "contact_loss_share": {"units": "1", "long_name": "share of the attractors that lose contact",
                           "comment": "NaN = no attractor stored"},
    "chaotic": {"units": "1", "long_name": "chaotic attractor present (largest Lyapunov exponent > "
                                           f"{LYAPUNOV_ZERO:g} per period)"},
    "max_period": {"units": "excitation periods", "long_name": "largest period of the periodic attractors",
                   "comment": "0 = only non-periodic attractors; -1 = no attractor stored"},
    "max_lambda1": {"units": "1/excitation period",
                    "long_name": "largest Lyapunov exponent of the attractors (periodic: ln max|mu| / period)",
                    "comment": "NaN = no attractor stored"},
    "friction_ratio_min": {"units": "1", "long_name": "lowest friction ratio <F_drive>/(mu W) of the attractors",
                           "comment": "NaN = no attractor with a friction ratio stored"},
    "friction_ratio_max": {"units": "1", "long_name": "highest friction ratio <F_drive>/(mu W) of the attractors",
                           "comment": "NaN = no attractor with a friction ratio stored"},
}


def _grid(ds):
    """(levels [Q], frequencies [Hz], df [Hz]) of the dataset: the sweep's grid from its settings
    (every stored f_e must lie on it), else the stored values."""
    fe = ds["fe_hz"].values
    levels = np.asarray(ResonanceData(ds).levels, float)
    try:
        s = json.loads(ds.attrs["settings"])
        fmin, fmax, df = float(s["fmin_hz"]), float(s["fmax_hz"]), float(s["df_hz"])
        n = int(np.floor((fmax - fmin) / df + 1e-9)) + 1
        grid = fmin + df * np.arange(n)
        if fe.size and np.max(np.abs(grid[np.clip(np.rint((fe - fmin) / df).astype(int), 0, n - 1)] - fe)) > 1e-6 * df:
            raise ValueError("off the grid")
    except (KeyError, TypeError, ValueError):
        grid = np.unique(fe)
        df = float(np.min(np.diff(grid))) if grid.size > 1 else float("nan")
    return levels, grid, df


def regime_maps(ds):
    """The regime maps of a resonance dataset on its grid (P_a levels × frequencies).

    Parameters
    ----------
    ds : xarray.Dataset
        A resonance dataset (``contactvib.sweeps.dataset`` layout).

    Returns
    -------
    xarray.Dataset
        Dimensions ``pa_over_q`` [Q] × ``fe_hz`` [Hz]; the variables of ``MAP_VARIABLES``
        with ``units`` and ``long_name``; attributes ``df_hz``, ``fn0_hz`` and the dataset's
        ``model``; for a dataset with friction columns also ``FRICTION_MAPS`` and the
        attribute ``friction``.
    """
    import xarray as xr

    levels, grid, df = _grid(ds)
    nl, nf = levels.size, grid.size
    pa = ds[level_variable(ds)].values
    fe = ds["fe_hz"].values
    il = np.searchsorted(levels, pa)
    jf = np.clip(np.searchsorted(grid, fe - 1e-6 * (df if np.isfinite(df) else 1.0)), 0, max(nf - 1, 0))
    cell = il * nf + jf
    size = nl * nf
    count = np.bincount(cell, minlength=size)
    max_order = np.full(size, -1, np.int64)
    if "resonance" in ds:  # a system's dataset carries no resonance labels
        labels = ds["resonance"].values
        uniq, inv = np.unique(labels.astype(str), return_inverse=True)
        orders = np.array([resonance_order(u) or 0 for u in uniq], dtype=np.int64)[inv]
        np.maximum.at(max_order, cell, orders)
    loses = ds["loses_contact"].values.astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.bincount(cell, weights=loses, minlength=size) / count
    lyap = ds["lyapunov_per_period"].values if "lyapunov_per_period" in ds else np.full(pa.size, np.nan)
    nonperiodic = ds["period"].values == 0
    chaos = nonperiodic & np.isfinite(lyap) & (lyap > LYAPUNOV_ZERO)
    system_spectra = "system" in ds.attrs and "lyapunov_per_s" in ds
    if system_spectra:  # a system's verdict: λ1 [1/s] per period, chaos as the verdict labels it
        lyap = np.asarray(ds["lyapunov_per_s"].values[:, 0], float) / fe
        chaos = np.asarray(ds["attractor_type"].values == "chaotic", bool)
    chaotic = (np.bincount(cell, weights=chaos.astype(float), minlength=size) > 0).astype(np.int8)
    max_period = np.full(size, -1, np.int64)
    np.maximum.at(max_period, cell, ds["period"].values.astype(np.int64))
    k = ds["period"].values.astype(float)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = ds["floquet_abs_max"].values.astype(float) if "floquet_abs_max" in ds else np.full(k.size, np.nan)
        lam1 = np.where(nonperiodic, lyap, np.log(mu) / np.maximum(k, 1.0))
    ok = np.isfinite(lam1)
    max_lam = np.full(size, -np.inf)
    np.maximum.at(max_lam, cell[ok], lam1[ok])
    shape = (nl, nf)
    data = {"n_attractors": count.reshape(shape).astype(np.int64), "max_order": max_order.reshape(shape),
            "contact_loss_share": share.reshape(shape), "chaotic": chaotic.reshape(shape),
            "max_period": max_period.reshape(shape),
            "max_lambda1": np.where(np.isfinite(max_lam), max_lam, np.nan).reshape(shape)}
    if "system" in ds.attrs:  # no resonance labels: orders are not known (nor chaos without the verdict's labels)
        del data["max_order"]
        if not system_spectra:
            del data["chaotic"]
    if "friction_ratio" in ds:
        data.update({k: v.reshape(shape) for k, v in _friction_extremes(ds, cell, size).items()})
    dims = ("pa_over_q", "fe_hz")
    level_attrs = {k: v for k, v in ds[level_variable(ds)].attrs.items() if k in ("units", "long_name")}
    coords = {"pa_over_q": ("pa_over_q", levels, level_attrs or {"units": "Q",
                                                                 "long_name": "excitation amplitude P_a/(M g)"}),
              "fe_hz": ("fe_hz", grid, {"units": "Hz", "long_name": "excitation frequency f_e"})}
    out = xr.Dataset({k: (dims, v, dict(_ATTRS[k])) for k, v in data.items()}, coords=coords)
    out.attrs.update({"title": "contactvib regime maps over (f_e, P_a)", "df_hz": df,
                      "fn0_hz": float(ds.attrs.get("fn0_hz", np.nan)), "model": ds.attrs.get("model", "")})
    if "friction" in ds.attrs:
        out.attrs["friction"] = ds.attrs["friction"]
    if "excitation" in ds.attrs:  # a base-motion dataset: the levels are U [um] or A [g]
        out.attrs.update({k: ds.attrs[k] for k in ("excitation", "level_symbol", "level_unit")})
    if "system" in ds.attrs:  # a system's dataset: its levels P_a/Q [Q] or P_a [N]
        out.attrs.update({k: ds.attrs[k] for k in ("system", "level_symbol", "level_unit")})
    return out


def _friction_extremes(ds, cell, size) -> dict:
    """The lowest and highest friction ratio in each cell (NaN where none is finite)."""
    fr = np.asarray(ds["friction_ratio"].values, float)
    ok = np.isfinite(fr)
    lo, hi = np.full(size, np.inf), np.full(size, -np.inf)
    np.minimum.at(lo, cell[ok], fr[ok])
    np.maximum.at(hi, cell[ok], fr[ok])
    return {"friction_ratio_min": np.where(np.isfinite(lo), lo, np.nan),
            "friction_ratio_max": np.where(np.isfinite(hi), hi, np.nan)}


@dataclass
class MapCurve:
    """A fold or period-doubling curve of the 1/``order`` resonance in the (f_e, P_a) plane."""

    order: int
    type: str
    fe_hz: np.ndarray
    pa_over_q: np.ndarray


def _from_result(res) -> list[MapCurve]:
    return [MapCurve(int(res["order"]), str(c["type"]), np.asarray(c["fe_hz"], float),
                     np.asarray(c["pa_over_q"], float))
            for c in res["curves"] if len(c["fe_hz"]) > 1]


def evolution_curves(model, orders, pa_min: float, pa_max: float, n_levels: int = 7, log=None,
                     out=None) -> list[MapCurve]:
    """The fold and period-doubling curves of the 1/m resonances, m in ``orders``, between P_a =
    ``pa_min`` and ``pa_max`` [Q] (:func:`contactvib.continuation.evolution.evolution` with
    ``n_levels`` one-parameter levels). With ``out``, each result is also written as
    ``out/evolution_order<m>.json`` (the file ``contactvib evolution`` writes), for
    :func:`load_curves`."""
    from contactvib.continuation.evolution import evolution

    curves = []
    for m in orders:
        res = evolution(model, order=m, pa_min=pa_min, pa_max=pa_max, n_levels=n_levels, log=log)
        if out is not None:
            (Path(out) / f"evolution_order{m}.json").write_text(res.to_json(indent=1))
        curves.extend(_from_result(res.to_dict()))
    return curves


def load_curves(folder) -> list[MapCurve]:
    """The curves of every ``evolution_order<m>.json`` in ``folder`` (written by ``contactvib
    evolution`` or :func:`evolution_curves`). Raises ``LookupError`` (one line) when there is none
    or one cannot be read."""
    files = sorted(Path(folder).glob("evolution_order*.json"))
    if not files:
        raise LookupError(f"{folder}: no evolution_order<m>.json (written by contactvib evolution)")
    curves = []
    for f in files:
        try:
            curves.extend(_from_result(json.loads(f.read_text())))
        except (OSError, ValueError, KeyError, TypeError) as e:
            raise LookupError(f"{f}: not an evolution result ({type(e).__name__})") from None
    return curves


def curves_dataset(curves: list[MapCurve]):
    """The curves as ragged NetCDF variables: ``curve_order``, ``curve_type``, ``curve_start``,
    ``curve_count`` (dimension ``curve``) and ``curve_fe_hz``, ``curve_pa_over_q`` (``curve_point``)."""
    import xarray as xr

    counts = np.array([c.fe_hz.size for c in curves], dtype=np.int64)
    starts = (np.cumsum(counts) - counts).astype(np.int64)

    def cat(name):
        return np.concatenate([getattr(c, name) for c in curves]) if curves else np.zeros(0)

    return xr.Dataset({
        "curve_order": ("curve", np.array([c.order for c in curves], dtype=np.int64),
                        {"long_name": "m of the 1/m resonance"}),
        "curve_type": ("curve", np.array([c.type for c in curves], dtype=str)),
        "curve_start": ("curve", starts), "curve_count": ("curve", counts),
        "curve_fe_hz": ("curve_point", cat("fe_hz"), {"units": "Hz"}),
        "curve_pa_over_q": ("curve_point", cat("pa_over_q"), {"units": "Q"}),
    })


def curve_crossings(curve: MapCurve, pa_over_q: float) -> np.ndarray:
    """Frequencies [Hz] where ``curve`` crosses the level P_a = ``pa_over_q`` (linear
    interpolation between its points)."""
    d = curve.pa_over_q - pa_over_q
    fe = curve.fe_hz
    out = []
    for i in np.nonzero((d[:-1] * d[1:] <= 0) & np.isfinite(d[:-1] * d[1:]))[0]:
        a = 0.0 if d[i] == d[i + 1] else d[i] / (d[i] - d[i + 1])
        out.append(fe[i] + a * (fe[i + 1] - fe[i]))
    return np.unique(np.array(out, float))


def count_changes(maps, pa_over_q: float) -> np.ndarray:
    """Frequencies [Hz] at the level ``pa_over_q`` (the nearest stored one) where the map's count
    of coexisting attractors changes: the midpoints between neighbouring grid points."""
    row = maps["n_attractors"].sel(pa_over_q=pa_over_q, method="nearest").values
    fe = maps["fe_hz"].values
    j = np.nonzero(row[1:] != row[:-1])[0]
    return 0.5 * (fe[j] + fe[j + 1])
