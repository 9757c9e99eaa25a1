"""Steady states: refinement of periodic orbits, their description, and the sameness rule.

A period-k orbit is a fixed point of the k-fold stroboscopic map, refined by Newton shooting
with the monodromy from the variational equations (:mod:`contactvib._kernels.shooting`). Its
description (extrema, minima count, A_pp, loss of contact) comes from the dense output of one
tight-tolerance pass over the orbit (:mod:`contactvib._kernels.orbit`).
"""

from __future__ import annotations

import math

import numpy as np

from contactvib._kernels.describe import harmonic_amplitudes
from contactvib._kernels.flow import REC_H, REC_MODE, REC_T
from contactvib._kernels.orbit import measure_orbit, record_steps, sample_records
from contactvib._kernels.shooting import newton_orbit, strobe_map
from contactvib._kernels.status import STATUS_OK, status_message
from contactvib.call_forms import old_form
from contactvib.errors import ComputationError
from contactvib.model import ContactModel, Excitation, check_excitation
from contactvib.steady.lyapunov import floquet_spectrum
from contactvib.steady.results import Attractor

__all__ = ["refine_orbit", "describe_orbit", "same_orbit", "strobe_points",
           "RTOL_REFINE", "CLOSE_TOL"]

#: Integration tolerance for refined orbits and their description.
RTOL_REFINE = 1e-12
#: An orbit is accepted when its relative closure |P^k(z) − z| / max(1, |z|) is at most this.
CLOSE_TOL = 1e-10
#: Two orbits are the same when their stroboscopic sets agree to this (relative), any cyclic order.
SAME_TOL = 1e-6


def strobe_points(excitation: Excitation, z, k: int, rtol: float = RTOL_REFINE) -> np.ndarray:
    """The k stroboscopic points (nondimensional, shape (k, 2)) of the orbit through ``z``."""
    par = excitation.kernel_parameters()
    pts = np.empty((k, 2))
    cur = np.asarray(z, dtype=float).copy()
    nxt = np.empty(2)
    for j in range(k):
        pts[j] = cur
        st = strobe_map(cur, 1, par, rtol, rtol, nxt, np.empty((0, 0)))
        if st != STATUS_OK:
            raise ComputationError(f"integration failed ({status_message(st)})", stage="integration")
        cur = nxt.copy()
    return pts


@old_form("excitation", "z", "k", "tol", "rtol", "max_iter")
def refine_orbit(excitation: Excitation, z, k: int, *, tol: float = CLOSE_TOL,
                 rtol: float = RTOL_REFINE, max_iter: int = 20):
    """Newton shooting for a period-``k`` orbit from the nondimensional state ``z``.

    Returns
    -------
    z : ndarray (2,)
        Orbit point at phase 0, nondimensional.
    monodromy : ndarray (2, 2)
    closure : float
        Relative closure achieved.

    Raises
    ------
    ComputationError
        If Newton does not reach ``tol`` (``stage`` "newton").
    """
    par = excitation.kernel_parameters()
    out_z = np.empty(2)
    out_M = np.empty((2, 2))
    st, res = newton_orbit(np.asarray(z, float), int(k), par, rtol, rtol, tol, max_iter, out_z, out_M)
    if st != STATUS_OK:
        raise ComputationError(f"Newton shooting for a period-{k} orbit failed ({status_message(st)}, "
                               f"closure {res:.2e}); try another start", stage="newton")
    return out_z, out_M, res


def same_orbit(strobe_a: np.ndarray, strobe_b: np.ndarray, rtol: float = SAME_TOL) -> bool:
    """Same period and stroboscopic sets equal to ``rtol`` (relative) in some cyclic order."""
    if strobe_a.shape != strobe_b.shape:
        return False
    k = strobe_a.shape[0]
    scale = max(1.0, float(np.max(np.abs(strobe_a))), float(np.max(np.abs(strobe_b))))
    for s in range(k):
        if np.max(np.abs(strobe_a - np.roll(strobe_b, s, axis=0))) <= rtol * scale:
            return True
    return False


def record(excitation: Excitation, z, n_periods: int, rtol: float = RTOL_REFINE, phase0: float = 0.0):
    """Dense step records over ``n_periods`` from ``z`` (grows its buffer as needed)."""
    par = excitation.kernel_parameters()
    rec, z_end, t_flight, _n_events, st = record_steps(
        np.asarray(z, float), phase0, int(n_periods), par, rtol, 4096 * max(1, n_periods), 0)
    if st != STATUS_OK:
        raise ComputationError(f"integration failed ({status_message(st)})", stage="integration")
    return rec, z_end, t_flight


#: Samples per excitation period of the slider's absolute motion s = y + u under base motion (its
#: A_pp from samples: relative error below (π/n)²/2 ≈ 3e-7).
SLIDER_SAMPLES = 4000
#: Peak-to-peak amplitude [y0] at or below which an orbit is an equilibrium (its "extrema" are
#: round-off): it has no minima. The paper's smallest A_pp is about 0.1 µm, ~0.4 y0.
EQUILIBRIUM_APP = 1e-9


def slider_app_um(excitation: Excitation, z_or_records, n_periods: int) -> float:
    """Peak-to-peak [µm] of the slider's absolute motion s = y + u over ``n_periods`` under base
    motion u(t) (:attr:`Excitation.base_amplitude_um`), from the orbit point ``z`` at phase 0 (or
    its step records), sampled :data:`SLIDER_SAMPLES` times a period."""
    rec = record(excitation, z_or_records, n_periods)[0] if np.ndim(z_or_records) == 1 else z_or_records
    tau = np.linspace(0.0, n_periods * excitation.tau_period, n_periods * SLIDER_SAMPLES + 1)
    xs, _v, _c = sample_records(rec, tau)
    s = excitation.model.units.position_um(xs) + excitation.base_amplitude_um * np.cos(excitation.r * tau)
    return float(s.max() - s.min())


#: Gauss–Legendre nodes per recorded step for the mean contact force (exact for the polynomial
#: force of the power law, m2 = 2, l = 1, on the steps' 7th-order interpolants: degree ≤ 15).
FORCE_NODES = 8


def mean_contact_force_n(model: ContactModel, excitation: Excitation, rec, n_periods: int) -> float:
    """Time average [N] of the contact force F_c(y, ẏ) (:meth:`ContactModel.contact_force`) over
    ``n_periods`` excitation periods of the step records ``rec`` (from phase 0): Gauss–Legendre
    quadrature with :data:`FORCE_NODES` nodes on every in-contact step's dense output (the steps
    end at the contact events, so each lies in one mode; flight steps add 0)."""
    u_t, u_v = excitation.tau_period, model.y0 * model.omega_n0
    steps = rec[rec[:, REC_MODE] > 0.5]
    if steps.shape[0] == 0:
        return 0.0
    theta, weight = np.polynomial.legendre.leggauss(FORCE_NODES)
    h = steps[:, REC_H][:, None]
    tau = (steps[:, REC_T][:, None] + 0.5 * h * (theta[None, :] + 1.0)).ravel()
    x, v, _c = sample_records(rec, tau)
    f = model.contact_force(x * model.y0 + model.spring_law.engagement_m, v * u_v).reshape(-1, FORCE_NODES)
    return float(np.sum(0.5 * h * weight[None, :] * f) / (n_periods * u_t))


def first_harmonic_um(excitation: Excitation, rec, n_periods: int) -> float:
    """One-sided amplitude [µm] of the f_e component of y over ``n_periods`` periods of the step
    records ``rec``: the tracer's DFT (:func:`contactvib._kernels.describe.harmonic_amplitudes`,
    the dataset's ``harmonics_um``) at j = ``n_periods``."""
    out = np.empty(int(n_periods))
    harmonic_amplitudes(rec, int(n_periods), excitation.tau_period, out)
    return float(out[-1]) * excitation.model.units.y_um


@old_form("model", "excitation", "z", "period", "monodromy", "closure", "basin_fraction", "hits",
          "n_periods_nonperiodic", "kind", "lyapunov")
def describe_orbit(excitation: Excitation, z, period: int | None, *, monodromy=None,
                   closure: float = math.inf, basin_fraction: float = 0.0, hits: int = 0,
                   n_periods_nonperiodic: int = 32, kind: str | None = None, lyapunov: float = math.nan,
                   spectrum=None) -> Attractor:
    """Measure an orbit through the nondimensional state ``z`` at phase 0.

    For a periodic orbit (``period`` = k) the extrema, A_pp and contact loss are taken over one
    k-period; for a non-periodic attractor (of type ``kind``, "chaotic" or "quasi-periodic",
    with largest Lyapunov exponent ``lyapunov`` [1/period], or its Benettin ``spectrum``, a
    ``LyapunovSpectrum``, whose λ1/f_e then replaces it) over
    ``n_periods_nonperiodic`` periods. A periodic orbit's exponents are ln ``|μ_i|`` / (k T) from its
    Floquet multipliers. The f_e amplitude (``first_harmonic_um``) and the mean contact force
    (``mean_contact_force_n``) are measured over the same span.
    """
    model = check_excitation(excitation).model
    u = model.units
    n = period if period is not None else n_periods_nonperiodic
    rec, _z_end, t_flight = record(excitation, z, n)
    xmin, xmax, flight, n_min, t_ext, x_ext, is_min = measure_orbit(rec, t_flight, n, excitation.r)
    if xmax - xmin <= EQUILIBRIUM_APP:  # an equilibrium (the rest state at P_a = 0): no extrema
        n_min, t_ext, x_ext, is_min = 0, np.empty(0), np.empty(0), np.empty(0, bool)
    slider_app = slider_app_um(excitation, rec, n) if excitation.base_amplitude_um is not None else None
    if period is not None:
        strobe = strobe_points(excitation, z, period)
        multipliers = np.linalg.eigvals(monodromy) if monodromy is not None else np.empty(0, complex)
        minima = int(n_min)
        kind = "periodic"
        spectrum = floquet_spectrum(multipliers, period, excitation.f_e) if multipliers.size else None
    else:
        strobe = np.asarray(z, float)[None, :]
        multipliers = np.empty(0, complex)
        minima = None
        kind = kind or "non-periodic"
        if spectrum is not None:
            lyapunov = float(spectrum.exponents_per_period[0])
    return Attractor(
        period=period,
        kind=kind,
        minima_per_period=minima,
        app_um=(xmax - xmin) * u.y_um,
        ymin_um=u.position_um(xmin),
        ymax_um=u.position_um(xmax),
        loses_contact=bool(xmin < 0.0),
        contact_loss_fraction=float(flight),
        basin_fraction=float(basin_fraction),
        floquet_multipliers=np.asarray(multipliers, complex),
        strobe_y_um=u.position_um(strobe[:, 0]),
        strobe_ydot_mm_s=strobe[:, 1] * u.ydot_mm_s,
        extrema_t_ms=t_ext * u.t_ms,
        extrema_y_um=u.position_um(x_ext),
        extrema_is_min=np.asarray(is_min, bool),
        closure=float(closure),
        hits=int(hits),
        state=np.asarray(z, float).copy(),
        lyapunov_per_period=float(lyapunov) if period is None else math.nan,
        slider_app_um=slider_app,
        h1_um=first_harmonic_um(excitation, rec, n),
        mean_contact_force_n=mean_contact_force_n(model, excitation, rec, n),
        lyapunov_per_s=spectrum.exponents_per_s.copy() if spectrum is not None else np.empty(0),
        lyapunov_stderr_per_s=spectrum.stderr_per_s.copy() if spectrum is not None else np.empty(0),
    )
