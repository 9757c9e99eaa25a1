"""The index page of the paper's reproduction: every statement of Sections 3–4 (numbered in
``paper-statements.md``) next to the figure that shows it and what the dataset says, computed from
the data by :mod:`contactvib.sweeps.facts`, never typed in."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from contactvib.labels import resonance_order
from contactvib.sweeps.facts import SUPERHARMONIC_ORDERS, intervals, level_stages, max_coexistence, resonance_facts

__all__ = ["write_index", "S3_LEVELS", "paper_statements", "peak_place", "minima_sentence"]

#: The P_a levels [Q] of each statement S3.1–S3.7 (S3.8 is the sequence over all of them).
S3_LEVELS = _S3_LEVELS = {"S3.1": (0.50, 0.60), "S3.2": (0.65,), "S3.3": (0.70,), "S3.4": (0.75,),
              "S3.5": (0.80,), "S3.6": (0.85,), "S3.7": (0.90,)}


def paper_statements(spec_path: Path | None = None) -> dict:
    """The paper's statements by id (``"S3.2"`` → text) from ``spec_path`` (default: the package's
    ``data/paper_statements.md``)."""
    if spec_path is None:
        spec_path = Path(__file__).resolve().parents[1] / "data" / "paper_statements.md"
    return _statements(Path(spec_path))


def _statements(spec_path: Path | None) -> dict:
    """Statement texts by id from paper-statements.md if available (else the ids only)."""
    out: dict = {}
    if spec_path is None or not spec_path.exists():
        return out
    cur = None
    for line in spec_path.read_text().splitlines():
        s = line.strip()
        if s.startswith("- S") and " " in s:
            cur, _, text = s[2:].partition(" ")
            out[cur] = text
        elif cur and s and not s.startswith("#") and not s.startswith("- "):
            out[cur] += " " + s
        else:
            cur = None if not s.startswith("- S") else cur
    return out


def _fmt_iv(iv) -> str:
    return ", ".join(f"{a:g}–{b:g}" if a != b else f"{a:g}" for a, b in iv) + " Hz" if iv else "—"


def peak_place(fe_hz: float, grid: tuple) -> tuple[str, str]:
    """Where a resonance peak lies on the sweep's grid ``(f_min, f_max, Δf)`` [Hz], as ("at F
    Hz", note): at an end of the grid "at or below F Hz" with the note "the sweep's lower edge"
    (or "at or above", "the sweep's upper edge"), since the largest amplitude there may belong to
    a peak beyond the range; the note is "" inside the grid."""
    fmin, fmax, df = grid
    if fe_hz <= fmin + 0.5 * df:
        return f"at or below {fe_hz:g} Hz", "the sweep's lower edge"
    if fe_hz >= fmax - 0.5 * df:
        return f"at or above {fe_hz:g} Hz", "the sweep's upper edge"
    return f"at {fe_hz:g} Hz", ""


def minima_sentence(time_rows) -> str:
    """S4.7 from the tables of Figs. 4–9 (``time_rows``: (TimeFigure, path, [(attractor record,
    note)])): whether the 1/m orbits (main: m = 1) have m minima per excitation period, i.e.
    ``minima_per_period`` = m × period, and which do not."""
    n, odd = 0, []
    for tf, _path, rows in time_rows:
        for a, _note in rows:
            m = resonance_order(a["resonance"])
            if m is None or a["period"] is None or a["minima_per_period"] is None:
                continue
            n += 1
            k, mins = int(a["period"]), int(a["minima_per_period"])
            if mins != m * k:
                per = f"{mins} minima" if k == 1 else f"{mins} minima over {k} periods"
                odd.append(f"the {a['resonance']} at {tf.pa_over_q:g} Q, {tf.fe_hz:g} Hz "
                           f"({per}, {tf.statement})")
    if n == 0:
        return "Dataset: the tables above hold no 1/m orbit."
    if not odd:
        which = "the one periodic 1/m orbit (main: m = 1) has" if n == 1 else \
            f"all {n} periodic 1/m orbits (main: m = 1) have"
        return f"Dataset: in the tables above {which} m minima per excitation period."
    return (f"Dataset: in the tables above {n - len(odd)} of the {n} periodic 1/m orbits (main: m = 1) have "
            f"m minima per excitation period; the exception{'s are' if len(odd) > 1 else ' is'} "
            + "; ".join(odd) + ". contactvib therefore names a resonance by the harmonic the contact "
            "amplifies, not by its minima (documentation: tutorials/resonance, 'Resonance labels').")


def _level_text(ds, pa: float, m_max: int = 6) -> list:
    settings = json.loads(ds.attrs["settings"])
    grid = (float(settings["fmin_hz"]), float(settings["fmax_hz"]), float(settings["df_hz"]))
    gap = 1.5 * grid[2]
    lines = []
    n, fs = max_coexistence(ds, pa)
    if n > 1:
        lines.append(f"at most {n} resonances coexist at one frequency ({_fmt_iv(intervals(np.array(fs), gap))})")
    elif n == 1:
        lines.append("no two resonances coexist at one frequency")
    for m in range(1, m_max + 1):
        f = resonance_facts(ds, pa, m)
        name = "main" if m == 1 else f"1/{m}"
        if not f.present:
            lines.append(f"{name}: not found")
            continue
        if math.isfinite(f.peak_fe_hz):
            where, edge = peak_place(f.peak_fe_hz, grid)
            bits = [f"peak {f.peak_app_um:.3g} µm {where} ({edge + '; ' if edge else ''}"
                    f"f_n0/{m} = {f.fn0_over_m_hz:.0f} Hz)"]
        else:
            bits = ["no period-1 orbit"]
        if f.coexisting_fe_hz:
            bits.append(f"bent (two period-1 orbits at {_fmt_iv(intervals(np.array(f.coexisting_fe_hz), gap))})")
        elif f.bent:
            bits.append("bent (peak below 0.9 f_n0/m)")
        if f.period_doubled:
            cascade = sorted(f.period_doubled.items())
            bits.append("period " + ", ".join(f"{k} at {a:g}–{b:g} Hz" for k, (a, b) in cascade))
        if f.nonperiodic_fe_hz:
            bits.append(f"non-periodic at {_fmt_iv(intervals(np.array(f.nonperiodic_fe_hz), gap))}")
        if len(f.parts_hz) > 1:
            bits.append(f"{len(f.parts_hz)} parts: {_fmt_iv(f.parts_hz)}")
        if f.isolated_hz:
            bits.append(f"not reached by sweeps: {_fmt_iv(f.isolated_hz)}")
        lines.append(f"{name} [{f.stage()}]: " + "; ".join(bits))
    return lines


def nonperiodic_text(ds, levels) -> list:
    """What the points the sweep reached without a period ≤ kmax are, by the attractor search's
    rule (``attractor_type``, ``true_period``, ``lyapunov_per_s`` of the dataset): per level the
    chaotic bands and the long-period orbits, computed; empty for a dataset without them."""
    if "true_period" not in ds or "lyapunov_per_s" not in ds:
        return []
    k, typ = ds["period"].values, ds["attractor_type"].values.astype(str)
    tp, pa, fe = ds["true_period"].values, ds["pa_over_q"].values, ds["fe_hz"].values
    lam = ds["lyapunov_per_s"].values[:, 0]
    out = ["Dataset, the points the sweep reached without a period ≤ kmax, judged by the attractor search's "
           "rule (the Lyapunov spectrum over 2000 periods: chaotic when λ1 > 3 standard errors; a stable orbit "
           "of a longer period is periodic; a transient still converging is not stored):", ""]
    for p in levels:
        sel = (np.abs(pa - p) < 1e-9) & (k == 0)
        if not sel.any():
            continue
        chaos = sel & (typ == "chaotic")
        long = sel & (typ == "periodic")
        parts = []
        if chaos.any():
            parts.append(f"chaotic at {int(chaos.sum())} points ({_fmt_iv(_runs(np.unique(fe[chaos])))}, "
                         f"λ1 {lam[chaos].min():.3g}..{lam[chaos].max():.3g} /s)")
        if long.any():
            ks = ", ".join(f"{int(x)} ({int(((tp == x) & long).sum())})" for x in np.unique(tp[long]))
            parts.append(f"long-period orbits at {int(long.sum())} points (period (points): {ks})")
        quasi = sel & (typ == "quasi-periodic")
        if quasi.any():
            parts.append(f"quasi-periodic at {int(quasi.sum())} points")
        out.append(f"- {p:g} Q: " + "; ".join(parts) + ".")
    out.append("")
    return out


def _runs(f: np.ndarray, gap: float = 1.5) -> list:
    """Runs of frequencies [Hz] closer than ``gap`` as (start, end) intervals."""
    if f.size == 0:
        return []
    cut = np.flatnonzero(np.diff(f) > gap)
    return [(float(a), float(b)) for a, b in zip(np.r_[f[0], f[cut + 1]], np.r_[f[cut], f[-1]])]


def write_index(ds, out: Path, levels, level_paths, time_rows, timing: dict, spec_path) -> Path:
    st = _statements(spec_path)
    L = ["# contactvib reproduction of Kostek (2013), Part 3", ""]
    law = ds.attrs.get("law", "")
    L.append(f"Model: f_n0 = {float(ds.attrs['fn0_hz']):.1f} Hz, y0 = {float(ds.attrs['y0_um']):.4f} µm "
             f"(S2.1, S2.2){'; ' + law if law else ''}; parameters `{ds.attrs.get('model', '')}`. "
             f"Dataset `paper.nc`: {ds.sizes['point']} attractor points, "
             f"{ds.sizes['branch']} branches on {len(levels)} levels. Sweep settings: "
             f"`{ds.attrs['settings']}`.")
    L.append(f"Wall time: {timing['sweeps_and_figures_s']:.1f} s for the sweeps and figures "
             "(figures drawn in the sweep workers as each level finishes).")
    L.append("")
    L.append("Every 'dataset' line below is computed from `paper.nc` by `contactvib.sweeps.facts.resonance_facts`; "
             "stages follow S3.8 (grows → bent → period doubling → chaos → divided). Bouncing "
             "sub-/ultrasubharmonic orbits (dotted in the resonance graphs, light blue in the extrema "
             "diagrams) are not drawn in the paper.")
    L.append("")
    L.append("## Section 3: resonance graphs (Fig. 2) and local-extrema diagrams (Fig. 3)")
    L.append("")
    for sid, pas in _S3_LEVELS.items():
        L.append(f"### {sid}")
        if sid in st:
            L.append(f"> {st[sid]}")
        L.append("")
        for pa in pas:
            if pa not in level_paths:
                continue
            p2, p3 = level_paths[pa]
            L.append(f"**P_a = {pa:g} Q** — dataset:")
            L.extend(f"- {x}" for x in _level_text(ds, pa))
            L.append("")
            L.append("| resonance graph (Fig. 2) | local extrema (Fig. 3) |")
            L.append("|---|---|")
            L.append(f"| ![]({p2.name}) | ![]({p3.name}) |")
            L.append("")
    L.append("### S3.8")
    if "S3.8" in st:
        L.append(f"> {st['S3.8']}")
    L.append("")
    L.append("| resonance | " + " | ".join(f"{p:g} Q" for p in levels) + " |")
    L.append("|---|" + "---|" * len(levels))
    stages = {p: level_stages(ds, p) for p in levels}
    for m in SUPERHARMONIC_ORDERS:
        L.append(f"| 1/{m} | " + " | ".join(stages[p][m] for p in levels) + " |")
    L.append("")
    L.extend(nonperiodic_text(ds, levels))
    L.append("### S3.9")
    if "S3.9" in st:
        L.append(f"> {st['S3.9']}")
    f1 = [resonance_facts(ds, p, 1) for p in levels]
    L.append("")
    L.append("Dataset: the main resonance is traced over " + "; ".join(
        f"{p:g} Q: {_fmt_iv(f.parts_hz)}" for p, f in zip(levels, f1)) + ".")
    L.append("")
    L.append("## Section 4: time histories and phase portraits (Figs. 4–9)")
    L.append("")
    for tf, path, rows in time_rows:
        L.append(f"### {tf.statement} — Fig. {tf.number}: P_a = {tf.pa_over_q:g} Q, f_e = {tf.fe_hz:g} Hz")
        L.append(f"> {st.get(tf.statement, tf.paper_says)}")
        L.append("")
        L.append("| resonance | period | minima | A_pp [µm] | y_min [µm] | loses contact | found by | note |")
        L.append("|---|---|---|---|---|---|---|---|")
        for a, note in rows:
            L.append(f"| {a['resonance']} | {a['period'] or '—'} | {a['minima_per_period'] or '—'} | "
                     f"{a['app_um']:.4g} | {a['ymin_um']:.4g} | {'yes' if a['loses_contact'] else 'no'} | "
                     f"{a['found_by']} | {note.lstrip('; ')} |")
        L.append("")
        L.append(f"![]({path.name})")
        L.append("")
    L.append("### S4.7")
    if "S4.7" in st:
        L.append(f"> {st['S4.7']}")
    L.append("")
    L.append(minima_sentence(time_rows))
    path = out / "index.md"
    tmp = out / ".index.md.tmp"
    tmp.write_text("\n".join(L) + "\n")
    tmp.replace(path)
    return path


# ----------------------------------------------------------------------------- driver
