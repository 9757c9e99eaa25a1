"""Reproduction of Kostek (2013), Part 3: resonance graphs, extrema diagrams, Figs. 4–9, index page.

:func:`reproduce_paper` sweeps the eight P_a levels of Figs. 2–3 (:mod:`contactvib.sweeps.resonance`),
draws one resonance graph and one local-extrema diagram per level, the time histories and phase
portraits of Figs. 4–9 from the attractors stored in the dataset, and writes ``index.md``
(:mod:`contactvib.sweeps.paper_index`): for every statement of Sections 3–4 the figure that shows
it and what the dataset says, computed from the data (:mod:`contactvib.sweeps.facts`).

Output folder::

    OUT/paper.nc            every attractor of the sweeps (layout: contactvib.sweeps.dataset)
    OUT/.chunks/            one finished P_a level per file (resume)
    OUT/fig2<a-h>_pa<P>.png resonance graphs, OUT/fig3<a-h>_pa<P>.png extrema diagrams
    OUT/fig<4-9>_pa<P>_fe<F>.png  time histories and phase portraits
    OUT/index.md            the figures side by side with the paper's statements
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contactvib.call_forms import old_form
from contactvib.labels import resonance_order
from contactvib.model import ContactModel
from contactvib.sweeps.paper_index import write_index
from contactvib.sweeps.stage_times import stage
from contactvib.sweeps.stored import ResonanceData, matching_level
from contactvib.sweeps.sweep import SweepSettings

__all__ = ["PAPER_LEVELS", "PAPER_TIME_FIGURES", "TimeFigure", "write_level_figures",
           "PaperResult", "reproduce_paper"]

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



#: Frequency step [Hz] of the perturbation series overlaid on the resonance graphs.
PERTURBATION_STEP_HZ = 20.0
#: Number of terms N of the perturbation series overlaid on Figs. 4–9 (Padé-summed; converged to < 1e-5 at
#: the paper's in-contact orbits, see the perturbation tutorial, docs/tutorials/perturbation.md).
PERTURBATION_TERMS = 80


def write_level_figures(ds, pa: float, graph_path, extrema_path, model: ContactModel | None = None,
                        ref: str = ""):
    """Write the resonance graph (Fig. 2) and local-extrema diagram (Fig. 3) of one level.

    With ``model`` the perturbation series (24 terms) is overlaid on the resonance graph every
    ``PERTURBATION_STEP_HZ`` where it is valid (its small-amplitude parts). ``ref`` names the
    paper's panel in the titles (e.g. "c"). Returns the two paths.
    """
    from contactvib.frequency.perturbation import perturbation_curve
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.paper import level_figures

    curve = None
    if (model is not None and model.is_paper_family  # the series exists for the paper's law only
            and ds.attrs.get("excitation", "force") == "force"):  # and a force level
        f = np.arange(float(ds["fe_hz"].min()), float(ds["fe_hz"].max()) + 1e-9, PERTURBATION_STEP_HZ)
        with stage("perturbation overlay"):
            curve = perturbation_curve(model, pa_over_q=pa, fe_hz=f)
    with stage("level figures"):
        graph, extrema = level_figures(ds, pa, perturbation=curve, ref=ref)
        save_figure(graph, graph_path, dpi=120)
        save_figure(extrema, extrema_path, dpi=120)
    return Path(graph_path), Path(extrema_path)


class _LevelProducts:
    """Figures of one finished level, drawn in the sweep worker (picklable ``on_level`` hook)."""

    def __init__(self, out: Path, letters: dict, time_figures, settings: SweepSettings):
        self.out, self.letters, self.time_figures, self.settings = out, letters, time_figures, settings

    def __call__(self, model: ContactModel, ds):
        pa = float(ds["pa_over_q"].values[0])
        letter = self.letters.get(round(pa, 6), "")
        tag = f"pa{pa:.2f}"
        panels = write_level_figures(ds, pa, self.out / f"fig2{letter}_{tag}.png",
                                     self.out / f"fig3{letter}_{tag}.png", model, ref=letter)
        st = self.settings
        rows = []
        for tf in self.time_figures:
            if matching_level([pa], tf.pa_over_q) is None:  # another level's figure
                continue
            if not (st.fmin_hz - 0.5 * st.df_hz <= tf.fe_hz <= st.fmax_hz + 0.5 * st.df_hz):
                continue
            with stage("time figures"):
                path, att_rows = _time_figure(ds, model, tf, self.out)
            rows.append((tf, path, att_rows))
        return panels, rows


def _in_paper(att: dict) -> bool:
    """True for the orbits the paper draws: a 1/m resonance, or the non-resonant motion."""
    return resonance_order(att["resonance"]) is not None or att["resonance"] == "non-resonant"


def _time_figure(ds, model: ContactModel, tf: TimeFigure, out: Path):
    """Fig. 4–9 style figure: one row (y(t), phase portrait) per attractor stored at the point."""
    from contactvib.frequency.perturbation import perturbation_series
    from contactvib.plotting.figures import save_figure
    from contactvib.plotting.paper import TimeRow, time_figure
    from contactvib.steady.simulate import simulate
    res = ResonanceData(ds).attractors_at(tf.pa_over_q, tf.fe_hz)
    exc = model.excitation(tf.pa_over_q, res["fe_hz"])
    # the paper's resonances first (by amplitude), then the orbits the paper does not draw
    atts = sorted(res["attractors"], key=lambda a: (not _in_paper(a), -a["app_um"]))
    ps = perturbation_series(exc, terms=PERTURBATION_TERMS)
    rows, figure_rows = [], []
    for a in atts:
        y, yd = _state_of(a)
        n_per = max(2, 2 * a["period"]) if a["period"] else 10
        h = simulate(exc, y_um=y, ydot_mm_s=yd, n_periods=n_per, samples_per_period=600)
        note = _perturbation_note(ps, a)
        series = (ps.history(n_periods=n_per, samples_per_period=600)
                  if note.startswith("perturbation agrees") else None)
        k = "non-periodic" if a["period"] is None else f"period {a['period']}"
        n = a["minima_per_period"]
        mins = "" if n is None else f", {n} {'minimum' if n == 1 else 'minima'}"
        paper = "" if _in_paper(a) else " (not drawn in the paper)"
        title = f"{a['resonance']}{paper}: {k}{mins}, $A_{{pp}}$ = {a['app_um']:.4g} µm; {note}"
        figure_rows.append(TimeRow(h, title, series, f"perturbation, N = {ps.terms}"))
        rows.append((a, note))
    fig = time_figure(figure_rows, f"cf. Fig. {tf.number}: $P_a$ = {tf.pa_over_q:g} Q, $f_e$ = "
                                   f"{res['fe_hz']:g} Hz (all attractors stored in the dataset)")
    path = out / f"fig{tf.number}_pa{tf.pa_over_q:.2f}_fe{res['fe_hz']:g}.png"
    save_figure(fig, path, dpi=110)
    return path, rows


def _perturbation_note(ps, att: dict) -> str:
    """How the perturbation series relates to one attractor (Sec. 4: agrees / not applicable)."""
    if att["loses_contact"]:
        return "perturbation not applicable (contact is lost)"
    if not ps.valid:
        return f"perturbation series invalid at N = {ps.terms}"
    rel = abs(ps.app_um - att["app_um"]) / att["app_um"]
    if rel <= 1e-2:
        return f"perturbation agrees (N = {ps.terms}, A_pp differs by {rel:.1e})"
    return f"perturbation series describes another orbit (A_pp = {ps.app_um:.4g} µm)"


def _state_of(att: dict):
    """Orbit point (y [µm], ẏ [mm/s]) at phase 0 stored for this attractor."""
    sp = att["strobe_points"]
    if att["period"] is not None and sp:
        return sp[0]["y_um"], sp[0]["ydot_mm_s"]
    return sp[-1]["y_um"], sp[-1]["ydot_mm_s"]


# ----------------------------------------------------------------------------- index page


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


@old_form("out", "model", "settings", "levels", "resume", "workers", "progress", "time_figures", "spec_path")
def reproduce_paper(model: ContactModel | None = None, *, out="paper",
                    settings: SweepSettings | None = None, levels=PAPER_LEVELS,
                    resume: bool = False, workers: int | None = None, progress: bool = True,
                    time_figures=PAPER_TIME_FIGURES, spec_path=None) -> PaperResult:
    """Reproduce Figs. 2–9 of the paper into ``out`` (see the module docstring for the files).

    ``settings`` default to the paper's grid (30–2000 Hz, 1 Hz); figures whose operating point
    lies outside the grid or levels are skipped.
    """
    from contactvib.sweeps.resonance import resonance_dataset

    model = model or ContactModel()
    settings = settings or SweepSettings()
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    levels = sorted({round(float(p), 6) for p in levels})
    letters = {p: (_LETTERS[i] if len(levels) == len(_LETTERS) else "") for i, p in enumerate(levels)}
    products: dict = {}
    ds = resonance_dataset(model, levels=levels, settings=settings, out=out, name="paper", resume=resume,
                           workers=workers, progress=progress,
                           on_level=_LevelProducts(out, letters, tuple(time_figures), settings),
                           level_results=products)
    t1 = time.perf_counter()
    level_paths = {p: products[p][0] for p in levels}
    time_rows = sorted((r for p in levels for r in products[p][1]), key=lambda r: r[0].number)
    timing = {"sweeps_and_figures_s": t1 - t0}
    if spec_path is None:
        spec_path = Path(__file__).resolve().parents[1] / "data" / "paper_statements.md"
    with stage("index page"):
        index = write_index(ds, out, levels, level_paths, time_rows, timing, spec_path)
    return PaperResult(ds, out, level_paths, [p for _, p, _ in time_rows], index, timing)
