"""Basins of attraction: the grid of initial states (y [µm], ẏ [mm/s]) coloured by the attractor
each start reaches (grey: none within the transient limit), the attractors' stroboscopic points
on top, and a legend of the labels with period, minima, A_pp and basin fraction."""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import axes_or_new, new_figure
from contactvib.plotting.style import NO_ATTRACTOR_COLOUR, label_colours
from contactvib.steady.basins import BasinMap

__all__ = ["plot_basins", "basins_figure", "label_text"]

#: Markers of the strobe points, by label (cycled).
_MARKERS = ("o", "s", "D", "^", "v", "P", "X", "*", "h", "<", ">")


def label_text(bmap: BasinMap, label: int) -> str:
    """``"2: period 1, 2 minima, A_pp 2.4 µm, 17.37 ± 0.09 %"`` (label −1: no attractor reached)."""
    p, se = bmap.fraction(label)
    share = f"{100 * p:.2f} ± {100 * se:.2f} %"
    if label < 0:
        return f"−1: no attractor reached, {share}"
    a = bmap.attractors[label]
    kind = f"period {a.period}" if a.period is not None else f"{a.kind} (marker: one point of its cloud)"
    mins = "" if a.minima_per_period is None else \
        f", {a.minima_per_period} {'minimum' if a.minima_per_period == 1 else 'minima'}"
    new = "" if label < bmap.n_known else " (grid only)"
    return f"{label}: {kind}{mins}, $A_{{pp}}$ {a.app_um:.3g} µm, {share}{new}"


def plot_basins(bmap: BasinMap, ax=None, legend: bool = True):
    """The label image over y [µm] × ẏ [mm/s] with the strobe points of every attractor
    (markers; those outside the box are named in the legend)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.legend_handler import HandlerTuple
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    ax = axes_or_new(ax, (7.5, 5.0))
    n = len(bmap.attractors)
    colors = label_colours(n)
    cmap = ListedColormap([NO_ATTRACTOR_COLOUR, *colors])
    norm = BoundaryNorm(np.arange(-1.5, n + 0.5), cmap.N)
    ax.pcolormesh(bmap.y_um, bmap.ydot_mm_s, bmap.labels, cmap=cmap, norm=norm, shading="nearest",
                  rasterized=True)
    (x0, x1), (v0, v1) = ax.get_xlim(), ax.get_ylim()
    handles, texts = [], []
    for i, a in enumerate(bmap.attractors):
        y, v = a.strobe_y_um, a.strobe_ydot_mm_s
        inside = (y >= x0) & (y <= x1) & (v >= v0) & (v <= v1)
        style = {"marker": _MARKERS[i % len(_MARKERS)], "ms": 9, "mfc": "w", "mec": "k", "mew": 1.5,
                 "ls": "none"}
        ax.plot(y, v, clip_on=True, zorder=3, **style)
        handles.append((Patch(facecolor=colors[i], edgecolor="k"), Line2D([], [], **style)))
        texts.append(label_text(bmap, i) + ("" if inside.any() else "; strobe points off the map"))
    ax.set_xlim(x0, x1)
    ax.set_ylim(v0, v1)
    if np.any(bmap.labels < 0):
        handles.append(Patch(facecolor=NO_ATTRACTOR_COLOUR, edgecolor="k"))
        texts.append(label_text(bmap, -1))
    ax.set_xlabel("initial displacement y [µm] (y > 0: contact deflection)")
    ax.set_ylabel("initial velocity dy/dt [mm/s]")
    if legend:
        ax.legend(handles, texts, handler_map={tuple: HandlerTuple(ndivide=None, pad=0.3)},
                  loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8, frameon=False,
                  handlelength=3.0, title="label: attractor, basin fraction ± s.e.\n"
                                          "(markers: its stroboscopic points, phase 0)",
                  title_fontsize=8, alignment="left")
    return ax


def basins_figure(bmap: BasinMap, title: str | None = None):
    """A figure of :func:`plot_basins`, titled with P_a, f_e and the grid."""
    fig, axes = new_figure(1, 1, figsize=(12.0, 5.4))
    plot_basins(bmap, axes[0, 0])
    s = bmap.search
    ny, nv = bmap.y_um.size, bmap.ydot_mm_s.size
    fig.suptitle(title or (f"Basins of attraction at $P_a$ = {s.pa_over_q:g} Q, $f_e$ = {s.fe_hz:g} Hz: "
                           f"{ny} × {nv} initial states (y, dy/dt) at phase 0"), fontsize=11)
    fig.tight_layout()
    return fig
