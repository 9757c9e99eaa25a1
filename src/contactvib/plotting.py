"""Figures in the paper's style (matplotlib only here; every function takes ``ax=None``).

Time history: y [µm] against t [ms], the equilibrium y0 dashed, the loss of contact (y < 0)
shaded. Phase portrait: ẏ [mm/s] against y [µm] (Kostek 2013, Figs. 4–9).
"""

from __future__ import annotations

import numpy as np

from .results import Attractor, TimeHistory

__all__ = ["plot_time_history", "plot_phase_portrait", "attractor_figure"]


def _ax(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6, 3.2))
    return ax


def plot_time_history(history: TimeHistory, ax=None, label: str | None = None):
    """y(t) [µm vs ms] with y0 marked and the gap (y < 0) shaded."""
    ax = _ax(ax)
    ax.plot(history.t_ms, history.y_um, color="k", lw=1.0, label=label)
    ax.axhline(history.y0_um, color="0.4", ls="--", lw=0.8, label="equilibrium $y_0$")
    ax.axhline(0.0, color="0.6", lw=0.6)
    gap = ~history.in_contact
    if gap.any():
        lo = min(float(history.y_um.min()), 0.0)
        ax.fill_between(history.t_ms, lo, 0.0, where=gap, color="tab:red", alpha=0.15,
                        step="mid", label="loss of contact")
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("y [µm]")
    ax.legend(loc="best", fontsize=7, frameon=False)
    return ax


def plot_phase_portrait(history: TimeHistory, ax=None):
    """Phase portrait ẏ [mm/s] against y [µm]; the contact boundary y = 0 dotted."""
    ax = _ax(ax)
    ax.plot(history.y_um, history.ydot_mm_s, color="k", lw=0.9)
    ax.axvline(0.0, color="tab:red", ls=":", lw=0.8, label="y = 0 (contact boundary)")
    ax.plot([history.y0_um], [0.0], "+", color="0.3", ms=8, label="equilibrium")
    ax.set_xlabel("y [µm]")
    ax.set_ylabel("dy/dt [mm/s]")
    ax.legend(loc="best", fontsize=7, frameon=False)
    return ax


def attractor_figure(history: TimeHistory, attractor: Attractor, title: str | None = None):
    """A two-panel figure (time history, phase portrait) for one attractor."""
    import matplotlib.pyplot as plt

    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.8), gridspec_kw={"width_ratios": [1.6, 1]})
    plot_time_history(history, a1)
    plot_phase_portrait(history, a2)
    k = "non-periodic" if attractor.period is None else f"period {attractor.period}"
    n = attractor.minima_per_period
    mins = "" if n is None else f", {n} {'minimum' if n == 1 else 'minima'} per period"
    head = title or (f"$P_a$ = {history.pa_over_q:g} Q, $f_e$ = {history.fe_hz:g} Hz: {k}{mins}, "
                     f"$A_{{pp}}$ = {attractor.app_um:.4g} µm")
    fig.suptitle(head, fontsize=10)
    fig.tight_layout()
    return fig
