"""The Taylor-series flow (transients of the attractor search) against independent results.

Checks: the scipy DOP853 reference end states (rtol 1e-12, contact-losing, ``tests/data``), the
closed-form free flight, any integer power law against scipy (in contact) and against the
event-located DOP853 kernel at 1e-13 (through contact loss, same number of switching instants),
convergence with the tolerance, the crossing search on a polynomial with a dip between two
sample points, and the DOP853 fallback for non-integer exponents.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel, TableLaw
from contactvib._kernels.flow import REC_WIDTH, STATUS_OK, advance, initial_mode
from contactvib._kernels.taylor import (
    N_SUB,
    SERIES_EXPONENTIAL,
    SERIES_NONE,
    SERIES_TABLE,
    advance_state,
    advance_taylor,
    advance_taylor_table,
    crossing,
    is_polynomial_law,
    order_for,
    series_law,
)
from contactvib.testing import scipy_in_contact

REFERENCE = json.loads((Path(__file__).parents[1] / "data" / "reference.json").read_text())
MODEL = ContactModel()


def _taylor(z, t0, t1, par, tol):
    y = np.array(z, float)
    flow = advance_taylor_table if series_law(par) == SERIES_TABLE else advance_taylor
    contact, _h, _ns, t_flight, n_events, st = flow(y, t0, t1, initial_mode(y[0], y[1]), par, tol, 10**7)
    assert st == STATUS_OK
    return y, n_events, t_flight


def _dop853(z, t0, t1, par, tol):
    y = np.array(z, float)
    _c, _h, _i, _ns, t_flight, n_events, st = advance(
        y, t0, t1, initial_mode(y[0], y[1]), 0.01, par, tol, tol, np.empty((0, REC_WIDTH)), 0, 10**7)
    assert st == STATUS_OK
    return y, n_events, t_flight


def _rel_err(y, exact):
    exact = np.asarray(exact, float)
    return float(np.max(np.abs(y - exact)) / max(1.0, np.max(np.abs(exact))))


@pytest.mark.parametrize("case", REFERENCE["end_states"],
                         ids=lambda c: f"{c['pa_over_q']}Q-{c['f_e']}Hz-{c['z0']}")
def test_end_states_match_scipy_reference(case):
    """5 periods from contact-losing starts agree with scipy DOP853 (rtol 1e-12) to 1e-8."""
    par = MODEL.excitation(case["pa_over_q"], case["f_e"]).kernel_parameters()
    T = 2.0 * math.pi / par[4]
    y, _ne, _tf = _taylor(case["z0"], 0.0, case["n_periods"] * T, par, 1e-12)
    assert _rel_err(y, case["z_end"]) < 1e-8


def test_free_flight_is_the_closed_form():
    """Far from the surface, x'' = (1 + p cos rτ)/m2 integrates to its closed form to 1e-13."""
    par = MODEL.excitation(0.9, 120.0).kernel_parameters()
    m2, p, r = par[0], par[3], par[4]
    x0, v0, t0 = -20000.0, -3.0, 0.7
    t1 = t0 + 2.0 * 2.0 * math.pi / r
    y, n_events, t_flight = _taylor([x0, v0], t0, t1, par, 1e-10)
    d = t1 - t0
    v = v0 + d / m2 + p / (m2 * r) * (math.sin(r * t1) - math.sin(r * t0))
    x = x0 + v0 * d + d * d / (2 * m2) + p / (m2 * r) * (
        -(math.cos(r * t1) - math.cos(r * t0)) / r - d * math.sin(r * t0))
    assert n_events == 0 and t_flight == pytest.approx(d, rel=1e-14)
    assert abs(y[0] - x) / abs(x) < 1e-13 and abs(y[1] - v) / max(1, abs(v)) < 1e-13


def _law(m2, l):
    """A contact with exponents (m2, l) and the paper's nondimensional damping c (h_n rescaled:
    with the paper's h_n and c_n, other exponents give c from 1e-11 to 1e4)."""
    c_paper = MODEL.excitation(0.5, 500.0).kernel_parameters()[2]
    model = ContactModel(m2=m2, l=l, h_n=1.0)  # c is proportional to h_n
    c = model.excitation(0.5, 500.0).kernel_parameters()[2]
    return ContactModel(m2=m2, l=l, h_n=c_paper / c)


@pytest.mark.parametrize("m2,l", [(2.0, 1.0), (3.0, 0.0), (1.0, 1.0), (3.0, 2.0), (4.0, 1.0)])
def test_integer_power_law_matches_scipy_in_contact(m2, l):
    """x'' = [1 − x^m2 − c x^l x' + p cos rτ]/m2, written independently here and integrated by
    scipy DOP853 at rtol 1e-12, equals the Taylor flow to 1e-9 over three periods."""
    model = _law(m2, l)
    par = model.excitation(0.2, 0.6 * model.f_n0).kernel_parameters()
    assert is_polynomial_law(par)
    T = 2.0 * math.pi / par[4]
    z0 = np.array([1.05, 0.02])
    z_end = scipy_in_contact(par, z0, 3 * T)
    y, n_events, _tf = _taylor(z0, 0.0, 3 * T, par, 1e-11)
    assert n_events == 0
    assert _rel_err(y, z_end) < 1e-9


def _taylor_against_dop853(par) -> int:
    """4 periods from several starts: the Taylor flow at 1e-12 and the DOP853 kernel at 1e-13
    cross x = 0 the same number of times and agree to 1e-8, with the same time in flight to
    1e-8; returns the crossings."""
    T = 2.0 * math.pi / par[4]
    crossed = 0
    for z0 in ([1.0, 0.0], [3.0, -1.0], [-5.0, 0.5], [0.2, 2.0]):
        yt, nt, ft = _taylor(z0, 0.0, 4 * T, par, 1e-12)
        yd, nd, fd = _dop853(z0, 0.0, 4 * T, par, 1e-13)
        assert nt == nd
        assert _rel_err(yt, yd) < 1e-8
        assert abs(ft - fd) < 1e-8 * T
        crossed += nt
    return crossed


@pytest.mark.parametrize("m2,l,pa,fe_ratio", [(2.0, 1.0, 0.65, 360 / 1485), (3.0, 0.0, 0.8, 0.45),
                                              (1.0, 1.0, 0.9, 0.8), (3.0, 2.0, 0.85, 0.3)])
def test_contact_losing_trajectories_match_dop853(m2, l, pa, fe_ratio):
    """Through loss of contact and re-contact (impacts after flight), 4 periods from several
    starts: the Taylor flow at 1e-12 and the DOP853 kernel at 1e-13 cross x = 0 the same
    number of times and agree to 1e-8, with the same time in flight to 1e-8."""
    model = _law(m2, l)
    par = model.excitation(pa, fe_ratio * model.f_n0).kernel_parameters()
    crossed = _taylor_against_dop853(par)
    assert crossed > 0  # the cases do lose contact


def test_error_falls_with_the_tolerance():
    """One period of the main resonance at 360 Hz, 0.65 Q (long flight, stiff impact): the error
    against scipy (rtol 1e-12) falls with the tolerance, by at least 1000 from 1e-3 to 1e-9."""
    case = next(c for c in REFERENCE["end_states"] if c["z0"][0] < -40)
    par = MODEL.excitation(case["pa_over_q"], case["f_e"]).kernel_parameters()
    T = 2.0 * math.pi / par[4]
    errs = [_rel_err(_taylor(case["z0"], 0.0, case["n_periods"] * T, par, tol)[0], case["z_end"])
            for tol in (1e-3, 1e-6, 1e-9)]
    assert errs[0] > 10 * errs[1] > 100 * errs[2]
    assert errs[2] < 1e-9
    assert order_for(1e-6) < order_for(1e-10)


def test_crossing_finds_a_dip_between_sample_points():
    """x(s) = (s − s*)² − d, s* midway between two of the N_SUB sample points: positive at every
    sample point but below zero between them. The first root s* − √d is returned."""
    h = 1.0
    s_star = (4.5) / N_SUB
    d = 0.25 * (0.5 / N_SUB) ** 2  # the dip: positive at s* ± 0.5/N_SUB
    N = 2
    X = np.array([s_star**2 - d, -2 * s_star, 1.0])
    V = np.array([-2 * s_star, 2.0, 0.0])
    s = crossing(True, X, V, N, h, np.empty((2, N_SUB + 1)))
    assert s == pytest.approx(s_star - math.sqrt(d), rel=1e-12)
    # shallower than zero: no crossing
    X[0] = s_star**2 + d
    assert crossing(True, X, V, N, h, np.empty((2, N_SUB + 1))) == -1.0


def test_crossing_from_the_surface_is_not_at_zero():
    """Right after a switch (x = 0) the search runs on x(s)/s: a grazing contact x(s) = s(0.1 − s)
    leaves again at s = 0.1, not at s = 0."""
    X = np.array([0.0, 0.1, -1.0])
    V = np.array([0.1, -2.0, 0.0])
    s = crossing(True, X, V, 2, 0.5, np.empty((2, N_SUB + 1)))
    assert s == pytest.approx(0.1, rel=1e-12)


def test_non_integer_exponent_falls_back_to_dop853():
    model = ContactModel(m2=1.5, l=0.5)
    par = model.excitation(0.6, 0.5 * model.f_n0).kernel_parameters()
    assert not is_polynomial_law(par)
    T = 2.0 * math.pi / par[4]
    y1 = np.array([0.5, 0.3])
    out = advance_state(y1, 0.0, T, True, 0.01, par, 1e-10, 10**6)
    y2, n2, _f2 = _dop853([0.5, 0.3], 0.0, T, par, 1e-10)
    assert out[5] == STATUS_OK and out[4] == n2
    assert np.array_equal(y1, y2)


@pytest.mark.parametrize("kw, exc", [({"damping": "hunt-crossley"}, ("force", 0.65, 360.0)),
                                     ({"damping": "hunt-crossley", "alpha": 60.0, "preload": 1.0},
                                      ("force", 0.8, 700.0)),
                                     ({"damping": "hunt-crossley", "m2": 3.0, "c_n": 1e23}, ("base", 0.05, 900.0))])
def test_hunt_crossley_on_the_power_spring_takes_the_taylor_flow(kw, exc):
    """Hunt–Crossley damping on the power spring, c f_s(x) x' = c x^m2 x', is the power damping
    with l = m2: the Taylor flow takes it, through loss of contact and impacts, and agrees with
    the DOP853 kernel (1e-13) to 1e-8 with the same crossings and time in flight (as the power
    law's test above)."""
    from contactvib import Excitation

    model = ContactModel(**kw)
    e = model.excitation(exc[1], exc[2]) if exc[0] == "force" else Excitation.base(model, exc[2], u_um=exc[1])
    par = e.kernel_parameters()
    assert par.size > 5 and is_polynomial_law(par)
    crossed = _taylor_against_dop853(par)
    assert crossed > 0
    for other in ({"law": "exponential", "damping": "hunt-crossley"}, {"damping": "hunt-crossley", "m2": 1.5,
                                                                       "c_n": 1e13}):
        assert not is_polynomial_law(ContactModel(**other).excitation(0.3, 900.0).kernel_parameters())


EXPONENTIAL_CASES = [({"law": "exponential"}, ("force", 0.65, 360.0)),
                     ({"law": "exponential", "l": 2.0}, ("force", 0.8, 700.0)),
                     ({"law": "exponential", "l": 0.0, "h_n": 1e3}, ("force", 0.9, 1200.0)),
                     ({"law": "exponential", "damping": "hunt-crossley", "preload": 0.5}, ("force", 0.8, 700.0)),
                     ({"law": "exponential"}, ("base", 0.05, 900.0))]


def _excitation(model, exc):
    from contactvib import Excitation

    return model.excitation(exc[1], exc[2]) if exc[0] == "force" else Excitation.base(model, exc[2], u_um=exc[1])


@pytest.mark.parametrize("kw, exc", EXPONENTIAL_CASES)
def test_exponential_law_takes_the_taylor_flow(kw, exc):
    """The exponential spring b (e^{ax} − 1) with power damping of integer exponent or
    Hunt–Crossley damping has its own Taylor recurrence (series of e^{ax} from G' = a x' G): the
    Taylor flow takes it, through loss of contact and impacts, and agrees with the DOP853 kernel
    (1e-13) to 1e-8 with the same crossings and time in flight."""
    par = _excitation(ContactModel(**kw), exc).kernel_parameters()
    assert series_law(par) == SERIES_EXPONENTIAL and not is_polynomial_law(par)
    assert _taylor_against_dop853(par) > 0
    for other in ({"law": "exponential", "l": 1.5, "h_n": 1e6},):
        assert series_law(ContactModel(**other).excitation(0.3, 900.0).kernel_parameters()) == SERIES_NONE


@pytest.mark.parametrize("kw, exc", EXPONENTIAL_CASES[::2])
def test_exponential_law_matches_the_si_scipy_reference(kw, exc):
    """Three periods from a contact-losing start: the Taylor flow at 1e-12 equals scipy DOP853
    (rtol 1e-12) on the SI equation written independently (``contactvib.testing.model_ode``, located
    contact events) to 1e-8 of the state, with the same number of contact switches."""
    from contactvib.testing import integrate_contact, model_ode

    model = ContactModel(**kw)
    e = _excitation(model, exc)
    par = e.kernel_parameters()
    w_n0 = 2.0 * math.pi * model.f_n0
    T = 2.0 * math.pi / par[4]
    z0 = np.array([2.0, -0.5])
    y, n_events, _tf = _taylor(z0, 0.0, 3 * T, par, 1e-12)
    tr = integrate_contact(model_ode(model, e), z0[0] * model.y0, z0[1] * model.y0 * w_n0, 0.0,
                           3 * T / w_n0, rtol=1e-12, y_scale=model.y0, v_scale=model.y0 * w_n0)
    assert n_events == tr.n_switches > 0
    assert _rel_err(y, [tr.y / model.y0, tr.ydot / (model.y0 * w_n0)]) < 1e-8


def _table_reference(model, e, z0, n_periods, rtol=1e-12):
    """End state (x, x') and contact switches of the table law from ``z0`` (nondimensional),
    integrated in SI by scipy DOP853 segment by segment: on each of the table's intervals the
    spring is scipy's own PCHIP cubic of that interval (continued past its ends), and reaching a
    row or y = 0 is a terminal event, so no step straddles a row (where the curve is only C¹)."""
    from scipy.integrate import solve_ivp
    from scipy.interpolate import PchipInterpolator

    d, F = model.table.deflection_m, model.table.load_n
    pp = PchipInterpolator(d, F)
    slope_end = float(pp.derivative()(d[-1]))
    n = d.size
    M, Q = model.M, model.M * model.g
    W = Q + model.preload
    w, w_n0 = 2.0 * math.pi * e.f_e, 2.0 * math.pi * model.f_n0

    def spring(y, seg):
        if seg == n - 1:
            return F[-1] + slope_end * (y - d[-1])
        u = y - d[seg]
        c = pp.c[:, seg]
        return ((c[0] * u + c[1]) * u + c[2]) * u + c[3]

    def rate(y, seg):
        return model.alpha * spring(y, seg) if model.damping == "hunt-crossley" else model.S * model.h_n * y**model.l

    def bound(level, direction):
        def ev(t, s):
            return s[0] - level

        ev.terminal, ev.direction = True, direction
        return ev

    s = np.array([z0[0] * model.y0, z0[1] * model.y0 * w_n0])
    t, t1 = 0.0, n_periods / e.f_e
    contact = s[0] > 0.0
    seg = min(int(np.searchsorted(d, s[0], side="right")) - 1, n - 1) if contact else 0
    switches = 0
    while t < t1:
        if contact:
            events = [bound(d[seg], -1.0)] + ([bound(d[seg + 1], 1.0)] if seg < n - 1 else [])

            def rhs(tt, q, g=seg):
                return [q[1], (W + e.pa_over_q * Q * math.cos(w * tt) - spring(q[0], g) - rate(q[0], g) * q[1]) / M]
        else:
            events = [bound(0.0, 1.0)]

            def rhs(tt, q):
                return [q[1], (W + e.pa_over_q * Q * math.cos(w * tt)) / M]
        sol = solve_ivp(rhs, (t, t1), s, method="DOP853", rtol=rtol,
                        atol=rtol * np.array([model.y0, model.y0 * w_n0]), events=events)
        t, s = float(sol.t[-1]), sol.y[:, -1].copy()
        if sol.status != 1:
            break
        hit = next(i for i, te in enumerate(sol.t_events) if te.size)
        if not contact or (seg == 0 and hit == 0):
            contact, seg, s[0] = not contact, 0, 0.0
            switches += 1
        else:
            seg += 1 if hit == 1 else -1
            s[0] = d[seg] if hit == 1 else d[seg + 1]
    return np.array([s[0] / model.y0, s[1] / (model.y0 * w_n0)]), switches


def _tables():
    even = TableLaw.from_function(lambda y: 0.0009 * 4.52e16 * y**2, 3e-6, 31, source="power law, 31 rows")
    y = 3e-6 * np.linspace(0.0, 1.0, 25) ** 1.5  # rows closer near the origin, as measured ones often are
    uneven = TableLaw(y, 0.0009 * 4.52e16 * y**2 * (1.0 + 2e5 * y), source="uneven")
    return even, uneven


@pytest.mark.parametrize("table, damping, pa, f_e, z0", [
    (0, "power", 0.65, 360.0, [0.2, 2.0]), (0, "hunt-crossley", 0.8, 700.0, [3.0, -1.0]),
    (1, "power", 0.8, 700.0, [-5.0, 0.5]), (1, "hunt-crossley", 0.65, 360.0, [15.0, 0.0])])
def test_table_law_takes_the_taylor_flow_row_by_row(table, damping, pa, f_e, z0):
    """The table law in contact: the Taylor series of each interval's cubic, every row an event.
    Two periods through loss of contact and impacts (and from beyond the last row, on the linear
    continuation) equal a scipy DOP853 reference integrated interval by interval on scipy's own
    PCHIP (rtol 1e-12) to 1e-8, with the same number of contact switches (and the DOP853
    kernel, whose steps straddle the rows, to 1e-6)."""
    model = ContactModel(law=_tables()[table], damping=damping)
    e = model.excitation(pa, f_e)
    par = e.kernel_parameters()
    assert series_law(par) == SERIES_TABLE
    T = 2.0 * math.pi / par[4]
    y, n_events, _tf = _taylor(z0, 0.0, 2 * T, par, 1e-12)
    ref, switches = _table_reference(model, e, z0, 2)
    assert n_events == switches > 0
    assert _rel_err(y, ref) < 1e-8
    yd, nd, _fd = _dop853(z0, 0.0, 2 * T, par, 1e-13)
    assert nd == n_events and _rel_err(yd, ref) < 1e-6
