"""Time histories of the contact oscillator (Eq. 2.5) from an initial state or an attractor."""

from __future__ import annotations

import numpy as np

from contactvib._kernels.orbit import sample_records
from contactvib.model import ContactModel, Excitation, ParameterError, check_finite, check_int
from contactvib.steady.orbits import record
from contactvib.steady.results import Attractor, TimeHistory

__all__ = ["simulate", "attractor_history"]


def _check_types(model, excitation) -> None:
    if not isinstance(model, ContactModel):
        raise ParameterError("model", model, "must be a ContactModel")
    if not isinstance(excitation, Excitation):
        raise ParameterError("excitation", excitation, "must be an Excitation (model.excitation(P_a/Q, f_e))")


def _history(model: ContactModel, excitation: Excitation, z, n_periods: int,
             samples_per_period: int, rtol: float) -> TimeHistory:
    rec, _z_end, _tf = record(excitation, z, n_periods, rtol=rtol)
    T = excitation.tau_period
    tau = np.linspace(0.0, n_periods * T, n_periods * samples_per_period + 1)
    x, v, c = sample_records(rec, tau)
    u = model.units
    return TimeHistory(
        t_ms=tau * u.t_ms,
        y_um=x * u.y_um,
        ydot_mm_s=v * u.ydot_mm_s,
        in_contact=x > 0.0,
        y0_um=u.y_um,
        fe_hz=excitation.f_e,
        pa_over_q=excitation.pa_over_q,
    )


def simulate(model: ContactModel, excitation: Excitation, y_um: float | None = None,
             ydot_mm_s: float = 0.0, n_periods: int = 20, samples_per_period: int = 400,
             rtol: float = 1e-10) -> TimeHistory:
    """Integrate from y = ``y_um`` µm, ẏ = ``ydot_mm_s`` mm/s at phase 0 for ``n_periods``.

    ``y_um`` defaults to the static deflection y0. The time history is sampled from the
    integrator's dense output (``samples_per_period`` points per excitation period).
    """
    _check_types(model, excitation)
    u = model.units
    y_um = u.y_um if y_um is None else check_finite("y", y_um)
    ydot_mm_s = check_finite("ydot", ydot_mm_s)
    n_periods = check_int("n_periods", n_periods, 1)
    samples_per_period = check_int("samples_per_period", samples_per_period, 2)
    z = np.array(u.state(y_um, ydot_mm_s))
    return _history(model, excitation, z, n_periods, samples_per_period, rtol)


def attractor_history(model: ContactModel, excitation: Excitation, attractor: Attractor,
                      n_periods: int | None = None, samples_per_period: int = 800) -> TimeHistory:
    """Time history over ``n_periods`` (default: two orbit periods, at least 3) of an attractor."""
    _check_types(model, excitation)
    if n_periods is None:
        n_periods = max(3, 2 * (attractor.period or 4))
    return _history(model, excitation, attractor.state, n_periods, samples_per_period, 1e-12)
