"""The resonance dataset of a :class:`~contactvib.model.system.System`: the levels of
:func:`~contactvib.sweeps.system_sweep.sweep_system_level` in the layout of the 1-DOF dataset
(:mod:`contactvib.sweeps.dataset`) where its variables make sense.

Dimension ``point`` — one stable attractor at one (P_a, f_e) (the verdict's rows last):
    ``pa_newton`` [N] (the level), ``pa_over_q`` [Q] where the system has a Q (``rocking``: M g),
    ``fe_hz`` [Hz], ``kind`` ("periodic" / "non-periodic"), ``period`` [excitation periods; 0 =
    non-periodic], ``minima_per_period`` [1] (of the first contact's deflection; −1 =
    non-periodic), ``app_um`` (peak-to-peak of the first coordinate, in its display unit: µm or
    µrad), ``loses_contact`` [1] (some contact opens on the orbit), ``basin_fraction`` [1] (share
    of the search's starts; NaN for points reached by a walk), ``floquet_re``/``floquet_im``
    (point, multiplier: 2n) [1], ``floquet_abs_max`` [1], ``closure`` [1] (NaN: non-periodic),
    ``attractor_type`` (periodic / chaotic / quasi-periodic), ``true_period`` [excitation periods;
    0 = none], ``lyapunov_per_s``/``lyapunov_stderr_per_s`` (point, exponent: 2n) [1/s]
    (periodic: ln ``|μ_i|`` f_e / k; else the verdict's Benettin run), ``kaplan_yorke_dimension``
    [1] (NaN unless chaotic), ``branch_index``, ``origin`` ("newton" / "jump" / "start"),
    ``found_by`` ("sweep" / "multi-start"), ``state_q``, ``state_qdot`` (point, dof) [display
    units] (the orbit point at phase 0; non-periodic: the last strobe point),
    ``strobe_start``/``strobe_count`` (ragged) into ``strobe_q``, ``strobe_qdot`` (strobe, dof).
Dimensions ``dof`` and ``contact`` — as :func:`contactvib.sweeps.dataset.level_dataset` writes
    them: ``dof_min``, ``dof_max``, ``dof_app``, ``dof_h1`` (point, dof) [the dof's unit],
    ``contact_loses_contact``, ``contact_loss_frac``, ``contact_mean_force_n`` [N] (point, contact),
    coordinates ``dof_name``, ``dof_unit``, ``contact_name``.
Dimension ``branch`` — points joined by Newton continuation (no jump) at one period, or
    consecutive non-periodic points of a sweep of one type (the verdict's branches last):
    ``branch_id``, ``branch_label`` ("period-k", "chaotic", "quasi-periodic": systems carry no
    resonance labels),
    ``branch_pa_newton`` [N] (and ``branch_pa_over_q``), ``branch_period``, ``branch_minima``,
    ``branch_fmin_hz``, ``branch_fmax_hz``, ``branch_npoints``, ``branch_app_max_um``,
    ``branch_reached_by_sweep``.
Dimension ``trace`` — one row per walk: ``trace_label``, ``trace_pa_newton`` (and
    ``trace_pa_over_q``), ``trace_direction``, ``trace_f_start_hz``, ``trace_f_stop_hz``,
    ``trace_stop``, ``trace_root``.
Attributes: ``system`` ("rocking" or the TOML file's text), ``system_parameters`` (JSON: the
rocking unit's a, J, e), ``system_coordinates``, ``system_units`` ("m"/"rad"), ``contacts`` (JSON
lists; not ``coordinates``, which NetCDF readers take for the CF attribute),
``natural_frequencies_hz`` (JSON), ``level_variable`` ("pa_over_q" or "pa_newton": the variable
that holds the levels), ``level_symbol``, ``level_unit``, ``settings`` (JSON), ``format``; for
``rocking`` also ``model`` (the slider's parameters), ``fn0_hz`` and ``y0_um``.
Not written (1-DOF only): ``resonance``, ``dominant_harmonic``, ``lyapunov_per_period``,
``harmonics_um``, the extrema, ``ymin_um``/``ymax_um``, ``contact_loss_fraction``.
"""

from __future__ import annotations

import json

import numpy as np

from contactvib.sweeps.dataset import FORMAT

__all__ = ["system_level_dataset", "merge_system_levels", "SystemDescription"]


class SystemDescription(dict):
    """What a system dataset says about its system: ``label`` ("rocking" or the file's name),
    ``text`` (the ``system`` attribute), ``q_newton`` (Q [N] or None), ``model`` (JSON or None),
    ``fn0_hz``, ``y0_um`` (or None), ``parameters`` (JSON of the rocking unit's a, J, e or "{}")."""


def _level_names(desc) -> tuple[str, str, str]:
    """(variable, symbol, unit) of the levels."""
    return ("pa_over_q", "P_a/Q", "Q") if desc.get("q_newton") else ("pa_newton", "P_a", "N")


def _dof_coords(system):
    from contactvib.steady.system_orbits import DISPLAY_UNITS

    return {"dof_name": ("dof", np.array(system.coordinates, dtype=object),
                         {"long_name": "the system's coordinates"}),
            "dof_unit": ("dof", np.array([DISPLAY_UNITS[u][0] for u in system.units], dtype=object),
                         {"long_name": "display unit of each coordinate (of dof_min, dof_max, dof_app, dof_h1)"})}


def _array(dims, values, attrs, coords):
    import xarray as xr

    return xr.DataArray(values, dims=dims, attrs=attrs, coords={k: xr.Variable(*v) for k, v in coords.items()})


def _dof_contact(system, rows) -> dict:
    """The ``dof``/``contact`` variables, as :mod:`contactvib.sweeps.dataset` writes them."""
    dof = _dof_coords(system)
    contact = {"contact_name": ("contact", np.array([c.name for c in system.contacts], dtype=object),
                                {"long_name": "the system's contact elements"})}
    unit = "the dof's unit (dof_unit)"

    size = {"dof": system.n, "contact": len(system.contacts)}

    def per(dim, coords, name, attrs, dtype=float):
        values = np.array([np.asarray(r["columns"][name]) for r in rows], dtype=dtype).reshape(len(rows), size[dim])
        return _array(("point", dim), values, attrs, coords)

    return {
        "dof_min": per("dof", dof, "dof_min", {"units": unit, "long_name": "minimum of the coordinate"}),
        "dof_max": per("dof", dof, "dof_max", {"units": unit, "long_name": "maximum of the coordinate"}),
        "dof_app": per("dof", dof, "dof_app", {"units": unit, "long_name": "peak-to-peak amplitude of the coordinate"}),
        "dof_h1": per("dof", dof, "dof_h1", {"units": unit,
                                             "long_name": "one-sided amplitude of the coordinate at f_e"}),
        "contact_loses_contact": per("contact", contact, "contact_loses_contact",
                                     {"units": "1", "comment": "1 where the contact opens on the orbit"}, np.int8),
        "contact_loss_frac": per("contact", contact, "contact_loss_frac",
                                 {"units": "1", "long_name": "fraction of the period with the contact open"}),
        "contact_mean_force_n": per("contact", contact, "contact_mean_force_n", {
            "units": "N", "long_name": "time-averaged contact force over the period (Gauss-Legendre on every step)"}),
    }


def _branches(level, rows, names, pa_value):
    """Branch index of every row (Newton links without a jump, same period; ordered by lowest
    frequency, then amplitude) and the ``branch`` variables."""
    n = len(rows)
    parent = np.arange(n)

    def find(a):
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a

    for a, b, jump in level.links:
        if not jump and rows[a]["k"] == rows[b]["k"] and _type(rows[a]) == _type(rows[b]):
            ra, rb = find(a), find(b)
            parent[max(ra, rb)] = min(ra, rb)
    roots = np.array([find(j) for j in range(n)], np.int64)
    fe = np.array([level.f_hz[r["i"]] for r in rows])
    app = np.array([r["columns"]["dof_app"][0] for r in rows])
    verdict = np.array([r.get("verdict", False) for r in rows], bool)
    uniq = list(dict.fromkeys(roots[np.lexsort((-app, fe, verdict))]))
    index = {r: b for b, r in enumerate(uniq)}
    branch = np.array([index[r] for r in roots], np.int64)
    nb = len(uniq)

    def per_branch(fn, values, fill, dtype=float):
        out = np.full(nb, fill, dtype)
        for j in range(n):
            out[branch[j]] = fn(out[branch[j]], values[j])
        return out

    k = np.array([r["k"] for r in rows], np.int64)
    sweep = np.array([r["found_by"] == "sweep" for r in rows], np.int8)
    var, _sym, unit = names
    tag = f"{pa_value:g}{unit}"
    return branch, {
        "branch_id": ("branch", np.array([f"{tag}-b{b:03d}" for b in range(nb)], dtype=object)),
        "branch_label": ("branch", np.array([f"period-{kk}" if kk else str(t) for kk, t in zip(
                            per_branch(lambda a, b: b, k, 0, np.int64),
                            per_branch(lambda a, b: b, np.array([_type(r) for r in rows], dtype=object), "", object))],
                                            dtype=object),
                         {"comment": "the branch's period, or chaotic / quasi-periodic (systems carry no resonance "
                                     "labels)"}),
        f"branch_{var}": ("branch", np.full(nb, pa_value), {"units": unit}),
        "branch_period": ("branch", per_branch(lambda a, b: b, k, 0, np.int64)),
        "branch_minima": ("branch", per_branch(lambda a, b: b, np.array([r["minima"] for r in rows]), 0, np.int64)),
        "branch_fmin_hz": ("branch", per_branch(min, fe, np.inf), {"units": "Hz"}),
        "branch_fmax_hz": ("branch", per_branch(max, fe, -np.inf), {"units": "Hz"}),
        "branch_npoints": ("branch", per_branch(lambda a, b: a + 1, fe, 0, np.int64)),
        "branch_app_max_um": ("branch", per_branch(max, app, 0.0), {"units": "the first coordinate's unit"}),
        "branch_reached_by_sweep": ("branch", per_branch(max, sweep, 0, np.int8),
                                    {"units": "1", "comment": "1 if the laboratory sweeps reach the branch"}),
    }


def _type(row) -> str:
    """A row's attractor type: "periodic", "chaotic" or "quasi-periodic"."""
    return row.get("type", "periodic")


def _spectra(rows, fe, n2) -> dict:
    """The earned labels and Lyapunov spectra of the rows: ``attractor_type``, ``true_period``,
    ``lyapunov_per_s``/``lyapunov_stderr_per_s`` (point, exponent) [1/s] (a periodic row:
    ln ``|μ_i|`` f_e / k of its Floquet multipliers, descending, errors 0; a non-periodic one: its
    verdict's Benettin run) and ``kaplan_yorke_dimension`` (a chaotic row's)."""
    from contactvib.steady.results import kaplan_yorke_dimension

    n = len(rows)
    lam, se = np.full((n, n2), np.nan), np.zeros((n, n2))
    ky = np.full(n, np.nan)
    for j, r in enumerate(rows):
        if r["k"]:
            with np.errstate(divide="ignore"):
                lam[j] = np.sort(np.log(np.abs(np.asarray(r["mu"]))) * fe[j] / r["k"])[::-1]
        else:
            lam[j], se[j] = r["lyap"], r["lyap_se"]
        if _type(r) == "chaotic":
            d = kaplan_yorke_dimension(lam[j])
            ky[j] = np.nan if d is None else d
    return {
        "attractor_type": ("point", np.array([_type(r) for r in rows], dtype=object),
                           {"comment": "periodic / chaotic / quasi-periodic, earned by the attractor search's "
                                       "verdict (Lyapunov spectrum, section)"}),
        "true_period": ("point", np.array([r["k"] for r in rows], np.int64),
                        {"units": "excitation periods", "comment": "minimal period, beyond kmax too; 0 = none"}),
        "lyapunov_per_s": (("point", "exponent"), lam, {"units": "1/s", "long_name": "Lyapunov exponents, "
                                                        "descending (periodic: ln|mu|/T; else Benettin)"}),
        "lyapunov_stderr_per_s": (("point", "exponent"), se,
                                  {"units": "1/s", "long_name": "standard error of the exponents (batch means)"}),
        "kaplan_yorke_dimension": ("point", ky, {"units": "1", "comment": "NaN unless chaotic"}),
    }


def _traces(level, names, pa_value) -> dict:
    t = level.traces
    var, _sym, unit = names
    return {
        "trace_label": ("trace", np.array([x["label"] for x in t], dtype=object)),
        f"trace_{var}": ("trace", np.full(len(t), pa_value), {"units": unit}),
        "trace_direction": ("trace", np.array([x["direction"] for x in t], np.int64)),
        "trace_f_start_hz": ("trace", np.array([x["f_start_hz"] for x in t]), {"units": "Hz"}),
        "trace_f_stop_hz": ("trace", np.array([x["f_stop_hz"] for x in t]), {"units": "Hz"}),
        "trace_stop": ("trace", np.array([x["stop"] for x in t], dtype=object)),
        "trace_root": ("trace", np.array([x["root"] for x in t], dtype=object)),
        "trace_unsettled": ("trace", np.array([x["unsettled"] for x in t], np.int64),
                            {"units": "1", "comment": "grid points the sweep passed without a period <= kmax "
                                                      "settling (a non-periodic motion or a long transient)"}),
    }


def _states(system, rows) -> dict:
    """The orbit point and the stroboscopic points in display units."""
    from contactvib.steady.system_orbits import DISPLAY_UNITS

    n = system.n
    qf = np.array([DISPLAY_UNITS[u][1] for u in system.units])
    vf = np.array([DISPLAY_UNITS[u][3] for u in system.units])
    z = np.array([r["z"] for r in rows], dtype=float).reshape(len(rows), 2 * n)
    strobe = np.concatenate([r["strobe"] for r in rows]) if rows else np.zeros((0, 2 * n))
    count = np.array([len(r["strobe"]) for r in rows], np.int64)
    dof = _dof_coords(system)
    qunit, vunit = "the dof's unit (um or urad)", "mm/s or mrad/s"
    return {
        "state_q": _array(("point", "dof"), z[:, :n] * qf, {"units": qunit, "long_name": "orbit point at phase 0"},
                          dof),
        "state_qdot": _array(("point", "dof"), z[:, n:] * vf, {"units": vunit}, dof),
        "strobe_start": ("point", (np.cumsum(count) - count).astype(np.int64)),
        "strobe_count": ("point", count),
        "strobe_q": _array(("strobe", "dof"), strobe[:, :n] * qf, {"units": qunit}, dof),
        "strobe_qdot": _array(("strobe", "dof"), strobe[:, n:] * vf, {"units": vunit}, dof),
    }


def system_level_dataset(system, level, settings, desc: dict):
    """The Dataset of one level (a :class:`~contactvib.sweeps.system_sweep.SystemLevel`) of
    ``system`` swept with ``settings``; ``desc`` a :class:`SystemDescription`. Layout in the
    module docstring."""
    import xarray as xr

    rows = level.rows  # none where no periodic attractor settled at any grid point
    n = len(rows)
    names = _level_names(desc)
    q = desc.get("q_newton")
    pa_value = level.pa_newton / q if q else level.pa_newton
    pa_value = desc.get("level", pa_value)
    branch, branch_vars = _branches(level, rows, names, pa_value)
    mu = np.array([r["mu"] for r in rows], dtype=complex).reshape(n, 2 * system.n)
    fe = np.array([level.f_hz[r["i"]] for r in rows], float)
    point = {
        "pa_newton": ("point", np.full(n, level.pa_newton), {"units": "N", "long_name": "excitation amplitude P_a"}),
        "fe_hz": ("point", fe, {"units": "Hz", "long_name": "excitation frequency f_e"}),
        "kind": ("point", np.array(["periodic" if r["k"] else "non-periodic" for r in rows], dtype=object)),
        "period": ("point", np.array([r["k"] for r in rows], np.int64),
                   {"units": "excitation periods", "comment": "0 = non-periodic"}),
        "minima_per_period": ("point", np.array([r["minima"] for r in rows], np.int64),
                              {"units": "1", "comment": "local minima of the first contact's deflection; "
                                                        "-1 = non-periodic"}),
        "app_um": ("point", np.array([r["columns"]["dof_app"][0] for r in rows]),
                   {"units": _dof_coords(system)["dof_unit"][1][0],
                    "long_name": f"peak-to-peak amplitude of the first coordinate {system.coordinates[0]}"}),
        "loses_contact": ("point", np.array([np.any(r["columns"]["contact_loses_contact"]) for r in rows], np.int8),
                          {"units": "1", "comment": "1 where some contact opens on the orbit"}),
        "basin_fraction": ("point", np.array([r["basin"] for r in rows], float),
                           {"units": "1", "comment": "share of the search's starts; NaN where not measured"}),
        "floquet_re": (("point", "multiplier"), mu.real, {"units": "1"}),
        "floquet_im": (("point", "multiplier"), mu.imag, {"units": "1"}),
        "floquet_abs_max": ("point", np.abs(mu).max(axis=1), {"units": "1"}),
        "closure": ("point", np.array([r["closure"] for r in rows], float),
                    {"units": "1", "long_name": "relative closure of the refined orbit"}),
        **_spectra(rows, fe, 2 * system.n),
        "branch_index": ("point", branch, {"comment": "index into the branch dimension"}),
        "origin": ("point", np.array([r["origin"] for r in rows], dtype=object)),
        "found_by": ("point", np.array([r["found_by"] for r in rows], dtype=object)),
    }
    if q:
        point["pa_over_q"] = ("point", np.full(n, pa_value), {"units": "Q", "long_name": "excitation amplitude "
                                                                                          "P_a/(M g)"})
    attrs = {"title": "contactvib resonance dataset of a system of several coordinates", "format": FORMAT,
             "system": desc["text"], "system_parameters": desc.get("parameters", "{}"),
             "system_coordinates": json.dumps(list(system.coordinates)),
             "system_units": json.dumps(list(system.units)),
             "contacts": json.dumps([c.name for c in system.contacts]),
             "natural_frequencies_hz": json.dumps([float(f) for f in system.linear_modes()]),
             "level_variable": names[0], "level_symbol": names[1], "level_unit": names[2], "level": pa_value,
             "settings": json.dumps(settings.to_dict()),
             "conventions": "coordinates as the system defines them; ragged strobe points via strobe_start/count"}
    for key in ("model", "fn0_hz", "y0_um"):
        if desc.get(key) is not None:
            attrs[key] = desc[key]
    return xr.Dataset({**point, **_dof_contact(system, rows), **_states(system, rows), **branch_vars,
                       **_traces(level, names, pa_value)}, attrs=attrs)


def merge_system_levels(datasets: list):
    """Concatenate system level datasets (offsetting the ragged and branch indices), levels increasing."""
    import xarray as xr

    datasets = sorted(datasets, key=lambda d: float(d.attrs["level"]))
    parts, s_off, b_off = [], 0, 0
    for d in datasets:
        d = d.copy()
        d["strobe_start"] = d["strobe_start"] + s_off
        d["branch_index"] = d["branch_index"] + b_off
        s_off += d.sizes["strobe"]
        b_off += d.sizes["branch"]
        parts.append(d)
    out = {name: xr.concat([p[name] for p in parts], dim=parts[0][name].dims[0]) for name in parts[0].data_vars}
    ds = xr.Dataset(out, attrs=dict(parts[0].attrs))
    ds.attrs["levels"] = json.dumps([float(p.attrs["level"]) for p in parts])
    del ds.attrs["level"]
    return ds
