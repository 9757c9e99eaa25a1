"""Time histories of the contact oscillator (Eq. 2.5) from an initial state or an attractor."""

from __future__ import annotations

import numpy as np

from contactvib._kernels.flow import REC_WIDTH
from contactvib._kernels.orbit import sample_records
from contactvib.call_forms import old_form
from contactvib.model import ContactModel, Excitation, check_excitation, check_int, check_range
from contactvib.model.checks import MEMORY_MAX, check_memory
from contactvib.steady.orbits import record
from contactvib.steady.results import Attractor, TimeHistory
from contactvib.steady.transients import check_work, steps_per_period

__all__ = ["simulate", "attractor_history", "check_start"]


def _history(model: ContactModel, excitation: Excitation, z, n_periods: int,
             samples_per_period: int, rtol: float) -> TimeHistory:
    rec, _z_end, _tf = record(excitation, z, n_periods, rtol=rtol)
    T = excitation.tau_period
    tau = np.linspace(0.0, n_periods * T, n_periods * samples_per_period + 1)
    x, v, c = sample_records(rec, tau)
    u = model.units
    U = excitation.base_amplitude_um
    sym, val, unit = excitation.level
    return TimeHistory(
        t_ms=tau * u.t_ms,
        y_um=u.position_um(x),
        ydot_mm_s=v * u.ydot_mm_s,
        in_contact=x > 0.0,
        y0_um=u.y_static_um,
        engagement_um=u.y_offset_um,
        fe_hz=excitation.f_e,
        pa_over_q=excitation.pa_over_q,
        base_um=None if U is None else U * np.cos(excitation.r * tau),
        level=f"{'P_a' if sym == 'P_a/Q' else sym} = {val:g} {'µm' if unit == 'um' else unit}",
    )


#: Largest |y| / y0 and |ẏ| / (y0 ω_n0) of an initial state.
STATE_MAX = 1e6
#: Bytes per excitation period of the integrator's initial step records (4096 rows of REC_WIDTH
#: floats) and per sample of a time history (its arrays and the sampling's).
_BYTES_PER_PERIOD = 4096 * REC_WIDTH * 8
_BYTES_PER_SAMPLE = 64


def check_start(model: ContactModel, y_um, ydot_mm_s, n_periods, samples_per_period=400):
    """The checked inputs of :func:`simulate`: ``(y_um, ydot_mm_s, n_periods, samples_per_period)``.

    The state must be bounded, ``|y| <= 1e6 y0`` and ``|ẏ| <= 1e6 y0 ω_n0``, and the time
    history must fit in :data:`~contactvib.model.checks.MEMORY_MAX`."""
    u = model.units
    ymax, vmax = STATE_MAX * u.y_um, STATE_MAX * u.ydot_mm_s
    y_um = u.y_static_um if y_um is None else check_range("y", y_um, u.y_offset_um - ymax, True,
                                                          "um (|y - y_e| <= 1e6 y0)", upper=u.y_offset_um + ymax)
    ydot_mm_s = check_range("ydot", ydot_mm_s, -vmax, True, "mm/s (|ydot| <= 1e6 y0 omega_n0)",
                            upper=vmax)
    n_periods = check_int("n_periods", n_periods, 1)
    samples_per_period = check_int("samples_per_period", samples_per_period, 2)
    per_period = _BYTES_PER_PERIOD + _BYTES_PER_SAMPLE * samples_per_period
    check_memory("n_periods", n_periods, float(n_periods) * per_period, MEMORY_MAX // per_period)
    return y_um, ydot_mm_s, n_periods, samples_per_period


@old_form("model", "excitation", "y_um", "ydot_mm_s", "n_periods", "samples_per_period", "rtol")
def simulate(excitation: Excitation, *, y_um: float | None = None, ydot_mm_s: float = 0.0,
             n_periods: int = 20, samples_per_period: int = 400, rtol: float = 1e-10) -> TimeHistory:
    """Integrate from y = ``y_um`` µm, ẏ = ``ydot_mm_s`` mm/s at phase 0 for ``n_periods``.

    ``y_um`` defaults to the static deflection y0. The time history is sampled from the
    integrator's dense output (``samples_per_period`` points per excitation period).
    """
    model = check_excitation(excitation).model
    y_um, ydot_mm_s, n_periods, samples_per_period = check_start(model, y_um, ydot_mm_s, n_periods,
                                                                 samples_per_period)
    rtol = check_range("rtol", rtol, 0.0, False)
    check_work(excitation, 1, n_periods, "--periods")
    rows = max(4096.0, 2.0 * steps_per_period(excitation))  # step records per period, with room
    row_bytes = rows * REC_WIDTH * 8
    check_memory("n_periods", n_periods, n_periods * row_bytes, int(MEMORY_MAX // row_bytes))
    z = np.array(model.units.state(y_um, ydot_mm_s))
    hist = _history(model, excitation, z, n_periods, samples_per_period, rtol)
    model.check_motion(float(np.max(hist.y_um)), "the trajectory")
    return hist


@old_form("model", "excitation", "attractor", "n_periods", "samples_per_period")
def attractor_history(excitation: Excitation, attractor: Attractor, *, n_periods: int | None = None,
                      samples_per_period: int = 800) -> TimeHistory:
    """Time history over ``n_periods`` (default: two orbit periods, at least 3) of an attractor."""
    model = check_excitation(excitation).model
    if n_periods is None:
        n_periods = max(3, 2 * (attractor.period or 4))
    return _history(model, excitation, attractor.state, n_periods, samples_per_period, 1e-12)
