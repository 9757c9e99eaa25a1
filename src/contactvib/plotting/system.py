"""Figures of a system of several coordinates: time histories and phase portraits per
coordinate, and the contact forces of every element against time."""

from __future__ import annotations

from contactvib.plotting.figures import new_figure

__all__ = ["system_history_figure", "contact_forces_figure"]


def system_history_figure(history, title: str):
    """One row per coordinate: its time history (left) and phase portrait (right).

    ``history`` is a :class:`~contactvib.steady.system_orbits.SystemHistory` (display units)."""
    n = len(history.coordinates)
    fig, axes = new_figure(n, 2, figsize=(11, 2.9 * n + 0.6), gridspec_kw={"width_ratios": [1.6, 1]})
    for j, (name, qu, vu) in enumerate(zip(history.coordinates, history.q_units, history.qdot_units)):
        ax, ph = axes[j, 0], axes[j, 1]
        ax.plot(history.t_ms, history.q[j], lw=0.9)
        ax.set_xlabel("t [ms]")
        ax.set_ylabel(f"{name} [{qu.replace('u', 'µ', 1)}]")
        ax.grid(alpha=0.3)
        ph.plot(history.q[j], history.qdot[j], lw=0.8)
        ph.set_xlabel(f"{name} [{qu.replace('u', 'µ', 1)}]")
        ph.set_ylabel(f"d{name}/dt [{vu}]")
        ph.grid(alpha=0.3)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def contact_forces_figure(history, title: str):
    """Every contact element's force [N] against time, one line each (0 while it is open)."""
    fig, axes = new_figure(1, 1, figsize=(9, 3.8))
    ax = axes[0, 0]
    for name, f in zip(history.contacts, history.forces_n):
        ax.plot(history.t_ms, f, lw=0.9, label=name)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("contact force [N]")
    ax.grid(alpha=0.3)
    if len(history.contacts):
        ax.legend(fontsize=8, loc="upper right")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig
