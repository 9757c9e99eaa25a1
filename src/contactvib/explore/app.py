"""The explore page of one browser session (Panel): fields, derived quantities, the attractor
table, the time history, phase portrait and Poincaré section (:mod:`.section_view`) of the
selected attractor. Every session has its own :class:`Page` (tabs share nothing); searches run
in a worker thread, a generation counter drops a stale result, and the time limit stops the
kernels (:func:`.state.run_limited`). Without a dataset, a button sweeps the current level in
the background (:mod:`.level_graph`) and draws its resonance graph as the dataset mode does."""

from __future__ import annotations

import asyncio
import html
import logging
import time
from concurrent.futures import ThreadPoolExecutor
from urllib.parse import urlencode

import numpy as np
import panel as pn
from bokeh.models import Span
from bokeh.plotting import figure

from contactvib.explore.level_graph import GRAPH_TIME_LIMIT_S, LevelRun, sweep_level
from contactvib.explore.section_view import attractor_sections, section_figure
from contactvib.explore.state import (
    DEFAULTS,
    LAW_PARAMETERS,
    MODEL_FIELDS,
    TIME_LIMIT_S,
    BadInput,
    Point,
    Stopped,
    derived,
    resonance_of,
    run_limited,
    search,
    table_rows,
)
from contactvib.model.laws import DAMPING_NAMES

log = logging.getLogger("contactvib.explore")
_LABELS = {"pa": "P_a [Q]", "fe": "f_e [Hz]", "M": "M [kg]", "g": "g [m/s²]", "S": "S [m²]",
           "c_n": "c_n [N/m^(2+m2)]", "m2": "m2 [1]", "h_n": "h_n [N s/m^(3+l)]", "l": "l [1]",
           "law": "contact law (--law)", "damping": "damping (--damping)", "preload": "preload F_pre [N]",
           "alpha": "alpha [s/m]", **{k: f"{k} [{u}]" for k, (u, _d) in LAW_PARAMETERS.items()},
           "c_e": "c_e [N/m²]"}
#: The page's choosers (Select widgets); every other field is typed.
_CHOOSERS = ("law", "damping")
_EXECUTOR = ThreadPoolExecutor(max_workers=2, thread_name_prefix="contactvib-explore")
#: The background levels of every session, one at a time (a queued one shows 0 points done).
_GRAPH_EXECUTOR = ThreadPoolExecutor(max_workers=1, thread_name_prefix="contactvib-graph")


def _table_html(rows: list[dict], request: int = 0) -> str:
    """The attractor table; every number also in a ``data-v`` attribute at full precision, and
    the request it answers in ``data-request`` (the status line names the same request: the
    browser may draw the two panes in either order, so a reader can tell the table of the
    current point from an older one)."""
    if not rows:
        return f'<p class="no-attractor" id="attractors" data-request="{request}">no attractor</p>'
    head = "".join(f"<th>{html.escape(k)}</th>" for k in rows[0])
    body = []
    for r in rows:
        cells = []
        for k, v in r.items():
            if isinstance(v, float):
                text = f"{v:.2%}" if k == "basin" else f"{v:.5g}"
                cells.append(f'<td data-k="{html.escape(k)}" data-v="{v!r}">{text}</td>')
            else:
                cells.append(f'<td data-k="{html.escape(k)}">{html.escape("-" if v is None else str(v))}</td>')
        body.append(f'<tr class="attractor">{"".join(cells)}</tr>')
    style = ("<style>table.att{border-collapse:collapse;font-family:monospace}"
             "table.att td,table.att th{padding:2px 8px;border-bottom:1px solid #ccc;text-align:right}</style>")
    return (f'{style}<table class="att" id="attractors" data-request="{request}"><tr>{head}</tr>'
            f'{"".join(body)}</table>')


def _history_figures(hist, series=None):
    """Time history y(t) (contact loss shaded, y = 0 and y0 drawn) and phase portrait, with the
    perturbation series' orbit ``series`` (a TimeHistory over the same times, or None) dashed."""
    th = figure(height=300, width=520, title="Time history", x_axis_label="t [ms]",
                y_axis_label="y [µm] (> 0 contact deflection)")
    ph = figure(height=300, width=400, title="Phase portrait", x_axis_label="y [µm]",
                y_axis_label="ẏ [mm/s]")
    if hist is None:
        return th, ph
    t, y = hist.t_ms, hist.y_um
    gap = ~np.asarray(hist.in_contact)
    edges = np.flatnonzero(np.diff(np.r_[0, gap.astype(int), 0]))
    lo, hi = float(np.min(y)), float(np.max(y))
    if len(edges):  # one glyph for every interval of lost contact
        th.quad(left=t[edges[::2]], right=t[np.minimum(edges[1::2], len(t) - 1)], bottom=lo, top=hi,
                color="#f4b183", alpha=0.35, legend_label="contact lost")
    th.line(t, y, line_width=1.5, legend_label="y(t)")
    th.add_layout(Span(location=0.0, dimension="width", line_color="black", line_dash="dashed"))
    th.add_layout(Span(location=hist.y0_um, dimension="width", line_color="green", line_dash="dotted"))
    ph.line(y, hist.ydot_mm_s, line_width=1.5)
    if series is not None:  # on top of the numerics
        th.line(series.t_ms, series.y_um, line_width=2, line_dash="dashed", color="#c00000",
                legend_label="perturbation series")
        ph.line(series.y_um, series.ydot_mm_s, line_width=2, line_dash="dashed", color="#c00000")
    th.legend.location = "bottom_right"
    ph.add_layout(Span(location=0.0, dimension="height", line_color="black", line_dash="dashed"))
    ph.add_layout(Span(location=hist.y0_um, dimension="height", line_color="green", line_dash="dotted"))
    return th, ph


def _compute(point: Point, ops, limit_s: float):
    """Worker thread: checks, search, histories. ``("error", message)`` or ``("ok", payload)``;
    ``ops = (check, find)``: ``check(point) -> (model, excitation)`` and ``find(model, exc)``,
    both raising :class:`.BadInput` with the CLI's message."""
    from contactvib.explore.state import series_overlay
    from contactvib.steady.simulate import attractor_history

    check, find = ops[:2]
    try:
        model, exc = check(point)
        result, seconds = search(find, model, exc, limit_s)
        hists = [attractor_history(exc, a) for a in result]
        sections = attractor_sections(exc, result)
    except (Stopped, BadInput) as e:
        return "error", str(e)
    labels = [resonance_of(a, h, model.f_n0) for a, h in zip(result, hists)]
    return "ok", {"model": model, "exc": exc, "result": result, "hists": hists, "search_s": seconds,
                  "labels": labels, "series": series_overlay(model, exc, result), "sections": sections}


def _continue_compute(point: Point, ops, payload, n: int, limit_s: float):
    """Worker thread: the continuation of attractor ``n`` (``ops[2]``, the CLI's: see
    :func:`contactvib.cli.explore._continue`): ``("ok", (branch, command, seconds))`` or
    ``("error", message)``."""
    t0 = time.perf_counter()
    try:
        branch, command = run_limited(lambda: ops[2](point, payload["model"], payload["exc"],
                                                     payload["result"], n), limit_s)
    except (Stopped, BadInput) as e:
        return "error", str(e)
    return "ok", (branch, command, time.perf_counter() - t0)


class Page:
    """One session's page."""

    def __init__(self, point: Point, ops, limit_s: float = TIME_LIMIT_S, levels=None,
                 graph_limit_s: float = GRAPH_TIME_LIMIT_S):
        self.point, self.ops, self.limit_s, self.generation, self.payload = point, ops, limit_s, 0, None
        self.graph_limit_s, self.graph_run, self.graph_level = graph_limit_s, None, None
        self.graph_key = self._level_key()  # the (P_a, model) of graph_run or graph_level
        self.levels, self.pick_um = levels, None  # a DatasetLevels; A_pp [µm] of the last click
        self.fields = {k: pn.widgets.TextInput(label=_LABELS[k], value=point.fields[k], width=150,
                                               css_classes=[f"field-{k}"]) for k in DEFAULTS if k not in _CHOOSERS}
        for k, options in (("law", point.law_choices()), ("damping", DAMPING_NAMES)):
            self.fields[k] = pn.widgets.Select(label=_LABELS[k], options=list(options), value=point.fields[k],
                                               width=150, css_classes=[f"field-{k}"])
        self.model_grid = pn.GridBox(ncols=4)
        self._show_families()
        self.fe_slider = pn.widgets.FloatSlider(label="f_e slider [Hz]", start=50, end=1000, step=1,
                                                value=self._float("fe", 360.0), width=320)
        if levels is None:
            self.pa_slider = pn.widgets.FloatSlider(label="P_a slider [Q]", start=0.05, end=2.0, step=0.05,
                                                    value=self._float("pa", 0.65), width=320)
        else:  # the dataset's levels
            pa = levels.nearest_level(self._float("pa", levels.levels[0])) or levels.levels[0]
            self.pa_slider = pn.widgets.DiscreteSlider(label="P_a level of the dataset [Q]", width=320,
                                                       options=list(levels.levels), value=pa)
        self.graph = pn.Column(css_classes=["graph"])
        self.graph_button = pn.widgets.Button(label="compute the resonance graph of this P_a", width=300,
                                              css_classes=["graph-compute"],
                                              visible=levels is None and len(ops) > 3)
        self.graph_progress = pn.indicators.Progress(value=0, max=1, width=260, visible=False,
                                                     css_classes=["graph-progress"])
        self.graph_status = pn.pane.HTML("", css_classes=["graph-status"], width=700)
        self.graph_button.on_click(self._graph_clicked)
        self.message = pn.pane.HTML("", css_classes=["message"], width=900)
        self.status = pn.pane.HTML("", css_classes=["status"], width=900)
        self.derived = pn.pane.HTML("", css_classes=["derived"], width=900)
        self.table = pn.pane.HTML("", css_classes=["table"], width=900)
        self.select = pn.widgets.Select(label="attractor", options={"-": -1}, width=230,
                                        css_classes=["attractor-select"])
        self.download = pn.widgets.FileDownload(callback=self._json, filename="attractors.json",
                                                label="attractors.json (the CLI's --json)", width=260,
                                                css_classes=["download-json"])
        self.figure_files = [pn.widgets.FileDownload(callback=lambda fmt=fmt: self._figure_file(fmt),
                                                     filename=f"attractor.{fmt}", width=170,
                                                     label=f"figure ({fmt.upper()})",
                                                     css_classes=[f"download-{fmt}"])
                             for fmt in ("png", "svg")]
        self.plots = pn.Row(*(pn.pane.Bokeh(f) for f in (*_history_figures(None), section_figure())))
        self.series_note = pn.pane.HTML("", css_classes=["series-note"], width=900)
        self.cont_button = pn.widgets.Button(label="continue the selected orbit in f_e", width=260,
                                             css_classes=["continue"], visible=len(ops) > 2)
        self.cont_status = pn.pane.HTML("", css_classes=["cont-status"], width=700)
        self.cont_plot = pn.Column(css_classes=["cont-plot"])
        self.cont_generation = 0
        self.cont_button.on_click(self._continue_clicked)
        for w in self.fields.values():
            w.param.watch(self._changed, "value")
        self.fe_slider.param.watch(lambda e: self._set("fe", e.new), "value_throttled")
        self.pa_slider.param.watch(lambda e: self._set("pa", e.new), "value_throttled")
        self.select.param.watch(lambda e: self._draw(), "value")

    def _float(self, name, default):
        try:
            return float(self.point.fields[name])
        except ValueError:
            return default

    def _set(self, name, value):
        self.fields[name].value = f"{value:g}"

    def _show_families(self):
        """Show the model fields of the chosen law and damping only (:meth:`.state.Point.active`);
        the others keep their values, hidden."""
        active = self.point.active()
        if list(self.model_grid.objects) != [self.fields[k] for k in active]:
            self.model_grid.objects = [self.fields[k] for k in active]
        for k in MODEL_FIELDS:
            self.fields[k].visible = k in active

    def layout(self):
        ops = pn.Column("### Operating point", pn.Row(self.fields["pa"], self.pa_slider),
                        pn.Row(self.fields["fe"], self.fe_slider), "### Model",
                        pn.Row(*(self.fields[k] for k in ("law", "damping", "preload"))),
                        self.model_grid,
                        self.derived)
        return pn.Column("## contactvib explore: the contact oscillator of Kostek 2013", ops, self.message,
                         self.status, pn.Row(self.graph_button, self.graph_progress, self.graph_status),
                         self.graph, "### Attractors", self.table,
                         pn.Row(self.select, self.download, *self.figure_files), self.plots, self.series_note,
                         pn.Row(self.cont_button, self.cont_status), self.cont_plot)

    async def _changed(self, event=None):
        await self.refresh()

    async def refresh(self):
        """Check the fields and search (the newest request wins; older results are dropped)."""
        self.point = Point({k: w.value for k, w in self.fields.items()}, self.point.law_file)
        self._show_families()
        if self._level_key() != self.graph_key:
            self._drop_graph()
        for name, slider in (("fe", self.fe_slider), ("pa", self.pa_slider)):
            value = self._float(name, None)
            if value is None:
                continue
            if isinstance(slider, pn.widgets.DiscreteSlider):
                if value in slider.options:
                    slider.value = value
            elif slider.start <= value <= slider.end:
                slider.value = value
        self.generation += 1
        mine = self.generation
        self.cont_generation += 1  # a continuation under way belongs to the old point
        self.cont_status.object, self.cont_plot[:] = "", []
        self._sync_url()
        self.status.object = '<span class="busy">computing…</span>'
        t0 = time.perf_counter()
        kind, payload = await asyncio.get_running_loop().run_in_executor(
            _EXECUTOR, _compute, self.point, self.ops, self.limit_s)
        if mine != self.generation:
            return  # a newer request is under way
        if kind == "error":
            self.message.object = f'<b style="color:#b00" class="error">{html.escape(payload)}</b>'
            self.status.object = ""
            self.payload, self.table.object = None, "<p>(no result for these values)</p>"
            self.select.options = {"-": -1}
            self._draw()
            self._draw_graph(None)
            return
        self.message.object = ""
        self.payload = payload
        d = derived(payload["model"])
        self.derived.object = (f"f_n0 = {d['f_n0']:.1f} Hz, y0 = {d['y0']:.4f} µm, "
                               f"ζ = {d['zeta']:.4f}; {html.escape(payload['model'].describe_law())}")
        result = payload["result"]
        rows = table_rows(result, payload["labels"])
        self.table.object = _table_html(rows, mine)
        opts = {f"#{i} {r['resonance']}": i for i, r in enumerate(rows)} or {"-": -1}
        self.select.options = opts
        self.select.value = self._picked(result, next(iter(opts.values())))
        self._draw()
        self._draw_graph(result)
        total = time.perf_counter() - t0
        log.info("explore: P_a=%s Q f_e=%s Hz: find_attractors %.3f s, total with render %.3f s",
                 self.point.fields["pa"], self.point.fields["fe"], payload["search_s"], total)
        self.status.object = (f'<span class="done" data-request="{mine}" data-n="{len(result)}" '
                              f'data-fe="{html.escape(self.point.fields["fe"].strip())}">'
                              f'{len(result)} attractors; search '
                              f'{payload["search_s"]:.2f} s, with histories and render {total:.2f} s</span>')

    def _json(self):
        """The attractors as ``contactvib attractors --json`` prints them."""
        import io
        import json
        import math

        def finite(obj):  # strict JSON, as the CLI writes it: a non-finite number is null
            if isinstance(obj, float):
                return obj if math.isfinite(obj) else None
            if isinstance(obj, dict):
                return {k: finite(v) for k, v in obj.items()}
            return [finite(v) for v in obj] if isinstance(obj, list) else obj

        obj = {} if self.payload is None else finite(json.loads(self.payload["result"].to_json()))
        return io.StringIO(json.dumps(obj, allow_nan=False, indent=1))

    def _selected(self):
        """(history, attractor) of the selected attractor, or (None, None)."""
        i = self.select.value
        hists = [] if self.payload is None else self.payload["hists"]
        if not (isinstance(i, int) and 0 <= i < len(hists)):
            return None, None
        return hists[i], self.payload["result"][i]

    def _series_history(self, hist):
        """The perturbation series' orbit over the selected attractor's times, when the series is
        drawn on that attractor (:func:`.state.series_overlay`), else None."""
        overlay = None if self.payload is None else self.payload["series"]
        if hist is None or overlay is None or overlay.attractor != self.select.value:
            return None
        n_periods = max(1, round(float(hist.t_ms[-1] - hist.t_ms[0]) * hist.fe_hz / 1000.0))
        return overlay.series.history(n_periods=n_periods, samples_per_period=200)  # both from phase 0

    def _draw(self):
        hist, _a = self._selected()
        i = self.select.value
        sections = [] if self.payload is None else self.payload.get("sections", [])
        section = sections[i] if hist is not None and isinstance(i, int) and 0 <= i < len(sections) else None
        self.plots[:] = [pn.pane.Bokeh(f) for f in (*_history_figures(hist, self._series_history(hist)),
                                                    section_figure(section))]
        note = "" if self.payload is None else self.payload["series"].note
        self.series_note.object = f"<small>{html.escape(note)}</small>"
        stem = (f"attractor{self.select.value}_pa{self.point.fields['pa'].strip()}_"
                f"fe{self.point.fields['fe'].strip()}")
        for w in self.figure_files:
            w.filename = f"{stem}.{w.filename.rsplit('.', 1)[-1]}"

    def _figure_file(self, fmt: str):
        """The selected attractor's time history and phase portrait as a PNG or SVG file (the
        figure ``contactvib simulate`` writes for each attractor)."""
        import io

        from contactvib.plotting.figures import attractor_figure, figure_bytes

        hist, attractor = self._selected()
        if hist is None:
            return io.BytesIO(b"")
        return io.BytesIO(figure_bytes(attractor_figure(hist, attractor), fmt))

    async def _continue_clicked(self, event=None):
        """Continue the selected periodic attractor in f_e and draw its branch (a newer
        request or a new operating point drops the result)."""
        from contactvib.explore.continuation_view import branch_figure

        _hist, a = self._selected()
        if a is None or a.period is None:
            self.cont_status.object = '<span class="cont-error">select a periodic attractor first</span>'
            return
        self.cont_generation += 1
        mine, n, payload = self.cont_generation, self.select.value, self.payload
        self.cont_status.object = '<span class="busy">continuing…</span>'
        kind, out = await asyncio.get_running_loop().run_in_executor(
            _EXECUTOR, _continue_compute, self.point, self.ops, payload, n, self.limit_s)
        if mine != self.cont_generation:
            return
        if kind == "error":
            self.cont_status.object = f'<b style="color:#b00" class="cont-error">{html.escape(out)}</b>'
            return
        branch, command, seconds = out
        fe = self._float("fe", float("nan"))
        self.cont_plot[:] = [pn.pane.Bokeh(branch_figure(branch, fe, a.app_um))]
        specials = ", ".join(f"{s.type} {s.fe_hz:.2f} Hz" for s in branch.special) or "no special point"
        self.cont_status.object = (f'<span class="cont-done">{len(branch)} points, '
                                   f'{branch.fe_hz.min():.1f}–{branch.fe_hz.max():.1f} Hz; '
                                   f'{html.escape(specials)}; {seconds:.1f} s</span><br>'
                                   f'<code>{html.escape(command)}</code>')

    def _picked(self, result, default):
        """After a click on the graph: the attractor whose A_pp is nearest the clicked one (log)."""
        pick, self.pick_um = self.pick_um, None
        if pick is None or pick <= 0 or not len(result):
            return default
        app = np.array([a.app_um for a in result], float)
        return int(np.nanargmin(np.abs(np.log(np.maximum(app, 1e-300)) - np.log(pick))))

    def _level_key(self):
        """What a level's graph depends on: P_a and the model (law options and fields), as typed."""
        return self.point.fields["pa"].strip(), self.point.model_args()

    def _drop_graph(self):
        """A new P_a or model: stop the background level under way, drop the computed graph."""
        if self.graph_run is not None:
            self.graph_run.stop()
        self.graph_run, self.graph_level, self.graph_key = None, None, self._level_key()
        self.graph_status.object, self.graph_progress.visible = "", False
        self.graph_button.visible, self.graph_button.disabled = self.levels is None and len(self.ops) > 3, False

    async def _graph_clicked(self, event=None):
        """Sweep the current level in the background (:func:`.level_graph.sweep_level`), showing
        its progress; a new P_a or model stops it (:meth:`_drop_graph`)."""
        if self.graph_run is not None:
            return
        try:
            run = LevelRun(*self.ops[3](self.point))
        except BadInput as e:
            self.graph_status.object = f'<b style="color:#b00" class="graph-error">{html.escape(str(e))}</b>'
            return
        self.graph_run, self.graph_button.disabled = run, True
        self.graph_progress.max, self.graph_progress.value, self.graph_progress.visible = run.total, 0, True
        t0 = time.perf_counter()
        future = asyncio.wrap_future(_GRAPH_EXECUTOR.submit(sweep_level, run, self.graph_limit_s))
        while run is self.graph_run and not future.done():
            self.graph_progress.value = min(run.points, run.total)
            self.graph_status.object = (f'<span class="graph-busy">P_a = {run.pa_over_q:g} Q: {run.points}/'
                                        f'{run.total} f_e points, {time.perf_counter() - t0:.0f} s</span>')
            await asyncio.wait({future}, timeout=0.25)
        if run is not self.graph_run:
            return  # dropped: a new P_a or model
        kind, out = future.result()
        self.graph_run, self.graph_button.disabled = None, False
        if kind != "ok":
            self.graph_progress.visible = False
            self.graph_status.object = f'<b style="color:#b00" class="graph-error">{html.escape(out)}</b>'
            return
        self.graph_level, seconds = out
        self.graph_progress.value, self.graph_button.visible = run.total, False
        self.graph_status.object = (f'<span class="graph-done">{run.total}/{run.total} f_e points, '
                                    f'{len(self.graph_level.fe_hz)} attractor points in {seconds:.1f} s, as '
                                    f'<code style="white-space:nowrap">{html.escape(run.command)}</code> '
                                    'computes them</span>')
        self._draw_graph(None if self.payload is None else self.payload["result"])

    def _graph_points(self):
        """(the current level's points or None, a note or None): the dataset's level, or the
        level computed in the background for this P_a and model."""
        if self.levels is None:
            return (self.graph_level if self.graph_key == self._level_key() else None), None
        from contactvib.explore.dataset_view import MissingLevel

        try:
            return self.levels.level(self._float("pa", float("nan"))), None
        except MissingLevel as e:
            return None, str(e)

    def _draw_graph(self, result):
        """The level's resonance graph (the dataset's, or the one computed in the background)
        with the page's attractors on it; a one-line note when P_a is not a stored level."""
        from bokeh.events import Tap

        from contactvib.explore.dataset_view import friction_figure, graph_figure

        lv, note = self._graph_points()
        if lv is None:
            self.graph[:] = [] if note is None else [
                pn.pane.HTML(f'<p class="graph-note">{html.escape(note)}</p>')]
            return
        fig, current = graph_figure(lv)
        if result is not None:
            fe = self._float("fe", float("nan"))
            current.data = {"fe_hz": [fe] * len(result), "app_um": [a.app_um for a in result],
                            "name": [f"#{i}" for i in range(len(result))]}

        def tapped(event):
            if event.x is None:
                return
            self.pick_um = event.y
            self.fields["fe"].value = f"{lv.snap(event.x):g}"

        fig.on_event(Tap, tapped)
        friction = friction_figure(lv, fig.x_range)  # a dataset swept with --friction
        self.graph[:] = [pn.pane.Bokeh(fig, css_classes=["resonance-graph"])] + (
            [] if friction is None else [pn.pane.Bokeh(friction, css_classes=["friction-graph"])])

    def _sync_url(self):
        loc = pn.state.location
        if loc is not None:
            q = self.point.query()
            loc.search = ("?" + urlencode(q)) if q else ""


def build(ops, limit_s: float = TIME_LIMIT_S, levels=None, graph_limit_s: float = GRAPH_TIME_LIMIT_S,
          start: Point | None = None):
    """The page of a new session, from its URL query parameters over ``start`` (the explore
    command's law options; default the paper's point) (``ops``: see :func:`_compute`;
    ``levels``: a :class:`.dataset_view.DatasetLevels` or None). With a dataset and no P_a in
    the URL, P_a starts at the stored level nearest the default."""
    args = {k: [v.decode("utf-8", "replace") if isinstance(v, bytes) else v for v in vs]
            for k, vs in (pn.state.session_args or {}).items()}
    point = Point.from_query(args, start)
    if levels is not None and "pa" not in args:
        lv = np.asarray(levels.levels)
        point.fields["pa"] = f"{lv[np.argmin(np.abs(lv - float(point.fields['pa'])))]:g}"
    page = Page(point, ops, limit_s, levels, graph_limit_s)
    pn.state.onload(page.refresh)
    pn.state.on_session_destroyed(lambda _context: page.graph_run and page.graph_run.stop())  # tab closed
    return page.layout()
