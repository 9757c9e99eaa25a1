"""The explore page of a structure with contacts (``contactvib explore --system rocking|FILE.toml``):
the level and f_e typed or slid, every attractor of the system's search in a table with each
coordinate's peak-to-peak value and each contact's share of the period open, and for the selected
attractor one row per coordinate (time history, phase portrait in its display unit) and the
contact forces against time. As on the slider's page, each session has its own page, searches run
in a worker thread under the time limit, and an older request's result is dropped.

``ops = (check, find, history)``, handed in by :mod:`contactvib.cli.explore`: ``check(fields)`` →
``(system, P_a [N], f_e [Hz], level text)`` raising :class:`.state.BadInput` with the CLI's
one-line message; ``find(system, P_a, f_e)`` → a ``SystemAttractorSet``;
``history(system, P_a, f_e, attractor)`` → a ``SystemHistory``.
"""

from __future__ import annotations

import asyncio
import html
import time
from concurrent.futures import ThreadPoolExecutor

import panel as pn
from bokeh.plotting import figure

from contactvib.explore.state import BadInput, Stopped, run_limited

__all__ = ["SystemPage", "build_system_page", "system_table_html"]

#: One worker thread for every session's searches (as the slider's page).
_EXECUTOR = ThreadPoolExecutor(max_workers=1, thread_name_prefix="contactvib-explore-system")
#: Line colours of the contacts' forces.
_COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b")


def system_table_html(result, request: int = 0) -> str:
    """The attractor table: period, minima, |μ|max, stable, basin, each coordinate's A_pp, each
    contact's share of the period open and mean force."""
    rows = [a.to_dict() for a in result]
    if not rows:
        return "<p>no periodic attractor settled (see the message above)</p>"
    head = ["#", "period", "minima", "|μ|max", "stable", "basin"]
    head += [f"{d['name']} A_pp [{d['unit'].replace('u', 'µ', 1)}]" for d in rows[0]["dofs"]]
    head += [f"{c['name']} open" for c in rows[0]["contacts"]]
    head += [f"{c['name']} mean F [N]" for c in rows[0]["contacts"]]
    out = [f'<table id="system-attractors" data-request="{request}"><tr>'
           + "".join(f"<th>{html.escape(h)}</th>" for h in head) + "</tr>"]
    for i, d in enumerate(rows):
        values = [i, d["period"], d["minima_per_period"], d["floquet_abs_max"], d["stable"], d["basin_fraction"]]
        values += [x["app"] for x in d["dofs"]] + [c["contact_loss_fraction"] for c in d["contacts"]]
        values += [c["mean_force_n"] for c in d["contacts"]]
        texts = [str(i), str(d["period"]), str(d["minima_per_period"]), f"{d['floquet_abs_max']:.4f}",
                 "yes" if d["stable"] else "no", f"{d['basin_fraction']:.1%}"]
        texts += [f"{v:.5g}" for v in values[6:6 + len(d["dofs"])]]
        texts += [f"{v:.3f}" for v in values[6 + len(d["dofs"]):6 + len(d["dofs"]) + len(d["contacts"])]]
        texts += [f"{v:.5g}" for v in values[6 + len(d["dofs"]) + len(d["contacts"]):]]
        # the full-precision value of each cell in data-v (the tests compare it with the CLI's JSON)
        out.append('<tr class="attractor">' + "".join(
            f'<td data-k="{html.escape(h)}" data-v="{float(v)!r}">{html.escape(t)}</td>'
            for h, v, t in zip(head, values, texts)) + "</tr>")
    return "".join(out) + "</table>"


def _figures(hist):
    """One (time history, phase portrait) pair per coordinate and the contact forces."""
    if hist is None:
        return [figure(height=260, width=520, title="Time history"), figure(height=260, width=380,
                                                                             title="Phase portrait")]
    figs = []
    for j, (name, qu, vu) in enumerate(zip(hist.coordinates, hist.q_units, hist.qdot_units)):
        unit = qu.replace("u", "µ", 1)
        th = figure(height=240, width=520, title=f"{name}(t)", x_axis_label="t [ms]", y_axis_label=f"{name} [{unit}]")
        th.line(hist.t_ms, hist.q[j], line_width=1.5)
        ph = figure(height=240, width=380, title=f"{name} phase portrait", x_axis_label=f"{name} [{unit}]",
                    y_axis_label=f"d{name}/dt [{vu}]")
        ph.line(hist.q[j], hist.qdot[j], line_width=1.5)
        figs += [th, ph]
    fc = figure(height=240, width=520, title="Contact forces", x_axis_label="t [ms]", y_axis_label="force [N]")
    for i, (name, f) in enumerate(zip(hist.contacts, hist.forces_n)):
        fc.line(hist.t_ms, f, line_width=1.5, color=_COLOURS[i % len(_COLOURS)], legend_label=name)
    figs.append(fc)
    return figs


def _compute(fields: dict, ops, limit_s: float):
    """Worker thread: checks, search, histories: ``("ok", payload)`` or ``("error", message)``."""
    check, find, history = ops
    try:
        system, p, fe, level = check(fields)
        t0 = time.perf_counter()
        result = run_limited(lambda: find(system, p, fe), limit_s)
        seconds = time.perf_counter() - t0
        hists = [history(system, p, fe, a) for a in result]
    except (Stopped, BadInput) as e:
        return "error", str(e)
    return "ok", {"system": system, "result": result, "hists": hists, "level": level, "search_s": seconds,
                  "fe": fe}


class SystemPage:
    """The page of one browser session for a system (see the module docstring)."""

    def __init__(self, label: str, level_unit: str, fields: dict, ops, limit_s: float):
        self.label, self.ops, self.limit_s, self.generation, self.payload = label, ops, limit_s, 0, None
        self.fields = {"pa": pn.widgets.TextInput(name=f"P_a [{level_unit}]", value=fields["pa"], width=150,
                                                  css_classes=["field-pa"]),
                       "fe": pn.widgets.TextInput(name="f_e [Hz]", value=fields["fe"], width=150,
                                                  css_classes=["field-fe"])}
        self.message = pn.pane.HTML("", css_classes=["message"], width=900)
        self.status = pn.pane.HTML("", css_classes=["status"], width=900)
        self.modes = pn.pane.HTML("", css_classes=["derived"], width=900)
        self.table = pn.pane.HTML("", css_classes=["table"], width=1100)
        self.select = pn.widgets.Select(name="attractor", options={"-": -1}, width=230,
                                        css_classes=["attractor-select"])
        self.plots = pn.GridBox(*(pn.pane.Bokeh(f) for f in _figures(None)), ncols=2)
        for w in self.fields.values():
            w.param.watch(self._changed, "value")
        self.select.param.watch(lambda e: self._draw(), "value")

    def layout(self):
        return pn.Column(f"## contactvib explore: the system {html.escape(self.label)}",
                         pn.Row(self.fields["pa"], self.fields["fe"]), self.modes, self.message, self.status,
                         "### Attractors", self.table, self.select, self.plots)

    async def _changed(self, event=None):
        await self.refresh()

    async def refresh(self):
        """Check the fields and search (the newest request wins)."""
        self.generation += 1
        mine = self.generation
        self.status.object = '<span class="busy">computing…</span>'
        fields = {k: w.value for k, w in self.fields.items()}
        kind, payload = await asyncio.get_running_loop().run_in_executor(
            _EXECUTOR, _compute, fields, self.ops, self.limit_s)
        if mine != self.generation:
            return
        if kind == "error":
            self.message.object = f'<b style="color:#b00" class="error">{html.escape(payload)}</b>'
            self.status.object, self.payload = "", None
            self.table.object = "<p>(no result for these values)</p>"
            self.select.options = {"-": -1}
            self._draw()
            return
        self.message.object, self.payload = "", payload
        system, result = payload["system"], payload["result"]
        self.modes.object = ("linear modes: " + ", ".join(f"{f:.4g}" for f in system.linear_modes()) + " Hz; "
                             f"coordinates {', '.join(system.coordinates)}; contacts "
                             f"{', '.join(c.name for c in system.contacts) or 'none'}")
        self.table.object = system_table_html(result, mine)
        opts = {f"#{i} period {a.period}": i for i, a in enumerate(result)} or {"-": -1}
        self.select.options = opts
        self.select.value = next(iter(opts.values()))
        self._draw()
        self.status.object = (f'<span class="done" data-request="{mine}" data-n="{len(result)}">'
                              f'{payload["level"]}, f_e = {payload["fe"]:g} Hz: {len(result)} attractors; '
                              f'search {payload["search_s"]:.2f} s</span>')

    def _draw(self):
        i = self.select.value
        hists = [] if self.payload is None else self.payload["hists"]
        hist = hists[i] if isinstance(i, int) and 0 <= i < len(hists) else None
        self.plots.objects = [pn.pane.Bokeh(f) for f in _figures(hist)]


def build_system_page(label: str, level_unit: str, fields: dict, ops, limit_s: float):
    """A new session's page (its first search scheduled), as the server asks for one."""
    page = SystemPage(label, level_unit, fields, ops, limit_s)
    pn.state.onload(page.refresh)
    return page.layout()
