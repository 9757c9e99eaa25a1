"""Figures of friction under normal contact vibration: the friction ratio against the
excitation frequency or the drive velocity (one point per normal attractor, coloured by its
period), and the steady tangential motion of one attractor over time (R, μR, F_t and the drive
force; the slip velocity; stick shaded)."""

from __future__ import annotations

import numpy as np

from contactvib.friction.sweep import FrictionSweep
from contactvib.friction.tangential import FrictionHistory, FrictionResult
from contactvib.plotting.figures import axes_or_new, new_figure
from contactvib.plotting.style import FRICTION_PERIOD_COLOURS, friction_period_colour

__all__ = ["plot_friction_sweep", "friction_sweep_figure", "plot_friction_history", "friction_history_figure"]


def plot_friction_sweep(sweep: FrictionSweep, x: str = "fe_hz", ax=None):
    """The friction ratio ⟨F_drive⟩/(μ W) (= μ_apparent/μ, the ratio to the value without vibration)
    against ``x`` ("fe_hz" or "vd_mm_s"), one marker per normal attractor, coloured by its period
    (hollow: the tangential motion did not become periodic, its long-time mean); the no-vibration
    value 1 dashed. Returns the axes."""
    ax = axes_or_new(ax)
    rows = sweep.rows
    periods = np.minimum(rows["period"].astype(int), 5) if len(sweep) else np.empty(0, int)
    if x == "vd_mm_s":  # one curve per attractor of the operating point
        for rank in sorted(set(rows["attractor"].astype(int).tolist())):
            sel = rows["attractor"] == rank
            k = int(rows["period"][sel][0])
            ax.plot(rows[x][sel], rows["friction_ratio"][sel], "o-", ms=3.5, lw=1.0,
                    label=f"#{rank}: period {k}, A_pp {rows['app_um'][sel][0]:.3g} µm, "
                          f"flight {rows['contact_loss_fraction'][sel][0]:.0%}")
        periods = periods[:0]
    settled = rows["settled"].astype(bool) if len(sweep) else np.empty(0, bool)
    for k in sorted(set(periods.tolist())):
        sel = periods == k
        color = friction_period_colour(k)
        ax.plot(rows[x][sel & settled], rows["friction_ratio"][sel & settled], "o", ms=3.5, color=color,
                label=f"normal period {k}" if k in FRICTION_PERIOD_COLOURS else "normal period > 4")
        ax.plot(rows[x][sel & ~settled], rows["friction_ratio"][sel & ~settled], "o", ms=4.5, mfc="none",
                color=color)
    if len(sweep) and not settled.all():
        ax.plot([], [], "o", mfc="none", color="0.3", label="tangential motion not periodic (mean)")
    ax.axhline(1.0, color="0.4", ls="--", lw=0.8, label="no vibration")
    ax.set_ylim(0.0, 1.1)
    ax.set_xlabel("excitation frequency f_e [Hz]" if x == "fe_hz" else "drive velocity v_d [mm/s]")
    ax.set_ylabel("friction ratio  μ_app / μ")
    if x == "vd_mm_s":
        ax.set_xscale("log")
    if len(sweep):
        if x == "fe_hz":  # the points fill the plane: the legend beside it
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        else:
            ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)
    return ax


def friction_sweep_figure(sweep: FrictionSweep, x: str = "fe_hz"):
    """:func:`plot_friction_sweep` on a new figure, titled with the level and the parameters."""
    fig, axes = new_figure(figsize=(8.6 if x == "fe_hz" else 7.0, 4.0))
    ax = plot_friction_sweep(sweep, x, axes[0, 0])
    p = sweep.friction
    vd = "" if x == "vd_mm_s" else f", v_d = {p['vd']:g} mm/s"
    ax.set_title(f"Friction under normal vibration: P_a = {sweep.pa_over_q:g} Q{vd}, μ = {p['mu']:g},\n"
                 f"k_t = {p['kt_ratio']:.3g} dF_s/dy ({p['kt_law']}), k_d = {p['kd']:g} N/m, "
                 f"c_d = {p['cd']:g} N s/m", fontsize=8)
    fig.tight_layout()
    return fig


def plot_friction_history(history: FrictionHistory, mu: float, axes=None):
    """Three stacked panels over t [ms]: R and μR [N]; F_t and the drive force [N]; the slip
    velocity [mm/s]. Stick shaded grey, no compression (flight) shaded blue. Returns the axes."""
    if axes is None:
        _fig, arr = new_figure(3, 1, figsize=(7.0, 6.0), sharex=True)
        axes = arr[:, 0]
    t = history.t_ms
    axes[0].plot(t, history.normal_force_n, lw=1.0, label="R")
    axes[0].plot(t, mu * history.normal_force_n, lw=0.8, ls="--", label="μ R")
    axes[0].set_ylabel("normal force [N]")
    axes[1].plot(t, history.friction_force_n, lw=1.0, label="F_t (contact)")
    axes[1].plot(t, history.drive_force_n, lw=0.8, label="F_drive")
    axes[1].set_ylabel("tangential force [N]")
    axes[2].plot(t, history.slip_velocity_mm_s, lw=1.0, color="C3")
    axes[2].set_ylabel("slip velocity [mm/s]")
    axes[2].set_xlabel("t [ms]")
    for ax in axes:
        for mode, color in (("stick", "0.85"), ("free", "#dde8f5")):
            ax.fill_between(t, 0, 1, where=history.mode == mode, color=color, lw=0,
                            transform=ax.get_xaxis_transform(), zorder=0)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="upper right")
    axes[1].legend(fontsize=7, loc="upper right")
    return axes


def friction_history_figure(history: FrictionHistory, result: FrictionResult, title: str = ""):
    """:func:`plot_friction_history` on a new figure, titled with the friction ratio and the stick
    fraction."""
    fig, arr = new_figure(3, 1, figsize=(7.0, 6.0), sharex=True)
    plot_friction_history(history, result.friction["mu"], arr[:, 0])
    arr[0, 0].set_title(f"{title}friction ratio {result.friction_ratio:.4f}, stick {result.stick_fraction:.1%}, "
                        f"no compression {result.free_fraction:.1%} (grey: stick, blue: free)", fontsize=8)
    fig.tight_layout()
    return fig
