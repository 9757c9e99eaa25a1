"""Response of the contact oscillator to a random, band-limited Gaussian force (simulation only).

The force is the spectral representation of a stationary Gaussian process (Shinozuka &
Deodatis 1991) with a flat one-sided power spectral density S_F [N²/Hz] over [f_lo, f_hi] Hz::

    P(t) = Σ_j A_j cos(2π f_j t + φ_j),     A_j = sqrt(2 S_F Δf),  Δf = (f_hi − f_lo) / n

with f_j the midpoints of the n bins, each moved by a small random jitter inside its bin (so that
the sum does not repeat with the period 1/Δf), and φ_j independent and uniform in [0, 2π) from
``numpy.random.default_rng(seed)``. By the central limit theorem P(t) is Gaussian for large n;
its one-sided PSD is S_F over the band (resolved to Δf) and its RMS is exactly
sqrt(S_F (f_hi − f_lo)), Σ A_j²/2.

The kernels' ``spectrum`` excitation (:func:`contactvib._kernels.contact.forcing`) integrates
κ x'' = 1 + Σ a_j cos(ω_j τ + φ_j) − f(x, x') with a_j = A_j / W and ω_j = f_j / f_n0 (W = Q + F_pre
the static load, τ = ω_n0 t), on the DOP853 flow with contact events
(:func:`contactvib._kernels.flow.advance`), in chunks of bounded memory, from the static
equilibrium at rest; the first ``discard_s`` seconds (the start transient) are dropped.

References
----------
M. Shinozuka, G. Deodatis, Simulation of stochastic processes by spectral representation,
*Applied Mechanics Reviews* 44 (1991) 191–204.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib._kernels import contact as kc
from contactvib._kernels.flow import REC_WIDTH, advance, initial_mode
from contactvib._kernels.orbit import sample_records
from contactvib._kernels.shooting import MAX_STEPS_PER_PERIOD
from contactvib._kernels.status import STATUS_OK, STATUS_RECORD_FULL, status_message
from contactvib.errors import ComputationError
from contactvib.interrupts import check_interrupt
from contactvib.model import ContactModel, ParameterError, check_int, check_range
from contactvib.model.checks import MEMORY_MAX, PA_MAX, check_memory, format_number
from contactvib.steady.transients import STEPS_PER_NATURAL_PERIOD

__all__ = ["RandomForce", "RandomResponse", "random_response", "check_random", "contact_force_n",
           "N_COMPONENTS_RANGE", "F_HI_MAX_RATIO"]

#: Number of spectral components n of a random force allowed, inclusive.
N_COMPONENTS_RANGE = (8, 4096)
#: Largest upper band edge f_hi as a multiple of the model's f_n0.
F_HI_MAX_RATIO = 20.0
#: Width of the random jitter of each component's frequency, a fraction of the bin Δf.
JITTER_FRACTION = 0.1
#: Default samples per cycle of the fastest of f_hi and f_n0.
SAMPLES_PER_CYCLE = 32
#: Largest work of one random response: integration steps × spectral components (about a quarter
#: of an hour).
WORK_MAX = 1e10
#: Chunk of integration [τ] between two samplings of the step records (bounds the memory).
_CHUNK_TAU = 1000.0
#: Bytes per sample of the result (its arrays and the sampling's).
_BYTES_PER_SAMPLE = 96


@dataclass(frozen=True)
class RandomForce:
    """A stationary Gaussian force with a flat one-sided PSD ``S_F`` [N²/Hz] over
    [``f_lo``, ``f_hi``] Hz, built from ``n`` cosines with random phases (module docstring).

    Parameters
    ----------
    S_F : float
        One-sided force power spectral density [N²/Hz], > 0.
    f_lo, f_hi : float
        Band edges [Hz], 0 < f_lo < f_hi (f_hi ≤ 20 f_n0 of the model, checked by
        :func:`random_response`).
    seed : int
        Seed of ``numpy.random.default_rng`` for the phases and the jitter, ≥ 0.
    n : int
        Number of spectral components, in :data:`N_COMPONENTS_RANGE`.
    """

    S_F: float
    f_lo: float
    f_hi: float
    seed: int = 0
    n: int = 400

    def __post_init__(self):
        object.__setattr__(self, "S_F", check_range("S_F", self.S_F, 0.0, False, "N^2/Hz"))
        lo = check_range("f_lo", self.f_lo, 0.0, False, "Hz")
        hi = check_range("f_hi", self.f_hi, lo, False, "Hz", lower_name="f_lo")
        object.__setattr__(self, "f_lo", lo)
        object.__setattr__(self, "f_hi", hi)
        object.__setattr__(self, "seed", check_int("seed", self.seed, 0))
        object.__setattr__(self, "n", check_int("n", self.n, *N_COMPONENTS_RANGE))

    @property
    def rms_n(self) -> float:
        """RMS of the force [N]: sqrt(S_F (f_hi − f_lo))."""
        return math.sqrt(self.S_F * (self.f_hi - self.f_lo))

    @property
    def df_hz(self) -> float:
        """Width Δf of one spectral bin [Hz]."""
        return (self.f_hi - self.f_lo) / self.n

    def components(self):
        """``(f_hz, amplitude_n, phase_rad)``: the n cosines' frequencies [Hz] (bin midpoints with
        a jitter of ±JITTER_FRACTION/2 of a bin), amplitudes sqrt(2 S_F Δf) [N] and phases [rad]."""
        rng = np.random.default_rng(self.seed)
        phase = rng.uniform(0.0, 2.0 * math.pi, self.n)
        jitter = rng.uniform(-0.5, 0.5, self.n) * JITTER_FRACTION
        df = self.df_hz
        f = self.f_lo + (np.arange(self.n) + 0.5 + jitter) * df
        return f, np.full(self.n, math.sqrt(2.0 * self.S_F * df)), phase

    def force_n(self, t_s) -> np.ndarray:
        """The force P(t) [N] at the instants ``t_s`` [s]."""
        t = np.asarray(t_s, dtype=float)
        f, a, ph = self.components()
        out = np.zeros(t.shape)
        for fj, aj, pj in zip(f, a, ph):
            out += aj * np.cos(2.0 * math.pi * fj * t + pj)
        return out

    def describe(self) -> dict:
        """The force as a JSON-able record (units in the keys)."""
        return {"S_F_n2_hz": self.S_F, "f_lo_hz": self.f_lo, "f_hi_hz": self.f_hi, "seed": self.seed,
                "n_components": self.n, "rms_n": self.rms_n}

    def kernel_parameters(self, model: ContactModel) -> np.ndarray:
        """The kernels' parameter vector of ``model`` under this force: the law's full layout
        (:meth:`Excitation.kernel_parameters`) with p = 0, the ``spectrum`` excitation code and
        the triples (ω_j = f_j / f_n0, a_j = A_j / W, φ_j) appended."""
        par = model.excitation(0.0, model.f_n0).kernel_parameters()
        if par.shape[0] <= kc.P_SPRING:  # the paper's law: [m2, l, c, p, r] → full layout
            head = np.zeros(kc.HEADER)
            head[:5] = par
            head[kc.P_SPRING] = kc.SPRING_POWER
            head[kc.P_DAMPING] = kc.DAMPING_POWER
            head[kc.P_S1] = par[0]
            par = head
        par = par.copy()
        par[3] = 0.0
        par[kc.P_EXCITATION] = kc.EXCITATION_SPECTRUM
        f, a, ph = self.components()
        triples = np.column_stack([f / model.f_n0, a / model.W, ph]).ravel()
        par[kc.P_NEXC] = self.n
        par[kc.P_OEXC] = par.shape[0]
        return np.concatenate([par, triples])


@dataclass(frozen=True)
class RandomResponse:
    """Time history and statistics of the response to a :class:`RandomForce`.

    Attributes
    ----------
    t_ms : ndarray
        Time [ms] since the force started (the record starts after the discarded transient).
    y_um, ydot_mm_s : ndarray
        Displacement y [µm] (> 0 contact deflection, < 0 gap) and velocity ẏ [mm/s].
    force_n : ndarray
        The applied random force P(t) [N] (positive into the contact).
    contact_force_n : ndarray
        Contact force R(t) = F_s + F_d [N] in contact (y > 0), 0 in flight.
    rms_um, mean_um : float
        RMS of y about its mean [µm], and the mean [µm].
    psd_f_hz, psd_um2_hz : ndarray
        One-sided PSD of y (Welch, Hann window) [µm²/Hz] at the frequencies [Hz].
    contact_loss_probability : float
        Fraction of the samples with y ≤ 0 [1].
    pdf_edges_n, pdf_per_n : ndarray
        Histogram of R: bin edges [N] and probability density [1/N] (integrates to 1).
    mean_contact_force_n, mean_contact_force_err_n : float
        Mean of R [N] and its standard error [N] by batch means (``n_batches`` batches); the
        static balance requires mean R = W.
    static_load_n : float
        W = Q + F_pre [N].
    force : RandomForce
    y0_um, f_n0_hz, discard_s : float
        Static deflection [µm], linear natural frequency [Hz], discarded start [s].
    n_batches : int
    """

    t_ms: np.ndarray
    y_um: np.ndarray
    ydot_mm_s: np.ndarray
    force_n: np.ndarray
    contact_force_n: np.ndarray
    rms_um: float
    mean_um: float
    psd_f_hz: np.ndarray
    psd_um2_hz: np.ndarray
    contact_loss_probability: float
    pdf_edges_n: np.ndarray
    pdf_per_n: np.ndarray
    mean_contact_force_n: float
    mean_contact_force_err_n: float
    static_load_n: float
    force: RandomForce
    y0_um: float
    f_n0_hz: float
    discard_s: float
    n_batches: int
    engagement_um: float = 0.0

    @property
    def in_contact(self) -> np.ndarray:
        """True where the contact is deflected (y > y_e, the law's engagement point)."""
        return self.y_um > self.engagement_um

    @property
    def mean_force_deviation(self) -> float:
        """(mean R − W) in standard errors [1]."""
        err = self.mean_contact_force_err_n
        d = self.mean_contact_force_n - self.static_load_n
        return d / err if err > 0.0 else (0.0 if d == 0.0 else math.inf)

    def summary(self) -> dict:
        """The statistics as a JSON-able record (units in the keys)."""
        return {**self.force.describe(), "rms_um": self.rms_um, "mean_um": self.mean_um,
                "contact_loss_probability": self.contact_loss_probability,
                "mean_contact_force_n": self.mean_contact_force_n,
                "mean_contact_force_err_n": self.mean_contact_force_err_n,
                "static_load_n": self.static_load_n, "duration_s": float(self.t_ms[-1] - self.t_ms[0]) / 1e3,
                "discard_s": self.discard_s, "y0_um": self.y0_um, "f_n0_hz": self.f_n0_hz}

    def to_dataset(self):
        """The response as an xarray Dataset (dimensions ``time``, ``frequency``, ``force_bin``),
        units in each variable's ``units`` attribute, the statistics as attributes."""
        import xarray as xr

        centres = 0.5 * (self.pdf_edges_n[1:] + self.pdf_edges_n[:-1])
        data = {
            "y_um": ("time", self.y_um, {"units": "um", "long_name": "displacement y (> 0: contact deflection)"}),
            "ydot_mm_s": ("time", self.ydot_mm_s, {"units": "mm/s", "long_name": "velocity dy/dt"}),
            "force_n": ("time", self.force_n, {"units": "N", "long_name": "random force P(t)"}),
            "contact_force_n": ("time", self.contact_force_n,
                                {"units": "N", "long_name": "contact force R = F_s + F_d (0 in flight)"}),
            "psd_um2_hz": ("frequency", self.psd_um2_hz, {"units": "um^2/Hz", "long_name": "one-sided PSD of y"}),
            "pdf_per_n": ("force_bin", self.pdf_per_n, {"units": "1/N", "long_name": "probability density of R"}),
            "pdf_edges_n": ("force_edge", self.pdf_edges_n, {"units": "N", "long_name": "bin edges of R"}),
        }
        coords = {"t_ms": ("time", self.t_ms, {"units": "ms"}),
                  "psd_f_hz": ("frequency", self.psd_f_hz, {"units": "Hz"}),
                  "force_bin_n": ("force_bin", centres, {"units": "N"})}
        attrs = {k: v for k, v in self.summary().items()}
        attrs["units"] = ("S_F: N^2/Hz, f: Hz, rms/mean/y0: um, forces: N, durations: s; "
                          "contact_loss_probability: fraction of time with y <= 0")
        return xr.Dataset(data, coords=coords, attrs=attrs)


def check_random(model: ContactModel, force: RandomForce, duration_s, dt_sample_s=None, discard_s=None,
                 rtol=1e-9, n_batches=20):
    """The checked ``(duration_s, dt_sample_s, discard_s, rtol, n_batches)`` of :func:`random_response`
    (ParameterError naming the parameter: ``f_hi``, ``S_F``, ``duration``, ``dt_sample``, ``discard``,
    ``rtol``, ``n_batches``), before anything is computed."""
    if not isinstance(model, ContactModel):
        raise ParameterError("model", model, "must be a ContactModel")
    if not isinstance(force, RandomForce):
        raise ParameterError("force", force, "must be a RandomForce(S_F, f_lo, f_hi, seed, n)")
    fn = model.f_n0
    check_range("f_hi", force.f_hi, None, unit=f"Hz ({format_number(F_HI_MAX_RATIO)} f_n0, f_n0 = "
                f"{fn:.6g} Hz)", upper=F_HI_MAX_RATIO * fn)
    check_range("S_F", force.S_F, None, unit=f"N^2/Hz (RMS force sqrt(S_F (f_hi - f_lo)) <= "
                f"{format_number(PA_MAX)} W, W = {model.W:.6g} N)",
                upper=(PA_MAX * model.W) ** 2 / (force.f_hi - force.f_lo))
    duration_s = check_range("duration", duration_s, 0.0, False, "s")
    f_fast = max(force.f_hi, fn)
    dt_max = 0.5 / f_fast
    if dt_sample_s is None:
        dt_sample_s = 1.0 / (SAMPLES_PER_CYCLE * f_fast)
    dt_sample_s = check_range("dt_sample", dt_sample_s, 0.0, False, f"s (1 / (2 max(f_hi, f_n0)) = "
                              f"{dt_max:.4g} s, the Nyquist limit)", upper=dt_max)
    n_batches = check_int("n_batches", n_batches, 2, 1000)
    n_samples = duration_s / dt_sample_s
    if n_samples < 10 * n_batches:
        raise ParameterError("duration", duration_s, f"must hold at least {10 * n_batches} samples of "
                             f"dt_sample = {dt_sample_s:.4g} s (10 per batch of the mean's error)")
    if discard_s is None:
        decay = 5.0 / (model.zeta * model.omega_n0) if model.zeta > 0.0 else duration_s
        discard_s = min(decay, duration_s)
    discard_s = check_range("discard", discard_s, 0.0, True, "s")
    rtol = check_range("rtol", rtol, 1e-14, True, "", upper=1e-4)
    check_memory("duration", duration_s, n_samples * _BYTES_PER_SAMPLE,
                 int(MEMORY_MAX / _BYTES_PER_SAMPLE * dt_sample_s))
    steps = STEPS_PER_NATURAL_PERIOD * (duration_s + discard_s) * max(fn, 2.0 * force.f_hi)
    if steps * force.n > WORK_MAX:
        raise ParameterError("duration", duration_s, f"with discard = {discard_s:.4g} s needs about "
                             f"{steps:.2g} integration steps x {force.n} components = {steps * force.n:.2g}; at "
                             f"most {WORK_MAX:.0e} can be done in reasonable time: shorten the duration or use "
                             f"fewer components (n)")
    return duration_s, dt_sample_s, discard_s, rtol, n_batches


def _integrate(par, tau_start, tau_end, tau_samples, rtol):
    """x, x' [y0, y0 ω_n0] at the sorted instants ``tau_samples`` (in [tau_start, tau_end]) of the
    trajectory from rest at the static equilibrium at τ = 0; chunks of :data:`_CHUNK_TAU`."""
    y = np.array([1.0, 0.0])
    contact = initial_mode(y[0], y[1])
    h = 0.01
    none = np.empty((0, REC_WIDTH))
    max_steps = np.int64(MAX_STEPS_PER_PERIOD)
    m = tau_samples.shape[0]
    xs, vs = np.empty(m), np.empty(m)
    t = 0.0
    if tau_start > 0.0:  # the start transient, unrecorded
        contact, h, _i, _n, _tf, _ne, st = advance(y, 0.0, tau_start, contact, h, par, rtol, rtol, none,
                                                   np.int64(0), max_steps)
        _raise_status(st, 0.0)
        t = tau_start
    cap = 4096
    j0 = 0
    while t < tau_end:
        check_interrupt()
        t1 = min(t + _CHUNK_TAU, tau_end)
        state = (y.copy(), contact, h)
        while True:
            rec = np.empty((cap, REC_WIDTH))
            contact, h, irec, _n, _tf, _ne, st = advance(y, t, t1, contact, h, par, rtol, rtol, rec,
                                                         np.int64(0), max_steps)
            if st != STATUS_RECORD_FULL:
                break
            cap *= 4
            y, contact, h = state[0].copy(), state[1], state[2]
        _raise_status(st, t)
        j1 = m if t1 >= tau_end else int(np.searchsorted(tau_samples, t1, side="left"))
        if j1 > j0:
            xs[j0:j1], vs[j0:j1], _c = sample_records(rec[:irec], tau_samples[j0:j1])
        j0 = j1
        t = t1
    return xs, vs


def _raise_status(st: int, tau: float) -> None:
    if st != STATUS_OK:
        raise ComputationError(f"integration of the random response failed near tau = {tau:.6g} "
                               f"({status_message(st)})", stage="integration")


def contact_force_n(model: ContactModel, y_um, ydot_mm_s) -> np.ndarray:
    """Contact force R = F_s + F_d [N] at y [µm], ẏ [mm/s]: 0 in flight (δ = y − y_e ≤ 0); F_s from
    :meth:`ContactModel.spring_force`, F_d = S h_n δ^l ẏ (power) or α F_s ẏ (Hunt–Crossley)."""
    y = np.asarray(y_um, dtype=float) * 1e-6
    v = np.asarray(ydot_mm_s, dtype=float) * 1e-3
    fs = -model.spring_force(y)
    y = y - model.spring_law.engagement_m
    yc = np.where(y > 0.0, y, 0.0)
    if model.damping == "hunt-crossley":
        fd = model.alpha * fs * v
    else:
        fd = model.S * model.h_n * yc**model.l * v
    return np.where(y > 0.0, fs + fd, 0.0)


def _statistics(y_um, R, dt_s, n_batches, bins):
    """(mean, rms, psd_f, psd, edges, pdf, mean R, its error) of the samples."""
    from scipy.signal import welch

    n = y_um.shape[0]
    nperseg = int(2 ** math.floor(math.log2(max(n // 4, 8))))
    psd_f, psd = welch(y_um, fs=1.0 / dt_s, nperseg=min(nperseg, n), detrend="constant")
    pdf, edges = np.histogram(R, bins=bins, density=True)
    batches = np.array([b.mean() for b in np.array_split(R, n_batches)])
    err = float(np.std(batches, ddof=1) / math.sqrt(n_batches))
    return (float(np.mean(y_um)), float(np.std(y_um)), psd_f, psd, edges, pdf, float(np.mean(R)), err)


def random_response(model: ContactModel, force: RandomForce, duration_s: float = 1.0,
                    dt_sample_s: float | None = None, discard_s: float | None = None,
                    rtol: float = 1e-9, n_batches: int = 20, bins: int = 60) -> RandomResponse:
    """Simulate ``model`` under the random ``force`` for ``duration_s`` seconds after a discarded
    start of ``discard_s`` seconds, and measure the response's statistics.

    Parameters
    ----------
    model : ContactModel
    force : RandomForce
        Its f_hi must be ≤ 20 f_n0 and its RMS ≤ 1000 W.
    duration_s : float
        Recorded duration [s], > 0 (at least 10 samples per batch).
    dt_sample_s : float or None
        Sampling interval [s], ≤ 1/(2 max(f_hi, f_n0)); default 1/(32 max(f_hi, f_n0)).
    discard_s : float or None
        Start transient dropped [s], ≥ 0; default five linear decay times 1/(ζ ω_n0), at most
        ``duration_s``.
    rtol : float
        Integrator tolerance (relative and absolute, in y0 units), in [1e-14, 1e-4].
    n_batches : int
        Batches of the batch-means error of the mean contact force, 2..1000.
    bins : int
        Bins of the contact force's histogram, 2..10000.

    Returns
    -------
    RandomResponse
    """
    duration_s, dt_s, discard_s, rtol, n_batches = check_random(model, force, duration_s, dt_sample_s,
                                                          discard_s, rtol, n_batches)
    bins = check_int("bins", bins, 2, 10000)
    w = model.omega_n0
    n = int(math.floor(duration_s / dt_s + 1e-9)) + 1
    t_s = discard_s + dt_s * np.arange(n)
    xs, vs = _integrate(force.kernel_parameters(model), discard_s * w, t_s[-1] * w, t_s * w, rtol)
    u = model.units
    y_um, ydot = u.position_um(xs), vs * u.ydot_mm_s
    R = contact_force_n(model, y_um, ydot)
    mean, rms, psd_f, psd, edges, pdf, mean_R, err = _statistics(y_um, R, dt_s, n_batches, bins)
    return RandomResponse(
        t_ms=t_s * 1e3, y_um=y_um, ydot_mm_s=ydot, force_n=force.force_n(t_s), contact_force_n=R,
        rms_um=rms, mean_um=mean, psd_f_hz=psd_f, psd_um2_hz=psd,
        contact_loss_probability=float(np.mean(xs <= 0.0)), pdf_edges_n=edges, pdf_per_n=pdf,
        mean_contact_force_n=mean_R, mean_contact_force_err_n=err, static_load_n=model.W, force=force,
        y0_um=u.y_static_um, f_n0_hz=model.f_n0, discard_s=discard_s, n_batches=n_batches,
        engagement_um=u.y_offset_um)
