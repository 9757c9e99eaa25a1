"""Figures for the perturbation series and harmonic balance (matplotlib; functions take ax=None).

* :func:`overlay_figure` — series against the numerical steady state: time history and phase
  portrait (as Kostek 2013, Figs. 4g, 5a, 9a). An invalid series is not drawn; the figure says
  why.
* :func:`plot_convergence` — |A_pp error| against the number of terms N (plain and Padé sums).
* :func:`plot_branch` — HB branch A_pp against f_e, stable solid, unstable dashed.
"""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import axes_or_new, new_figure
from contactvib.steady.results import TimeHistory

__all__ = ["overlay_figure", "plot_convergence", "plot_branch", "convergence_figure", "hbm_figure"]


def overlay_figure(numeric: TimeHistory, series: TimeHistory | None, title: str, note: str = ""):
    """Two panels: y(t) and ẏ(y) of the numerics (black) and the series (red dashed) if given."""
    fig, axes = new_figure(1, 2, figsize=(11, 3.8), gridspec_kw={"width_ratios": [1.6, 1]})
    a1, a2 = axes[0]
    a1.plot(numeric.t_ms, numeric.y_um, color="k", lw=1.2, label="numerical (shooting)")
    a2.plot(numeric.y_um, numeric.ydot_mm_s, color="k", lw=1.2, label="numerical (shooting)")
    if series is not None:
        a1.plot(series.t_ms, series.y_um, color="tab:red", ls="--", lw=1.2, label="perturbation")
        a2.plot(series.y_um, series.ydot_mm_s, color="tab:red", ls="--", lw=1.2,
                label="perturbation")
    a1.axhline(numeric.y0_um, color="0.5", ls=":", lw=0.8, label="equilibrium $y_0$")
    a2.plot([numeric.y0_um], [0.0], "+", color="0.3", ms=8, label="equilibrium")
    if note:
        a1.text(0.01, 0.02, note, transform=a1.transAxes, fontsize=8, color="tab:red", va="bottom")
    a1.set_xlabel("t [ms]")
    a1.set_ylabel("y [µm]")
    a2.set_xlabel("y [µm]")
    a2.set_ylabel("dy/dt [mm/s]")
    a1.legend(loc="upper right", fontsize=7, frameon=False)
    a2.legend(loc="best", fontsize=7, frameon=False)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def plot_convergence(rows_by_label: dict, ax=None):
    """Relative A_pp error (solid) and estimate (dotted) against N, one colour per summation.

    ``rows_by_label`` maps a label to rows ``(N, A_pp, rel_error, estimate_um, valid)`` and
    the reference A_pp is implied by the rows (estimate / A_pp is drawn).
    """
    ax = axes_or_new(ax)
    for (label, rows), colour in zip(rows_by_label.items(), ["tab:blue", "tab:red", "tab:green"]):
        rows = np.array([(n, a, e, est) for n, a, e, est, _v in rows], float)
        err = np.maximum(rows[:, 2], 1e-16)
        ax.semilogy(rows[:, 0], err, "o-", ms=3, color=colour, label=f"{label}: |error| of A_pp")
        est = rows[:, 3] / rows[:, 1]
        ok = np.isfinite(est)
        ax.semilogy(rows[ok, 0], est[ok], ":", color=colour, label=f"{label}: estimate")
    ax.axhline(1e-3, color="0.5", lw=0.8, ls="--", label="validity limit 1e-3")
    ax.set_xlabel("number of terms N")
    ax.set_ylabel("relative A_pp error [1]")
    ax.legend(loc="best", fontsize=7, frameon=False)
    return ax


def plot_branch(branch, ax=None, label: str = "HB branch", colour: str = "k"):
    """A_pp [µm] against f_e [Hz]: stable solid, unstable dashed, contact loss marked."""
    ax = axes_or_new(ax)
    f, a, s = branch.fe_hz, branch.app_um, branch.stable
    # split into runs of equal stability so that each run is one line
    start = 0
    first_s = first_u = True
    for i in range(1, f.size + 1):
        if i == f.size or s[i] != s[start]:
            seg = slice(start, min(i + 1, f.size))
            stable = bool(s[start])
            lab = None
            if stable and first_s:
                lab, first_s = f"{label}, stable", False
            elif not stable and first_u:
                lab, first_u = f"{label}, unstable", False
            ax.plot(f[seg], a[seg], color=colour, ls="-" if stable else "--", lw=1.2, label=lab)
            start = i
    lost = branch.loses_contact
    if lost.any():
        ax.plot(f[lost], a[lost], ".", color=colour, ms=2.5, alpha=0.5)
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel("$A_{pp}$ [µm]")
    ax.set_yscale("log")
    return ax


def convergence_figure(rows_by_label: dict, title: str):
    """A figure of :func:`plot_convergence`."""
    fig, axes = new_figure(figsize=(6, 3.8))
    plot_convergence(rows_by_label, axes[0, 0])
    axes[0, 0].set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


_BRANCH_COLOURS = ["k", "tab:blue", "tab:green", "tab:purple", "tab:orange", "tab:brown", "tab:olive"]


def hbm_figure(branches, series, fn0_hz: float, f_range, title: str):
    """Harmonic-balance branches A_pp(f_e) (stable solid, unstable dashed, dots for loss of
    contact), the valid perturbation points ``series = (fe_hz, app_um)`` as circles, and f_n0/m
    marked. ``branches``: (label, HBBranch) pairs; ``f_range``: (f_min, f_max) [Hz]."""
    fig, axes = new_figure(figsize=(8, 4.2))
    ax = axes[0, 0]
    for i, (label, b) in enumerate(branches):
        plot_branch(b, ax, label=label, colour=_BRANCH_COLOURS[i % len(_BRANCH_COLOURS)])
    fs, apps = series
    if fs:
        ax.plot(fs, apps, "o", mfc="none", color="tab:red", ms=3.5,
                label="perturbation (N = 40, Padé), valid points only")
    for m in range(1, 7):
        fm = fn0_hz / m
        if f_range[0] <= fm <= f_range[1]:
            ax.axvline(fm, color="0.8", lw=0.6, zorder=0)
            ax.text(fm, 1.0, f"1/{m}" if m > 1 else "$f_{n0}$", transform=ax.get_xaxis_transform(),
                    fontsize=7, ha="center", va="bottom", color="0.4")
    ax.set_title(title, fontsize=10, pad=14)
    ax.legend(loc="upper right", fontsize=7, frameon=False)
    fig.tight_layout()
    return fig
