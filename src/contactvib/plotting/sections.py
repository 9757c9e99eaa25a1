"""Poincaré sections, impact maps and orbit diagrams.

- :func:`plot_section`: every attractor's stroboscopic points (y [µm], ẏ [mm/s] at t = k/f_e),
  a period-k orbit as its k points (large markers), a non-periodic attractor as its cloud;
- :func:`plot_impact_map`: the states at each contact loss (excitation phase [fraction of the
  period], ẏ [mm/s]);
- :func:`plot_orbit_diagram`: stroboscopic y (or ẏ at contact loss) against f_e or P_a, each point
  coloured by λ1 [1/period] with a colour bar (turbo, two slopes about 0: blue contracting, green
  λ1 ≈ 0 (a bifurcation or quasi-periodic motion), red chaotic).
"""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import axes_or_new, new_figure
from contactvib.plotting.style import label_colours

__all__ = ["plot_section", "plot_impact_map", "section_figure", "plot_orbit_diagram", "orbit_diagram_figure",
           "LAMBDA_LABEL"]

#: The colour bar's label of λ1.
LAMBDA_LABEL = "λ1 [1/period]"
_MARKERS = ("o", "s", "D", "^", "v", "P", "X", "*", "h", "<", ">")


def _style(i: int, section, colour):
    if section.period is not None:
        return {"marker": _MARKERS[i % len(_MARKERS)], "ms": 8, "mfc": colour, "mec": "k", "mew": 1.0, "ls": "none",
                "zorder": 3}
    return {"marker": ".", "ms": 2.0, "color": colour, "ls": "none", "zorder": 2, "rasterized": True}


def _count(n: int, one: str, many: str) -> str:
    return f"{n} {one if n == 1 else many}"


def _level_tex(level: str) -> str:
    """``"P_a = 0.75 Q"`` with the symbol in math text."""
    sym, _, rest = level.partition(" = ")
    return f"${sym}$ = {rest}" if rest else level


def _legend_text(i: int, section) -> str:
    return f"#{i} {section.label}, λ1 = {section.lambda1:.3g}/period"


def plot_section(sections, ax=None, legend: bool = True):
    """The stroboscopic section of every attractor of a :class:`~contactvib.SectionSet`."""
    ax = axes_or_new(ax, (6.5, 5.0))
    colours = label_colours(len(sections))
    for i, s in enumerate(sections):
        ax.plot(s.y_um, s.ydot_mm_s, label=_legend_text(s.index, s), **_style(i, s, colours[i]))
    ax.axvline(0.0, color="0.6", lw=0.8, ls=":", zorder=1)
    ax.set_xlabel("y at t = k/$f_e$ [µm] (y > 0: contact deflection)")
    ax.set_ylabel("dy/dt at t = k/$f_e$ [mm/s]")
    ax.set_title("stroboscopic section", fontsize=10)
    if legend:
        ax.legend(fontsize=8, loc="best", markerscale=1.0, title="attractor: stroboscopic points", title_fontsize=8)
    return ax


def plot_impact_map(sections, ax=None, legend: bool = False):
    """The impact map: excitation phase at each contact loss [fraction of the period] against the
    velocity there [mm/s], every attractor that loses contact."""
    ax = axes_or_new(ax, (6.5, 5.0))
    colours = label_colours(len(sections))
    for i, s in enumerate(sections):
        if s.loss_phase_rad.size:
            text = f"#{s.index}: {_count(s.loss_phase_rad.size, 'loss', 'losses')}"
            ax.plot(s.loss_phase_fraction, s.loss_ydot_mm_s, label=text, **_style(i, s, colours[i]))
    ax.set_xlim(0.0, 1.0)
    ax.set_xlabel("excitation phase at contact loss [fraction of the period]")
    ax.set_ylabel("dy/dt at contact loss [mm/s]")
    ax.set_title("impact map (contact losses)", fontsize=10)
    if legend:
        ax.legend(fontsize=8, loc="best")
    return ax


def section_figure(sections, impacts: bool = False, title: str | None = None):
    """The section (and with ``impacts`` the impact map beside it) of a ``SectionSet``."""
    fig, axes = new_figure(1, 2 if impacts else 1, figsize=(12.5, 5.2) if impacts else (7.5, 5.6))
    plot_section(sections, axes[0, 0])
    if impacts:
        plot_impact_map(sections, axes[0, 1], legend=True)
    fig.suptitle(title or (f"Poincaré section at {_level_tex(sections.level)}, $f_e$ = {sections.fe_hz:g} Hz "
                           f"({sections.n_periods} periods per non-periodic attractor)"), fontsize=11)
    fig.tight_layout()
    return fig


def _norm(lam: np.ndarray):
    """A diverging norm about λ1 = 0 over the finite values (at least ±0.01/period)."""
    from matplotlib.colors import TwoSlopeNorm

    finite = lam[np.isfinite(lam)]
    lo = min(float(finite.min()) if finite.size else -0.01, -0.01)
    hi = max(float(finite.max()) if finite.size else 0.01, 0.01)
    return TwoSlopeNorm(vmin=lo, vcenter=0.0, vmax=hi)


def plot_orbit_diagram(ds, measure: str = "y", ax=None, colorbar: bool = True):
    """The orbit diagram of :func:`contactvib.orbit_diagram`: stroboscopic y
    (``measure`` ``"y"``) or ẏ at contact loss (``"v-loss"``) against the varied parameter, coloured
    by λ1."""
    ax = axes_or_new(ax, (8.0, 5.0))
    vary = ds.attrs.get("vary", "fe")
    if measure == "y":
        x = ds["fe_hz" if vary == "fe" else "pa_over_q"].values
        y, lam = ds["y_um"].values, ds["lambda1"].values
        ax.set_ylabel("y at t = k/$f_e$ [µm] (y > 0: contact deflection)")
    else:
        x = ds["loss_fe_hz" if vary == "fe" else "loss_pa_over_q"].values
        y, lam = ds["v_loss_mm_s"].values, ds["loss_lambda1"].values
        ax.set_ylabel("dy/dt at contact loss [mm/s]")
    order = np.argsort(np.nan_to_num(lam, nan=-np.inf), kind="stable")  # chaotic points on top
    sc = ax.scatter(x[order], y[order], c=lam[order], s=3.0, cmap="turbo", norm=_norm(lam), linewidths=0,
                    rasterized=True)
    ax.set_xlabel("excitation frequency $f_e$ [Hz]" if vary == "fe" else "excitation amplitude $P_a$ [Q]")
    if colorbar:
        ax.figure.colorbar(sc, ax=ax, label=LAMBDA_LABEL, pad=0.02)
    return ax


def orbit_diagram_figure(ds, measure: str = "y", title: str | None = None):
    """A figure of :func:`plot_orbit_diagram`, titled with the fixed parameter and the grid."""
    fig, axes = new_figure(1, 1, figsize=(9.0, 5.4))
    plot_orbit_diagram(ds, measure, axes[0, 0])
    fixed = ds.attrs.get("fixed", float("nan"))
    what = f"$P_a$ = {fixed:g} Q" if ds.attrs.get("vary", "fe") == "fe" else f"$f_e$ = {fixed:g} Hz"
    n_grid = int(ds["grid_index"].max()) + 1 if ds.sizes.get("point", 0) else 0
    fig.suptitle(title or (f"Orbit diagram at {what}: every attractor followed over {n_grid} grid points "
                           f"(colour: largest Lyapunov exponent λ1)"), fontsize=11)
    fig.tight_layout()
    return fig
