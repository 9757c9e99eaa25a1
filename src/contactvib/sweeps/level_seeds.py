"""Seeds of one level from the others' orbits (``SweepSettings.level_seeds``).

A small superharmonic or ultrasubharmonic window (period k ≤ 4, m minima per period; e.g. the
period 4 with 3 minima near 1300–1400 Hz at 0.70–0.85 Q) has a basin of a few per cent of the
start box, and a level's multi-start at a handful of frequencies per octave may miss it where a
neighbouring level found it. :func:`level_seeds` takes, for every level, the windows of period
k ≤ :data:`SEED_KMAX` of its neighbouring levels (the nearest below and above; runs of grid points
holding a (k, m) orbit) that this level lacks at the same grid points, and walks each window's
orbit at up to :data:`WINDOW_SAMPLES` of its frequencies (evenly spaced) in the level from the
neighbour to this one at fixed f_e: Newton on the period-k map
(:func:`contactvib._kernels.shooting.newton_orbit`) at steps of at most
:data:`LEVEL_STEP` (in the levels' unit), each from the previous step's orbit — natural
continuation in P_a. What arrives as a stable orbit of minimal period ≤ k (the settle's
refinement, :func:`contactvib._kernels.settle.refine_stable_orbit`) that the level does not hold
at that frequency (:func:`contactvib.sweeps.completeness.same_attractor`) is a seed: the level is
then swept again with it (:func:`contactvib.sweeps.sweep.trace_level`'s ``seeds``).
"""

from __future__ import annotations

import json
import math

import numpy as np

__all__ = ["level_seeds", "walk_orbit", "SEED_KMAX", "LEVEL_STEP", "WINDOW_SAMPLES"]

#: Largest period of the orbits walked from one level to another.
SEED_KMAX = 4
#: Largest step of the walk in the level [Q, µm or g]: 0.0025 Q reaches the period-4 orbit with 3
#: minima at 0.80 Q from 0.75 Q, where a single Newton solve from the 0.75 Q orbit diverges.
LEVEL_STEP = 0.0025
#: Frequencies of a window whose orbit is walked: evenly spaced over the window, its ends included
#: (the walk reaches a stable orbit from some of them only: from 0.75 Q to 0.80 Q the period-4
#: orbit with 3 minima arrives stable at 1385 Hz, unstable at 1377 and 1381 Hz).
WINDOW_SAMPLES = 12
#: Newton iterations per step of the walk.
WALK_ITERATIONS = 20


def walk_orbit(model, settings, z, k: int, f_e: float, level_from: float, level_to: float):
    """The period-k orbit through ``z`` (x, x' at phase 0 [y0, y0 ω_n0]) at ``level_from``, walked
    at f_e [Hz] to ``level_to`` (:data:`LEVEL_STEP`); returns (orbit point, minimal period) of
    the stable orbit it arrives at, or None (Newton failed on the way, or unstable there)."""
    from contactvib._kernels.settle import refine_stable_orbit
    from contactvib._kernels.shooting import newton_orbit
    from contactvib._kernels.status import STATUS_OK
    from contactvib.interrupts import check_interrupt

    st = settings
    n = max(1, math.ceil(abs(level_to - level_from) / LEVEL_STEP - 1e-9))
    z = np.array(z, float)
    oz, oM = np.empty(2), np.empty((2, 2))
    for level in np.linspace(level_from, level_to, n + 1)[1:]:
        check_interrupt()
        par = st.excitation_at(model, float(level), f_e).kernel_parameters()
        s, _res = newton_orbit(z, int(k), par, st.rtol, st.rtol, st.tol, WALK_ITERATIONS, oz, oM)
        if s != STATUS_OK:
            return None
        z = oz.copy()
    ok, kk, _res = refine_stable_orbit(z, int(k), par, st.rtol, st.tol, oz, oM)
    return (oz.copy(), int(kk)) if ok else None


def level_seeds(model, levels: dict, settings) -> dict:
    """The seeds of every level: ``{level: [(grid index, orbit point, period), ...]}`` for the
    level datasets ``levels`` (``{level: xarray Dataset}``, one level each, the layout of
    :mod:`contactvib.sweeps.dataset`) swept with ``settings`` (a SweepSettings); only levels with
    at least one seed are listed."""
    from contactvib.steady.orbits import describe_orbit

    st = settings
    u = model.units
    stored = {p: _records(ds) for p, ds in levels.items()}
    seeds: dict = {}
    for p in sorted(levels):
        done = set()  # (k, m, grid index) already seeded or tried at this level
        for q in _neighbours(sorted(levels), p):
            ds = levels[q]
            for k, m, idx in _windows(ds, st):
                for j in idx:
                    fe = float(ds["fe_hz"].values[j])
                    i = int(round((fe - st.fmin_hz) / st.df_hz))
                    if (k, m, i) in done or any(r["period"] == k and r["minima_per_period"] == m
                                                for r in stored[p].get(i, [])):
                        continue
                    done.add((k, m, i))
                    z = u.state(float(ds["state_y_um"].values[j]), float(ds["state_ydot_mm_s"].values[j]))
                    got = walk_orbit(model, st, z, k, fe, q, p)
                    if got is None:
                        continue
                    oz, kk = got
                    a = describe_orbit(st.excitation_at(model, p, fe), oz, kk)
                    rec = {"period": a.period, "minima_per_period": a.minima_per_period, "app_um": a.app_um,
                           "strobe": np.column_stack([a.strobe_y_um, a.strobe_ydot_mm_s])}
                    if not _holds(stored[p].get(i, []), rec) and not _holds(
                            [s[3] for s in seeds.get(p, []) if s[0] == i], rec):
                        seeds.setdefault(p, []).append((i, oz, kk, rec))
    return {p: [(i, z, k) for i, z, k, _rec in s] for p, s in seeds.items()}


def _neighbours(levels: list, p: float) -> list:
    """The stored levels next to ``p``: the nearest below and the nearest above (nearest first)."""
    j = levels.index(p)
    return sorted(levels[max(0, j - 1):j] + levels[j + 1:j + 2], key=lambda q: (abs(q - p), q))


def _holds(records, rec) -> bool:
    from contactvib.sweeps.completeness import same_attractor

    return any(same_attractor(rec, r) for r in records)


def _windows(ds, st):
    """(k, m, rows) of each window of a level: the periodic points of period k ≤ SEED_KMAX and m
    minima, split where the grid has a gap; rows = up to WINDOW_SAMPLES of its points, evenly
    spaced, its ends included."""
    per, mins = ds["period"].values, ds["minima_per_period"].values
    periodic = ds["kind"].values == "periodic"
    fe = ds["fe_hz"].values
    out = []
    for k, m in sorted({(int(a), int(b)) for a, b in zip(per[periodic], mins[periodic]) if 1 <= a <= SEED_KMAX}):
        rows = np.flatnonzero(periodic & (per == k) & (mins == m))
        rows = rows[np.argsort(fe[rows], kind="stable")]
        cuts = np.flatnonzero(np.diff(fe[rows]) > 1.5 * st.df_hz) + 1
        for run in np.split(rows, cuts):
            pick = np.unique(np.round(np.linspace(0, len(run) - 1, min(len(run), WINDOW_SAMPLES))).astype(int))
            out.append((k, m, [int(run[j]) for j in pick]))
    return out


def _records(ds) -> dict:
    """The stored orbits of a level by grid index, as records of ``same_attractor``."""
    grid = json.loads(ds.attrs["settings"])
    fmin, df = float(grid["fmin_hz"]), float(grid["df_hz"])
    per, mins, app = (ds[v].values for v in ("period", "minima_per_period", "app_um"))
    kind, fe = ds["kind"].values, ds["fe_hz"].values
    s0, ns = ds["strobe_start"].values, ds["strobe_count"].values
    sy, sv = ds["strobe_y_um"].values, ds["strobe_ydot_mm_s"].values
    out: dict = {}
    for j in range(fe.size):
        periodic = str(kind[j]) == "periodic"
        q = slice(int(s0[j]), int(s0[j] + ns[j]))
        out.setdefault(int(round((float(fe[j]) - fmin) / df)), []).append(
            {"period": int(per[j]) if periodic else None, "minima_per_period": int(mins[j]) if periodic else None,
             "app_um": float(app[j]), "strobe": np.column_stack([sy[q], sv[q]])})
    return out
