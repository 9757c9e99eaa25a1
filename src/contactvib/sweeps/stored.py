"""Stored resonance datasets, read through one accessor (one place for every reader: the commands
``query``, ``map``, ``animate``, ``explore`` and ``continue --dataset``, the paper's figures, its
index page and the film): :func:`open_resonance` finds a dataset (:func:`find_dataset`: a file, or
the first of :data:`DATASET_NAMES` in a folder), opens it and refuses an unusable one in one line
(:class:`DatasetError`); :class:`ResonanceData` wraps it with its ``levels``, the points of one
level (:meth:`ResonanceData.level`, matched by the one tolerance rule :data:`LEVEL_TOL`,
:func:`matching_level`) and the attractors stored at one (level, f_e)
(:meth:`ResonanceData.attractors_at`); :func:`check_damage` says where a dataset is damaged.

Example (``paper.nc`` of ``contactvib paper``)::

    from contactvib import open_resonance

    with open_resonance("paper/") as data:
        data.levels                     # (0.5, 0.6, ..., 0.9): the P_a levels [Q], increasing
        one = data.level(0.65)          # the points of 0.65 Q (an xarray Dataset)
        data.attractors_at(0.65, 360.0)["attractors"]   # what ``contactvib query`` prints
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from contactvib.call_forms import old_form
from contactvib.errors import ContactvibError
from contactvib.steady.results import dofs_and_contacts
from contactvib.sweeps.dataset import FORMAT

__all__ = ["DATASET_NAMES", "LEVEL_TOL", "find_dataset", "open_resonance", "ResonanceData", "matching_level",
           "attractors_at", "check_damage", "level_variable", "DatasetError", "DamagedDataset", "MissingLevel"]

#: The dataset files a folder (an atlas, paper or resonance output folder) may hold, in the order
#: they are looked for: the first one found is the folder's dataset.
DATASET_NAMES = ("atlas.nc", "paper.nc", "resonance.nc")
#: The dof/contact variables of a point and their names, from which ``dofs`` and ``contacts`` are rebuilt.
_DOF_POINT = ("dof_min", "dof_max", "dof_app", "dof_h1", "contact_loses_contact", "contact_loss_frac",
              "contact_mean_force_n")
_DOF_NAMES = ("dof_name", "dof_unit", "contact_name")
#: Attributes every reader of a dataset may need (the model, the sweep's grid, f_n0).
_ATTRIBUTES = ("model", "settings", "fn0_hz")
#: Variables that must be finite everywhere (the others may hold NaN: basin, Lyapunov, ...).
_FINITE = ("pa_over_q", "fe_hz", "app_um", "ymin_um", "ymax_um", "contact_loss_fraction",
           "extremum_t_ms", "extremum_y_um", "strobe_y_um", "strobe_ydot_mm_s")
#: A requested level matches the stored level nearest it when they differ by at most this much
#: (in the level's unit: Q, µm or g): the one rule for finding a level (:func:`matching_level`).
LEVEL_TOL = 1e-6


class DatasetError(ContactvibError, ValueError):
    """A resonance dataset that cannot be used: missing, not a contactvib resonance dataset of
    this version, or without levels. The message is one line naming the path."""


class DamagedDataset(ContactvibError, LookupError):
    """A resonance dataset whose variables are missing, not finite where they must be, or
    refer outside their arrays; the message says where (one line)."""


class MissingLevel(DatasetError, LookupError):
    """A level that a resonance dataset does not hold (none within ``LEVEL_TOL``). The message
    is one line naming the stored levels; ``level`` is the requested one, ``levels`` the stored
    ones (increasing). A ``DatasetError``, a ``ValueError`` and a ``LookupError``."""

    def __init__(self, message: str, level: float = math.nan, levels: tuple = ()):
        super().__init__(message)
        self.level, self.levels = level, tuple(levels)

    def __reduce__(self):  # raised in a pool worker, it comes back whole
        return type(self), (str(self), self.level, self.levels)


#: Per-point variables :func:`attractors_at` reads, the ragged arrays and the branch table.
_QUERY_POINT = ("pa_over_q", "fe_hz", "period", "kind", "minima_per_period", "app_um", "ymin_um", "ymax_um",
                "loses_contact", "contact_loss_fraction", "basin_fraction", "floquet_abs_max", "floquet_re",
                "floquet_im", "closure", "lyapunov_per_period", "resonance", "branch_index", "extrema_start",
                "extrema_count", "strobe_start", "strobe_count", "origin", "dominant_harmonic", "found_by",
                "attractor_type")
_QUERY_OTHER = ("extremum_t_ms", "extremum_y_um", "extremum_is_min", "strobe_y_um", "strobe_ydot_mm_s",
                "branch_id", "branch_label", "branch_reached_by_sweep")
#: Attributes every reader of a dataset may need (the model, the sweep's grid, f_n0).
_ATTRIBUTES = ("model", "settings", "fn0_hz")
#: Variables that must be finite everywhere (the others may hold NaN: basin, Lyapunov, ...).
_FINITE = ("pa_over_q", "fe_hz", "app_um", "ymin_um", "ymax_um", "contact_loss_fraction",
           "extremum_t_ms", "extremum_y_um", "strobe_y_um", "strobe_ydot_mm_s")


def find_dataset(path) -> Path:
    """The dataset file of ``path``: the file itself, or in a folder the first of
    :data:`DATASET_NAMES` it holds. Raises ``DatasetError`` (one line) otherwise."""
    p = Path(path)
    if p.is_file():
        return p
    if p.is_dir():
        for name in DATASET_NAMES:
            if (p / name).is_file():
                return p / name
        raise DatasetError(f"{path}: a folder without {', '.join(DATASET_NAMES[:-1])} or {DATASET_NAMES[-1]}")
    raise DatasetError(f"{path}: no such file or folder")


def matching_level(levels, level: float) -> float | None:
    """The value of ``levels`` nearest ``level`` when it lies within ``LEVEL_TOL`` of it,
    else None: how a requested level is found among stored ones, everywhere."""
    lv = np.asarray(levels, float).reshape(-1)
    if lv.size == 0:
        return None
    j = int(np.argmin(np.abs(lv - level)))
    return float(lv[j]) if abs(lv[j] - level) <= LEVEL_TOL else None


@old_form("path", "load")
def open_resonance(path, *, load: bool = False) -> ResonanceData:
    """The resonance dataset of ``path`` (a file, or a folder: ``find_dataset``) as a
    :class:`ResonanceData`, opened with xarray: read into memory with ``load``, else lazily
    (close it, or use it in a ``with`` block).

    Raises ``DatasetError`` with a one-line message naming the file when it is not NetCDF,
    not a contactvib resonance dataset, of another layout version (``contactvib.sweeps.dataset.FORMAT``),
    without one of the variables or attributes of the layout, or without a level. The values
    themselves are checked where they are read (``check_damage``)."""
    import xarray as xr

    file = find_dataset(path)
    try:
        ds = xr.load_dataset(file) if load else xr.open_dataset(file)
    except Exception as e:  # not NetCDF, damaged, unreadable
        raise DatasetError(f"{file}: not a readable NetCDF dataset ({type(e).__name__})") from None
    try:
        if "branch_label" not in ds or level_variable(ds) not in ds:
            raise DatasetError(f"{file}: not a contactvib resonance dataset (made by paper, resonance or atlas)")
        if ds.attrs.get("format") != FORMAT:
            raise DatasetError(f"{file}: written by another contactvib version (format "
                               f"{ds.attrs.get('format')!r}, not {FORMAT!r}): recompute it")
        needed, attributes = _required(ds)
        missing = [f"variable {v!r}" for v in needed if v not in ds]
        missing += [f"attribute {a!r}" for a in attributes if a not in ds.attrs]
        if missing:
            raise DatasetError(f"{file}: damaged: {missing[0]} is missing: recompute it")
        if ds[level_variable(ds)].size == 0:
            raise DatasetError(f"{file}: holds no P_a level")
    except BaseException:
        ds.close()
        raise
    return ResonanceData(ds, file)


class ResonanceData:
    """A resonance dataset (``contactvib.sweeps.dataset`` layout) read by level.

    ``ResonanceData(ds, path=None)`` wraps an xarray Dataset (a file opened by
    :func:`open_resonance`, or a sweep's dataset in memory); nothing is read until asked for, and
    ``pa_over_q`` is read once. ``ds`` is the Dataset, ``path`` its file (or None).

    A level is a value of the variable ``pa_over_q``: P_a/Q [Q] for a force, U [µm] or A [g] for
    base motion (``kind``, ``level_symbol``, ``level_unit``). A requested level ``p`` is the
    stored level nearest it within ``LEVEL_TOL`` (``matching_level``); otherwise
    :class:`MissingLevel` names the stored levels.
    """

    def __init__(self, ds, path=None):
        self.ds = ds
        self.path = None if path is None else Path(path)
        self._pa = None
        self._levels = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self) -> None:
        """Close the file (a lazily opened dataset)."""
        self.ds.close()

    @property
    def kind(self) -> str:
        """What a level holds: "force", "base-um" or "base-g" (:data:`contactvib.model.LEVEL_KINDS`)."""
        return str(self.ds.attrs.get("excitation", "force"))

    @property
    def level_symbol(self) -> str:
        """The levels' symbol: "P_a/Q", "U" or "A"."""
        return self._kind_entry()[0]

    @property
    def level_unit(self) -> str:
        """The levels' unit: "Q", "um" or "g"."""
        return self._kind_entry()[1]

    def _kind_entry(self):
        from contactvib.model import LEVEL_KINDS

        if "level_variable" in self.ds.attrs:  # a system's dataset: P_a/Q [Q] or P_a [N]
            return self.ds.attrs["level_symbol"], self.ds.attrs["level_unit"]

        return LEVEL_KINDS.get(self.kind, LEVEL_KINDS["force"])

    @property
    def pa_over_q(self) -> np.ndarray:
        """The level of every point (the variable ``pa_over_q``), float, read once."""
        if self._pa is None:
            self._pa = np.asarray(self.ds[level_variable(self.ds)].values, float)
        return self._pa

    @property
    def levels(self) -> tuple:
        """The distinct stored levels, increasing (floats, in ``level_unit``)."""
        if self._levels is None:
            self._levels = tuple(float(v) for v in np.unique(self.pa_over_q))
        return self._levels

    def levels_text(self) -> str:
        """The stored levels as messages list them: "0.5, 0.65, 0.7"."""
        return ", ".join(f"{v:g}" for v in self.levels)

    def match(self, level: float) -> float | None:
        """The stored level that ``level`` designates (``matching_level``), or None."""
        return matching_level(self.levels, level)

    def stored_level(self, level: float) -> float:
        """The stored level that ``level`` designates; :class:`MissingLevel` when there is none."""
        found = self.match(level)
        if found is None:
            sym, unit = self.level_symbol, self.level_unit
            sym, unit = ("P_a" if sym == "P_a/Q" else sym), ("µm" if unit == "um" else unit)
            where = self.path.name if self.path is not None else "the dataset"
            raise MissingLevel(f"{sym} = {level:g} {unit} is not a level of {where} "
                               f"(levels: {self.levels_text()} {unit})", level, self.levels)
        return found

    def points(self, level: float) -> np.ndarray:
        """The indices (increasing, along ``point``) of the points of the stored level that
        ``level`` designates; :class:`MissingLevel` when there is none. Reads only
        ``pa_over_q`` (kept) and costs one pass over it."""
        pa = self.pa_over_q
        near = np.flatnonzero(np.abs(pa - level) <= LEVEL_TOL)  # the candidates of matching_level
        found = matching_level(pa[near], level)
        if found is None:
            self.stored_level(level)  # raises, naming the levels
        return near[pa[near] == found]

    def level(self, level: float):
        """The points of the stored level that ``level`` designates, as an xarray Dataset: the
        dataset with ``point`` restricted to them (its other dimensions — extrema, strobe
        points, branches — whole, so the points' indices into them stay valid; a level's points
        are contiguous, so a lazily opened file reads only their part). :class:`MissingLevel`
        when there is none."""
        idx = self.points(level)
        if idx.size and idx[-1] - idx[0] + 1 == idx.size:
            return self.ds.isel(point=slice(int(idx[0]), int(idx[-1]) + 1))
        return self.ds.isel(point=idx)

    def attractors_at(self, level: float, fe_hz: float) -> dict:
        """The attractors stored at the grid point nearest (level, f_e [Hz]), in the attractors
        JSON contract (what ``contactvib query`` prints).

        The level must designate a stored one (:meth:`match`), f_e the nearest grid frequency
        within half a grid step. Raises ``LookupError`` with a one-line message otherwise
        (:class:`MissingLevel` for the level), ``DamagedDataset`` if the dataset is damaged
        (``check_damage``).
        """
        ds = self.ds
        _refuse_damaged(ds)
        pa = self.match(level)
        if pa is None:
            system = "level_variable" in ds.attrs  # a system's dataset: its levels in Q or N
            sym = self.level_symbol if system and self.level_unit != "Q" else "P_a/Q"
            raise MissingLevel(f"--pa ({sym}) = {level:g}: not in the dataset; stored levels: "
                               + self.levels_text() + (f" {self.level_unit}" if system else ""), level, self.levels)
        df, fmin, fmax = _grid_settings(ds)
        sel = self.points(pa)
        fes = ds["fe_hz"].values[sel]
        grid = np.unique(fes)
        g = grid[int(np.argmin(np.abs(grid - fe_hz)))]
        if abs(g - fe_hz) > 0.5 * df + 1e-9 or fe_hz < fmin - 0.5 * df or fe_hz > fmax + 0.5 * df:
            raise LookupError(f"--fe (f_e) = {fe_hz:g}: no grid point within half a step ({0.5 * df:g} Hz); "
                              f"grid {fmin:g}..{fmax:g} Hz step {df:g} Hz")
        idx = sel[np.abs(fes - g) <= 1e-9]
        if "system" in ds.attrs:
            return _system_records(self, ds, idx, pa, g, (level, fe_hz))
        atts = _attractor_records(ds, idx)
        atts.sort(key=lambda a: -a["app_um"])
        return {
            "fn0_hz": float(ds.attrs["fn0_hz"]),
            "y0_um": float(ds.attrs["y0_um"]),
            "pa_over_q": float(pa),
            "fe_hz": float(g),
            "requested": {"pa_over_q": float(level), "fe_hz": float(fe_hz)},
            "units": {"y": "um (positive = contact deflection)", "ydot": "mm/s", "t": "ms",
                      "f": "Hz", "P_a": "Q = M g"},
            "attractors": atts,
            **_level_kind_record(ds, idx),
        }


@old_form("ds", "pa_over_q", "fe_hz")
def attractors_at(ds, *, pa_over_q: float, fe_hz: float) -> dict:
    """The attractors stored in the resonance dataset ``ds`` (an xarray Dataset) at the grid
    point nearest (P_a [Q], f_e [Hz]): :meth:`ResonanceData.attractors_at`."""
    return ResonanceData(ds).attractors_at(pa_over_q, fe_hz)


def check_damage(ds) -> str | None:
    """Where a resonance dataset is damaged, in one line (a variable :func:`attractors_at` needs
    is missing, a value that must be finite is not, an index points outside its array), or
    None."""
    for name in _required(ds)[0]:
        if name not in ds:
            return f"variable {name!r} is missing"
    pa, fe = np.asarray(ds[level_variable(ds)].values, float), np.asarray(ds["fe_hz"].values, float)

    def at(name, i):
        dim = ds[name].dims[0]
        return f"point {i} (P_a = {pa[i]:g} Q, f_e = {fe[i]:g} Hz)" if dim == "point" else f"{dim} {i}"

    for name in (_SYSTEM_FINITE if "system" in ds.attrs else _FINITE):
        bad = np.nonzero(~np.isfinite(np.asarray(ds[name].values, float)))[0]
        if bad.size:
            return f"{name} is {ds[name].values[bad[0]]} at {at(name, int(bad[0]))}"
    ragged = (("extrema_start", "extrema_count", "extremum"), ("strobe_start", "strobe_count", "strobe"),
              ("branch_index", None, "branch"))
    for start, count, dim in (r for r in ragged if r[0] in ds):
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


def _grid_settings(ds) -> tuple:
    """(df, fmin, fmax) [Hz] of the sweep's grid, from the settings stored as JSON: a damaged
    attribute is one line (LookupError), not a traceback."""
    try:
        settings = json.loads(ds.attrs["settings"])
        return tuple(float(settings[k]) for k in ("df_hz", "fmin_hz", "fmax_hz"))
    except (KeyError, TypeError, ValueError) as e:  # JSONDecodeError is a ValueError
        raise LookupError(f"dataset attribute 'settings' is missing or damaged ({type(e).__name__}): "
                          "recompute it") from None


def _attractor_records(ds, idx) -> list:
    """The attractors JSON contract's records of the points ``idx`` of ``ds``."""
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
    return atts

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


#: What a system's dataset (``contactvib.sweeps.system_dataset``) must hold, and its finite variables.
_SYSTEM_POINT = ("fe_hz", "period", "kind", "minima_per_period", "app_um", "loses_contact", "basin_fraction",
                 "floquet_abs_max", "floquet_re", "floquet_im", "closure", "branch_index", "origin", "found_by",
                 "strobe_start", "strobe_count", "strobe_q", "strobe_qdot", "branch_id", "branch_label",
                 "branch_reached_by_sweep") + _DOF_POINT
_SYSTEM_ATTRIBUTES = ("settings", "system", "system_coordinates", "system_units", "level_variable", "level_symbol",
                      "level_unit")
_SYSTEM_FINITE = ("pa_newton", "fe_hz", "app_um", "strobe_q", "strobe_qdot")


def level_variable(ds) -> str:
    """The variable that holds a dataset's levels: ``pa_over_q``, or a system dataset's
    ``level_variable`` attribute (``pa_newton`` [N] for a system without a Q)."""
    return str(ds.attrs.get("level_variable", "pa_over_q"))


def _required(ds) -> tuple:
    """(variables, attributes) a reader needs of ``ds``: a system's dataset or the 1-DOF layout."""
    if "system" in ds.attrs:
        return (level_variable(ds),) + _SYSTEM_POINT, _SYSTEM_ATTRIBUTES
    return _QUERY_POINT + _QUERY_OTHER, _ATTRIBUTES


def _system_spectra(ds):
    """A function of the point index: its ``attractor_type``, ``lyapunov_per_s``,
    ``lyapunov_stderr_per_s`` [1/s] and ``kaplan_yorke_dimension`` (null unless chaotic) as
    ``contactvib attractors --system --json`` writes them (nothing for a dataset written without
    them)."""
    from contactvib.steady.results import lyapunov_fields

    if "lyapunov_per_s" not in ds.variables:
        return lambda p: {}
    typ, lam, se = (ds[x].values for x in ("attractor_type", "lyapunov_per_s", "lyapunov_stderr_per_s"))
    ky = ds["kaplan_yorke_dimension"].values

    def fields(p):
        d = lyapunov_fields(str(typ[p]), lam[p], se[p])
        d["kaplan_yorke_dimension"] = float(ky[p]) if math.isfinite(float(ky[p])) else None
        return d

    return fields


def _system_records(data, ds, idx, level, fe, requested) -> dict:
    """:meth:`ResonanceData.attractors_at` of a system's dataset: the attractors at the rows
    ``idx`` in the JSON contract of ``contactvib attractors --system`` (dofs, contacts), with their
    stroboscopic points per coordinate (display units)."""
    v = {name: ds[name].values for name in ("period", "minima_per_period", "app_um", "basin_fraction",
                                            "floquet_abs_max", "floquet_re", "floquet_im", "closure",
                                            "branch_index", "origin", "found_by", "strobe_start", "strobe_count")}
    sq, sv = ds["strobe_q"].values, ds["strobe_qdot"].values
    names = [str(x) for x in ds["dof_name"].values]
    dofs = _dofs_and_contacts_of(ds)
    b_id = ds["branch_id"].values
    spectra = _system_spectra(ds)
    atts = []
    for p in idx:
        s0, ns = int(v["strobe_start"][p]), int(v["strobe_count"][p])
        basin = float(v["basin_fraction"][p])
        periodic = int(v["period"][p]) > 0
        atts.append({
            "period": int(v["period"][p]) if periodic else None,
            "minima_per_period": int(v["minima_per_period"][p]) if periodic else None,
            "floquet_multipliers": [[float(v["floquet_re"][p, q]), float(v["floquet_im"][p, q])]
                                    for q in range(ds.sizes["multiplier"])] if periodic else None,
            "floquet_abs_max": float(v["floquet_abs_max"][p]) if periodic else None,
            "stable": True if periodic else None,
            "basin_fraction": basin if math.isfinite(basin) else None,
            "closure": float(v["closure"][p]) if periodic else None,
            **spectra(p),
            "app_um": float(v["app_um"][p]), "branch": str(b_id[int(v["branch_index"][p])]),
            "origin": str(v["origin"][p]), "found_by": str(v["found_by"][p]),
            "strobe_points": [{"q": dict(zip(names, map(float, sq[q]))), "qdot": dict(zip(names, map(float, sv[q])))}
                              for q in range(s0, s0 + ns)],
            **dofs(p)})
    atts.sort(key=lambda a: -a["app_um"])
    return {"system": ds.attrs["system"] if ds.attrs["system"] == "rocking" else "file",
            "system_label": ds.attrs["system"] if ds.attrs["system"] == "rocking" else "from a TOML file",
            "coordinates": json.loads(ds.attrs["system_coordinates"]), "level": float(level),
            "level_symbol": data.level_symbol, "level_unit": data.level_unit, "fe_hz": float(fe),
            "requested": {"level": float(requested[0]), "fe_hz": float(requested[1])},
            "units": {"m": "um", "rad": "urad", "force": "N", "f": "Hz"}, "attractors": atts}
