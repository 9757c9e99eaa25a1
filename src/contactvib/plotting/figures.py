"""Figures in the paper's style (matplotlib only here; every function takes ``ax=None``).

Time history: y [µm] against t [ms], the equilibrium y0 dashed, the loss of contact (y < 0)
shaded. Phase portrait: ẏ [mm/s] against y [µm] (Kostek 2013, Figs. 4–9).
"""

from __future__ import annotations

import numpy as np

from contactvib.labels import label_family
from contactvib.plotting.style import order_colour
from contactvib.steady.results import Attractor, TimeHistory

__all__ = ["plot_time_history", "plot_phase_portrait", "attractor_figure", "resonance_graph", "save_figure",
           "history_figure", "new_figure",
           "extrema_diagram"]


def axes_or_new(ax, size=(6, 3.2)):
    """``ax``, or the axes of a new pyplot figure of ``size`` inches when None."""
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=size)
    return ax


def new_figure(nrows: int = 1, ncols: int = 1, figsize=(7.0, 4.2), **subplot_kw):
    """A figure and its axes array (squeeze=False) outside pyplot's state: for files, any backend,
    no need to close. ``subplot_kw`` goes to :meth:`matplotlib.figure.Figure.subplots`."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, squeeze=False, **subplot_kw)


def set_margins(fig, left: float, right: float, bottom: float, top: float, wspace: float = 0.2,
                hspace: float = 0.2):
    """Fixed subplot margins [inches] from the figure's edges (``wspace``, ``hspace`` as in
    :meth:`~matplotlib.figure.Figure.subplots_adjust`): for figures of a fixed design, what
    ``tight_layout`` would find, without its extra pass over every tick label (a quarter of the
    drawing time of ``contactvib paper``'s figures)."""
    w, h = fig.get_size_inches()
    fig.subplots_adjust(left=left / w, right=1.0 - right / w, bottom=bottom / h, top=1.0 - top / h,
                        wspace=wspace, hspace=hspace)


def mark_equilibrium_and_gap(ax, t_ms, y_um, y0_um: float, gap, engagement_um: float = 0.0) -> None:
    """On a y(t) panel: the equilibrium y0 dashed, the engagement point y = y_e thin (0 but for a
    law with a clearance), and the samples in flight (``gap``, boolean) shaded down from it
    (every time-history panel of the package)."""
    ax.axhline(y0_um, color="0.4", ls="--", lw=0.8, label="equilibrium $y_0$")
    ax.axhline(engagement_um, color="0.6", lw=0.6)
    if gap.any():
        lo = min(float(y_um.min()), engagement_um)
        ax.fill_between(t_ms, lo, engagement_um, where=gap, color="tab:red", alpha=0.15, step="mid",
                        label="loss of contact")


def plot_time_history(history: TimeHistory, ax=None, label: str | None = None):
    """y(t) [µm vs ms] with y0 marked and the gap (y < 0) shaded."""
    ax = axes_or_new(ax)
    ax.plot(history.t_ms, history.y_um, color="k", lw=1.0,
            label=label or ("contact deflection y (relative)" if history.base_um is not None else None))
    if history.base_um is not None:  # base motion: the slider's absolute motion and the base's
        ax.plot(history.t_ms, history.slider_um, color="tab:blue", lw=0.9, label="slider, absolute: s = y + u")
        ax.plot(history.t_ms, history.base_um, color="tab:green", lw=0.7, ls=":", label="base u(t)")
    mark_equilibrium_and_gap(ax, history.t_ms, history.y_um, history.y0_um, ~history.in_contact,
                             history.engagement_um)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("y [µm]" if history.base_um is None else "y, s, u [µm]")
    ax.legend(loc="best", fontsize=7, frameon=False)
    return ax


def plot_phase_portrait(history: TimeHistory, ax=None):
    """Phase portrait ẏ [mm/s] against y [µm]; the contact boundary y = y_e dotted (y_e = 0 but
    for a law with a clearance)."""
    ax = axes_or_new(ax)
    ax.plot(history.y_um, history.ydot_mm_s, color="k", lw=0.9)
    y_e = history.engagement_um
    ax.axvline(y_e, color="tab:red", ls=":", lw=0.8,
               label="y = 0 (contact boundary)" if y_e == 0.0 else f"y = {y_e:g} µm (contact boundary)")
    ax.plot([history.y0_um], [0.0], "+", color="0.3", ms=8, label="equilibrium")
    ax.set_xlabel("y [µm]")
    ax.set_ylabel("dy/dt [mm/s]")
    ax.legend(loc="best", fontsize=7, frameon=False)
    return ax


def history_figure(history: TimeHistory, title: str):
    """A two-panel figure: time history (left) and phase portrait (right) of one trajectory."""
    fig, axes = new_figure(1, 2, figsize=(11, 3.8), gridspec_kw={"width_ratios": [1.6, 1]})
    plot_time_history(history, axes[0, 0])
    plot_phase_portrait(history, axes[0, 1])
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def attractor_figure(history: TimeHistory, attractor: Attractor, title: str | None = None):
    """``history_figure`` of one attractor, titled with its period, minima and A_pp."""
    k = "non-periodic" if attractor.period is None else f"period {attractor.period}"
    n = attractor.minima_per_period
    mins = "" if n is None else f", {n} {'minimum' if n == 1 else 'minima'} per period"
    level = history.level or f"P_a = {history.pa_over_q:g} Q"
    sym, rest = level.split(" = ", 1)
    slider = ("" if attractor.slider_app_um is None
              else f" (slider, absolute: {attractor.slider_app_um:.4g} µm; base motion)")
    head = title or (f"${sym}$ = {rest}, $f_e$ = {history.fe_hz:g} Hz: {k}{mins}, "
                     f"$A_{{pp}}$ = {attractor.app_um:.4g} µm{slider}")
    return history_figure(history, head)


# ---------------------------------------------------------------- resonance graphs (Figs. 2, 3)


def level_title(ds, level: float) -> str:
    """A dataset level as a title writes it: "$P_a$ = 0.65 Q", or "$U$ = 0.05 µm" / "$A$ = 0.3 g"
    for a base-motion sweep (the dataset attribute ``excitation``); a model other than the paper's
    power law adds its law on a second line."""
    import json

    from contactvib.model import LEVEL_KINDS

    kind = str(ds.attrs.get("excitation", "force"))
    sym, unit, _name = LEVEL_KINDS.get(kind, LEVEL_KINDS["force"])
    sym = "P_a" if sym == "P_a/Q" else sym
    text = f"${sym}$ = {level:g} {'µm' if unit == 'um' else unit}"
    if kind != "force":
        text += " (base motion)"
    try:
        params = json.loads(ds.attrs.get("model", "{}"))
    except (ValueError, TypeError):
        params = {}
    own_law = bool({"law", "damping", "preload"} & set(params))  # keys only a model off the paper's family has
    return text + (f"\n{ds.attrs.get('law', '')}" if own_law else "")


def _level(ds, pa_over_q):
    """The indices of the points of the level ``pa_over_q`` (MissingLevel, a ValueError, when
    the dataset does not hold it)."""
    from contactvib.sweeps.stored import ResonanceData

    return ResonanceData(ds).points(pa_over_q)


def resonance_graph(ds, pa_over_q: float, ax=None, fn0_hz: float | None = None, m_max: int = 6,
                    annotate: bool = True, perturbation=None, marks_um: float | None = None):
    """A_pp [µm, log] against f_e [Hz] for one P_a level, one line per branch (Fig. 2).

    Colour = resonance order (main black, 1/m coloured; dashed after period doubling); thin grey
    = non-resonant (quasistatic) motion; dotted = sub-/ultrasubharmonic (bouncing) orbits; red
    dots = non-periodic attractors; gold underlay = branches no laboratory sweep reaches
    (``branch_reached_by_sweep`` = 0); plus signs at f_n0/m (Eq. 2.6) inside the level's f_e range. ``perturbation``:
    ``(fe_hz, app_um, valid)`` from :func:`contactvib.perturbation_curve`, drawn as
    red crosses where the series is valid. ``marks_um``: the height of the f_n0/m marks (default:
    just above the level's smallest amplitude).
    """

    ax = axes_or_new(ax)
    sel = _level(ds, pa_over_q)
    fe = ds["fe_hz"].values[sel]
    app = ds["app_um"].values[sel]
    br = ds["branch_index"].values[sel]
    kind = ds["kind"].values[sel]
    labels = ds["resonance"].values[sel]
    reach = (ds["branch_reached_by_sweep"].values if "branch_reached_by_sweep" in ds
             else np.ones(ds.sizes["branch"], np.int8))
    best: dict = {}
    isolated_drawn = False
    for b in np.unique(br):
        pts = np.nonzero(br == b)[0]
        pts = pts[np.argsort(fe[pts])]
        lab = str(labels[pts[0]])
        if kind[pts[0]] != "periodic":
            ax.plot(fe[pts], app[pts], ".", color="tab:red", ms=1.5, zorder=3)
            continue
        m, variant = label_family(lab)
        if m is None:
            style = dict(color="0.55", lw=0.6, ls=":") if lab != "non-resonant" else dict(color="0.35", lw=0.8)
        else:
            style = dict(color=order_colour(m), lw=1.1 if not variant else 0.9,
                         ls="-" if not variant else "--")
        # split at grid gaps so that a branch is never drawn across a hole
        gaps = np.nonzero(np.diff(fe[pts]) > 1.5 * np.min(np.diff(np.unique(fe))) if fe.size > 1 else [])[0]
        for seg in np.split(pts, gaps + 1):
            ax.plot(fe[seg], app[seg], **style)
            if m is not None and not reach[b]:  # a sweep never reaches it (Sec. 3: isolated part)
                ax.plot(fe[seg], app[seg], color="gold", lw=4.5, alpha=0.55, zorder=0,
                        solid_capstyle="round",
                        label=None if isolated_drawn else "isolated: not reached by sweeps")
                isolated_drawn = True
        if m is not None and not variant:
            j = pts[np.argmax(app[pts])]
            if m not in best or app[j] > best[m][1]:
                best[m] = (fe[j], app[j])
    if annotate:
        for m, (f, a) in best.items():
            ax.annotate("main" if m == 1 else f"1/{m}", (f, a), xytext=(2, 3),
                        textcoords="offset points", fontsize=7, color=order_colour(m))
    fn0 = fn0_hz if fn0_hz is not None else float(ds.attrs["fn0_hz"])
    ax.set_yscale("log")
    lo = max(np.nanmin(app[app > 0]) * 0.5, 1e-3) if np.any(app > 0) else 1e-3
    marks = [fn0 / m for m in range(1, m_max + 1)]
    if fe.size:  # only the marks inside the level's frequency range (a narrow sweep keeps its axis)
        marks = [f for f in marks if np.nanmin(fe) <= f <= np.nanmax(fe)]
    mark_y = lo * 1.3 if marks_um is None else marks_um
    ax.plot(marks, [mark_y] * len(marks), "+", color="k", ms=7, mew=1.0, label="$f_{n0}/m$ (Eq. 2.6)")
    if perturbation is not None:
        pf, pa_app, ok = (np.asarray(x) for x in perturbation)
        ax.plot(pf[ok], pa_app[ok], "x", color="tab:red", ms=3.5, mew=0.8,
                label="perturbation series (where valid)")
    ax.plot([], [], color="0.3", lw=1.1, label="period 1 (colour: order m)")
    ax.plot([], [], color="0.3", lw=0.9, ls="--", label="period-k (doubled, windows)")
    ax.plot([], [], color="0.55", lw=0.6, ls=":", label="sub-/ultrasubharmonic bouncing")
    ax.plot([], [], ".", color="tab:red", ms=3, label="non-periodic")
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("$A_{pp}$ [µm]")
    ax.set_title(level_title(ds, pa_over_q), fontsize=9)
    ax.legend(loc="upper right", fontsize=7, frameon=False)
    return ax


def extrema_diagram(ds, pa_over_q: float, ax=None, linthresh_um: float = 1.0):
    """Local extrema of y(t) [µm] against f_e [Hz] for one P_a level (Fig. 3).

    Minima grey, maxima black, the extrema of sub-/ultrasubharmonic bouncing orbits light blue;
    the y axis is linear within ±``linthresh_um`` and logarithmic
    beyond (symlog), so the small superharmonic loops and the large main-resonance orbits show
    together; y < 0 is loss of contact. For a law with a clearance (the dataset's attribute
    ``engagement_um`` = y_e) the extrema are drawn as the contact deflection y − y_e, so that
    the symlog axis is centred where the contact engages.
    """

    ax = axes_or_new(ax)
    sel = _level(ds, pa_over_q)
    fe = ds["fe_hz"].values[sel]
    e0 = ds["extrema_start"].values[sel]
    ne = ds["extrema_count"].values[sel]
    idx = np.concatenate([np.arange(a, a + n) for a, n in zip(e0, ne)]) if sel.size else np.array([], int)
    f_rep = np.repeat(fe, ne)
    bouncing = np.repeat([str(x).startswith(("subharmonic", "ultrasubharmonic"))
                          for x in ds["resonance"].values[sel]], ne)
    y_e = float(ds.attrs.get("engagement_um", 0.0))
    y = ds["extremum_y_um"].values[idx] - y_e if y_e else ds["extremum_y_um"].values[idx]
    is_min = ds["extremum_is_min"].values[idx].astype(bool)
    ax.plot(f_rep[bouncing], y[bouncing], ",", color="#9ecae1", rasterized=True)
    ax.plot(f_rep[is_min & ~bouncing], y[is_min & ~bouncing], ",", color="0.55", rasterized=True)
    ax.plot(f_rep[~is_min & ~bouncing], y[~is_min & ~bouncing], ",", color="k", rasterized=True)
    ax.plot([], [], "s", color="0.55", ms=4, label="minima")
    ax.plot([], [], "s", color="k", ms=4, label="maxima")
    ax.plot([], [], "s", color="#9ecae1", ms=4, label="bouncing orbits (not in the paper)")
    ax.axhline(0.0, color="tab:red", lw=0.5, ls=":")
    ax.set_yscale("symlog", linthresh=linthresh_um)
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("local extrema of y [µm]" if not y_e else f"local extrema of y − y_e [µm] (y_e = {y_e:g} µm)")
    ax.set_title(level_title(ds, pa_over_q), fontsize=9)
    ax.legend(loc="upper right", fontsize=7, frameon=False, markerscale=1)
    return ax


def figure_bytes(fig, fmt: str = "png", dpi: int = 130) -> bytes:
    """``fig`` as the bytes of a ``fmt`` file ("png", "svg", "pdf"), e.g. for a download."""
    import io

    buf = io.BytesIO()
    fig.savefig(buf, format=fmt, dpi=dpi)
    return buf.getvalue()


def save_figure(fig, path, dpi: int = 130):
    """Write ``fig`` to ``path`` (format from the suffix) and release it; returns the path."""
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=dpi)
    plt.close(fig)  # a pyplot figure is dropped from pyplot's list; others are left to the GC
    return path
