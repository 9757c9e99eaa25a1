"""The event-located DOP853 flow and the shooting kernels against exact and independent results.

Equation (``x = y/y0``, ``τ = ω_n0 t``, ``par = [m2, l, c, p, r]``)::

    x'' = [1 − x^m2 − c x^l x' + p cos(r τ)] / m2    contact (x > 0)
    x'' = [1 + p cos(r τ)] / m2                      flight  (x ≤ 0)

Checks: convergence to closed-form solutions (flight parabola + cosine, the linear forced damped
oscillator), the exact re-contact instant of a free flight, the linear frequency response at small
excitation (S2.2: the linear natural frequency f_n0 and damping ratio ζ), agreement with the
scipy reference (``tests/data/reference.json``, made by ``tests/data/make_reference.py``), and
the monodromy with saltation matrices against finite differences.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib._kernels.flow import REC_H, REC_MODE, REC_T, REC_WIDTH, STATUS_OK, advance, initial_mode
from contactvib._kernels.shooting import newton_orbit, strobe_map
from contactvib.testing import scipy_in_contact

MODEL = ContactModel()
NOREC = np.zeros((0, REC_WIDTH))
NOJAC = np.empty((0, 0))
TOLS = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
REFERENCE = json.loads((Path(__file__).parents[1] / "data" / "reference.json").read_text())


def _advance(z, t0, t1, par, tol, contact=None, rec=NOREC):
    y = np.array(z, dtype=float)
    mode = initial_mode(y[0], y[1]) if contact is None else contact
    contact, _h, irec, n_steps, t_flight, n_events, status = advance(
        y, float(t0), float(t1), mode, 0.01, np.asarray(par, float), tol, tol, rec, 0, 10**7)
    assert status == STATUS_OK
    return y, contact, irec, n_events, t_flight


def _rel_err(y, exact):
    exact = np.asarray(exact, float)
    return np.max(np.abs(y - exact)) / max(1.0, np.max(np.abs(exact)))


def _check_convergence(errors):
    """Error falls with the tolerance (roughly proportionally) and is ~1e-9 or less at 1e-12."""
    errors = np.asarray(errors)
    assert np.all(np.diff(np.log10(errors)) < -0.5), errors  # > 3x gain per 100x tighter tol
    slope = np.polyfit(np.log10(TOLS), np.log10(errors), 1)[0]
    assert 0.7 < slope < 1.5, (slope, errors)
    assert errors[-1] < 1e-9


# ---------------------------------------------------------------- (i) closed-form solutions
def test_flight_mode_converges_to_closed_form():
    """Flight, x'' = (1 + p cos rτ)/m2: x = x0 + v0 τ + τ²/(2 m2) + p (1 − cos rτ)/(m2 r²)."""
    m2, p, r = 2.0, 0.5, 1.3
    par = [m2, 1.0, 0.1, p, r]
    x0, v0, t1 = -100.0, -1.0, 10.0
    exact = (x0 + v0 * t1 + t1**2 / (2 * m2) + p * (1 - math.cos(r * t1)) / (m2 * r**2),
             v0 + t1 / m2 + p * math.sin(r * t1) / (m2 * r))
    errors = []
    for tol in TOLS:
        y, contact, _, n_ev, t_fl = _advance([x0, v0], 0.0, t1, par, tol)
        assert not contact and n_ev == 0 and t_fl == pytest.approx(t1, rel=1e-14)
        errors.append(max(_rel_err(y, exact), 1e-16))
    # the polynomial part is integrated exactly, so the error saturates early: only monotone-ish
    assert errors[2] < 1e-3 * errors[0]
    assert errors[-1] < 1e-12


def _linear_response(t, x0, v0, c, p, r):
    """u = x − 1 of u'' + c u' + u = p cos rτ (underdamped), exact."""
    H = 1.0 / (1.0 - r * r + 1j * c * r)
    up0, upd0 = (H * p).real, (1j * r * H * p).real
    wd = math.sqrt(1.0 - c * c / 4.0)
    A = x0 - 1.0 - up0
    B = (v0 - upd0 + 0.5 * c * A) / wd
    e = math.exp(-0.5 * c * t)
    cs, sn = math.cos(wd * t), math.sin(wd * t)
    forced = H * p * np.exp(1j * r * t)
    u = e * (A * cs + B * sn) + forced.real
    ud = e * (-0.5 * c * (A * cs + B * sn) + wd * (-A * sn + B * cs)) + (1j * r * forced).real
    return 1.0 + u, ud


def test_linear_contact_mode_converges_to_closed_form():
    """Contact with m2 = 1, l = 0: x'' = 1 − x − c x' + p cos rτ, a linear forced damped
    oscillator (x stays > 0, so no event)."""
    c, p, r = 0.1, 0.2, 1.7
    par = [1.0, 0.0, c, p, r]
    x0, v0, t1 = 1.1, 0.0, 20.0
    exact = _linear_response(t1, x0, v0, c, p, r)
    errors = []
    for tol in TOLS:
        y, contact, _, n_ev, _ = _advance([x0, v0], 0.0, t1, par, tol)
        assert contact and n_ev == 0
        errors.append(_rel_err(y, exact))
    _check_convergence(errors)


# ---------------------------------------------------------------- (ii) re-contact instant
def test_free_flight_recontact_time_is_exact():
    """p = 0, m2 = 2, start x = −1, x' = −3 in flight: x = −1 − 3τ + τ²/4 = 0 at τ* = 6 + √40,
    landing speed √10; the event instant equals τ* to 1e-12."""
    par = np.array([2.0, 1.0, 0.07, 0.0, 1.0])
    t_star = 6.0 + math.sqrt(40.0)
    rec = np.zeros((4000, REC_WIDTH))
    y, contact, irec, n_ev, t_flight = _advance([-1.0, -3.0], 0.0, 13.0, par, 1e-10, rec=rec)
    assert contact and n_ev == 1
    rows = rec[:irec]
    flight_rows = rows[rows[:, REC_MODE] < 0.5]
    t_event = flight_rows[-1, REC_T] + flight_rows[-1, REC_H]
    assert abs(t_event - t_star) <= 1e-12 * t_star
    assert abs(t_flight - t_star) <= 1e-12 * t_star
    # the first contact step starts on the event
    first_contact = rows[rows[:, REC_MODE] > 0.5][0]
    assert first_contact[REC_T] == pytest.approx(t_event, rel=1e-15)
    # landing state: integrate exactly to the event
    y_ev, contact_ev, _, n_ev2, _ = _advance([-1.0, -3.0], 0.0, t_event, par, 1e-12)
    assert abs(y_ev[0]) < 1e-11 and y_ev[1] == pytest.approx(math.sqrt(10.0), rel=1e-12)


# ---------------------------------------------------------------- (iii) linear response
@pytest.mark.parametrize("r", [0.5, 1.2])
def test_small_amplitude_matches_linear_frequency_response(r):
    """S2.2: at p = 1e-4 the paper model is a linear oscillator about x = 1,
    u'' = −u − 2ζ u' + (p/m2) cos rτ; steady amplitude and phase of x − 1 match
    H(r) = (p/m2)/(1 − r² + 2iζ r) to 1 % (nonlinear corrections are O(p))."""
    p = 1e-4
    exc = MODEL.excitation(p, r * MODEL.f_n0)
    par = exc.kernel_parameters()
    assert par[4] == pytest.approx(r, rel=1e-14)
    m2, zeta = MODEL.m2, MODEL.zeta
    H = (p / m2) / (1.0 - r * r + 2j * zeta * r)
    # start on the linear steady state so that only O(p²) transients remain
    z = np.array([1.0 + H.real, (1j * r * H).real])
    T = 2.0 * math.pi / r
    n_settle, n_grid = 10, 128
    z, _, _, _, _ = _advance(z, 0.0, n_settle * T, par, 1e-12)
    t = n_settle * T
    us = []
    contact = True
    for j in range(n_grid):
        t_next = n_settle * T + (j + 1) * T / n_grid
        us.append(z[0] - 1.0)
        z, contact, _, _, _ = _advance(z, t, t_next, par, 1e-12, contact=contact)
        t = t_next
    phase = r * (n_settle * T + np.arange(n_grid) * T / n_grid)
    us = np.array(us)
    amp = 2.0 / n_grid * np.sum(us * np.exp(-1j * phase))  # u ≈ Re(amp e^{i r τ})
    assert abs(amp) == pytest.approx(abs(H), rel=1e-2)
    dphi = np.angle(amp / H)
    assert abs(dphi) < 1e-2


# ---------------------------------------------------------------- (iv) scipy reference
@pytest.mark.parametrize("case", REFERENCE["end_states"],
                         ids=lambda c: f"{c['pa_over_q']}Q-{c['f_e']}Hz-{c['z0']}")
def test_end_states_match_scipy_reference(case):
    """5 periods from contact-losing starts agree with scipy DOP853 (mode by mode, rtol 1e-12)."""
    par = MODEL.excitation(case["pa_over_q"], case["f_e"]).kernel_parameters()
    out = np.empty(2)
    st = strobe_map(np.array(case["z0"], float), case["n_periods"], par, 1e-12, 1e-12, out, NOJAC)
    assert st == STATUS_OK
    assert _rel_err(out, case["z_end"]) < 1e-8


def test_reference_records_its_provenance():
    assert REFERENCE["method"] == "DOP853" and REFERENCE["rtol"] <= 1e-12
    assert REFERENCE["atol"] <= 1e-12 and REFERENCE["scipy_version"]
    assert REFERENCE["model"]["y0"] == pytest.approx(MODEL.y0, rel=1e-14)
    assert REFERENCE["model"]["f_n0"] == pytest.approx(MODEL.f_n0, rel=1e-14)
    assert REFERENCE["model"]["c"] == pytest.approx(MODEL.damping_coefficient, rel=1e-14)


# ---------------------------------------------------------------- (v) monodromy / saltation
def _fd_jacobian(z, k, par, tol=1e-13, d=1e-5):
    J = np.empty((2, 2))
    for j in range(2):
        h = d * max(1.0, abs(z[j]))
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        a, b = np.empty(2), np.empty(2)
        assert strobe_map(zp, k, par, tol, tol, a, NOJAC) == STATUS_OK
        assert strobe_map(zm, k, par, tol, tol, b, NOJAC) == STATUS_OK
        J[:, j] = (a - b) / (2.0 * h)
    return J


def _n_events(z, k, par):
    y = np.array(z, float)
    contact = initial_mode(y[0], y[1])
    T = 2.0 * math.pi / par[4]
    n = 0
    for _ in range(k):
        contact, _h, _i, _ns, _tf, ne, st = advance(y, 0.0, T, contact, 0.01, par, 1e-12, 1e-12,
                                                    NOREC, 0, 10**7)
        assert st == STATUS_OK
        n += ne
    return n


def _model_with_l(l):
    """Paper model with damping exponent l and h_n rescaled so that ζ (and c) are unchanged."""
    return MODEL.replace(l=l, h_n=MODEL.h_n * MODEL.y0 ** (MODEL.l - l))


ORBIT_STARTS = [
    (0.65, 360.0, (-45.6107, 0.5061), 1),
    (0.65, 360.0, (3.3857, -1.2839), 1),
    (0.65, 360.0, (-0.2552, 0.5431), 1),
    (0.70, 470.0, (3.0978978, -0.25592713), 2),
]


@pytest.mark.parametrize("l", [0.0, 1.0], ids=["l=0-discontinuous", "l=1-paper"])
@pytest.mark.parametrize("case", ORBIT_STARTS, ids=lambda c: f"{c[0]}Q-{c[1]}Hz-k{c[3]}")
def test_monodromy_matches_finite_differences(l, case):
    """∂P^k/∂z from the variational equation (with the saltation matrix at every switch; for
    l = 0 the damping force jumps at x = 0) equals a central finite-difference Jacobian."""
    pq, fe, z, k = case
    model = _model_with_l(l)
    assert model.damping_coefficient == pytest.approx(MODEL.damping_coefficient, rel=1e-12)
    par = model.excitation(pq, fe).kernel_parameters()
    z = np.array(z, float)
    assert _n_events(z, k, par) >= 2  # the trajectory loses and regains contact
    out_z, M = np.empty(2), np.empty((2, 2))
    assert strobe_map(z, k, par, 1e-12, 1e-12, out_z, M) == STATUS_OK
    J = _fd_jacobian(z, k, par)
    assert np.max(np.abs(M - J)) <= 1e-5 * np.max(np.abs(J)), (M, J)


@pytest.mark.parametrize("case", ORBIT_STARTS, ids=lambda c: f"{c[0]}Q-{c[1]}Hz-k{c[3]}")
def test_floquet_multipliers_of_refined_orbit(case):
    """Newton-refined orbits: the Floquet multipliers (eigenvalues of M) equal those of the FD
    Jacobian of P^k at the orbit point; the orbits are stable (|μ| < 1)."""
    pq, fe, z, k = case
    par = MODEL.excitation(pq, fe).kernel_parameters()
    oz, oM = np.empty(2), np.empty((2, 2))
    st, res = newton_orbit(np.array(z, float), k, par, 1e-12, 1e-12, 1e-10, 30, oz, oM)
    assert st == STATUS_OK and res <= 1e-10
    mu = np.sort_complex(np.linalg.eigvals(oM))
    mu_fd = np.sort_complex(np.linalg.eigvals(_fd_jacobian(oz, k, par)))
    assert np.max(np.abs(mu - mu_fd)) <= 1e-5 * max(1.0, np.max(np.abs(mu_fd)))
    assert np.max(np.abs(mu)) < 1.0
    # Liouville: det M = exp(−∫ c x^l / m2 dτ over the contact time) ∈ (0, 1)
    assert 0.0 < np.linalg.det(oM) < 1.0


# ---------------------------------------------------------------- (vi) any power law
@pytest.mark.parametrize("m2,l", [(1.5, 0.5), (2.0, 1.0), (3.0, 2.0), (1.0, 0.0)])
def test_power_law_in_contact_matches_scipy(m2, l):
    """In contact, x'' = [1 − x^m2 − c x^l x' + p cos rτ]/m2 integrated by the kernel (which takes
    pow-free paths for the exponents 1 and 2) equals scipy DOP853 at rtol 1e-12 on the same
    equation written independently here, to 1e-9 over three periods; and the monodromy equals
    finite differences to 1e-6."""
    model = ContactModel(m2=m2, l=l)
    par = model.excitation(0.2, 0.6 * model.f_n0).kernel_parameters()
    T = 2.0 * math.pi / par[4]
    z0 = np.array([1.05, 0.02])
    z_end = scipy_in_contact(par, z0, 3 * T)
    y, _contact, _irec, n_events, _tf = _advance(z0, 0.0, 3 * T, par, 1e-12)
    assert n_events == 0
    assert _rel_err(y, z_end) < 1e-9
    M = np.empty((2, 2))
    out = np.empty(2)
    assert strobe_map(z0, 1, par, 1e-12, 1e-12, out, M) == STATUS_OK
    assert np.max(np.abs(M - _fd_jacobian(z0, 1, par))) < 1e-6
