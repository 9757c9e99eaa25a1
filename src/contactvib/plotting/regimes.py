"""Regime maps over (f_e [Hz], P_a [Q]): one panel per quantity of
:func:`contactvib.sweeps.regimes.regime_maps`, with its colour bar (discrete for counts, orders,
periods and chaos, sequential for the contact-loss share and the friction ratios) and the fold (solid) and
period-doubling (dashed) curves of the 1/m resonances on top, coloured by m as in the resonance
graphs."""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import axes_or_new, new_figure
from contactvib.plotting.style import order_colour

__all__ = ["plot_regime_map", "regime_figure", "PANEL_TITLES"]

#: Title and colour-bar label of each map.
PANEL_TITLES = {
    "n_attractors": ("Coexisting attractors", "number of attractors"),
    "max_order": ("Highest resonance order present", "highest m of the 1/m labels (1 = main, 0 = none)"),
    "contact_loss_share": ("Attractors that lose contact", "share of the attractors with y < 0"),
    "chaotic": ("Chaos", "chaotic attractor present (λ > 0)"),
    "max_period": ("Largest period", "largest period [excitation periods]"),
    "max_lambda1": ("Largest Lyapunov exponent", "largest λ1 of the attractors [1/excitation period]"),
    "friction_ratio_min": ("Lowest friction ratio", "lowest <F_drive>/(μ W) of the attractors"),
    "friction_ratio_max": ("Highest friction ratio", "highest <F_drive>/(μ W) of the attractors"),
}


def _edges(c: np.ndarray, single: float) -> np.ndarray:
    """Cell edges around the centres ``c`` (midpoints; the ends half a neighbouring gap out;
    ``single`` either side of a lone centre)."""
    if c.size == 1:
        return np.array([c[0] - single, c[0] + single])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _discrete(values: np.ndarray, cmap_name: str):
    """(cmap, norm, ticks) of integer values: one colour per integer from the smallest to the
    largest present (grey for −1: no attractor stored)."""
    from matplotlib import colormaps
    from matplotlib.colors import BoundaryNorm, ListedColormap

    v = values[values >= 0]
    lo, hi = (int(v.min()), int(v.max())) if v.size else (0, 1)
    if np.any(values < 0):  # grey at -1, then every integer from 0: the bins stay contiguous
        lo = min(lo, 0)
    hi = max(hi, lo + 1)
    base = colormaps[cmap_name].resampled(hi - lo + 1)
    colours = [base(i) for i in range(hi - lo + 1)]
    start = lo
    if np.any(values < 0):
        colours, start = ["0.75", *colours], -1
    bounds = np.arange(start - 0.5, hi + 1.0)
    step = max(1, int(np.ceil((hi - start + 1) / 12)))
    return ListedColormap(colours), BoundaryNorm(bounds, len(colours)), np.arange(start, hi + 1, step)


def _curve_style(curve):
    return {"color": order_colour(curve.order), "ls": "-" if curve.type == "fold" else (0, (4, 2)), "lw": 2.0}


def _draw_curves(ax, curves):
    """The curves on ``ax`` with a white halo; one legend entry per (order, type)."""
    import matplotlib.patheffects as pe

    seen = set()
    for c in sorted(curves, key=lambda c: (c.order, c.type)):
        key = (c.order, c.type)
        label = None if key in seen else f"1/{c.order} {c.type}"
        seen.add(key)
        ax.plot(c.fe_hz, c.pa_over_q, label=label, zorder=3,
                path_effects=[pe.Stroke(linewidth=3.6, foreground="w"), pe.Normal()], **_curve_style(c))
    if seen:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), fontsize=8, frameon=False,
                  ncol=min(len(seen), 5), title="two-parameter continuation (fold: solid, period doubling: dashed)",
                  title_fontsize=8)


def plot_regime_map(maps, name: str, curves=(), ax=None, log_f: bool = True):
    """The map ``name`` (one of :data:`PANEL_TITLES`) over f_e [Hz] × P_a [Q] with its colour
    bar, the fold and period-doubling ``curves`` (:class:`~contactvib.sweeps.regimes.MapCurve`)
    on top, and ticks at the dataset's levels on the right-hand axis."""
    ax = axes_or_new(ax, (9.0, 4.6))
    fe = maps["fe_hz"].values
    pa = maps["pa_over_q"].values
    z = maps[name].values
    df = float(maps.attrs.get("df_hz", np.nan))
    fx = _edges(fe, 0.5 * df if np.isfinite(df) else 0.5)
    py = _edges(pa, 0.025)
    title, cbar_label = PANEL_TITLES[name]
    if name in ("contact_loss_share", "friction_ratio_min", "friction_ratio_max"):
        from matplotlib import colormaps

        cmap = colormaps["viridis" if name == "contact_loss_share" else "magma"].with_extremes(bad="0.75")
        mesh = ax.pcolormesh(fx, py, np.ma.masked_invalid(z), cmap=cmap, vmin=0.0, vmax=1.0, rasterized=True)
        cbar = ax.figure.colorbar(mesh, ax=ax, pad=0.02)
    elif name == "max_lambda1":  # diverging about λ1 = 0: red chaotic, blue strongly contracting
        from matplotlib import colormaps
        from matplotlib.colors import TwoSlopeNorm

        finite = z[np.isfinite(z)]
        lo = min(float(finite.min()), -1e-3) if finite.size else -1.0
        hi = max(float(finite.max()), 1e-3) if finite.size else 1.0
        mesh = ax.pcolormesh(fx, py, np.ma.masked_invalid(z), cmap=colormaps["RdBu_r"].with_extremes(bad="0.75"),
                             norm=TwoSlopeNorm(0.0, lo, hi), rasterized=True)
        cbar = ax.figure.colorbar(mesh, ax=ax, pad=0.02)
    else:
        cmap, norm, ticks = _discrete(z, {"chaotic": "Reds", "max_order": "turbo"}.get(name, "viridis"))
        if name == "chaotic":
            cmap, norm, ticks = _discrete(np.array([0, 1]), "Reds")
        mesh = ax.pcolormesh(fx, py, z, cmap=cmap, norm=norm, rasterized=True)
        cbar = ax.figure.colorbar(mesh, ax=ax, pad=0.02, ticks=ticks)
        if name == "chaotic":
            cbar.ax.set_yticklabels(["no", "yes"])
        elif np.any(z < 0):
            cbar.ax.set_yticklabels(["none"] + [str(t) for t in ticks[1:]])
    cbar.set_label(cbar_label)
    _draw_curves(ax, curves)
    if log_f and fx[0] > 0:
        from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

        ax.set_xscale("log")
        ticks = [t * 10.0 ** k for k in range(-1, 6) for t in (1, 2, 5)]
        ax.xaxis.set_major_locator(FixedLocator([t for t in ticks if fx[0] <= t <= fx[-1]] or ticks))
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlim(fx[0], fx[-1])
    ax.set_ylim(py[0], py[-1])
    ax.set_xlabel("excitation frequency $f_e$ [Hz]")
    ax.set_ylabel(_level_axis(maps))
    ax.set_title(title)
    ax.set_yticks(pa if pa.size <= 12 else ax.get_yticks())
    return ax


def _level_axis(maps) -> str:
    """The y label of the levels: P_a [Q] (a system's dataset: [Q] or [N]), or the base motion's
    U [µm] / A [g]."""
    kind = maps.attrs.get("excitation", "force")
    if "system" in maps.attrs:
        return f"excitation amplitude $P_a$ [{maps.attrs.get('level_unit', 'Q')}]"
    if kind == "base-um":
        return "base displacement amplitude $U$ [µm]"
    if kind == "base-g":
        return "base acceleration amplitude $A$ [g]"
    return "excitation amplitude $P_a$ [Q]"


def regime_figure(maps, name: str, curves=(), title: str | None = None):
    """A figure of one map (:func:`plot_regime_map`), titled with the grid."""
    fig, axes = new_figure(1, 1, figsize=(10.0, 4.8))
    fig.set_layout_engine("constrained")  # the colour bar and the legend below take their room
    ax = plot_regime_map(maps, name, curves, axes[0, 0])
    nl, nf = maps.sizes["pa_over_q"], maps.sizes["fe_hz"]
    sym = maps.attrs.get("level_symbol", "P_a").replace("P_a/Q", "P_a")
    ax.set_title(title or f"{PANEL_TITLES[name][0]}: {nl} levels of ${sym}$ × {nf} frequencies "
                          f"(step {maps.attrs.get('df_hz', float('nan')):g} Hz)", fontsize=11)
    return fig
