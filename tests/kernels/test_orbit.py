"""The one orbit measurement (``_kernels.orbit.measure_orbit``) against exact and independent
results.

* A pure flight, x'' = (1 + p cos rτ)/m2 (x ≤ 0 throughout), has the closed form
  x = x0 + v0 τ + τ²/(2 m2) + p (1 − cos rτ)/(m2 r²): its single minimum, the flight
  fraction 1 and, for v0 > 0 (x' > 0, no extremum), the range over the step starts.
* The scipy reference orbits (``tests/data/reference.json``: DOP853 at rtol 1e-12, extrema from
  the roots of x'): x_min, x_max and the minima and extrema counts.
* The tracer's row (``describe.describe_point``), the continuation's ``orbit_range`` and
  ``steady.orbits.describe_orbit`` report the same numbers for the same orbit.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from contactvib import ContactModel
from contactvib._kernels.continuation import orbit_range
from contactvib._kernels.describe import describe_point, new_rows
from contactvib._kernels.flow import REC_X, STATUS_OK, STATUS_RECORD_FULL
from contactvib._kernels.orbit import RECORD_CAP_MAX, measure_orbit, record_orbit, record_steps
from contactvib._kernels.shooting import newton_orbit
from contactvib.steady.orbits import describe_orbit

MODEL = ContactModel()
REFERENCE = json.loads((Path(__file__).parents[1] / "data" / "reference.json").read_text())
RTOL = 1e-12


def _flight(x0, v0, par):
    m2, _l, _c, p, r = par
    def x(t):
        return x0 + v0 * t + t * t / (2 * m2) + p * (1 - math.cos(r * t)) / (m2 * r * r)

    def v(t):
        return v0 + t / m2 + p * math.sin(r * t) / (m2 * r)

    return x, v


def _record(z, k, par):
    rec, z_end, t_flight, _n_ev, st = record_steps(np.asarray(z, float), 0.0, k, par, RTOL, 16,
                                                   RECORD_CAP_MAX)
    assert st == STATUS_OK
    return rec, z_end, t_flight


def test_flight_minimum_and_fraction_are_exact():
    """Deep in flight with v0 < 0: one minimum where x' = 0, all the period in flight; the top
    of the range is the higher end of the span (a single extremum is not a range)."""
    par = MODEL.excitation(0.65, 300.0).kernel_parameters()
    T = 2 * math.pi / par[4]
    x0, v0 = -1e4, -0.5 * T / par[0]  # x' = 0 half-way through the period (at p = 0)
    x, v = _flight(x0, v0, par)
    rec, z_end, t_flight = _record((x0, v0), 1, par)
    assert abs(z_end[0] - x(T)) < 1e-12 * abs(x0)
    xmin, xmax, flight, n_min, t_e, x_e, is_min = measure_orbit(rec, t_flight, 1, par[4])
    t_star = brentq(v, 0.0, T, xtol=1e-15)
    assert n_min == 1 and list(is_min) == [True]
    assert abs(t_e[0] - t_star) < 1e-9 * T
    assert xmin == x_e[0]
    assert abs(xmin - x(t_star)) < 1e-13 * abs(x0)
    assert abs(xmax - max(x0, x(T))) < 1e-12 * abs(x0)
    assert abs(flight - 1.0) < 1e-14


def test_no_extremum_takes_the_range_of_the_ends():
    """x' > 0 throughout: the range is [x(0), x(T)], one rule everywhere."""
    par = MODEL.excitation(0.65, 300.0).kernel_parameters()
    T = 2 * math.pi / par[4]
    z = np.array([-1e4, 1.0])
    x, _v = _flight(z[0], z[1], par)
    rec, _z_end, t_flight = _record(z, 1, par)
    xmin, xmax, flight, n_min, t_e, _x_e, _m = measure_orbit(rec, t_flight, 1, par[4])
    assert t_e.size == 0 and n_min == 0 and abs(flight - 1.0) < 1e-14
    assert xmin == z[0] and xmin == rec[0, REC_X]
    assert abs(xmax - x(T)) < 1e-12 * abs(z[0])  # x at the end of the span
    # the continuation's measurement follows the same rule (it used to report x(0), x(0))
    r_min, r_max, r_flight, r_nmin, st = orbit_range(z, 1, par, RTOL)
    assert st == STATUS_OK and (r_min, r_max, r_flight, r_nmin) == (xmin, xmax, flight, n_min)


def test_record_grows_its_buffer_and_gives_the_same_record():
    par = MODEL.excitation(0.65, 360.0).kernel_parameters()
    z = np.array([1.0, 0.0])
    *_, st = record_orbit(z, 0.0, 2, par, RTOL, 4)
    assert st == STATUS_RECORD_FULL
    rec_a, ze_a, tf_a, ne_a, st_a = record_steps(z, 0.0, 2, par, RTOL, 4, 0)
    rec_b, ze_b, tf_b, ne_b, st_b = record_orbit(z, 0.0, 2, par, RTOL, 100_000)
    assert st_a == st_b == STATUS_OK and np.array_equal(rec_a, rec_b)
    assert np.array_equal(ze_a, ze_b) and tf_a == tf_b and ne_a == ne_b
    # a bound stops the growth
    *_, st = record_steps(z, 0.0, 2, par, RTOL, 4, 16)
    assert st == STATUS_RECORD_FULL


def _reference_orbit(o):
    par = MODEL.excitation(o["pa_over_q"], o["f_e"]).kernel_parameters()
    oz, oM = np.empty(2), np.empty((2, 2))
    st, _res = newton_orbit(np.asarray(o["strobe"], float), o["period"], par, RTOL, RTOL, 1e-10,
                            12, oz, oM)
    assert st == STATUS_OK
    return par, oz, oM


def _id(o):
    return f"{o['pa_over_q']}Q-{o['f_e']}Hz-{o['label']}"


@pytest.mark.parametrize("o", REFERENCE["orbits"], ids=_id)
def test_reference_orbits_are_measured_as_scipy_does(o):
    par, z, _M = _reference_orbit(o)
    k = o["period"]
    rec, _z_end, t_flight = _record(z, k, par)
    xmin, xmax, flight, n_min, t_e, _x_e, _m = measure_orbit(rec, t_flight, k, par[4])
    scale = max(1.0, abs(o["x_min"]), abs(o["x_max"]))
    assert abs(xmin - o["x_min"]) < 1e-9 * scale
    assert abs(xmax - o["x_max"]) < 1e-9 * scale
    assert n_min == o["minima_per_period"] and t_e.size == o["n_extrema"]
    assert (flight > 0.0) == (o["x_min"] < 0.0) and 0.0 <= flight < 1.0


@pytest.mark.parametrize("o", [REFERENCE["orbits"][0], REFERENCE["orbits"][-1]], ids=_id)
def test_tracer_continuation_and_describe_orbit_measure_alike(o):
    par, z, M = _reference_orbit(o)
    k = o["period"]
    rows = new_rows(1)
    z_end = np.empty(2)
    assert describe_point(z, k, par, RTOL, rows, 0, z_end) == STATUS_OK
    xmin, xmax, flight, n_min, st = orbit_range(z, k, par, RTOL)
    assert st == STATUS_OK
    assert (rows.xmin[0], rows.xmax[0], rows.flight[0], rows.n_min[0]) == (xmin, xmax, flight,
                                                                          n_min)
    exc = MODEL.excitation(o["pa_over_q"], o["f_e"])
    att = describe_orbit(exc, z, k, monodromy=M)
    y_um = MODEL.y0 * 1e6
    assert att.ymin_um == xmin * y_um and att.ymax_um == xmax * y_um
    assert att.contact_loss_fraction == flight and att.minima_per_period == n_min
    assert att.extrema_t_ms.size == rows.n_ext[0]
