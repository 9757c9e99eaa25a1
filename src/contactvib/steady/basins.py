"""Basins of attraction: a grid of initial states (y, ẏ) at one operating point, each labelled by
the attractor it reaches.

Procedure
---------
1. :func:`~contactvib.steady.attractors.find_attractors` runs first (same ``kmax`` and
   ``max_periods``); its attractors are the labels ``0 .. n−1``, in its order (A_pp, largest
   first).
2. Every grid start (phase 0 of the excitation) is settled by the search's own kernel
   (:func:`~contactvib.steady.attractors.settle_starts`, Ctrl-C ends it within one period), with
   the strobe points of the known periodic attractors as capture points: a start whose strobe
   point comes within the search's ``capture_tol`` of one is labelled with that attractor.
3. The others are grouped by the search's rules
   (:func:`~contactvib.steady.attractors.group_outcomes`): a periodic orbit is matched by
   :func:`~contactvib.steady.orbits.same_orbit`, a proven non-periodic attractor
   (:func:`~contactvib.steady.transients.nonperiodic_verdict`) by the overlap of its strobe cloud;
   an attractor the search did not find becomes a new label ``n, n+1, …``. Starts that did not
   settle within ``max_periods`` or whose integration failed get label −1.

The grid is split into blocks of rows (ẏ values); :func:`basin_block` computes one block as a
pure function of (model, excitation, the search's result, grid, box, rows), so blocks can run
anywhere in any order; :func:`merge_blocks` joins them (new attractors found in several blocks
are matched again). :func:`basins` runs the blocks here, one after the other, each in parallel
over its starts (numba threads).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np

from contactvib.call_forms import old_form
from contactvib.model import ContactModel, Excitation, check_excitation, check_int, check_range
from contactvib.model.checks import MEMORY_MAX, check_memory
from contactvib.steady.attractors import (
    box_half_width,
    check_search,
    default_max_periods,
    find_attractors,
    group_outcomes,
    same_cloud,
    settle_starts,
)
from contactvib.steady.orbits import describe_orbit, same_orbit, strobe_points
from contactvib.steady.results import Attractor, AttractorSet
from contactvib.steady.transients import WINDOW, check_damped, check_work

__all__ = ["basins", "basin_block", "merge_blocks", "default_box", "check_basins", "grid_axes",
           "BasinMap", "BasinBlock"]

#: Bytes per grid point kept for the whole map (start, label, grouping; rounded up). The settle
#: kernel's arrays are per block (:data:`BLOCK_STARTS`).
_BYTES_PER_POINT = 64
#: Grid starts per block when :func:`basins` runs locally (memory of one settle call ~ 35 MB).
BLOCK_STARTS = 16384


def default_box(model: ContactModel, excitation: Excitation) -> tuple[tuple[float, float], tuple[float, float]]:
    """The attractor search's start box in µm and mm/s: ``((y_min, y_max), (ydot_min, ydot_max))``
    with x ∈ [1 − a, 1 + a], x' ∈ [−a, a], a = 2 + 10 P_a/Q."""
    a = box_half_width(excitation)
    u = model.units
    return (u.position_um(1.0 - a), u.position_um(1.0 + a)), (-a * u.ydot_mm_s, a * u.ydot_mm_s)


def check_basins(grid, box, kmax, max_periods, n_starts=512, seed=0):
    """The checked inputs of :func:`basins`: ``(grid, box, kmax, max_periods, n_starts, seed)``.

    ``grid = (n_y, n_ydot)``: integers ≥ 2 whose map fits in
    :data:`~contactvib.model.checks.MEMORY_MAX`; ``box = ((y_min, y_max), (ydot_min, ydot_max))``
    [µm, mm/s], finite with y_min < y_max and ydot_min < ydot_max, or None (the search's box);
    the search's sizes as :func:`~contactvib.steady.attractors.check_search`."""
    n_y = check_int("n_y", grid[0], 2)
    n_ydot = check_int("n_ydot", grid[1], 2)
    check_memory("grid", f"{n_y}x{n_ydot}", float(n_y) * n_ydot * _BYTES_PER_POINT,
                 MEMORY_MAX // _BYTES_PER_POINT)
    if box is not None:
        (y_lo, y_hi), (v_lo, v_hi) = box
        y_lo = check_range("y_min", y_lo, unit="µm")
        y_hi = check_range("y_max", y_hi, y_lo, False, "µm", lower_name="y_min")
        v_lo = check_range("ydot_min", v_lo, unit="mm/s")
        v_hi = check_range("ydot_max", v_hi, v_lo, False, "mm/s", lower_name="ydot_min")
        box = ((y_lo, y_hi), (v_lo, v_hi))
    n_starts, seed, kmax, max_periods = check_search(n_starts, seed, kmax, max_periods)
    return (n_y, n_ydot), box, kmax, max_periods, n_starts, seed


def grid_axes(grid, box) -> tuple[np.ndarray, np.ndarray]:
    """The grid's y [µm] (``n_y`` values) and ẏ [mm/s] (``n_ydot``) values, ends included."""
    (y_lo, y_hi), (v_lo, v_hi) = box
    return np.linspace(y_lo, y_hi, grid[0]), np.linspace(v_lo, v_hi, grid[1])


@dataclass(frozen=True)
class BasinBlock:
    """Rows ``rows[0]:rows[1]`` (ẏ values) of a basin map.

    Attributes
    ----------
    rows : tuple of int
        First and past-the-last row.
    labels : ndarray of int64, shape (rows, n_y)
        ``0..n−1``: the search's attractors; ``n + j``: ``new[j]``; −1: none reached.
    new : list of dict
        Attractors the search did not find (the search's group records: period, strobe or tail,
        z, M, res, type, lyap), in order of first appearance.
    n_failed, n_unsettled : int
        Starts whose integration failed, or that did not settle.
    """

    rows: tuple
    labels: np.ndarray
    new: list
    n_failed: int
    n_unsettled: int


def _known_groups(excitation: Excitation, search: AttractorSet) -> list[dict]:
    """The search's attractors as group records of :func:`group_outcomes` (periodic: strobe
    points; non-periodic: a cloud of 2·WINDOW strobe points from its state)."""
    rtol = search.settings["rtol_transient"]
    groups = []
    for a in search:
        g = {"period": a.period, "z": a.state, "hits": 0, "box": 0, "type": a.kind}
        if a.period is None:
            g["tail"] = strobe_points(excitation, a.state, 2 * WINDOW, rtol)
        else:
            g["strobe"] = strobe_points(excitation, a.state, a.period)
        groups.append(g)
    return groups


def basin_block(model: ContactModel, excitation: Excitation, search: AttractorSet, grid, box,
                rows: tuple[int, int]) -> BasinBlock:
    """Label the grid starts of rows ``rows[0]:rows[1]`` (ẏ values) by the attractor they reach.

    ``search`` is the result of :func:`find_attractors` at this operating point (its settings
    give kmax, the transient limit and the tolerances); ``grid`` and ``box`` as :func:`basins`
    (checked). A pure function of its arguments: blocks can be computed independently."""
    ys, vs = grid_axes(grid, box)
    r0, r1 = rows
    u = model.units
    X, V = np.meshgrid(u.state(ys, 0.0)[0], vs[r0:r1] / u.ydot_mm_s)
    Z = np.column_stack([X.ravel(), V.ravel()])
    groups = _known_groups(excitation, search)
    n_known = len(groups)
    periodic = [(j, g) for j, g in enumerate(groups) if g["period"] is not None]
    cap_pts = np.vstack([g["strobe"] for _j, g in periodic]) if periodic else np.empty((0, 2))
    cap_id = np.array([j for j, g in periodic for _p in range(g["period"])], np.int64)
    s = search.settings
    out = settle_starts(excitation, Z, np.zeros(Z.shape[0]), s["kmax"], s["max_periods"], s["detect_tol"],
                        s["rtol_transient"], cap_pts, cap_id, s["capture_tol"])
    n_failed, n_unsettled, _, labels = group_outcomes(groups, excitation, np.ones(Z.shape[0], bool),
                                                      s["rtol_transient"], out, kmax=s["kmax"])
    new = [{k: v for k, v in g.items() if k not in ("hits", "box")} for g in groups[n_known:]]
    return BasinBlock(rows=(r0, r1), labels=labels.reshape(r1 - r0, grid[0]), new=new,
                      n_failed=int(n_failed), n_unsettled=int(n_unsettled))


def _same_group(a: dict, b: dict) -> bool:
    if a["period"] is None or b["period"] is None:
        return a["period"] is None and b["period"] is None and same_cloud(a["tail"], b["tail"])
    return a["period"] == b["period"] and same_orbit(a["strobe"], b["strobe"])


def merge_blocks(model: ContactModel, excitation: Excitation, search: AttractorSet, grid, box,
                 blocks: list[BasinBlock]) -> BasinMap:
    """The basin map of ``blocks`` that cover the rows ``0..n_ydot`` (any order): new attractors
    are matched across blocks and numbered after the search's, in row order."""
    blocks = sorted(blocks, key=lambda b: b.rows[0])
    if [b.rows[0] for b in blocks] != [0, *(b.rows[1] for b in blocks[:-1])] or blocks[-1].rows[1] != grid[1]:
        raise ValueError(f"blocks {[b.rows for b in blocks]} do not cover the rows 0..{grid[1]} once")
    n_known = len(search)
    new: list[dict] = []
    parts = []
    for b in blocks:
        lut = np.arange(-1, n_known + len(b.new), dtype=np.int64)  # lut[label + 1]
        for j, g in enumerate(b.new):
            match = next((i for i, h in enumerate(new) if _same_group(g, h)), None)
            if match is None:
                new.append(g)
                match = len(new) - 1
            lut[n_known + j + 1] = n_known + match
        parts.append(lut[b.labels + 1])
    labels = np.vstack(parts)
    n = labels.size
    described = [describe_orbit(excitation, g["z"], g["period"], monodromy=g["M"], closure=g["res"],
                                basin_fraction=float(np.count_nonzero(labels == n_known + j)) / n,
                                hits=int(np.count_nonzero(labels == n_known + j)), kind=g["type"],
                                spectrum=g["spectrum"])
                 for j, g in enumerate(new)]
    ys, vs = grid_axes(grid, box)
    return BasinMap(y_um=ys, ydot_mm_s=vs, labels=labels, attractors=[*search.attractors, *described],
                    n_known=n_known, search=search, n_failed=sum(b.n_failed for b in blocks),
                    n_unsettled=sum(b.n_unsettled for b in blocks))


@old_form("model", "excitation", "grid", "box", "kmax", "max_periods", "n_starts", "seed", "block_starts")
def basins(excitation: Excitation, *, grid=(400, 400), box=None, kmax: int = 8,
           max_periods: int | None = None, n_starts: int = 512, seed: int = 0,
           block_starts: int = BLOCK_STARTS) -> BasinMap:
    """Basins of attraction on a grid of initial states (y, ẏ) at phase 0 of the excitation.

    Parameters
    ----------
    excitation : Excitation
        The operating point (its model, ``excitation.model``, damped: h_n > 0).
    grid : (int, int)
        Grid points in y and in ẏ (each ≥ 2).
    box : ((float, float), (float, float)) or None
        ``((y_min, y_max), (ydot_min, ydot_max))`` [µm, mm/s], ends included; None: the attractor
        search's start box (``default_box``).
    kmax, max_periods, n_starts, seed
        Of the attractor search (:func:`find_attractors`), whose transient limit and tolerances
        the grid starts use too.
    block_starts : int
        Grid starts per block (whole rows, at least one row).

    Returns
    -------
    BasinMap
        Labels (−1: no attractor within ``max_periods``), the attractors and their fractions.
    """
    model = check_excitation(excitation).model
    check_damped(model, "basins of attraction")
    grid, box, kmax, max_periods, n_starts, seed = check_basins(grid, box, kmax, max_periods, n_starts, seed)
    block_starts = check_int("block_starts", block_starts, 1)
    box = default_box(model, excitation) if box is None else box
    limit = default_max_periods(excitation) if max_periods is None else max_periods
    check_work(excitation, grid[0] * grid[1], limit,
               options="--grid or --max-periods")
    search = find_attractors(excitation, n_starts=n_starts, seed=seed, kmax=kmax,
                             max_periods=max_periods)
    step = max(1, block_starts // grid[0])
    blocks = [basin_block(model, excitation, search, grid, box, (r, min(r + step, grid[1])))
              for r in range(0, grid[1], step)]
    return merge_blocks(model, excitation, search, grid, box, blocks)


@dataclass(frozen=True)
class BasinMap:
    """Basins of attraction on a grid of initial states at one operating point.

    Attributes
    ----------
    y_um, ydot_mm_s : ndarray
        The grid's y [µm] (n_y values) and ẏ [mm/s] (n_ydot values).
    labels : ndarray of int64, shape (n_ydot, n_y)
        The attractor reached from (y_um[j], ydot_mm_s[i]) at phase 0: an index into
        ``attractors``, or −1 (none within the transient limit, or the integration failed).
    attractors : list of Attractor
        The search's attractors (labels ``0..n_known−1``, their ``basin_fraction`` from the
        search's random box), then those only the grid reached (``basin_fraction`` on the grid).
    n_known : int
        Attractors found by the search.
    search : AttractorSet
        The attractor search that ran first.
    n_failed, n_unsettled : int
        Grid starts whose integration failed, or that did not settle (label −1).
    """

    y_um: np.ndarray
    ydot_mm_s: np.ndarray
    labels: np.ndarray
    attractors: list
    n_known: int
    search: AttractorSet
    n_failed: int = 0
    n_unsettled: int = 0

    @property
    def n_points(self) -> int:
        return int(self.labels.size)

    def fraction(self, label: int) -> tuple[float, float]:
        """Share of the grid starts with ``label`` [1] and its standard error sqrt(p(1−p)/N).

        Neighbouring grid points are correlated (basins are regions), so this standard error of
        independent samples is a lower bound of the grid's sampling error."""
        p = float(np.count_nonzero(self.labels == label)) / self.n_points
        return p, math.sqrt(p * (1.0 - p) / self.n_points)

    def fractions(self) -> list[dict]:
        """One entry per label, then label −1: ``{"label", "period", "minima_per_period", "app_um",
        "fraction", "stderr"}`` (the JSON contract of ``contactvib basins --json``)."""
        rows = []
        for label, a in [*enumerate(self.attractors), (-1, None)]:
            p, se = self.fraction(label)
            rows.append({"label": label, "period": None if a is None else a.period,
                         "minima_per_period": None if a is None else a.minima_per_period,
                         "app_um": None if a is None else float(a.app_um), "fraction": p, "stderr": se})
        return rows

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib basins --json``."""
        s = self.search
        return {
            "pa_over_q": float(s.pa_over_q), "fe_hz": float(s.fe_hz), "fn0_hz": float(s.fn0_hz),
            "y0_um": float(s.y0_um), "grid": [int(self.y_um.size), int(self.ydot_mm_s.size)],
            "y_range_um": [float(self.y_um[0]), float(self.y_um[-1])],
            "ydot_range_mm_s": [float(self.ydot_mm_s[0]), float(self.ydot_mm_s[-1])],
            "n_points": self.n_points, "n_failed": int(self.n_failed), "n_unsettled": int(self.n_unsettled),
            "n_known": int(self.n_known), "max_periods": int(s.settings["max_periods"]),
            "units": {"y": "um (positive = contact deflection)", "ydot": "mm/s", "P_a": "Q = M g"},
            "fractions": self.fractions(),
            "attractors": [{"label": i, **a.to_dict()} for i, a in enumerate(self.attractors)],
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), **kwargs)

    def to_dataset(self):
        """An xarray Dataset: ``label`` (ydot_mm_s, y_um), per attractor its period (0:
        non-periodic), minima, A_pp, fraction and standard error, its strobe points (``strobe``
        dimension, ``strobe_label``); units in each variable's ``units`` attribute."""
        import xarray as xr

        atts: list[Attractor] = self.attractors
        labels = np.arange(-1, len(atts))
        fr = np.array([self.fraction(int(k)) for k in labels]).reshape(-1, 2)
        strobe_label = np.concatenate([np.full(a.strobe_y_um.size, i) for i, a in enumerate(atts)] or [[]])

        def cat(name):
            return np.concatenate([getattr(a, name) for a in atts] or [[]])

        s = self.search
        ds = xr.Dataset(
            {"label": (("ydot_mm_s", "y_um"), self.labels, {"units": "1", "long_name": "attractor reached (-1: none)"}),
             "period": ("attractor", np.array([a.period or 0 for a in atts], np.int64),
                        {"units": "excitation periods", "long_name": "period (0: non-periodic)"}),
             "minima_per_period": ("attractor", np.array([-1 if a.minima_per_period is None else
                                                          a.minima_per_period for a in atts], np.int64),
                                   {"units": "1"}),
             "app_um": ("attractor", np.array([a.app_um for a in atts], float), {"units": "um"}),
             "fraction": ("label_all", fr[:, 0], {"units": "1"}),
             "stderr": ("label_all", fr[:, 1], {"units": "1", "note": "sqrt(p(1-p)/N), a lower bound"}),
             "strobe_label": ("strobe", strobe_label.astype(np.int64), {"units": "1"}),
             "strobe_y_um": ("strobe", cat("strobe_y_um").astype(float), {"units": "um"}),
             "strobe_ydot_mm_s": ("strobe", cat("strobe_ydot_mm_s").astype(float), {"units": "mm/s"})},
            coords={"y_um": ("y_um", self.y_um, {"units": "um"}),
                    "ydot_mm_s": ("ydot_mm_s", self.ydot_mm_s, {"units": "mm/s"}),
                    "attractor": ("attractor", np.arange(len(atts))), "label_all": ("label_all", labels)},
            attrs={"pa_over_q": float(s.pa_over_q), "fe_hz": float(s.fe_hz), "fn0_hz": float(s.fn0_hz),
                   "y0_um": float(s.y0_um), "n_known": int(self.n_known), "n_failed": int(self.n_failed),
                   "n_unsettled": int(self.n_unsettled),
                   "settings": json.dumps({k: v for k, v in s.settings.items()})})
        return ds
