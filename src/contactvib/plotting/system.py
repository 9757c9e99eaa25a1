"""Figures of a system of several coordinates: time histories and phase portraits per
coordinate, and the contact forces of every element against time."""

from __future__ import annotations

from contactvib.plotting.figures import new_figure

__all__ = ["system_history_figure", "contact_forces_figure", "system_hb_figure", "crossing_kind",
           "system_resonance_figure"]


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


def system_hb_figure(branches, coordinate: int, measure: str, title: str):
    """Harmonic-balance branches of a system: one coordinate's peak-to-peak (``measure`` "app") or
    first-harmonic amplitude ("h1") against f_e [Hz], stable parts solid, unstable parts dashed
    (red), and the points where a stability change is detected marked by the multiplier that
    crosses: −1 (period doubling), +1 (fold) or a complex pair (Neimark–Sacker).

    ``branches``: ``[(label, SystemHBBranch)]``."""
    import numpy as np

    fig, axes = new_figure(1, 1, figsize=(8, 4.6))
    ax = axes[0, 0]
    marks = {"period doubling": ("s", "tab:orange"), "fold": ("^", "tab:green"),
             "Neimark–Sacker": ("D", "tab:purple")}
    seen = set()
    unit = name = ""
    for label, br in branches:
        if not br.solutions:
            continue
        s0 = br.solutions[0]
        name, unit = s0.coordinates[coordinate], s0.units[coordinate].replace("u", "µ", 1)
        f = br.fe_hz
        y = br.app(coordinate) if measure == "app" else br.h1(coordinate)
        st = br.stable
        ax.plot(f, np.where(st, y, np.nan), "-", lw=1.2, color="tab:blue",
                label=f"{label}: stable" if label else "stable")
        ax.plot(f, np.where(st, np.nan, y), "--", lw=1.8, color="tab:red",
                label=f"{label}: unstable" if label else "unstable")
        for i in np.where(st[1:] != st[:-1])[0]:
            kind = crossing_kind(br.solutions[i].floquet_multipliers, br.solutions[i + 1].floquet_multipliers)
            m, c = marks[kind]
            ax.plot(f[i + 1], y[i + 1], m, color=c, ms=7, mfc="none", mew=1.5,
                    label=None if kind in seen else kind)
            seen.add(kind)
    what = "peak-to-peak" if measure == "app" else "first-harmonic amplitude"
    ax.set_xlabel("$f_e$ [Hz]")
    ax.set_ylabel(f"{name} {what} [{unit}]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def crossing_kind(mu_a, mu_b) -> str:
    """Which multiplier leaves (or enters) the unit circle between two branch points: "period
    doubling" (a real one through −1), "fold" (a real one through +1) or "Neimark–Sacker" (a
    complex pair)."""
    import numpy as np

    a, b = np.asarray(mu_a), np.asarray(mu_b)
    out = b if np.max(np.abs(b)) > np.max(np.abs(a)) else a  # the side where one is outside
    mu = out[np.argmax(np.abs(out))]
    if abs(mu.imag) > 1e-9 * max(1.0, abs(mu)):
        return "Neimark–Sacker"
    return "period doubling" if mu.real < 0 else "fold"


#: Colours of the non-periodic attractors' dots, by ``attractor_type``.
_NONPERIODIC_DOTS = {"chaotic": "tab:red", "quasi-periodic": "tab:purple"}
#: Colours of the periods, in the order they are met (the cycle without the dots' red and purple).
_PERIOD_COLOURS = ("C0", "C1", "C2", "C5", "C6", "C7", "C8", "C9")


def system_resonance_figure(ds, coordinates, measure: str, title: str):
    """Resonance graphs of one level of a system's dataset (``contactvib.sweeps.system_dataset``):
    one panel per coordinate index in ``coordinates``, its peak-to-peak value (``measure`` "app",
    ``dof_app``) or first-harmonic amplitude ("h1", ``dof_h1``) [the dof's unit] against f_e [Hz]
    for every stored (stable) periodic attractor; each branch a line, coloured by its period,
    points reached by the laboratory sweeps filled, those only found by the searches hollow; the
    non-periodic attractors (``kind`` "non-periodic") as dots, red chaotic, purple
    quasi-periodic (measured over 64 periods)."""
    import numpy as np

    names = [str(x) for x in ds["dof_name"].values]
    units = [str(x).replace("u", "µ", 1) for x in ds["dof_unit"].values]
    fig, axes = new_figure(len(coordinates), 1, figsize=(8, 2.9 * len(coordinates) + 0.8), sharex=True)
    var = "dof_app" if measure == "app" else "dof_h1"
    fe, period = ds["fe_hz"].values, ds["period"].values
    branch, sweep = ds["branch_index"].values, ds["found_by"].values == "sweep"
    kinds = ds["attractor_type"].values if "attractor_type" in ds else np.full(period.size, "periodic", object)
    colours, labelled = {}, set()
    for row, j in enumerate(coordinates):
        ax = axes[row, 0]
        y = ds[var].values[:, j]
        for b in np.unique(branch[period > 0]):
            sel = np.flatnonzero(branch == b)
            sel = sel[np.argsort(fe[sel])]
            k = int(period[sel[0]])
            c = colours.setdefault(k, _PERIOD_COLOURS[len(colours) % len(_PERIOD_COLOURS)])
            label = f"period {k}" if row == 0 and k not in labelled else None
            labelled.add(k)
            ax.plot(fe[sel], y[sel], "-", color=c, lw=1.0, label=label)
            ax.plot(fe[sel][sweep[sel]], y[sel][sweep[sel]], "o", color=c, ms=3.5)
            ax.plot(fe[sel][~sweep[sel]], y[sel][~sweep[sel]], "o", color=c, ms=3.5, mfc="none")
        for kind, colour in _NONPERIODIC_DOTS.items():
            sel = (period == 0) & (kinds == kind)
            if sel.any():
                ax.plot(fe[sel], y[sel], ".", color=colour, ms=4.0, zorder=3,
                        label=kind if row == 0 else None)
        what = "peak-to-peak" if measure == "app" else "amplitude at $f_e$"
        ax.set_ylabel(f"{names[j]} {what} [{units[j]}]")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("$f_e$ [Hz]")
    ax0 = axes[0, 0]
    ax0.plot([], [], "o", color="0.3", ms=3.5, label="reached by the sweeps")
    ax0.plot([], [], "o", color="0.3", ms=3.5, mfc="none", label="found by a search only")
    ax0.legend(fontsize=7, loc="best", ncol=2)
    fig.suptitle(title + (" (stable attractors)" if (period == 0).any() else " (stable periodic attractors)"),
                 fontsize=10)
    fig.tight_layout()
    return fig
