"""The explore page's continuation of the selected periodic attractor in f_e (Bokeh figure).

The continuation itself is the CLI's (``contactvib continue --attractor N --no-switch`` over a
window around f_e, handed in by :mod:`contactvib.cli.explore`); this module draws its branch:
A_pp [µm, log] against f_e [Hz], stable parts solid and unstable parts dashed, folds, period
doublings, Neimark–Sacker and grazing points marked, and the page's operating point."""

from __future__ import annotations

import numpy as np

__all__ = ["window_hz", "branch_figure", "MARKERS"]

#: How special points are marked: type -> (marker, colour).
MARKERS = {"fold": ("triangle", "#d62728"), "period-doubling": ("square", "#1f77b4"),
           "neimark-sacker": ("hex", "#9467bd"), "grazing": ("circle", "#2ca02c")}


def window_hz(fe_hz: float, fmin: float = 30.0, fmax: float = 2000.0) -> tuple[float, float]:
    """The f_e window [Hz] of a continuation from ``fe_hz``: f_e/2 … 2 f_e within the sweep's
    30–2000 Hz (and always around f_e)."""
    return min(max(fmin, fe_hz / 2.0), fe_hz * 0.99), max(min(fmax, 2.0 * fe_hz), fe_hz * 1.01)


def _runs(stable: np.ndarray) -> list[tuple[int, int, bool]]:
    """Index ranges [a, b] (inclusive, overlapping by one point so lines join) of equal stability."""
    runs, a = [], 0
    for j in range(1, stable.size + 1):
        if j == stable.size or stable[j] != stable[a]:
            runs.append((a, min(j, stable.size - 1), bool(stable[a])))
            a = j
    return runs


def branch_figure(branch, fe_hz: float, app_um: float, title: str = ""):
    """A Bokeh figure of ``branch`` (a :class:`contactvib.continuation.branch.Branch` in f_e)
    with the operating point (``fe_hz``, ``app_um``) marked."""
    from bokeh.plotting import figure

    fig = figure(height=320, width=1000, y_axis_type="log", x_axis_label="f_e [Hz]",
                 y_axis_label="A_pp [µm] (log)", tools="pan,box_zoom,wheel_zoom,reset,save",
                 title=title or f"Continuation of the period-{branch.period} orbit in f_e")
    order = np.argsort(branch.arclength)
    fe, app, stable = branch.fe_hz[order], branch.app_um[order], np.asarray(branch.stable)[order]
    done = set()
    for a, b, st in _runs(stable):
        label = "stable" if st else "unstable"
        kw = {"legend_label": label} if label not in done else {}
        done.add(label)
        fig.line(fe[a:b + 1], app[a:b + 1], line_color="black", line_width=2 if st else 1.5,
                 line_dash="solid" if st else "dashed", **kw)
    for kind, (marker, colour) in MARKERS.items():
        pts = [s for s in branch.special if s.type == kind]
        if pts:
            fig.scatter([s.fe_hz for s in pts], [s.app_um for s in pts], marker=marker, size=10,
                        fill_color=colour, line_color="black", legend_label=kind)
    fig.scatter([fe_hz], [app_um], marker="star", size=16, fill_color="gold", line_color="black",
                legend_label="selected attractor")
    fig.legend.label_text_font_size = "8pt"
    fig.add_layout(fig.legend[0], "right")
    return fig
