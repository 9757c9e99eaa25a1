"""The response to a random force (:class:`~contactvib.steady.random_response.RandomResponse`):
the time history y(t), the probability density of the contact force R and the one-sided PSD of
y on log axes, in one figure (``contactvib simulate --random-psd``)."""

from __future__ import annotations

from contactvib.plotting.figures import axes_or_new, mark_equilibrium_and_gap, new_figure
from contactvib.steady.random_response import RandomResponse

__all__ = ["plot_random_history", "plot_contact_force_pdf", "plot_response_psd", "random_figure"]

#: Longest stretch of the time history drawn [ms] (the whole record is in the dataset).
HISTORY_SPAN_MS = 100.0
#: Smallest PSD drawn, relative to its peak.
PSD_DECADES = 1e-10


def plot_random_history(resp: RandomResponse, ax=None, span_ms: float = HISTORY_SPAN_MS):
    """y(t) [µm vs ms] over the first ``span_ms`` of the record, y0 dashed, the gap (y ≤ 0) shaded."""
    ax = axes_or_new(ax)
    t = resp.t_ms
    sel = t <= t[0] + span_ms
    ax.plot(t[sel], resp.y_um[sel], color="k", lw=0.6)
    mark_equilibrium_and_gap(ax, t[sel], resp.y_um[sel], resp.y0_um, ~resp.in_contact[sel], resp.engagement_um)
    ax.set_xlabel("t [ms]")
    ax.set_ylabel("y [µm]")
    ax.set_title(f"RMS {resp.rms_um:.3g} µm about the mean {resp.mean_um:.3g} µm", fontsize=8)
    ax.legend(loc="upper right", fontsize=7, frameon=False)
    return ax


def plot_contact_force_pdf(resp: RandomResponse, ax=None):
    """Probability density [1/N] of the contact force R [N] (the flight's R = 0 included), the
    static load W and the mean of R marked."""
    ax = axes_or_new(ax)
    edges = resp.pdf_edges_n
    ax.stairs(resp.pdf_per_n, edges, color="k", lw=0.9, fill=True, alpha=0.25)
    ax.stairs(resp.pdf_per_n, edges, color="k", lw=0.9)
    ax.axvline(resp.static_load_n, color="tab:blue", ls="--", lw=0.9,
               label=f"W = Q + F_pre = {resp.static_load_n:.4g} N")
    ax.axvline(resp.mean_contact_force_n, color="tab:red", ls=":", lw=1.0,
               label=f"mean R = {resp.mean_contact_force_n:.4g} ± {resp.mean_contact_force_err_n:.2g} N")
    ax.set_xlabel("contact force R [N]")
    ax.set_ylabel("probability density [1/N]")
    ax.set_title(f"contact loss probability {resp.contact_loss_probability:.3g}", fontsize=8)
    ax.legend(loc="upper right", fontsize=7, frameon=False)
    return ax


def plot_response_psd(resp: RandomResponse, ax=None):
    """One-sided PSD of y [µm²/Hz] against f [Hz], log axes; the force's band shaded, f_n0 and its
    multiples marked."""
    ax = axes_or_new(ax)
    f, p = resp.psd_f_hz, resp.psd_um2_hz
    ok = (f > 0.0) & (p > 0.0)
    ax.loglog(f[ok], p[ok], color="k", lw=0.9)
    if ok.any():  # ten decades below the peak: the integrator's noise floor stays out of view
        top = float(p[ok].max())
        ax.set_ylim(max(float(p[ok].min()), top * PSD_DECADES) / 2.0, top * 3.0)
    ax.axvspan(resp.force.f_lo, resp.force.f_hi, color="tab:blue", alpha=0.08, label="force band")
    for m in range(1, 4):
        ax.axvline(m * resp.f_n0_hz, color="0.5", ls=":", lw=0.7,
                   label="$f_{n0}$, $2f_{n0}$, $3f_{n0}$" if m == 1 else None)
    ax.set_xlabel("f [Hz]")
    ax.set_ylabel("PSD of y [µm²/Hz]")
    ax.legend(loc="lower left", fontsize=7, frameon=False)
    return ax


def random_figure(resp: RandomResponse, title: str | None = None):
    """Time history (top), contact-force density and response PSD (bottom) in one figure."""
    fig, axes = new_figure(2, 2, figsize=(11, 7.0))
    gs = axes[0, 0].get_gridspec()
    axes[0, 0].remove()
    axes[0, 1].remove()
    top = fig.add_subplot(gs[0, :])
    plot_random_history(resp, top)
    plot_contact_force_pdf(resp, axes[1, 0])
    plot_response_psd(resp, axes[1, 1])
    f = resp.force
    head = title or (f"random force: $S_F$ = {f.S_F:.3g} N²/Hz over [{f.f_lo:g}, {f.f_hi:g}] Hz "
                     f"(RMS {f.rms_n:.3g} N), {f.n} components, seed {f.seed}")
    fig.suptitle(head, fontsize=10)
    fig.tight_layout()
    return fig
