"""Reproduction of Kostek (2013), Part 3: resonance graphs, extrema diagrams, Figs. 4–9, index page.

:func:`reproduce_paper` sweeps the eight P_a levels of Figs. 2–3 (:mod:`contactvib.resonance`),
draws one resonance graph and one local-extrema diagram per level, the time histories and phase
portraits of Figs. 4–9 from the attractors stored in the dataset, and writes ``index.md``: for
every statement of Sections 3–4 (numbered in ``paper-statements.md``) the figure that shows it
and what the dataset says, computed from the data (:func:`resonance_facts`), never typed in.

Output folder::

    OUT/paper.nc            every attractor of the sweeps (layout: contactvib.dataset)
    OUT/.chunks/            one finished P_a level per file (resume)
    OUT/fig2<a-h>_pa<P>.png resonance graphs, OUT/fig3<a-h>_pa<P>.png extrema diagrams
    OUT/fig<4-9>_pa<P>_fe<F>.png  time histories and phase portraits
    OUT/index.md            the figures side by side with the paper's statements
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from contactvib.model import ContactModel
from contactvib.sweeps.sweep import SweepSettings

__all__ = ["PAPER_LEVELS", "PAPER_TIME_FIGURES", "ResonanceFacts", "resonance_facts", "level_figures",
           "coexisting_resonances", "PaperResult", "reproduce_paper"]

#: The P_a levels of Figs. 2a–h and 3a–h [Q].
PAPER_LEVELS = (0.50, 0.60, 0.65, 0.70, 0.75, 0.80, 0.85, 0.90)
_LETTERS = "abcdefgh"


@dataclass(frozen=True)
class TimeFigure:
    """One of the paper's time-history figures: number, operating point, statement, content."""

    number: int
    pa_over_q: float
    fe_hz: float
    statement: str
    paper_says: str


PAPER_TIME_FIGURES = (
    TimeFigure(4, 0.65, 360.0, "S4.1", "four coexisting motions: main (1 minimum, largest, most "
               "asymmetric, loses contact), 1/2 (2 minima, loses contact), 1/3 (3 minima, loses "
               "contact), 1/4 (4 minima, small, loops; the perturbation solution agrees)"),
    TimeFigure(5, 0.65, 287.0, "S4.2", "the 1/5 at an early stage: small, asymmetric, "
               "multi-harmonic, two minima and two maxima per cycle; the perturbation solution agrees"),
    TimeFigure(6, 0.70, 470.0, "S4.3", "the 1/2 after the first period doubling: four minima over "
               "two excitation cycles, loss of contact, a subharmonic f_e/2 appears"),
    TimeFigure(7, 0.85, 234.0, "S4.4", "main, 1/5 (five minima, loses contact, perturbation fails) "
               "and 1/6 (early stage, six minima, loops) coexist"),
    TimeFigure(8, 0.90, 170.0, "S4.5", "the 1/6 with loss of contact and six minima per cycle"),
    TimeFigure(9, 0.90, 50.0, "S4.6", "quasistatic vibration below the resonances: non-linear, "
               "asymmetric, multi-harmonic; the perturbation solution agrees excellently"),
)


# ----------------------------------------------------------------------------- facts from data

def _order(label: str):
    """Resonance order m of a label ("main" → 1, "1/m …" → m, "non-periodic (1/m)" → m) or None."""
    label = str(label)
    if label.startswith("non-periodic ("):
        label = label[len("non-periodic ("):-1]
    if label.startswith("main"):
        return 1
    if label.startswith("1/"):
        return int(label[2:].split(" ")[0])
    return None


@dataclass
class ResonanceFacts:
    """What one P_a level of a dataset shows about the 1/m resonance (m = 1: main). Units: Hz, µm."""

    m: int
    fn0_over_m_hz: float
    present: bool
    peak_fe_hz: float = math.nan
    peak_app_um: float = math.nan
    coexisting_fe_hz: list = field(default_factory=list)   # ≥ 2 period-1 1/m orbits: a bent peak
    period_doubled: dict = field(default_factory=dict)      # period k → (f_min, f_max)
    nonperiodic_fe_hz: list = field(default_factory=list)   # non-periodic attractors of this order
    parts_hz: list = field(default_factory=list)            # disjoint f-intervals of its orbits
    isolated_hz: list = field(default_factory=list)         # branches no sweep reaches
    reached_by_sweep: bool = True                           # some orbit of it is reached by a sweep

    @property
    def bent(self) -> bool:
        """The peak leans left: its highest period-1 orbit lies below 0.9 f_n0/m, or two period-1
        orbits of the resonance coexist (a fold)."""
        return (len(self.coexisting_fe_hz) > 0
                or (math.isfinite(self.peak_fe_hz) and self.peak_fe_hz < 0.9 * self.fn0_over_m_hz))

    def stage(self) -> str:
        """The paper's stage (S3.8): absent / grows / bent / period doubling / chaos / divided.

        Divided: more than one part, or (m > 1) no orbit of it is reached by a sweep (the part
        that remains is isolated: S3.7)."""
        if not self.present:
            return "absent"
        if len(self.parts_hz) > 1 or (self.m > 1 and not self.reached_by_sweep):
            return "divided"
        if self.nonperiodic_fe_hz:
            return "chaos"
        if self.period_doubled:
            return "period doubling"
        if self.bent:
            return "bent"
        return "grows"


def _intervals(f: np.ndarray, gap: float) -> list:
    f = np.unique(f)
    if f.size == 0:
        return []
    cut = np.nonzero(np.diff(f) > gap)[0]
    return [(float(s[0]), float(s[-1])) for s in np.split(f, cut + 1)]


def resonance_facts(ds, pa_over_q: float, m: int, f_band=None) -> ResonanceFacts:
    """Facts about the 1/m resonance (main for m = 1) at one P_a level of a resonance dataset.

    Orbits of order m are the points labelled ``main``/``1/m`` and ``non-periodic (1/m)``;
    bouncing sub-/ultrasubharmonic orbits are not counted. The resonance proper is its period-1
    orbits plus its period-doubling cascade: period-2k branches that start within two grid steps
    of a period-k orbit of the cascade with an A_pp within 25 % (a period doubling is continuous),
    and non-periodic attractors next to a doubled orbit (within 50 %). Period-3, -5, … orbits of
    the same order (other attractors, e.g. in periodic windows) are not part of it. Parts are
    separated by gaps of more than 3 grid steps; ``f_band`` (Hz, optional) restricts f_e.
    """
    import json

    df = float(json.loads(ds.attrs["settings"])["df_hz"])
    fn0 = float(ds.attrs["fn0_hz"])
    sel = np.abs(ds["pa_over_q"].values - pa_over_q) <= 1e-6
    if not sel.any():
        raise ValueError(f"P_a = {pa_over_q:g} Q is not in the dataset")
    lab = ds["resonance"].values
    order = np.array([_order(x) if s else None for x, s in zip(lab, sel)], dtype=object)
    mine = sel & (order == m)
    if f_band is not None:
        fe_all = ds["fe_hz"].values
        mine &= (fe_all >= f_band[0]) & (fe_all <= f_band[1])
    facts = ResonanceFacts(m=m, fn0_over_m_hz=fn0 / m, present=bool(mine.any()))
    if not facts.present:
        return facts
    fe = ds["fe_hz"].values[mine]
    app = ds["app_um"].values[mine]
    k = ds["period"].values[mine]
    br = ds["branch_index"].values[mine]
    periodic = ds["kind"].values[mine] == "periodic"
    p1 = periodic & (k == 1)
    if p1.any():
        j = np.argmax(np.where(p1, app, -1.0))
        facts.peak_fe_hz, facts.peak_app_um = float(fe[j]), float(app[j])
        u, c = np.unique(fe[p1], return_counts=True)
        facts.coexisting_fe_hz = [float(x) for x in u[c >= 2]]

    def adjacent(cand, prev, rel):
        """Points of ``cand`` within 2 grid steps and ``rel`` (relative A_pp) of a ``prev`` point."""
        out = np.zeros_like(cand)
        pi = np.nonzero(prev)[0]
        if pi.size == 0:
            return out
        for j in np.nonzero(cand)[0]:
            near = np.abs(fe[pi] - fe[j]) <= 2.0 * df + 1e-9
            out[j] = np.any(near & (np.abs(app[pi] - app[j]) <= rel * np.maximum(app[pi], app[j])))
        return out

    # the period-doubling cascade: period-2k orbits born where a period-k orbit of the family
    # ends (within two grid steps, continuous amplitude), followed along their whole branches
    chain = p1.copy()
    kk = 1
    while kk < 64:
        cand = periodic & (k == 2 * kk)
        hit = adjacent(cand, chain & (k == kk), 0.25)
        if not hit.any():
            break
        new = cand & np.isin(br, np.unique(br[hit]))
        facts.period_doubled[2 * kk] = (float(fe[new].min()), float(fe[new].max()))
        chain |= new
        kk *= 2
    chaos = adjacent(~periodic, chain & (k > 1), 0.5)
    facts.nonperiodic_fe_hz = [float(x) for x in np.unique(fe[chaos])]
    facts.parts_hz = _intervals(fe[chain | chaos], 3.0 * df)
    reach = ds["branch_reached_by_sweep"].values
    iso = np.unique(br[chain & (reach[br] == 0)])
    facts.reached_by_sweep = bool(np.any(reach[br[chain]] == 1))
    facts.isolated_hz = _intervals(np.concatenate(
        [np.arange(ds["branch_fmin_hz"].values[x], ds["branch_fmax_hz"].values[x] + 0.5 * df, df)
         for x in iso]) if iso.size else np.array([]), 1.5 * df)
    return facts


def coexisting_resonances(ds, pa_over_q: float, fe_hz: float) -> list:
    """Resonance orders m of the stable period-1 orbits of order m stored at (P_a, f_e), sorted."""
    from contactvib.sweeps.dataset import attractors_at

    res = attractors_at(ds, pa_over_q, fe_hz)
    ms = {_order(a["resonance"]) for a in res["attractors"] if a["period"] == 1}
    return sorted(m for m in ms if m is not None)


def _max_coexistence(ds, pa_over_q: float):
    """(largest number of resonance orders with period-1 orbits at one frequency, those f [Hz])."""
    sel = np.nonzero((np.abs(ds["pa_over_q"].values - pa_over_q) <= 1e-6)
                     & (ds["period"].values == 1) & (ds["kind"].values == "periodic"))[0]
    by_f: dict = {}
    for j in sel:
        m = _order(ds["resonance"].values[j])
        if m is not None:
            by_f.setdefault(float(ds["fe_hz"].values[j]), set()).add(m)
    if not by_f:
        return 0, []
    n = max(len(v) for v in by_f.values())
    return n, sorted(f for f, v in by_f.items() if len(v) == n)


# ----------------------------------------------------------------------------- figures

#: Frequency step [Hz] of the perturbation series overlaid on the resonance graphs.
PERTURBATION_STEP_HZ = 20.0


def level_figures(ds, pa: float, graph_path, extrema_path, model: ContactModel | None = None,
                  ref: str = ""):
    """Draw the resonance graph (Fig. 2) and local-extrema diagram (Fig. 3) of one level.

    With ``model`` the perturbation series (order 24) is overlaid on the resonance graph every
    ``PERTURBATION_STEP_HZ`` where it is valid (its small-amplitude parts). ``ref`` names the
    paper's panel in the titles (e.g. "2c").
    """
    from functools import partial

    import matplotlib.pyplot as plt

    from contactvib.frequency.perturbation import perturbation_curve
    from contactvib.plotting.figures import extrema_diagram, resonance_graph

    graph = resonance_graph
    if model is not None:
        f = np.arange(float(ds["fe_hz"].min()), float(ds["fe_hz"].max()) + 1e-9, PERTURBATION_STEP_HZ)
        graph = partial(resonance_graph, perturbation=perturbation_curve(model, pa, f))
    for path, draw, what, fig_no in ((graph_path, graph, "Resonance graph", "2"),
                                     (extrema_path, extrema_diagram, "Local extrema of y(t)", "3")):
        fig, ax = plt.subplots(figsize=(7.0, 4.2))
        draw(ds, pa, ax=ax)
        ax.set_xlim(0, float(ds["fe_hz"].max()) * 1.02)
        cf = f" (cf. Fig. {fig_no}{ref})" if ref else ""
        ax.set_title(f"{what}, $P_a$ = {pa:g} Q{cf}", fontsize=10)
        fig.tight_layout()
        fig.savefig(path, dpi=120)
        plt.close(fig)
    return Path(graph_path), Path(extrema_path)


class _LevelProducts:
    """Figures of one finished level, drawn in the sweep worker (picklable ``on_level`` hook)."""

    def __init__(self, out: Path, letters: dict, time_figures, settings: SweepSettings):
        self.out, self.letters, self.time_figures, self.settings = out, letters, time_figures, settings

    def __call__(self, model: ContactModel, ds):
        import matplotlib

        matplotlib.use("Agg")
        pa = float(ds["pa_over_q"].values[0])
        letter = self.letters.get(round(pa, 6), "")
        tag = f"pa{pa:.2f}"
        panels = level_figures(ds, pa, self.out / f"fig2{letter}_{tag}.png",
                               self.out / f"fig3{letter}_{tag}.png", model, ref=letter)
        st = self.settings
        rows = []
        for tf in self.time_figures:
            if abs(tf.pa_over_q - pa) > 1e-6:
                continue
            if not (st.fmin_hz - 0.5 * st.df_hz <= tf.fe_hz <= st.fmax_hz + 0.5 * st.df_hz):
                continue
            path, att_rows = _time_figure(ds, model, tf, self.out)
            rows.append((tf, path, att_rows))
        return panels, rows


def _time_figure(ds, model: ContactModel, tf: TimeFigure, out: Path):
    """Fig. 4–9 style figure: one row (y(t), phase portrait) per attractor stored at the point."""
    import matplotlib.pyplot as plt

    from contactvib.sweeps.dataset import attractors_at
    from contactvib.frequency.perturbation import perturbation_series
    from contactvib.plotting.figures import plot_phase_portrait, plot_time_history
    from contactvib.steady.simulate import simulate

    res = attractors_at(ds, tf.pa_over_q, tf.fe_hz)
    atts = res["attractors"]
    exc = model.excitation(tf.pa_over_q, res["fe_hz"])
    # the paper's resonances first (by amplitude), then the orbits the paper does not draw
    atts = sorted(atts, key=lambda a: (_order(a["resonance"]) is None and a["resonance"] != "non-resonant",
                                       -a["app_um"]))
    n = max(len(atts), 1)
    fig, axes = plt.subplots(n, 2, figsize=(11, 2.5 * n + 0.6), squeeze=False,
                             gridspec_kw={"width_ratios": [1.7, 1]})
    rows = []
    ps = perturbation_series(model, exc, order=PERTURBATION_ORDER)
    for r, a in enumerate(atts):
        per = a["period"] or 10
        y, yd = _state_of(a)
        n_per = max(2, 2 * per) if a["period"] else 10
        h = simulate(model, exc, y_um=y, ydot_mm_s=yd, n_periods=n_per, samples_per_period=600)
        plot_time_history(h, axes[r, 0])
        plot_phase_portrait(h, axes[r, 1])
        note = _perturbation_note(ps, a)
        if note.startswith("perturbation agrees"):
            hp = ps.history(n_periods=n_per, samples_per_period=600)
            axes[r, 0].plot(hp.t_ms, hp.y_um, color="tab:red", ls="--", lw=1.0,
                            label=f"perturbation, N = {ps.order}")
            axes[r, 1].plot(hp.y_um, hp.ydot_mm_s, color="tab:red", ls="--", lw=1.0)
            axes[r, 0].legend(loc="best", fontsize=7, frameon=False)
        k = "non-periodic" if a["period"] is None else f"period {a['period']}"
        n = a["minima_per_period"]
        mins = "" if n is None else f", {n} {'minimum' if n == 1 else 'minima'}"
        paper = "" if (_order(a["resonance"]) is not None or a["resonance"] == "non-resonant") \
            else " (not drawn in the paper)"
        axes[r, 0].set_title(f"{a['resonance']}{paper}: {k}{mins}, $A_{{pp}}$ = {a['app_um']:.4g} µm; {note}",
                             fontsize=8.5, loc="left")
        rows.append((a, note))
    fig.suptitle(f"cf. Fig. {tf.number}: $P_a$ = {tf.pa_over_q:g} Q, $f_e$ = {res['fe_hz']:g} Hz "
                 f"(all attractors stored in the dataset)", fontsize=10)
    fig.tight_layout()
    path = out / f"fig{tf.number}_pa{tf.pa_over_q:.2f}_fe{res['fe_hz']:g}.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path, rows


#: Order of the perturbation series overlaid on Figs. 4–9 (Padé-summed; converged to < 1e-5 at
#: the paper's in-contact orbits, see the README's convergence tables).
PERTURBATION_ORDER = 80


def _perturbation_note(ps, att: dict) -> str:
    """How the perturbation series relates to one attractor (Sec. 4: agrees / not applicable)."""
    if att["loses_contact"]:
        return "perturbation not applicable (contact is lost)"
    if not ps.valid:
        return f"perturbation series invalid at N = {ps.order}"
    rel = abs(ps.app_um - att["app_um"]) / att["app_um"]
    if rel <= 1e-2:
        return f"perturbation agrees (N = {ps.order}, A_pp differs by {rel:.1e})"
    return f"perturbation series describes another orbit (A_pp = {ps.app_um:.4g} µm)"


def _state_of(att: dict):
    """Orbit point (y [µm], ẏ [mm/s]) at phase 0 stored for this attractor."""
    sp = att["strobe_points"]
    if att["period"] is not None and sp:
        return sp[0]["y_um"], sp[0]["ydot_mm_s"]
    return sp[-1]["y_um"], sp[-1]["ydot_mm_s"]


# ----------------------------------------------------------------------------- index page

_S3_LEVELS = {"S3.1": (0.50, 0.60), "S3.2": (0.65,), "S3.3": (0.70,), "S3.4": (0.75,),
              "S3.5": (0.80,), "S3.6": (0.85,), "S3.7": (0.90,)}


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


def _level_text(ds, pa: float, m_max: int = 6) -> list:
    import json

    gap = 1.5 * float(json.loads(ds.attrs["settings"])["df_hz"])
    lines = []
    n, fs = _max_coexistence(ds, pa)
    if n:
        lines.append(f"at most {n} resonances coexist at one frequency ({_fmt_iv(_intervals(np.array(fs), gap))})")
    for m in range(1, m_max + 1):
        f = resonance_facts(ds, pa, m)
        name = "main" if m == 1 else f"1/{m}"
        if not f.present:
            lines.append(f"{name}: not found")
            continue
        bits = [f"peak {f.peak_app_um:.3g} µm at {f.peak_fe_hz:g} Hz (f_n0/{m} = {f.fn0_over_m_hz:.0f} Hz)"
                if math.isfinite(f.peak_fe_hz) else "no period-1 orbit"]
        if f.coexisting_fe_hz:
            bits.append(f"bent (two period-1 orbits at {_fmt_iv(_intervals(np.array(f.coexisting_fe_hz), gap))})")
        elif f.bent:
            bits.append("bent (peak below 0.9 f_n0/m)")
        if f.period_doubled:
            bits.append("period " + ", ".join(f"{k} at {a:g}–{b:g} Hz" for k, (a, b) in sorted(f.period_doubled.items())))
        if f.nonperiodic_fe_hz:
            bits.append(f"non-periodic at {_fmt_iv(_intervals(np.array(f.nonperiodic_fe_hz), gap))}")
        if len(f.parts_hz) > 1:
            bits.append(f"{len(f.parts_hz)} parts: {_fmt_iv(f.parts_hz)}")
        if f.isolated_hz:
            bits.append(f"not reached by sweeps: {_fmt_iv(f.isolated_hz)}")
        lines.append(f"{name} [{f.stage()}]: " + "; ".join(bits))
    return lines


def _write_index(ds, out: Path, levels, level_paths, time_rows, timing: dict, spec_path) -> Path:
    st = _statements(spec_path)
    L = ["# contactvib reproduction of Kostek (2013), Part 3", ""]
    L.append(f"Model: f_n0 = {float(ds.attrs['fn0_hz']):.1f} Hz, y0 = {float(ds.attrs['y0_um']):.4f} µm "
             f"(S2.1, S2.2). Dataset `paper.nc`: {ds.sizes['point']} attractor points, "
             f"{ds.sizes['branch']} branches on {len(levels)} levels. Sweep settings: "
             f"`{ds.attrs['settings']}`.")
    L.append(f"Wall time: {timing['sweeps_and_figures_s']:.1f} s for the sweeps and figures "
             "(figures drawn in the sweep workers as each level finishes).")
    L.append("")
    L.append("Every 'dataset' line below is computed from `paper.nc` by `contactvib.paper.resonance_facts`; "
             "stages follow S3.8 (grows → bent → period doubling → chaos → divided). Bouncing "
             "sub-/ultrasubharmonic orbits (dotted in the graphs) are not drawn in the paper.")
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
    for m in range(2, 7):
        L.append(f"| 1/{m} | " + " | ".join(resonance_facts(ds, p, m).stage() for p in levels) + " |")
    L.append("")
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
    L.append("Dataset: in the tables above the minima per period equal m for the 1/m orbits except the "
             "early 1/5 at 287 Hz (two minima, S4.2), which is why contactvib names resonances by the "
             "dominant amplified harmonic (README, 'Resonance labels').")
    path = out / "index.md"
    tmp = out / ".index.md.tmp"
    tmp.write_text("\n".join(L) + "\n")
    tmp.replace(path)
    return path


# ----------------------------------------------------------------------------- driver

@dataclass
class PaperResult:
    """Outputs of :func:`reproduce_paper`: the dataset, figure paths, index page, timings [s]."""

    dataset: object
    out: Path
    level_figures: dict
    time_figures: list
    index: Path
    timing: dict


def reproduce_paper(out="paper", model: ContactModel | None = None,
                    settings: SweepSettings | None = None, levels=PAPER_LEVELS,
                    resume: bool = False, workers: int | None = None, progress: bool = True,
                    time_figures=PAPER_TIME_FIGURES, spec_path=None) -> PaperResult:
    """Reproduce Figs. 2–9 of the paper into ``out`` (see the module docstring for the files).

    ``settings`` default to the paper's grid (30–2000 Hz, 1 Hz); figures whose operating point
    lies outside the grid or levels are skipped.
    """
    import matplotlib

    matplotlib.use("Agg")
    from contactvib.sweeps.resonance import resonance_dataset

    model = model or ContactModel()
    settings = settings or SweepSettings()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    levels = sorted({round(float(p), 6) for p in levels})
    letters = {p: (_LETTERS[i] if len(levels) == len(_LETTERS) else "") for i, p in enumerate(levels)}
    products: dict = {}
    ds = resonance_dataset(model, levels, settings, out=out, name="paper", resume=resume,
                           workers=workers, progress=progress,
                           on_level=_LevelProducts(out, letters, tuple(time_figures), settings),
                           level_results=products)
    t1 = time.perf_counter()
    level_paths = {p: products[p][0] for p in levels}
    time_rows = sorted((r for p in levels for r in products[p][1]), key=lambda r: r[0].number)
    timing = {"sweeps_and_figures_s": t1 - t0}
    if spec_path is None:
        spec_path = Path(__file__).resolve().parents[1] / "data" / "paper_statements.md"
    index = _write_index(ds, out, levels, level_paths, time_rows, timing, spec_path)
    return PaperResult(ds, out, level_paths, [p for _, p, _ in time_rows], index, timing)
