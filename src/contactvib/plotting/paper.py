"""The paper's figures: one level's resonance graph and local-extrema diagram (Figs. 2, 3) and a
time-history figure with one row per attractor (Figs. 4–9). Matplotlib only; the data come in."""

from __future__ import annotations

from dataclasses import dataclass

from contactvib.plotting.figures import (
    extrema_diagram,
    level_title,
    new_figure,
    plot_phase_portrait,
    plot_time_history,
    resonance_graph,
    set_margins,
)

__all__ = ["level_figures", "draw_level", "TimeRow", "time_figure"]


def level_figures(ds, pa_over_q: float, perturbation=None, ref: str = ""):
    """The resonance graph (Fig. 2) and the local-extrema diagram (Fig. 3) of one P_a level.

    ``perturbation``: ``(fe_hz, app_um, valid)`` of the series, drawn on the graph where valid;
    ``ref`` names the paper's panel in the titles (e.g. "c" for Figs. 2c/3c).
    Returns the two figures ``(graph, extrema)``.
    """
    (graph, g_axes), (extrema, e_axes) = new_figure(figsize=(7.0, 4.2)), new_figure(figsize=(7.0, 4.2))
    draw_level(ds, pa_over_q, g_axes[0, 0], e_axes[0, 0], perturbation=perturbation, ref=ref)
    for fig in (graph, extrema):  # tight_layout's margins for these axes labels and titles
        set_margins(fig, left=0.82, right=0.22, bottom=0.58, top=0.34)
    return graph, extrema


def draw_level(ds, pa_over_q: float, ax_graph, ax_extrema, perturbation=None, ref: str = "",
               limits=None):
    """Draw one level's resonance graph (Fig. 2) on ``ax_graph`` and its local-extrema diagram
    (Fig. 3) on ``ax_extrema``, titled (``ref``: the paper's panel letter, e.g. "c").

    ``limits``: None (f_e from 0 to the level's highest frequency + 2 %, amplitudes as drawn), or
    fixed axes ``{"fe_hz": (lo, hi), "app_um": (lo, hi), "y_um": (lo, hi)}`` shared by several
    levels (the film, :mod:`contactvib.plotting.film`); the f_n0/m marks then sit at the fixed
    amplitude floor.
    """
    marks = None if limits is None else limits["app_um"][0] * 1.3
    for ax, draw, what, fig_no, kw in ((ax_graph, resonance_graph, "Resonance graph", "2",
                                        {"perturbation": perturbation, "marks_um": marks}),
                                       (ax_extrema, extrema_diagram, "Local extrema of y(t)", "3", {})):
        draw(ds, pa_over_q, ax=ax, **kw)
        ax.set_xlim(*((0, float(ds["fe_hz"].max()) * 1.02) if limits is None else limits["fe_hz"]))
        cf = f" (cf. Fig. {fig_no}{ref})" if ref else ""
        ax.set_title(f"{what}, {level_title(ds, pa_over_q)}{cf}", fontsize=10)
    if limits is not None:
        ax_graph.set_ylim(*limits["app_um"])
        ax_extrema.set_ylim(*limits["y_um"])
    return ax_graph, ax_extrema


@dataclass(frozen=True)
class TimeRow:
    """One attractor of a time-history figure: its history, the row title, and the perturbation
    series' history to overlay (None: not drawn) with its legend label."""

    history: object
    title: str
    series: object = None
    series_label: str = ""


def time_figure(rows, title: str):
    """Figs. 4–9: one row per attractor, y(t) [µm vs ms] left and the phase portrait right."""
    n = max(len(rows), 1)
    fig, axes = new_figure(n, 2, figsize=(11, 2.5 * n + 0.6), gridspec_kw={"width_ratios": [1.7, 1]})
    for r, row in enumerate(rows):
        plot_time_history(row.history, axes[r, 0])
        plot_phase_portrait(row.history, axes[r, 1])
        if row.series is not None:
            hp = row.series
            axes[r, 0].plot(hp.t_ms, hp.y_um, color="tab:red", ls="--", lw=1.0,
                            label=row.series_label)
            axes[r, 1].plot(hp.y_um, hp.ydot_mm_s, color="tab:red", ls="--", lw=1.0)
            axes[r, 0].legend(loc="best", fontsize=7, frameon=False)
        axes[r, 0].set_title(row.title, fontsize=8.5, loc="left")
    fig.suptitle(title, fontsize=10)
    # tight_layout's margins for the widest tick labels of Figs. 4–9 (y to four digits and a sign)
    set_margins(fig, left=0.95, right=0.16, bottom=0.59, top=0.62, wspace=0.2, hspace=0.43)
    return fig
