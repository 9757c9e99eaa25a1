"""The explore page's resonance graph from a stored dataset (``paper.nc``, ``resonance.nc`` or an
atlas): one P_a level at a time, read lazily, drawn as the paper's Fig. 2 (Bokeh).

:class:`DatasetLevels` holds the dataset, opened once as every reader opens one
(:class:`contactvib.sweeps.stored.ResonanceData`: only ``pa_over_q`` is read whole), and reads one
level's points when the page asks for it; :func:`graph_figure` draws it as
:func:`contactvib.plotting.figures.resonance_graph` does (A_pp [µm, log] against f_e [Hz]; colour
= resonance order with the same colours, :func:`contactvib.plotting.style.order_colour`; dashed
after period doubling; dotted = bouncing orbits; red dots = non-periodic attractors; a gold
underlay on parts no laboratory sweep reaches) with the page's current attractors on top; for a
dataset swept with friction (``--friction``), :func:`friction_figure` draws the friction ratio of
the same branches below it."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contactvib.sweeps.stored import DatasetError, MissingLevel, ResonanceData

__all__ = ["DatasetLevels", "LevelPoints", "level_points", "graph_figure", "friction_figure", "DatasetError",
           "MissingLevel"]

_VARS = ("fe_hz", "app_um", "branch_index", "kind", "resonance")


@dataclass(frozen=True)
class LevelPoints:
    """The stored attractor points of one level (per point; ``isolated`` per point: its branch
    is not reached by a laboratory sweep; ``friction_ratio`` [1] per point for a dataset swept
    with friction, else None)."""

    pa_over_q: float
    fe_hz: np.ndarray
    app_um: np.ndarray
    branch: np.ndarray
    kind: np.ndarray
    resonance: np.ndarray
    isolated: np.ndarray
    friction_ratio: np.ndarray | None = None

    def snap(self, fe_hz: float) -> float:
        """The stored grid frequency nearest ``fe_hz`` [Hz]."""
        grid = np.unique(self.fe_hz)
        return float(grid[np.argmin(np.abs(grid - fe_hz))])


class DatasetLevels:
    """The page's resonance dataset: a :class:`ResonanceData` (``data``; ``path``), its
    ``levels`` [level unit] (increasing), :meth:`nearest_level` and :meth:`level` (the points of
    a level, read on first use, then kept)."""

    def __init__(self, data: ResonanceData):
        self.data, self.path, self.levels = data, data.path, data.levels
        self._cache: dict[float, LevelPoints] = {}

    def nearest_level(self, pa_over_q: float) -> float | None:
        """The stored level that ``pa_over_q`` designates (within ``LEVEL_TOL``), or None."""
        return self.data.match(pa_over_q)

    def level(self, pa_over_q: float) -> LevelPoints:
        """The points of the stored level ``pa_over_q`` (read on first use, then kept);
        :class:`MissingLevel` (one line naming the levels) when it is not stored."""
        pa = self.data.stored_level(pa_over_q)
        if pa not in self._cache:
            self._cache[pa] = level_points(self.data, pa)
        return self._cache[pa]


def level_points(data: ResonanceData, pa_over_q: float) -> LevelPoints:
    """The points of level ``pa_over_q`` of a resonance dataset (:meth:`ResonanceData.level`: a
    file opened lazily, of which only that level's slice is read, or a sweep's dataset in memory,
    :mod:`.level_graph`). :class:`MissingLevel` when the dataset does not hold it."""
    part, ds = data.level(pa_over_q), data.ds
    v = {k: part[k].values for k in _VARS}
    reach = (ds["branch_reached_by_sweep"].values if "branch_reached_by_sweep" in ds
             else np.ones(ds.sizes.get("branch", 0), np.int8))
    br = v["branch_index"].astype(int)
    friction = part["friction_ratio"].values.astype(float) if "friction_ratio" in ds else None
    return LevelPoints(float(pa_over_q), v["fe_hz"].astype(float), v["app_um"].astype(float), br,
                       v["kind"].astype(str), v["resonance"].astype(str),
                       reach[br] == 0 if reach.size else np.zeros(br.size, bool), friction)


def _lines(lv: LevelPoints):
    """Per style, the branch segments to draw: {(colour, width, dash, legend): (xs, ys)}, the
    isolated segments (xs, ys) and the non-periodic points (x, y)."""
    from contactvib.labels import label_family
    from contactvib.plotting.style import order_colour

    styles: dict = {}
    iso_x, iso_y = [], []
    step = np.min(np.diff(np.unique(lv.fe_hz))) if np.unique(lv.fe_hz).size > 1 else 1.0
    nonper = lv.kind != "periodic"
    for b in np.unique(lv.branch[~nonper]):
        pts = np.flatnonzero((lv.branch == b) & ~nonper)
        pts = pts[np.argsort(lv.fe_hz[pts])]
        m, variant = label_family(lv.resonance[pts[0]])
        name = "main" if m == 1 else f"1/{m}"
        if m is None:
            key = (("#8c8c8c", 0.8, "dotted", "sub-/ultrasubharmonic bouncing")
                   if lv.resonance[pts[0]] != "non-resonant" else ("#595959", 1.0, "solid", "non-resonant"))
        elif not variant:
            key = (order_colour(m), 1.6, "solid", name)
        else:
            key = (order_colour(m), 1.2, "dashed", f"{name} period-k (doubled, windows)")
        gaps = np.flatnonzero(np.diff(lv.fe_hz[pts]) > 1.5 * step)
        for seg in np.split(pts, gaps + 1):
            xs, ys = styles.setdefault(key, ([], []))
            xs.append(lv.fe_hz[seg])
            ys.append(lv.app_um[seg])
            if m is not None and lv.isolated[seg[0]]:
                iso_x.append(lv.fe_hz[seg])
                iso_y.append(lv.app_um[seg])
    return styles, (iso_x, iso_y), (lv.fe_hz[nonper], lv.app_um[nonper])


def graph_figure(lv: LevelPoints, title: str = ""):
    """A Bokeh figure of the level's resonance graph (Fig. 2) with an empty ``"current"``
    renderer for the page's attractors (name ``current``; data ``fe_hz``, ``app_um``)."""
    from bokeh.models import ColumnDataSource, HoverTool
    from bokeh.plotting import figure

    fig = figure(height=360, width=1000, y_axis_type="log", x_axis_label="f_e [Hz]",
                 y_axis_label="A_pp [µm] (log)", tools="tap,pan,box_zoom,wheel_zoom,reset",
                 title=title or f"Resonance graph, P_a = {lv.pa_over_q:g} Q (click: move f_e there)")
    styles, (ix, iy), (nx, ny) = _lines(lv)
    if ix:
        fig.multi_line(ix, iy, line_color="gold", line_width=7, line_alpha=0.55,
                       legend_label="isolated: not reached by sweeps")
    for (colour, width, dash, label), (xs, ys) in sorted(styles.items(), key=lambda kv: _order_key(kv[0][3])):
        fig.multi_line(xs, ys, line_color=colour, line_width=width, line_dash=dash, legend_label=label)
    if nx.size:
        fig.scatter(nx, ny, size=2.5, color="#d62728", legend_label="non-periodic")
    current = ColumnDataSource({"fe_hz": [], "app_um": [], "name": []})
    r = fig.scatter("fe_hz", "app_um", source=current, size=11, marker="diamond", fill_color="white",
                    line_color="black", line_width=2, name="current", legend_label="this page's attractors")
    fig.add_tools(HoverTool(renderers=[r], tooltips=[("", "@name"), ("f_e [Hz]", "@fe_hz"),
                                                     ("A_pp [µm]", "@app_um")]))
    fig.legend.label_text_font_size = "8pt"
    fig.legend.click_policy = "hide"
    fig.add_layout(fig.legend[0], "right")
    return fig, current


def friction_figure(lv: LevelPoints, x_range=None):
    """A Bokeh figure of the friction ratio ⟨F_drive⟩/(μ W) [1] of the level's periodic points
    against f_e [Hz], branch by branch in the resonance graph's colours and styles (None when
    the dataset has no friction columns); ``x_range``: the resonance graph's, shared."""
    from dataclasses import replace

    from bokeh.plotting import figure

    if lv.friction_ratio is None:
        return None
    kw = {} if x_range is None else {"x_range": x_range}
    fig = figure(height=260, width=1000, x_axis_label="f_e [Hz]",
                 y_axis_label="friction ratio <F_drive>/(mu W)", tools="pan,box_zoom,wheel_zoom,reset",
                 title=f"Friction ratio, P_a = {lv.pa_over_q:g} Q (1: no reduction)", **kw)
    styles, _iso, _nonper = _lines(replace(lv, app_um=lv.friction_ratio))
    for (colour, width, dash, label), (xs, ys) in sorted(styles.items(), key=lambda kv: _order_key(kv[0][3])):
        fig.multi_line(xs, ys, line_color=colour, line_width=width, line_dash=dash, legend_label=label)
    if fig.legend:
        fig.legend.label_text_font_size = "8pt"
        fig.legend.click_policy = "hide"
        fig.add_layout(fig.legend[0], "right")
    return fig


def _order_key(label: str):
    """Legend order: main, 1/2, 1/3, … (each before its period-k variant), then the rest."""
    head = label.split(" ")[0]
    if head == "main":
        return (1, label)
    if head.startswith("1/") and head[2:].isdigit():
        return (int(head[2:]), label)
    return (1000, label)
