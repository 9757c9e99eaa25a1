"""Basins of attraction: the grid of initial states (y [µm], ẏ [mm/s]) coloured by the attractor
each start reaches (grey: none within the transient limit), the attractors' stroboscopic points
on top, and a legend of the labels with period, minima, A_pp and basin fraction."""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import axes_or_new, new_figure
from contactvib.plotting.style import NO_ATTRACTOR_COLOUR, label_colours
from contactvib.steady.basins import BasinMap

__all__ = ["plot_basins", "basins_figure", "label_text", "draw_label_map", "system_basins_figure",
           "system_label_text"]

#: Above this many strobe points an attractor's markers are drawn small (a cloud, not an orbit).
CLOUD_POINTS = 32
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
    points = [(a.strobe_y_um, a.strobe_ydot_mm_s) for a in bmap.attractors]
    texts = [label_text(bmap, i) for i in range(len(bmap.attractors))]
    return draw_label_map(bmap.y_um, bmap.ydot_mm_s, bmap.labels, points, texts, label_text(bmap, -1),
                          "initial displacement y [µm] (y > 0: contact deflection)", "initial velocity dy/dt [mm/s]",
                          ax=ax, legend=legend)


def draw_label_map(x, y, labels, points, texts, none_text: str, xlabel: str, ylabel: str, ax=None,
                   legend: bool = True):
    """A basin map: the image of ``labels`` (n_y, n_x; −1 grey) over ``x`` × ``y``, each label's
    points (``points[i]``: its stroboscopic points (xs, ys)) as markers, and a legend of
    ``texts[i]`` (``none_text`` for −1)."""
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.legend_handler import HandlerTuple
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    ax = axes_or_new(ax, (7.5, 5.0))
    n = len(points)
    colors = label_colours(n)
    cmap = ListedColormap([NO_ATTRACTOR_COLOUR, *colors])
    norm = BoundaryNorm(np.arange(-1.5, n + 0.5), cmap.N)
    ax.pcolormesh(x, y, labels, cmap=cmap, norm=norm, shading="nearest", rasterized=True)
    (x0, x1), (v0, v1) = ax.get_xlim(), ax.get_ylim()
    handles, legend_texts = [], []
    for i, (px, py) in enumerate(points):
        inside = (px >= x0) & (px <= x1) & (py >= v0) & (py <= v1)
        many = np.size(px) > CLOUD_POINTS  # a non-periodic attractor's cloud: small dots
        style = {"marker": _MARKERS[i % len(_MARKERS)], "ms": 3 if many else 9, "mfc": "w", "mec": "k",
                 "mew": 0.6 if many else 1.5, "ls": "none"}
        ax.plot(px, py, clip_on=True, zorder=3, **style)
        handles.append((Patch(facecolor=colors[i], edgecolor="k"), Line2D([], [], **style)))
        legend_texts.append(texts[i] + ("" if inside.any() else "; strobe points off the map"))
    ax.set_xlim(x0, x1)
    ax.set_ylim(v0, v1)
    if np.any(labels < 0):
        handles.append(Patch(facecolor=NO_ATTRACTOR_COLOUR, edgecolor="k"))
        legend_texts.append(none_text)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if legend:
        ax.legend(handles, legend_texts, handler_map={tuple: HandlerTuple(ndivide=None, pad=0.3)},
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


def system_label_text(bmap, label: int) -> str:
    """``"1: period 6, 6 minima, 15.39 ± 0.60 %"`` for a :class:`~contactvib.steady.system_basins.SystemBasinMap`
    (label −1: no attractor reached)."""
    p, se = bmap.fraction(label)
    share = f"{100 * p:.2f} ± {100 * se:.2f} %"
    if label < 0:
        return f"−1: no attractor reached within {bmap.search.settings['max_periods']} periods, {share}"
    a = bmap.attractors[label]
    new = "" if label < bmap.n_known else " (grid only)"
    if not a.period:
        return f"{label}: {a.attractor_type}, λ1 {a.lyapunov_per_s[0]:.3g} /s, {share}{new}"
    mins = f", {a.minima_per_period} {'minimum' if a.minima_per_period == 1 else 'minima'}"
    return f"{label}: period {a.period}{mins}, {share}{new}"


_UNIT_TEXT = {"um": "µm", "urad": "µrad", "mm/s": "mm/s", "mrad/s": "mrad/s"}


def system_basins_figure(bmap, title: str | None = None):
    """The basins of a system on its slice (``SystemBasinMap``): the label image over the two
    components [display units], the attractors' stroboscopic points, a legend."""
    fig, axes = new_figure(1, 1, figsize=(12.0, 5.4))
    points = [bmap.strobe(i) for i in range(len(bmap.attractors))]
    texts = [system_label_text(bmap, i) for i in range(len(bmap.attractors))]
    (na, nb), (ua, ub) = bmap.axes, bmap.units
    draw_label_map(bmap.a, bmap.b, bmap.labels, points, texts, system_label_text(bmap, -1),
                   f"initial {na} [{_UNIT_TEXT.get(ua, ua)}]", f"initial {nb} [{_UNIT_TEXT.get(ub, ub)}]",
                   ax=axes[0, 0])
    s = bmap.search
    fig.suptitle(title or (f"Basins of attraction at $P_a$ = {s.pa_newton:.4g} N, $f_e$ = {s.fe_hz:g} Hz: "
                           f"{bmap.a.size} × {bmap.b.size} initial states ({na}, {nb}) at phase 0, the other "
                           + ("components at a given state" if bmap.base_given else "components at the static state")),
                 fontsize=11)
    fig.tight_layout()
    return fig
