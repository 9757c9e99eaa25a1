"""Stored resonance datasets: where a dataset is found and how it is opened (one place for every
command that reads one: ``query``, ``map``, ``animate``, ``explore``, ``continue --dataset``:
:func:`find_dataset`, :func:`open_dataset`), the attractors stored at one (level, f_e), and the
checks that refuse a damaged dataset in one line (``contactvib query``, the paper's time
figures, the explorer)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from contactvib.errors import ContactvibError
from contactvib.steady.results import dofs_and_contacts
from contactvib.sweeps.dataset import FORMAT

__all__ = ["DATASET_NAMES", "find_dataset", "open_dataset", "attractors_at", "check_damage", "DatasetError",
           "DamagedDataset"]

#: The dataset files a folder (an atlas, paper or resonance output folder) may hold, in the order
#: they are looked for: the first one found is the folder's dataset.
DATASET_NAMES = ("atlas.nc", "paper.nc", "resonance.nc")


class DatasetError(ContactvibError, ValueError):
    """A resonance dataset that cannot be used: missing, not a contactvib resonance dataset of
    this version, or without levels. The message is one line naming the path."""


class DamagedDataset(ContactvibError, LookupError):
    """A resonance dataset whose variables are missing, not finite where they must be, or
    refer outside their arrays; the message says where (one line)."""


#: Per-point variables :func:`attractors_at` reads, the ragged arrays and the branch table.
_QUERY_POINT = ("pa_over_q", "fe_hz", "period", "kind", "minima_per_period", "app_um", "ymin_um", "ymax_um",
                "loses_contact", "contact_loss_fraction", "basin_fraction", "floquet_abs_max", "floquet_re",
                "floquet_im", "closure", "lyapunov_per_period", "resonance", "branch_index", "extrema_start",
                "extrema_count", "strobe_start", "strobe_count", "origin", "dominant_harmonic", "found_by",
                "attractor_type")
_QUERY_OTHER = ("extremum_t_ms", "extremum_y_um", "extremum_is_min", "strobe_y_um", "strobe_ydot_mm_s",
                "branch_id", "branch_label", "branch_reached_by_sweep")
#: The per-point dof/contact variables (point, dof) and (point, contact) and their name coordinates,
#: from which :func:`contactvib.steady.results.dofs_and_contacts` rebuilds ``dofs``/``contacts``.
_DOF_POINT = ("dof_min", "dof_max", "dof_app", "dof_h1", "contact_loses_contact", "contact_loss_frac",
              "contact_mean_force_n")
_DOF_NAMES = ("dof_name", "dof_unit", "contact_name")
#: Attributes every reader of a dataset may need (the model, the sweep's grid, f_n0).
_ATTRIBUTES = ("model", "settings", "fn0_hz")
#: Variables that must be finite everywhere (the others may hold NaN: basin, Lyapunov, ...).
_FINITE = ("pa_over_q", "fe_hz", "app_um", "ymin_um", "ymax_um", "contact_loss_fraction",
           "extremum_t_ms", "extremum_y_um", "strobe_y_um", "strobe_ydot_mm_s")


def find_dataset(path) -> Path:
    """The dataset file of ``path``: the file itself, or in a folder the first of
    :data:`DATASET_NAMES` it holds. Raises :class:`DatasetError` (one line) otherwise."""
    p = Path(path)
    if p.is_file():
        return p
    if p.is_dir():
        for name in DATASET_NAMES:
            if (p / name).is_file():
                return p / name
        raise DatasetError(f"{path}: a folder without {', '.join(DATASET_NAMES[:-1])} or {DATASET_NAMES[-1]}")
    raise DatasetError(f"{path}: no such file or folder")


def open_dataset(path, load: bool = False):
    """``(file, dataset)``: the resonance dataset of ``path`` (:func:`find_dataset`) opened with
    xarray (read into memory with ``load``; else lazily, to be closed by the caller).

    Raises :class:`DatasetError` with a one-line message naming the file when it is not NetCDF,
    not a contactvib resonance dataset, of another layout version (:data:`.dataset.FORMAT`),
    without one of the variables or attributes of the layout, or without a level. The values
    themselves are checked where they are read (:func:`check_damage`)."""
    import xarray as xr

    file = find_dataset(path)
    try:
        ds = xr.load_dataset(file) if load else xr.open_dataset(file)
    except Exception as e:  # not NetCDF, damaged, unreadable
        raise DatasetError(f"{file}: not a readable NetCDF dataset ({type(e).__name__})") from None
    try:
        if "branch_label" not in ds or "pa_over_q" not in ds:
            raise DatasetError(f"{file}: not a contactvib resonance dataset (made by paper, resonance or atlas)")
        if ds.attrs.get("format") != FORMAT:
            raise DatasetError(f"{file}: written by another contactvib version (format "
                               f"{ds.attrs.get('format')!r}, not {FORMAT!r}): recompute it")
        missing = [f"variable {v!r}" for v in _QUERY_POINT + _QUERY_OTHER if v not in ds]
        missing += [f"attribute {a!r}" for a in _ATTRIBUTES if a not in ds.attrs]
        if missing:
            raise DatasetError(f"{file}: damaged: {missing[0]} is missing: recompute it")
        if ds["pa_over_q"].size == 0:
            raise DatasetError(f"{file}: holds no P_a level")
    except BaseException:
        ds.close()
        raise
    return file, ds


def check_damage(ds) -> str | None:
    """Where a resonance dataset is damaged, in one line (a variable :func:`attractors_at` needs
    is missing, a value that must be finite is not, an index points outside its array), or
    None."""
    for name in _QUERY_POINT + _QUERY_OTHER:
        if name not in ds:
            return f"variable {name!r} is missing"
    pa, fe = np.asarray(ds["pa_over_q"].values, float), np.asarray(ds["fe_hz"].values, float)

    def at(name, i):
        dim = ds[name].dims[0]
        return f"point {i} (P_a = {pa[i]:g} Q, f_e = {fe[i]:g} Hz)" if dim == "point" else f"{dim} {i}"

    for name in _FINITE:
        bad = np.nonzero(~np.isfinite(np.asarray(ds[name].values, float)))[0]
        if bad.size:
            return f"{name} is {ds[name].values[bad[0]]} at {at(name, int(bad[0]))}"
    for start, count, dim in (("extrema_start", "extrema_count", "extremum"),
                              ("strobe_start", "strobe_count", "strobe"), ("branch_index", None, "branch")):
        s0 = np.asarray(ds[start].values)
        n = np.ones_like(s0) if count is None else np.asarray(ds[count].values)
        size = ds.sizes.get(dim, 0)
        bad = np.nonzero((s0 < 0) | (n < 0) | (s0 + n > size))[0]
        if bad.size:
            i = int(bad[0])
            what = f"{start} = {s0[i]}" + ("" if count is None else f", {count} = {n[i]}")
            return f"{what} at {at(start, i)} refers outside the {size} stored {dim} entries"
    return None


def _refuse_damaged(ds) -> None:
    """LookupError for another format; ``DamagedDataset`` where ``check_damage`` finds damage."""
    if ds.attrs.get("format") != FORMAT:
        raise LookupError(f"dataset format {ds.attrs.get('format')!r} is not {FORMAT!r} "
                          "(written by another contactvib version): recompute it")
    damage = check_damage(ds)
    if damage:
        raise DamagedDataset(f"damaged: {damage}: recompute it")


def attractors_at(ds, pa_over_q: float, fe_hz: float) -> dict:
    """The attractors stored at the grid point nearest (P_a, f_e), in the attractors JSON contract
    (``dofs`` and ``contacts`` rebuilt from the dof/contact variables).

    P_a must match a stored level within 1e-6, f_e the nearest grid frequency within half a
    grid step. Raises ``LookupError`` with a one-line message otherwise, ``DamagedDataset``
    if the dataset is damaged (``check_damage``).
    """
    _refuse_damaged(ds)
    levels = np.unique(ds["pa_over_q"].values)
    j = int(np.argmin(np.abs(levels - pa_over_q)))
    if abs(levels[j] - pa_over_q) > 1e-6:
        raise LookupError(f"--pa (P_a/Q) = {pa_over_q:g}: not in the dataset; stored levels: "
                          + ", ".join(f"{v:g}" for v in levels))
    pa = levels[j]
    try:  # the sweep's grid, stored as JSON: a damaged attribute is one line, not a traceback
        settings = json.loads(ds.attrs["settings"])
        df, fmin, fmax = (float(settings[k]) for k in ("df_hz", "fmin_hz", "fmax_hz"))
    except (KeyError, TypeError, ValueError) as e:  # JSONDecodeError is a ValueError
        raise LookupError(f"dataset attribute 'settings' is missing or damaged ({type(e).__name__}): "
                          "recompute it") from None
    sel = np.nonzero(np.abs(ds["pa_over_q"].values - pa) <= 1e-9)[0]
    fes = ds["fe_hz"].values[sel]
    grid = np.unique(fes)
    g = grid[int(np.argmin(np.abs(grid - fe_hz)))]
    if abs(g - fe_hz) > 0.5 * df + 1e-9 or fe_hz < fmin - 0.5 * df or fe_hz > fmax + 0.5 * df:
        raise LookupError(f"--fe (f_e) = {fe_hz:g}: no grid point within half a step ({0.5 * df:g} Hz); "
                          f"grid {fmin:g}..{fmax:g} Hz step {df:g} Hz")
    idx = sel[np.abs(fes - g) <= 1e-9]
    v = {name: ds[name].values for name in (
        "period", "kind", "minima_per_period", "app_um", "ymin_um", "ymax_um", "loses_contact",
        "contact_loss_fraction", "basin_fraction", "floquet_abs_max", "floquet_re", "floquet_im",
        "closure", "lyapunov_per_period", "resonance", "branch_index", "extrema_start", "extrema_count",
        "strobe_start", "strobe_count", "origin", "dominant_harmonic", "found_by", "attractor_type")}
    e_t, e_y, e_m = (ds[x].values for x in ("extremum_t_ms", "extremum_y_um", "extremum_is_min"))
    s_y, s_v = ds["strobe_y_um"].values, ds["strobe_ydot_mm_s"].values
    b_id, b_lab = ds["branch_id"].values, ds["branch_label"].values
    n_mult, dofs = int(ds.sizes["multiplier"]), _dofs_and_contacts_of(ds)  # 2n multipliers: two for y

    def num(x):
        x = float(x)
        return x if math.isfinite(x) else None

    atts = []
    for p in idx:
        periodic = v["kind"][p] == "periodic"
        e0, ne = int(v["extrema_start"][p]), int(v["extrema_count"][p])
        s0, ns = int(v["strobe_start"][p]), int(v["strobe_count"][p])
        b = int(v["branch_index"][p])
        d = {
            "period": int(v["period"][p]) if periodic else None,
            "kind": str(v["kind"][p]),
            "minima_per_period": int(v["minima_per_period"][p]) if periodic else None,
            "app_um": float(v["app_um"][p]),
            **({"slider_app_um": num(ds["slider_app_um"].values[p])} if "slider_app_um" in ds else {}),
            "ymin_um": float(v["ymin_um"][p]),
            "ymax_um": float(v["ymax_um"][p]),
            "loses_contact": bool(v["loses_contact"][p]),
            "contact_loss_fraction": float(v["contact_loss_fraction"][p]),
            "basin_fraction": num(v["basin_fraction"][p]),
            "floquet_abs_max": num(v["floquet_abs_max"][p]) if periodic else None,
            "floquet_multipliers": ([[float(v["floquet_re"][p, q]), float(v["floquet_im"][p, q])]
                                     for q in range(n_mult)] if periodic else []),
            "closure": num(v["closure"][p]),
            "lyapunov_per_period": num(v["lyapunov_per_period"][p]),
            "resonance": str(v["resonance"][p]),
            "attractor_type": str(v["attractor_type"][p]),
            "dominant_harmonic": float(v["dominant_harmonic"][p]),
            "branch": str(b_id[b]),
            "branch_label": str(b_lab[b]),
            "origin": str(v["origin"][p]),
            "found_by": str(v["found_by"][p]),
            "reached_by_sweep": bool(ds["branch_reached_by_sweep"].values[b]),
            "strobe_points": [{"y_um": float(s_y[q]), "ydot_mm_s": float(s_v[q])}
                              for q in range(s0, s0 + ns)],
            "extrema": [{"t_ms": float(e_t[q]), "y_um": float(e_y[q]),
                         "type": "min" if e_m[q] else "max"} for q in range(e0, e0 + ne)],
            **dofs(p),
        }
        atts.append(d)
    atts.sort(key=lambda a: -a["app_um"])
    return {
        "fn0_hz": float(ds.attrs["fn0_hz"]),
        "y0_um": float(ds.attrs["y0_um"]),
        "pa_over_q": float(pa),
        "fe_hz": float(g),
        "requested": {"pa_over_q": float(pa_over_q), "fe_hz": float(fe_hz)},
        "units": {"y": "um (positive = contact deflection)", "ydot": "mm/s", "t": "ms",
                  "f": "Hz", "P_a": "Q = M g"},
        "attractors": atts,
        **_level_kind_record(ds, idx),
    }


def _dofs_and_contacts_of(ds):
    """A function of the point index: the point's ``dofs`` and ``contacts``, rebuilt from the
    dataset's dof/contact variables by :func:`contactvib.steady.results.dofs_and_contacts` (an
    empty dict for a dataset written before these variables)."""
    if not all(name in ds.variables for name in _DOF_POINT + _DOF_NAMES):
        return lambda p: {}
    cols = {name: ds[name].values for name in _DOF_POINT + _DOF_NAMES}
    return lambda p: dofs_and_contacts(**{name: cols[name][p] for name in _DOF_POINT},
                                       **{name: cols[name] for name in _DOF_NAMES})


def _level_kind_record(ds, idx) -> dict:
    """A base-motion dataset's level kind and the inertial force [Q] at the rows ``idx`` (of one
    grid point) for :func:`attractors_at`; nothing for a force dataset."""
    if "excitation" not in ds.attrs:
        return {}
    return {"excitation": ds.attrs["excitation"], "level_symbol": ds.attrs["level_symbol"],
            "level_unit": ds.attrs["level_unit"],
            "force_pa_over_q": float(ds["force_pa_over_q"].values[idx[0]]) if idx.size else None}
