"""Figures of ``contactvib fit``: each data set against the fitted model, with its residuals.

Every drawing function takes ``ax=None`` and returns the axes; :func:`fit_figures` composes one
figure per data set (data and model above, residuals below). The curves come from
:func:`contactvib.fitting.curves.model_curves` (nothing is computed here).
"""

from __future__ import annotations

import numpy as np

from contactvib.plotting.figures import new_figure

_DIR_STYLE = {"up": ("^", "C0"), "down": ("v", "C3")}


def _axes(ax):
    if ax is None:
        _fig, axs = new_figure()
        ax = axs[0, 0]
    return ax


def frf_axes(c: dict, ax=None):
    """Measured A_pp (up ▲, down ▼) and the model's up and down sweeps at each force level."""
    ax = _axes(ax)
    for k, (F, fu, au, fd, ad) in enumerate(c["curves"]):
        col = f"C{k % 10}"
        ax.plot(fu, au, "-", color=col, lw=1.2, label=f"model up, P_a = {F:.3g} N")
        ax.plot(fd, ad, "--", color=col, lw=1.2, label=f"model down, P_a = {F:.3g} N")
        for d, (mk, _c) in _DIR_STYLE.items():
            sel = (c["force_n"] == F) & (c["direction"] == d)
            ax.plot(c["fe_hz"][sel], c["app_um"][sel], mk, color=col, ms=4, mfc="none",
                    label=f"data {d}, {F:.3g} N")
    ax.set_xlabel("f_e [Hz]")
    ax.set_ylabel("A_pp [um]")
    ax.legend(fontsize=6, ncol=2)
    return ax


def decay_axes(c: dict, ax=None):
    """The measured decay, the model and the model's envelope."""
    ax = _axes(ax)
    unit = "y - y0 [um]" if c["kind"] == "y_um" else "acceleration [m/s^2]"
    ax.plot(c["t_ms"], c["values"], ".", ms=2, color="0.4", label="data")
    ax.plot(c["curve_t_ms"], c["curve"], "-", lw=0.8, color="C0", label="model")
    (tu, yu), (tl, yl) = c["envelope"]
    ax.plot(tu, yu, "-", color="C3", lw=1.2, label="model envelope")
    ax.plot(tl, yl, "-", color="C3", lw=1.2)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel(unit)
    ax.legend(fontsize=7)
    return ax


def static_axes(c: dict, ax=None):
    """Measured load–deflection points and the fitted power law."""
    ax = _axes(ax)
    ax.plot(c["deflection_um"], c["load_n"], "o", ms=4, mfc="none", color="0.3", label="data")
    ax.plot(c["curve_um"], c["curve_load_n"], "-", color="C0", label="model S c_n y^m2")
    ax.set_xlabel("deflection y [um]")
    ax.set_ylabel("load F [N]")
    ax.legend(fontsize=7)
    return ax


def residual_axes(x, r, xlabel: str, ylabel: str, ax=None):
    """Residuals (data − model) against ``x``, with the zero line and ±2 RMS."""
    ax = _axes(ax)
    rms = float(np.sqrt(np.mean(np.square(r))))
    ax.axhline(0.0, color="0.5", lw=0.8)
    for s in (-2, 2):
        ax.axhline(s * rms, color="0.7", lw=0.8, ls=":")
    ax.plot(x, r, ".", ms=3, color="C2")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    return ax


def fit_figures(result, curves: dict) -> dict:
    """One figure per data set, name -> Figure: data and model on top, residuals below."""
    out = {}
    draw = {"static": (static_axes, "deflection_um", "deflection [um]", "residual_um", "residual [um]"),
            "decay": (decay_axes, "t_ms", "t [ms]", "residual", "residual"),
            "frf": (frf_axes, "fe_hz", "f_e [Hz]", "residual_um", "residual [um]")}
    for kind, c in curves.items():
        f, xname, xlabel, rname, rlabel = draw[kind]
        fig, axs = new_figure(2, 1, figsize=(7.0, 6.0), gridspec_kw={"height_ratios": [3, 1]})
        f(c, axs[0, 0])
        if kind == "decay":
            rlabel = "residual [um]" if c["kind"] == "y_um" else "residual [m/s^2]"
        residual_axes(c[xname], c[rname], xlabel, rlabel, axs[1, 0])
        rms = result.residual_rms.get(kind, float("nan"))
        axs[0, 0].set_title(f"{kind}: fitted model against the data (residual RMS {rms:.3g})", fontsize=9)
        fig.tight_layout()
        out[kind] = fig
    return out
