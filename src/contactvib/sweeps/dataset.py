"""Resonance datasets: the attractors of a sweep as an xarray Dataset (NetCDF), branches and labels.

Layout (one Dataset for any number of P_a levels; every variable states its unit)
---------------------------------------------------------------------------------
Dimension ``point`` — one row per attractor at one (P_a, f_e):
    ``pa_over_q`` [Q], ``fe_hz`` [Hz], ``kind`` ("periodic" / "non-periodic"), ``period``
    [excitation periods; 0 = non-periodic], ``minima_per_period`` [1; −1 = non-periodic],
    ``app_um``, ``ymin_um``, ``ymax_um`` [µm], ``loses_contact`` [bool],
    ``contact_loss_fraction`` [1], ``basin_fraction`` [1; NaN where no multi-start ran],
    ``floquet_re``/``floquet_im`` (point, multiplier) [1], ``floquet_abs_max`` [1],
    ``closure`` [1], ``lyapunov_per_period`` [1/excitation period; NaN for periodic],
    ``dominant_harmonic`` [multiples of f_e], ``resonance`` (label, see :func:`resonance_label`),
    ``attractor_type`` (periodic / chaotic / quasi-periodic, earned by the attractor search's rule:
    :func:`contactvib.sweeps.verdict.judge_rows`), ``true_period`` [excitation periods; the minimal
    period, beyond kmax too; 0 = none], ``lyapunov_per_s``/``lyapunov_stderr_per_s`` (point,
    exponent) [1/s] (periodic: ln|μ_i|/T; otherwise Benettin over 2000 periods with batch-means
    errors), ``kaplan_yorke_dimension`` [1; NaN unless λ1 > 0],
    ``branch_index`` (into the ``branch`` dimension), ``origin`` ("newton" / "jump" / "start"),
    ``found_by`` ("sweep" / "perturbation seed" / "multi-start" / "continuation": how the trace that first reached
    the point was started; see :mod:`contactvib.sweeps.sweep`),
    ``state_y_um`` [µm], ``state_ydot_mm_s`` [mm/s] (orbit point at phase 0),
    ``harmonics_um`` (point, harmonic) [µm] one-sided amplitudes at j·f_e/period, j = 1…,
    ``extrema_start``/``extrema_count`` and ``strobe_start``/``strobe_count`` (ragged indices).
Dimension ``dof`` — the model's coordinates (coordinates ``dof_name``, ``dof_unit``: "y", "um"), and
    per point ``dof_min``, ``dof_max``, ``dof_app``, ``dof_h1`` (point, dof) [the dof's unit]: range,
    peak-to-peak and one-sided amplitude at f_e.
Dimension ``contact`` — the model's contact elements (coordinate ``contact_name``: "contact"), and
    per point ``contact_loses_contact`` [bool], ``contact_loss_frac`` [1] and
    ``contact_mean_force_n`` [N] (point, contact): the time-averaged contact force, W = Q + F_pre
    for a periodic point (the period average of the equation of motion), NaN for a non-periodic one.
    :func:`contactvib.steady.results.dofs_and_contacts` rebuilds the JSON ``dofs``/``contacts``.
Dimension ``extremum`` — local extrema of y(t) over one orbit period (non-periodic: 32 periods):
    ``extremum_t_ms`` [ms], ``extremum_y_um`` [µm], ``extremum_is_min`` [bool].
Dimension ``strobe`` — stroboscopic points (phase 0 of the force): ``strobe_y_um``,
    ``strobe_ydot_mm_s``.
Dimension ``branch`` — ``branch_id``, ``branch_label``, ``branch_pa_over_q``, ``branch_period``,
    ``branch_minima``, ``branch_fmin_hz``, ``branch_fmax_hz``, ``branch_npoints``,
    ``branch_app_max_um``, ``branch_reached_by_sweep`` (0: isolated from the sweeps).
Dimension ``trace`` — one row per sweep/trace run: ``trace_label``, ``trace_pa_over_q``,
    ``trace_direction``, ``trace_f_start_hz``, ``trace_f_stop_hz``, ``trace_stop``, ``trace_root``.
Attributes: the model parameters, ``fn0_hz``, ``y0_um``, the sweep settings (JSON) and the grid.
"""

from __future__ import annotations

import json
import math

import numpy as np

from contactvib._kernels.status import STOP_FAILED, STOP_GRID_END, STOP_KNOWN, STOP_TABLE_FULL, status_message
from contactvib.labels import attractor_type, level_labels
from contactvib.model import LEVEL_KINDS, ContactModel, excitation_at

__all__ = ["level_dataset", "merge_levels", "write_atomic", "check_consistency", "STOP_REASONS", "TRACE_ROOTS"]

#: How a trace was started, inherited by the reverse traces it spawns ("level seed": an orbit of
#: another level walked in the level to this one, ``SweepSettings.level_seeds``). Points first reached by a
#: "sweep"-rooted trace are reachable by a laboratory sweep (up, down, reversing at a jump).
TRACE_ROOTS = ("sweep", "perturbation seed", "multi-start", "continuation", "level seed")

#: Layout version written into every dataset (``format`` attribute); chunks and datasets of
#: another version are recomputed (resume) or refused (query).
FORMAT = "contactvib-resonance-1"

#: Why a trace stopped, by trace stop code (the ``trace_stop`` strings of a dataset).
STOP_REASONS = {code: status_message(code, "stop")
                for code in (STOP_GRID_END, STOP_KNOWN, STOP_FAILED, STOP_TABLE_FULL)}


class _UnionFind:
    def __init__(self, n):
        self.p = np.arange(n)

    def find(self, a):
        p = self.p
        while p[a] != a:
            p[a] = p[p[a]]
            a = p[a]
        return a

    def union(self, a, b):
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.p[max(ra, rb)] = min(ra, rb)


def _components(n: int, links, same) -> np.ndarray:
    """Root of each of ``n`` rows in the components of the Newton links (no jump) between rows
    for which ``same(a, b)`` holds."""
    uf = _UnionFind(n)
    for a, b, jump in zip(links.a, links.b, links.jump):
        if jump == 0 and same(a, b):
            uf.union(int(a), int(b))
    return np.array([uf.find(j) for j in range(n)])


def _branch_variables(pa: float, fe, x_range, app, k, nmin, labels, roots, found_by):
    """Branch index of every row (branches ordered by their lowest frequency, then amplitude
    ``x_range`` = x_max − x_min) and the variables of dimension ``branch`` (``app`` in µm)."""
    uniq = list(dict.fromkeys(roots[np.lexsort((-x_range, fe))]))
    index = {r: b for b, r in enumerate(uniq)}
    branch = np.array([index[r] for r in roots], np.int64)
    nb = len(uniq)
    b_fmin, b_fmax = np.full(nb, np.inf), np.full(nb, -np.inf)
    b_np, b_app = np.zeros(nb, np.int64), np.zeros(nb)
    b_lab, b_k, b_min = np.empty(nb, dtype=object), np.zeros(nb, np.int64), np.zeros(nb, np.int64)
    for j in range(fe.size):
        b = branch[j]
        b_fmin[b] = min(b_fmin[b], fe[j])
        b_fmax[b] = max(b_fmax[b], fe[j])
        b_np[b] += 1
        b_app[b] = max(b_app[b], app[j])
        b_lab[b], b_k[b], b_min[b] = labels[j], k[j], nmin[j]
    b_sweep = np.zeros(nb, np.int8)
    b_sweep[branch[found_by == "sweep"]] = 1
    return branch, {
        "branch_id": ("branch", np.array([f"{pa:g}Q-b{b:03d}" for b in range(nb)], dtype=object)),
        "branch_label": ("branch", b_lab),
        "branch_pa_over_q": ("branch", np.full(nb, pa), {"units": "Q"}),
        "branch_period": ("branch", b_k),
        "branch_minima": ("branch", b_min),
        "branch_fmin_hz": ("branch", b_fmin, {"units": "Hz"}),
        "branch_fmax_hz": ("branch", b_fmax, {"units": "Hz"}),
        "branch_npoints": ("branch", b_np),
        "branch_app_max_um": ("branch", b_app, {"units": "um"}),
        "branch_reached_by_sweep": ("branch", b_sweep, {"units": "1", "comment": "1 if a laboratory "
                                    "sweep (up, down, reversing at jumps) reaches the branch"}),
    }


def _ragged_variables(rows, units) -> dict:
    """Extrema and stroboscopic points of every row, concatenated, with their start/count."""
    n_ext = rows.n_ext
    mask = np.arange(rows.ext_t.shape[1])[None, :] < n_ext[:, None]
    n_str = np.where(rows.kind == 0, rows.k, rows.n_strobe)
    smask = np.arange(rows.strobe.shape[1])[None, :] < n_str[:, None]
    sp = rows.strobe  # periodic: the k orbit points; non-periodic: the last recorded ones
    return {
        "extrema_start": ("point", np.concatenate([[0], np.cumsum(n_ext)[:-1]]).astype(np.int64)),
        "extrema_count": ("point", n_ext.astype(np.int64)),
        "strobe_start": ("point", np.concatenate([[0], np.cumsum(n_str)[:-1]]).astype(np.int64)),
        "strobe_count": ("point", n_str.astype(np.int64)),
        "extremum_t_ms": ("extremum", rows.ext_t[mask] * units.t_ms, {"units": "ms"}),
        "extremum_y_um": ("extremum", units.position_um(rows.ext_x[mask]), {"units": "um"}),
        "extremum_is_min": ("extremum", rows.ext_min[mask].astype(np.int8), {"units": "1"}),
        "strobe_y_um": ("strobe", units.position_um(sp[..., 0][smask]), {"units": "um"}),
        "strobe_ydot_mm_s": ("strobe", sp[..., 1][smask] * units.ydot_mm_s, {"units": "mm/s"}),
    }


def _trace_variables(pa: float, stops) -> dict:
    """One row per sweep or trace run: label, direction, start and stop, why it stopped."""
    return {
        "trace_label": ("trace", np.array([t.label for t in stops], dtype=object)),
        "trace_pa_over_q": ("trace", np.full(len(stops), pa), {"units": "Q"}),
        "trace_direction": ("trace", np.array([t.direction for t in stops], np.int64)),
        "trace_f_start_hz": ("trace", np.array([t.f_start_hz for t in stops]), {"units": "Hz"}),
        "trace_f_stop_hz": ("trace", np.array([t.f_stop_hz for t in stops]), {"units": "Hz"}),
        "trace_stop": ("trace", np.array([status_message(t.reason, "stop") for t in stops], dtype=object)),
        "trace_root": ("trace", np.array([t.root for t in stops], dtype=object)),
    }


def _level_kind_variables(model: ContactModel, kind: str, pa: float, fe: np.ndarray, rows) -> tuple[dict, dict]:
    """The level's variables and attributes of a base-motion sweep (``kind`` "base-um"/"base-g":
    the level is U [um] or A [g]; nothing for a force sweep): the level variable ``pa_over_q``
    with its own units, ``force_pa_over_q``, the inertial force of each point [Q], and
    ``slider_app_um``, the peak-to-peak of the slider's absolute motion s = y + u (periodic
    points; NaN for non-periodic ones)."""
    if kind == "force":
        return {}, {}
    from contactvib.errors import ComputationError
    from contactvib.steady.orbits import slider_app_um

    def slider(j):
        if rows.kind[j] != 0:
            return math.nan
        try:
            return slider_app_um(excitation_at(model, pa, float(fe[j]), kind), rows.z[j], int(rows.k[j]))
        except ComputationError:
            return math.nan

    sym, unit, long_name = LEVEL_KINDS[kind]
    variables = {
        "pa_over_q": ("point", np.full(fe.size, pa), {
            "units": unit, "long_name": f"{long_name} (the sweep's level)",
            "comment": f"this dataset's level is {sym} [{unit}], not P_a/Q (see the attribute 'excitation'); "
                       "the variable keeps its name so that every reader of a level finds it"}),
        "force_pa_over_q": ("point", np.array([excitation_at(model, pa, float(v), kind).pa_over_q for v in fe]),
                            {"units": "Q",
                             "long_name": "equivalent force amplitude M U (2 pi f_e)^2/(M g) or M A/(M g)"}),
        "slider_app_um": ("point", np.array([slider(j) for j in range(fe.size)]),
                          {"units": "um", "long_name": "peak-to-peak of the slider's absolute motion s = y + u",
                           "comment": "NaN for non-periodic points"}),
    }
    return variables, {"excitation": kind, "level_symbol": sym, "level_unit": unit}


def _dof_contact_variables(model: ContactModel, rows, app: np.ndarray, loses: np.ndarray, n_record: int) -> dict:
    """The ``dof`` and ``contact`` variables of every row (layout in the module docstring), from the
    range, the harmonics at j f_e / period (the f_e one at j = period; non-periodic: j = ``n_record``),
    the contact loss and, for a periodic row, the exact mean contact force W."""
    from contactvib.steady.results import CONTACT_NAMES, DOF_NAMES, DOF_UNITS

    u, n = model.units, rows.kind.size
    periodic = rows.kind == 0
    j = np.where(periodic, rows.k, n_record)
    ok = (j >= 1) & (j <= rows.harm.shape[1])
    h1 = np.full(n, np.nan)
    h1[ok] = rows.harm[np.nonzero(ok)[0], j[ok] - 1] * u.y_um
    dof = {"dof_name": ("dof", np.array(DOF_NAMES, dtype=object),
                        {"long_name": "the model's coordinates (y: the contact deflection)"}),
           "dof_unit": ("dof", np.array(DOF_UNITS, dtype=object),
                        {"long_name": "display unit of each coordinate (of dof_min, dof_max, dof_app, dof_h1)"})}
    contact = {"contact_name": ("contact", np.array(CONTACT_NAMES, dtype=object),
                                {"long_name": "the model's contact elements"})}

    def per_dof(values, attrs):
        return _with_coords(("point", "dof"), values[:, None], attrs, dof)

    def per_contact(values, attrs):
        return _with_coords(("point", "contact"), values[:, None], attrs, contact)

    return {
        "dof_min": per_dof(rows.xmin * u.y_um, {"units": "um", "long_name": "minimum of the coordinate"}),
        "dof_max": per_dof(rows.xmax * u.y_um, {"units": "um", "long_name": "maximum of the coordinate"}),
        "dof_app": per_dof(app, {"units": "um", "long_name": "peak-to-peak amplitude of the coordinate"}),
        "dof_h1": per_dof(h1, {"units": "um", "long_name": "one-sided amplitude of the coordinate at f_e",
                               "comment": "harmonics_um at j = period (non-periodic: over the recorded span)"}),
        "contact_loses_contact": per_contact(loses.astype(np.int8), {"units": "1",
                                             "comment": "1 where the contact opens on the orbit"}),
        "contact_loss_frac": per_contact(rows.flight, {"units": "1",
                                                       "long_name": "fraction of the period with the contact open"}),
        "contact_mean_force_n": per_contact(np.where(periodic, model.W, np.nan), {
            "units": "N", "long_name": "time-averaged contact force over the steady motion",
            "comment": "periodic points: exactly W = Q + F_pre (the period average of the equation of motion, "
                       "<y''> = 0 and <excitation> = 0); NaN for non-periodic points"}),
    }


def _with_coords(dims, values, attrs, coords):
    """An ``xarray.DataArray`` of ``values`` on ``dims`` with ``attrs`` and the coordinates ``coords``
    (name: (dim, values, attrs))."""
    import xarray as xr

    return xr.DataArray(values, dims=dims, attrs=attrs, coords={k: xr.Variable(*v) for k, v in coords.items()})


def _spectrum_variables(v: dict, kind: np.ndarray) -> dict:
    """The earned labels and Lyapunov spectra of a level's rows (:func:`.verdict.judge_rows`):
    ``attractor_type`` of the non-periodic rows replaced by their verdict, ``true_period``,
    ``lyapunov_per_s``/``lyapunov_stderr_per_s`` (point, exponent) and ``kaplan_yorke_dimension``."""
    from contactvib.steady.results import kaplan_yorke_dimension

    types = np.where(kind == 0, "periodic", v["attractor_type"]).astype(object)
    lam = v["lyapunov_per_s"]
    ky = np.array([np.nan if (d := kaplan_yorke_dimension(row)) is None else d for row in lam])
    return {
        "attractor_type": ("point", types, {"comment": "periodic / chaotic / quasi-periodic, earned by the "
                                                       "attractor search's rule (Lyapunov spectrum, section)"}),
        "true_period": ("point", v["true_period"], {"units": "excitation periods",
                                                    "comment": "minimal period, beyond kmax too; 0 = none"}),
        "lyapunov_per_s": (("point", "exponent"), lam, {"units": "1/s", "long_name": "Lyapunov exponents, "
                                                        "descending (periodic: ln|mu|/T; else Benettin)"}),
        "lyapunov_stderr_per_s": (("point", "exponent"), v["lyapunov_stderr_per_s"],
                                  {"units": "1/s", "long_name": "standard error of the exponents (batch means)"}),
        "kaplan_yorke_dimension": ("point", ky, {"units": "1", "comment": "NaN unless lambda1 > 0"}),
    }


def level_dataset(model: ContactModel, level, settings: dict):
    """The Dataset of one P_a level from :func:`contactvib.sweeps.sweep.trace_level`'s output
    (a :class:`contactvib.sweeps.sweep.LevelTrace`); layout in the module docstring."""
    import xarray as xr

    from contactvib._kernels.describe import NP_RECORD

    rows, pa, f, u = level.rows, level.pa_over_q, level.f_hz, model.units
    n = level.n_rows
    if n == 0:
        raise ValueError("no attractor was found on this level")
    fe, kind, k = f[rows.i], rows.kind, rows.k
    nmin = np.where(kind == 0, rows.n_min, -1)
    loses = rows.xmin < 0.0
    # chains: rows continued by Newton (no jump), same kind and period; short label flickers
    # along a chain are smoothed away; branches: chains of one label
    chains = _components(n, level.links, lambda a, b: kind[a] == kind[b] and k[a] == k[b])
    grid_step = float(np.min(np.diff(f))) if f.size > 1 else 1.0
    nus, labels = level_labels(rows, fe, model.f_n0, chains, grid_step, NP_RECORD)
    roots = _components(n, level.links, lambda a, b: (kind[a] == kind[b] and k[a] == k[b]
                                                      and labels[a] == labels[b]))
    found_by = np.array([TRACE_ROOTS[int(c)] for c in level.found_by], dtype=object)
    x_range = rows.xmax - rows.xmin
    app = x_range * u.y_um
    branch, branch_vars = _branch_variables(pa, fe, x_range, app, k, nmin, labels, roots, found_by)
    point_vars = {
        "pa_over_q": ("point", np.full(n, pa), {"units": "Q", "long_name": "excitation amplitude P_a/(M g)"}),
        "fe_hz": ("point", fe, {"units": "Hz", "long_name": "excitation frequency f_e"}),
        "kind": ("point", np.where(kind == 0, "periodic", "non-periodic").astype(object)),
        "period": ("point", k, {"units": "excitation periods", "comment": "0 = non-periodic"}),
        "minima_per_period": ("point", nmin, {"units": "1", "comment": "-1 = non-periodic"}),
        "app_um": ("point", app, {"units": "um", "long_name": "peak-to-peak amplitude y_max - y_min"}),
        "ymin_um": ("point", u.position_um(rows.xmin), {"units": "um"}),
        "ymax_um": ("point", u.position_um(rows.xmax), {"units": "um"}),
        "loses_contact": ("point", loses.astype(np.int8), {"units": "1", "comment": "1 where y < 0 on the orbit"}),
        "contact_loss_fraction": ("point", rows.flight,
                                  {"units": "1", "long_name": "fraction of the period with y < 0"}),
        "basin_fraction": ("point", level.basin,
                           {"units": "1", "comment": "share of the multi-start box; NaN where not measured"}),
        "floquet_re": (("point", "multiplier"), rows.mu_re, {"units": "1"}),
        "floquet_im": (("point", "multiplier"), rows.mu_im, {"units": "1"}),
        "floquet_abs_max": ("point", np.hypot(rows.mu_re, rows.mu_im).max(axis=1), {"units": "1"}),
        "closure": ("point", rows.closure, {"units": "1", "long_name": "relative closure of the refined orbit"}),
        "lyapunov_per_period": ("point", rows.lyap, {"units": "1/excitation period",
                                                     "long_name": "largest Lyapunov exponent of the stroboscopic map"}),
        "dominant_harmonic": ("point", np.array([float(v) if v is not None else np.nan for v in nus]),
                              {"units": "multiples of f_e", "long_name": "resonance ratio nu (dominant_ratio)"}),
        "resonance": ("point", labels),
        "attractor_type": ("point", np.array([attractor_type(int(kind[j]), float(rows.lyap[j]))
                                              for j in range(n)], dtype=object),
                           {"comment": "periodic / chaotic / quasi-periodic / long-period (attractor_type)"}),
        "branch_index": ("point", branch, {"comment": "index into the branch dimension"}),
        "origin": ("point", np.array([status_message(o, "origin") for o in rows.origin], dtype=object)),
        "found_by": ("point", found_by, {"comment": "root of the trace that first reached the point: "
                                                    "sweep / perturbation seed / multi-start / continuation"}),
        "state_y_um": ("point", u.position_um(rows.z[:, 0]), {"units": "um"}),
        "state_ydot_mm_s": ("point", rows.z[:, 1] * u.ydot_mm_s, {"units": "mm/s"}),
        "harmonics_um": (("point", "harmonic"), rows.harm * u.y_um,
                         {"units": "um", "comment": "one-sided amplitude at j f_e / period, j = 1.."}),
    }
    level_vars, attrs = _level_kind_variables(model, settings.get("excitation", "force"), pa, fe, rows)
    point_vars.update(level_vars)
    if level.verdicts is not None:
        point_vars.update(_spectrum_variables(level.verdicts, kind))
    point_vars.update(_dof_contact_variables(model, rows, app, loses, NP_RECORD))
    ds = xr.Dataset(
        {**point_vars, **_ragged_variables(rows, u), **branch_vars, **_trace_variables(pa, level.stops)},
        attrs={**attrs,
            "title": "contactvib resonance dataset (Kostek 2013 contact oscillator)",
            "format": FORMAT,
            "model": json.dumps(model.parameters()),
            "law": model.describe_law(),
            "fn0_hz": model.f_n0,
            "y0_um": model.units.y_um,
            "settings": json.dumps(settings),
            "conventions": "y > 0 contact deflection, y < 0 gap; ragged extrema/strobe via *_start/*_count",
        },
    )
    if attrs:
        for name in ("branch_pa_over_q", "trace_pa_over_q"):
            ds[name].attrs["units"] = attrs["level_unit"]
    if model.units.y_offset_um:  # a law with a clearance: where the contact engages
        ds.attrs["engagement_um"] = model.units.y_offset_um
        ds.attrs["conventions"] = "y > engagement_um contact deflection, below it a gap; ragged extrema/strobe " \
                                  "via *_start/*_count"
    return ds


def merge_levels(datasets: list):
    """Concatenate level datasets (offsetting the ragged and branch indices)."""
    import xarray as xr

    datasets = sorted(datasets, key=lambda d: float(d["pa_over_q"].values[0]))
    parts = []
    e_off = s_off = b_off = 0
    for d in datasets:
        d = d.copy()
        d["extrema_start"] = d["extrema_start"] + e_off
        d["strobe_start"] = d["strobe_start"] + s_off
        d["branch_index"] = d["branch_index"] + b_off
        e_off += d.sizes["extremum"]
        s_off += d.sizes["strobe"]
        b_off += d.sizes["branch"]
        parts.append(d)
    dims = ["point", "extremum", "strobe", "branch", "trace"]
    out = {}
    for name in parts[0].data_vars:
        dim = parts[0][name].dims[0]
        out[name] = xr.concat([p[name] for p in parts], dim=dim)
    ds = xr.Dataset(out, attrs=dict(parts[0].attrs))
    ds.attrs["levels_pa_over_q"] = json.dumps([float(p["pa_over_q"].values[0]) for p in parts])
    assert all(dm in ds.dims for dm in dims if dm in parts[0].dims)
    return ds


def check_consistency(ds, rtol: float = 1e-9, atol: float = 1e-12) -> list[str]:
    """The rows of a resonance dataset that contradict themselves, one line each (empty: none).

    Per point: ``app_um`` = ``ymax_um`` − ``ymin_um`` (within ``rtol`` relative / ``atol`` µm),
    and ``loses_contact`` ⇔ ``ymin_um`` < 0 ⇔ ``contact_loss_fraction`` > 0; where the dataset has
    the ``dof``/``contact`` variables, the coordinate y's ``dof_min``, ``dof_max``, ``dof_app`` and
    the contact's ``contact_loses_contact``, ``contact_loss_frac`` equal ``ymin_um``, ``ymax_um``,
    ``app_um``, ``loses_contact`` and ``contact_loss_fraction``."""
    app, lo, hi = (np.asarray(ds[v].values, dtype=float) for v in ("app_um", "ymin_um", "ymax_um"))
    loses = np.asarray(ds["loses_contact"].values).astype(bool)
    flight = np.asarray(ds["contact_loss_fraction"].values, dtype=float)
    span = hi - lo
    wrong_app = ~(np.abs(app - span) <= np.maximum(rtol * np.abs(span), atol))
    wrong_contact = (loses != (lo < 0.0)) | (loses != (flight > 0.0))
    pa, fe = ds["pa_over_q"].values, ds["fe_hz"].values
    wrong_dof = _dof_mismatch(ds, {"dof_min": lo, "dof_max": hi, "dof_app": app, "contact_loses_contact": loses,
                                   "contact_loss_frac": flight}, rtol, atol)
    out = []
    for p in np.nonzero(wrong_app | wrong_contact | wrong_dof.any(axis=1))[0]:
        what = []
        if wrong_app[p]:
            what.append(f"app_um = {app[p]:.17g} but ymax_um - ymin_um = {span[p]:.17g}")
        if wrong_contact[p]:
            what.append(f"loses_contact = {bool(loses[p])}, ymin_um = {lo[p]:.17g}, "
                        f"contact_loss_fraction = {flight[p]:.17g}")
        what += [f"{name} differs from the point's own variable" for name, bad in zip(_DOF_CHECKED, wrong_dof[p])
                 if bad]
        out.append(f"point {p} (P_a = {float(pa[p]):g} Q, f_e = {float(fe[p]):g} Hz): " + "; ".join(what))
    return out


#: The dof/contact variables :func:`check_consistency` compares with the point's own variables.
_DOF_CHECKED = ("dof_min", "dof_max", "dof_app", "contact_loses_contact", "contact_loss_frac")


def _dof_mismatch(ds, own: dict, rtol: float, atol: float) -> np.ndarray:
    """(point, variable) flags of :data:`_DOF_CHECKED` whose first dof/contact entry is not the
    value in ``own`` (numbers: within ``rtol`` relative / ``atol``; all False for a dataset without
    these variables)."""
    flags = np.zeros((own["dof_app"].size, len(_DOF_CHECKED)), bool)
    for q, name in enumerate(_DOF_CHECKED):
        if name in ds.variables:
            v, ref = np.asarray(ds[name].values)[:, 0], own[name]
            if ref.dtype == bool:
                flags[:, q] = v.astype(bool) != ref
            else:
                v = v.astype(float)
                flags[:, q] = ~(np.abs(v - ref) <= np.maximum(rtol * np.abs(ref), atol))
    return flags


#: Points per NetCDF chunk of a compressed dataset (one level is a contiguous run of points, so
#: reading it reads only its own chunks).
POINT_CHUNK = 4096


def compressed_encoding(ds) -> dict:
    """NetCDF4 encoding of ``ds``: zlib level 4 with byte shuffling for every variable, numeric
    ones chunked along their first dimension (``point``, ``extremum``, ``strobe``, ...) by
    :data:`POINT_CHUNK`; string arrays stored as UTF-8 character arrays (NetCDF4 cannot compress
    variable-length strings: they were a third of a compressed level); the values are unchanged."""
    enc = {}
    for name, var in ds.variables.items():
        e = {"zlib": True, "complevel": 4, "shuffle": True}
        if var.ndim and var.dtype.kind not in "OUS" and var.size:
            e["chunksizes"] = tuple(min(POINT_CHUNK, n) if i == 0 else n for i, n in enumerate(var.shape))
        elif var.ndim and var.dtype.kind in "OU":
            e["dtype"] = "S1"
        enc[name] = e
    return enc


def write_atomic(ds, path, compress: bool = False) -> None:
    """Write a NetCDF file via a temporary file and an atomic rename; ``compress``: NetCDF4 with
    :func:`compressed_encoding`."""
    import os
    from pathlib import Path

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.tmp{os.getpid()}")
    with _local_writes():
        if compress:
            ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=compressed_encoding(ds))
        else:
            ds.to_netcdf(tmp)
    os.replace(tmp, path)


def _local_writes():
    """Within: xarray locks its file writes in this process only, also on a Dask worker (where
    it would otherwise take a cluster-wide lock through the scheduler, which a cluster that is
    shutting down cannot release)."""
    try:
        import dask
    except ImportError:
        from contextlib import nullcontext

        return nullcontext()
    return dask.config.set(scheduler="synchronous")
