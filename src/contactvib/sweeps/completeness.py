"""How complete a stored resonance dataset is: random grid points searched again by brute force.

:func:`check_completeness` draws ``n_points`` grid points (level × f_e grid of the sweep's stored
settings) with ``numpy.random.default_rng(seed)``, runs :func:`contactvib.find_attractors` at each
with many random starts (the dataset's own model, law and level kind, read from its attributes)
and lists the attractors the search finds that the dataset does not hold at that point.

Sameness (:func:`same_attractor`): a found attractor is one of the stored points when both are
periodic with the same period k and minima per period m, their peak-to-peak amplitudes agree to
``APP_RTOL`` (relative) and their stroboscopic sets agree by the package's orbit rule
:func:`contactvib.steady.orbits.same_orbit` (any cyclic order) to ``STROBE_RTOL``; a non-periodic
attractor is one of the stored non-periodic points at that grid point, whatever its amplitude.
Both orbits are refined to a closure of 1e-9 or better, so the same orbit agrees to ~1e-8 and
the tolerances only keep apart orbits that differ.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np

from contactvib.sweeps.stored import DatasetError

__all__ = ["check_completeness", "completeness_points", "same_attractor", "COMPLETENESS_STARTS",
           "APP_RTOL", "STROBE_RTOL"]

#: Random starts of the search at each checked grid point (the sweep's multi-start uses 24).
COMPLETENESS_STARTS = 256
#: Relative tolerance on A_pp [µm] of two attractors that are the same.
APP_RTOL = 1e-3
#: Relative tolerance of :func:`~contactvib.steady.orbits.same_orbit` on the stroboscopic sets
#: (y [µm], ẏ [mm/s]) of two orbits that are the same.
STROBE_RTOL = 1e-3


def completeness_points(data, n_points: int, seed: int) -> list[tuple[float, float]]:
    """``n_points`` distinct (level, f_e [Hz]) grid points of ``data`` (a ``ResonanceData``)
    drawn without replacement by ``numpy.random.default_rng(seed)``, in drawing order; all of
    them when the grid has fewer."""
    grid = _grid(data)
    levels = data.levels
    n_all = len(levels) * grid.size
    rng = np.random.default_rng(int(seed))
    pick = rng.choice(n_all, size=min(int(n_points), n_all), replace=False)
    return [(float(levels[j // grid.size]), float(grid[j % grid.size])) for j in pick]


def same_attractor(a: dict, b: dict) -> bool:
    """Whether two attractor records (``period``, ``minima_per_period``, ``app_um``,
    ``strobe`` an array of (y [µm], ẏ [mm/s]) rows; period None for non-periodic) are the same
    attractor by the rule of this module's docstring."""
    from contactvib.steady.orbits import same_orbit

    if a["period"] is None or b["period"] is None:
        return a["period"] is None and b["period"] is None
    if a["period"] != b["period"] or a["minima_per_period"] != b["minima_per_period"]:
        return False
    if abs(a["app_um"] - b["app_um"]) > APP_RTOL * max(abs(a["app_um"]), abs(b["app_um"])):
        return False
    return same_orbit(np.asarray(a["strobe"], float), np.asarray(b["strobe"], float), rtol=STROBE_RTOL)


def check_completeness(data, *, n_points: int, seed: int = 0, n_starts: int = COMPLETENESS_STARTS,
                       progress=None) -> dict:
    """Search ``n_points`` random grid points of ``data`` (a ``ResonanceData``) again with
    ``n_starts`` random starts plus the ballistic seeds, up to the sweep's ``kmax``, and report
    what the dataset lacks.

    Returns ``{"points_checked", "seed", "n_starts", "missing", "unsettled_starts",
    "found_fraction", "rule", "units"}``:
    ``missing`` one record per attractor found but not stored (level, f_e [Hz], period, minima
    per period, A_pp [µm], basin fraction [1], kind), ``found_fraction`` the fraction of the
    search's attractors [1] that the dataset holds (1.0 when the search found none),
    ``unsettled_starts`` the starts of all points that settled on nothing within the transient
    limit (an attractor reached only from them would be missed by this check too).
    ``progress(done, total)`` is called with ``done = 0`` before the first point and after each.
    Ctrl-C stops the search between kernel calls (``KeyboardInterrupt``). A dataset whose model
    or grid cannot be rebuilt from its attributes is a ``DatasetError`` (one line).
    """
    from contactvib.interrupts import check_interrupt
    from contactvib.model import excitation_at
    from contactvib.steady.attractors import UnsettledWarning, find_attractors

    model = _model(data)
    kmax = int(json.loads(data.ds.attrs["settings"]).get("kmax", 8))
    points = completeness_points(data, n_points, seed)
    missing, n_found, n_unsettled = [], 0, 0
    if progress is not None:
        progress(0, len(points))
    for done, (level, fe) in enumerate(points):
        with warnings.catch_warnings():  # counted below, not one warning per point
            warnings.simplefilter("ignore", UnsettledWarning)
            found = find_attractors(excitation_at(model, level, fe, data.kind), n_starts=int(n_starts),
                                    seed=int(seed), kmax=kmax)
        n_unsettled += found.n_unsettled
        stored = _stored_at(data, level, fe)
        for a in found.attractors:
            n_found += 1
            rec = {"period": a.period, "minima_per_period": a.minima_per_period, "app_um": float(a.app_um),
                   "strobe": np.column_stack([a.strobe_y_um, a.strobe_ydot_mm_s])}
            if not any(same_attractor(rec, s) for s in stored):
                missing.append({"level": level, "fe_hz": fe, "period": a.period,
                                "minima_per_period": a.minima_per_period, "app_um": float(a.app_um),
                                "basin_fraction": float(a.basin_fraction), "kind": a.kind})
        check_interrupt()
        if progress is not None:
            progress(done + 1, len(points))
    return {"points_checked": len(points), "seed": int(seed), "n_starts": int(n_starts),
            "missing": missing, "unsettled_starts": n_unsettled,
            "found_fraction": 1.0 if n_found == 0 else (n_found - len(missing)) / n_found,
            "rule": f"same period and minima per period, A_pp within {APP_RTOL:g} (relative), "
                    f"strobe sets within {STROBE_RTOL:g} (relative); non-periodic: kind only",
            "units": {"level": data.level_unit, "fe_hz": "Hz", "app_um": "um", "basin_fraction": "1"}}


def _model(data):
    from contactvib import ContactModel

    try:
        return ContactModel(**json.loads(data.ds.attrs["model"]))
    except (KeyError, TypeError, ValueError) as e:
        raise DatasetError(f"the dataset's 'model' attribute is missing or damaged ({type(e).__name__}): "
                                "recompute it") from None


def _grid(data) -> np.ndarray:
    """The sweep's frequency grid [Hz] from the stored settings (``frequency_grid``'s rule)."""
    try:
        st = json.loads(data.ds.attrs["settings"])
        fmin, fmax, df = float(st["fmin_hz"]), float(st["fmax_hz"]), float(st["df_hz"])
    except (KeyError, TypeError, ValueError) as e:
        raise DatasetError(f"the dataset's 'settings' attribute is missing or damaged ({type(e).__name__}): "
                                "recompute it") from None
    n = int(math.floor((fmax - fmin) / df + 1e-9)) + 1
    return fmin + df * np.arange(n)


def _stored_at(data, level: float, fe: float) -> list[dict]:
    """The stored attractors of grid point (level, f_e) as records of :func:`same_attractor`."""
    one = data.level(level)
    idx = np.flatnonzero(np.abs(one["fe_hz"].values - fe) <= 1e-9)
    kind = one["kind"].values[idx]
    per, mins, app = (one[v].values[idx] for v in ("period", "minima_per_period", "app_um"))
    s0, ns = one["strobe_start"].values[idx], one["strobe_count"].values[idx]
    sy, sv = data.ds["strobe_y_um"].values, data.ds["strobe_ydot_mm_s"].values
    out = []
    for j in range(idx.size):
        periodic = str(kind[j]) == "periodic"
        q = slice(int(s0[j]), int(s0[j] + ns[j]))
        out.append({"period": int(per[j]) if periodic else None,
                    "minima_per_period": int(mins[j]) if periodic else None, "app_um": float(app[j]),
                    "strobe": np.column_stack([sy[q], sv[q]])})
    return out
