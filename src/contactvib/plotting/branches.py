"""Figures of branches (matplotlib only here; every function takes ``ax=None``).

Resonance graph: A_pp [µm, log axis] against f_e [Hz]; stable solid, unstable dashed, one colour
per period; special points marked. Evolution: fold and period-doubling curves in (f_e, P_a).
"""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import axes_or_new
from contactvib.plotting.style import branch_period_colour

__all__ = ["plot_branches", "plot_evolution", "branches_figure", "branches_over_dataset_figure",
           "evolution_figure"]

_MARKERS = {"fold": ("o", "tab:red"), "period-doubling": ("s", "tab:orange"),
            "neimark-sacker": ("D", "tab:pink"), "grazing": ("v", "0.45")}


def _runs(mask):
    """(start, stop) index pairs of the runs of equal values in a boolean array."""
    edges = np.nonzero(np.diff(mask.astype(int)))[0] + 1
    starts = np.concatenate([[0], edges])
    stops = np.concatenate([edges, [mask.size]])
    return list(zip(starts, stops))


def plot_branches(branches, ax=None, title: str | None = None, specials=True,
                  parameter: str = "f_e", ylabel: str | None = None):
    """A_pp against f_e (or P_a [Q], ``parameter="P_a"``, or P_a [N] of a system branch,
    ``"P_a_newton"``) for every branch; stable solid, unstable dashed, special points marked;
    ``ylabel`` names the amplitude (default the slider's A_pp [µm])."""
    from matplotlib.lines import Line2D

    ax = axes_or_new(ax, (7.5, 4.5))
    periods = set()
    for b in branches:
        if len(b) == 0:
            continue
        c = branch_period_colour(b.period)
        periods.add(b.period)
        for i0, i1 in _runs(b.stable):
            j1 = min(i1 + 1, len(b))  # join the runs
            q = _parameter_values(b, parameter)
            ax.plot(q[i0:j1], b.app_um[i0:j1], color=c, lw=1.2 if b.stable[i0] else 0.9,
                    ls="-" if b.stable[i0] else "--")
    used = set()
    if specials:
        for b in branches:
            for sp in b.special:
                m, c = _MARKERS[sp.type]
                q = _parameter_values(sp, parameter)
                ax.plot(q, sp.app_um, m, color=c, ms=5, mfc="none" if sp.type == "grazing" else c,
                        zorder=5)
                used.add(sp.type)
    ax.set_yscale("log")
    ax.set_xlabel({"f_e": "excitation frequency $f_e$ [Hz]", "P_a": "excitation amplitude $P_a$ [Q = Mg]",
                   "P_a_newton": "excitation amplitude $P_a$ [N]"}[parameter])
    ax.set_ylabel(ylabel or "peak-to-peak amplitude $A_{pp}$ [µm]")
    handles = [Line2D([], [], color="k", ls="-", label="stable"),
               Line2D([], [], color="k", ls="--", label="unstable")]
    handles += [Line2D([], [], color=branch_period_colour(k), label=f"period {k}")
                for k in sorted(periods) if k != 1]
    handles += [Line2D([], [], ls="none", marker=_MARKERS[t][0], color=_MARKERS[t][1],
                       mfc="none" if t == "grazing" else _MARKERS[t][1], label=t)
                for t in ("fold", "period-doubling", "neimark-sacker", "grazing") if t in used]
    ax.legend(handles=handles, fontsize=7, frameon=False, loc="best")
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", lw=0.3, color="0.85")
    return ax


def _parameter_values(obj, parameter: str):
    """The abscissa of a branch or special point: f_e [Hz], P_a [Q] or P_a [N]."""
    return getattr(obj, {"f_e": "fe_hz", "P_a": "pa_over_q", "P_a_newton": "pa_newton"}[parameter])


def plot_evolution(result, ax=None, title: str | None = None):
    """Fold and period-doubling curves of a 1/m resonance in the (f_e, P_a) plane."""
    from matplotlib.lines import Line2D

    ax = axes_or_new(ax, (7.0, 4.5))
    styles = {"fold": ("tab:red", "-"), "period-doubling": ("tab:orange", "--")}
    for curve in result.curves:
        c, ls = styles[curve.type]
        ax.plot(curve.fe_hz, curve.pa_over_q, color=c, ls=ls, lw=1.2)
    for sp in result.points:
        m, c = _MARKERS[sp.type]
        ax.plot(sp.fe_hz, sp.pa_over_q, m, color=c, ms=4)
    for name, (f, p) in result.extremes.items():
        ax.plot(f, p, "*", color="k", ms=9)
        ax.annotate(name, (f, p), textcoords="offset points", xytext=(5, -10), fontsize=7)
    ax.set_xlabel("excitation frequency $f_e$ [Hz]")
    ax.set_ylabel("excitation amplitude $P_a$ [Q]")
    handles = [Line2D([], [], color="tab:red", label="fold curve"),
               Line2D([], [], color="tab:orange", ls="--", label="period-doubling curve"),
               Line2D([], [], ls="none", marker="o", color="tab:red", label="fold (one-parameter)"),
               Line2D([], [], ls="none", marker="s", color="tab:orange", label="period doubling (one-parameter)"),
               Line2D([], [], ls="none", marker="*", color="k", label="onset (lowest $P_a$)")]
    ax.legend(handles=handles, fontsize=7, frameon=False, loc="best")
    if title:
        ax.set_title(title, fontsize=10)
    ax.grid(True, lw=0.3, color="0.85")
    return ax


def branches_figure(branches, title: str, parameter: str = "f_e", ylabel: str | None = None):
    """A figure of :func:`plot_branches` (A_pp against f_e, or P_a with ``parameter="P_a"``
    [Q] or ``"P_a_newton"`` [N])."""
    from contactvib.plotting.figures import new_figure

    fig, axes = new_figure(figsize=(7.5, 4.6))
    plot_branches(branches, axes[0, 0], title=title, parameter=parameter, ylabel=ylabel)
    fig.tight_layout()
    return fig


def branches_over_dataset_figure(branches, ds, pa_over_q: float, title: str):
    """Continued branches (stable solid, unstable dashed) over a sweep's resonance graph of the
    same P_a (drawn faint)."""
    from contactvib.plotting.figures import new_figure, resonance_graph

    fig, axes = new_figure(figsize=(8.0, 5.0))
    ax = axes[0, 0]
    resonance_graph(ds, pa_over_q, ax=ax, annotate=False)
    for line in ax.lines:
        line.set_alpha(0.45)
    plot_branches(branches, ax, title=f"{title}, over the sweep's attractors (faint)")
    fig.tight_layout()
    return fig


def evolution_figure(result, title: str):
    """A figure of :func:`plot_evolution`."""
    from contactvib.plotting.figures import new_figure

    fig, axes = new_figure(figsize=(7, 4.5))
    plot_evolution(result, axes[0, 0], title=title)
    fig.tight_layout()
    return fig
