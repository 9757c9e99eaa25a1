"""The Lyapunov spectrum (Benettin/QR on the period map with its monodromy) against its exact
identities and an independent scipy reference.

* The damping identity: λ1 + λ2 = −⟨S h_n y^l / M⟩ (time average over all time, 0 in flight),
  integrated independently of the variational equation (Gauss–Legendre on the dense output in the
  kernel; scipy's own quadrature component in the reference), on the chaotic attractor of the
  paper's model at 0.75 Q, 816.5 Hz and on periodic orbits (Liouville).
* A periodic orbit: Benettin's exponents agree with ln|μ_i|/T within their error bars; the
  reported ln|μ_i|/T agree with multipliers from scipy's variational equation to 1e-6.
* scipy's Benettin loop (``contactvib.testing.benettin_reference``, DOP853 at 1e-10, located
  switches) gives the kernel's finite-time exponents over 100 periods of the chaotic attractor.
* An n-DOF System: the sum of its 2n exponents is −⟨tr M⁻¹C(t)⟩ (the rocking unit).
"""

import math

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib.steady.lyapunov import (
    benettin,
    closed_curve,
    floquet_spectrum,
    kaplan_yorke,
    lyapunov_spectrum,
    system_lyapunov_spectrum,
)
from contactvib.steady.orbits import refine_orbit
from contactvib.testing import benettin_reference, integrate_modes, power_law_variational_rhs

MODEL = ContactModel()
#: A point of the chaotic attractor at 0.75 Q, 816.5 Hz (phase 0): y [µm], ẏ [mm/s].
CHAOS_STATE = (-0.20081059854145153, -4.106686232024136)


@pytest.fixture(scope="module")
def chaos():
    exc = MODEL.excitation(0.75, 816.5)
    return exc, lyapunov_spectrum(exc, CHAOS_STATE, periods=20_000, transient_periods=0)


def _combined_se(spec) -> float:
    return math.sqrt(float(np.sum(spec.stderr_per_s ** 2)) + spec.damping_stderr_per_s ** 2)


def test_chaotic_attractor_spectrum_and_damping_identity(chaos):
    """λ1 > 3 stderr (chaotic), λ1 + λ2 = −⟨S h_n y^l/M⟩ within the error bar (and to 1e-6:
    both sum the same run), Kaplan–Yorke dimension between 2 and 3."""
    exc, s = chaos
    assert s.exponents_per_s[0] > 3.0 * s.stderr_per_s[0] > 0.0
    assert s.attractor_type == "chaotic"
    assert s.exponents_per_s[0] > s.exponents_per_s[1]
    assert abs(s.sum_per_s - s.damping_average_per_s) <= 3.0 * _combined_se(s)
    assert s.sum_per_s == pytest.approx(s.damping_average_per_s, rel=1e-6)
    assert 2.0 < s.kaplan_yorke_dimension < 3.0
    assert s.kaplan_yorke_dimension == pytest.approx(
        2.0 + s.exponents_per_s[0] / abs(s.exponents_per_s[1]), rel=1e-12)
    assert 0.0 < s.contact_fraction < 1.0


def test_damping_average_from_scipy_on_the_chaotic_attractor(chaos):
    """The damping average of scipy's own trajectory (its quadrature component ∫ c x^l/m2 dτ over
    300 periods after the attractor's state) agrees with the kernel's λ1 + λ2 over 20 000 periods
    within 4 standard errors of a 300-period mean (the time averages of one ergodic attractor)."""
    exc, s = chaos
    logr, trace, _z = benettin_reference(exc.kernel_parameters(), MODEL.units.state(*CHAOS_STATE), 300)
    per_period = trace * exc.f_e  # ∫ tr J dτ per period → per second
    se = per_period.reshape(10, 30).mean(axis=1).std(ddof=1) / math.sqrt(10)
    assert abs(per_period.mean() - s.sum_per_s) <= 4.0 * se + 3.0 * _combined_se(s)
    # scipy's own Liouville identity, period by period: ln R11 + ln R22 = ∫ tr J dτ
    np.testing.assert_allclose(logr.sum(axis=1), trace, rtol=1e-7, atol=1e-9)


def test_kernel_against_scipy_benettin_short_run():
    """100 periods from the chaotic attractor's state, the same start: the kernel's exponents per
    period equal scipy's Benettin loop (DOP853 at 1e-10, located switches) to 2e-6."""
    exc = MODEL.excitation(0.75, 816.5)
    z = np.array(MODEL.units.state(*CHAOS_STATE))
    k = benettin(exc, z, 100, 10, 0, 1e-11)
    logr, trace, z_end = benettin_reference(exc.kernel_parameters(), z, 100, rtol=1e-11)
    ref = np.sort(logr.mean(axis=0))[::-1]
    np.testing.assert_allclose(k.exponents_per_period, ref, atol=2e-6)
    assert k.damping_average_per_s / exc.f_e == pytest.approx(trace.mean(), abs=2e-6)
    np.testing.assert_allclose(k.state, z_end, rtol=1e-5, atol=1e-5)


def _monodromy_scipy(exc, z, k):
    f_c, f_f = power_law_variational_rhs(exc.kernel_parameters())
    s = np.concatenate([z, [1.0, 0.0, 0.0, 1.0, 0.0]])
    tr = integrate_modes(f_c, f_f, s, 0.0, k * exc.tau_period, rtol=1e-12, atol=1e-12)
    return tr.y[2:6].reshape(2, 2), tr.y[6]


@pytest.mark.parametrize("k, y_um, ydot", [(2, -5.061820451075846, -5.19657688257),
                                           (3, -15.013068223023431, 1.4995459223380814),
                                           (1, 0.38485318729978546, -0.030350598743973403)])
def test_periodic_orbit_floquet_and_benettin(k, y_um, ydot):
    """Stable orbits at 0.75 Q, 816.5 Hz (periods 2, 3, 1): ln|μ_i|/T from the kernel's
    multipliers equal those of scipy's variational equation to 1e-6 (relative); Benettin's
    exponents (~20 000 periods, batches of whole orbits) agree with them within 4 standard
    errors + 1e-3 relative; their sum is the damping average (Liouville) and the Floquet sum to
    1e-6."""
    exc = MODEL.excitation(0.75, 816.5)
    z, M_kernel, _res = refine_orbit(exc, np.array(MODEL.units.state(y_um, ydot)), k)
    fl = floquet_spectrum(np.linalg.eigvals(M_kernel), k, exc.f_e)
    M, liouville = _monodromy_scipy(exc, z, k)
    ref = np.sort(np.log(np.abs(np.linalg.eigvals(M))) * exc.f_e / k)[::-1]
    np.testing.assert_allclose(fl.exponents_per_s, ref, rtol=1e-6)
    assert fl.sum_per_s == pytest.approx(liouville * exc.f_e / k, rel=1e-6)
    b = benettin(exc, z, 20 * k * (1000 // k), 20, 0)  # batches of whole orbits: no end bias in the sum
    assert np.all(np.abs(b.exponents_per_s - fl.exponents_per_s)
                  <= 4.0 * b.stderr_per_s + 1e-3 * np.abs(fl.exponents_per_s))
    assert b.sum_per_s == pytest.approx(b.damping_average_per_s, rel=1e-6)
    assert b.sum_per_s == pytest.approx(fl.sum_per_s, rel=1e-6)
    assert b.attractor_type != "chaotic" and fl.kaplan_yorke_dimension is None


def test_system_sum_equals_trace_of_damping():
    """The rocking unit (e = 1 cm offset: heave and pitch coupled) at 0.5 Q, 700 Hz: the sum of the
    four exponents equals −⟨tr M⁻¹C(t)⟩ over its periodic attractor (C with each patch's current
    damping rate), sampled at 2048 points per period, to 1e-3 relative; Benettin's exponents
    agree with the Floquet exponents within 4 standard errors + 1e-3 relative."""
    from contactvib.model.rocking import rocking_system
    from contactvib.steady.system_orbits import periodic_orbit, simulate_system

    system = rocking_system(MODEL, e=0.01)
    pa, fe = 0.5 * MODEL.Q, 700.0
    b = system_lyapunov_spectrum(system, pa, fe, periods=2000, batches=10, transient_periods=1000)
    orbit = periodic_orbit(system, pa, fe, system.kernel_form(pa, fe).scales.to_si(b.state), 1)
    fl = floquet_spectrum(orbit.floquet_multipliers, 1, fe)
    h = simulate_system(system, pa, fe, orbit.z[:2], orbit.z[2:], n_periods=1, samples_per_period=2048,
                        rtol=1e-12)
    Minv = np.linalg.inv(system.M)
    q_si = (h.q[:, :-1].T / 1e6)
    traces = []
    for q in q_si:
        C = np.array(system.C, float) + sum(c.damping_rate(c.deflection(q)) * np.outer(c.w, c.w)
                                            for c in system.contacts)
        traces.append(np.trace(Minv @ C))
    assert b.sum_per_s == pytest.approx(-np.mean(traces), rel=1e-3)
    assert fl.sum_per_s == pytest.approx(-np.mean(traces), rel=1e-3)
    assert np.all(np.abs(b.exponents_per_s - fl.exponents_per_s)
                  <= 4.0 * b.stderr_per_s + 1e-3 * np.abs(fl.exponents_per_s))


def test_closed_curve_circle_torus_and_cloud():
    """The section test: points of a circle visited at an irrational rotation are one closed curve,
    two interleaved circles (a period-2 torus) two, a random cloud and a periodic orbit none."""
    rng = np.random.default_rng(1)
    n = 400
    theta = 2.0 * math.pi * ((math.sqrt(5.0) - 1.0) / 2.0) * np.arange(n)
    circle = np.column_stack([1.0 + 0.3 * np.cos(theta), 0.5 * np.sin(theta)])
    circle += rng.normal(0.0, 1e-4, circle.shape)
    assert closed_curve(circle) == 1
    two = np.empty((2 * n, 2))
    two[0::2] = circle
    two[1::2] = circle + np.array([3.0, 0.0])
    assert closed_curve(two) == 2
    assert closed_curve(rng.normal(size=(n, 2))) == 0
    assert closed_curve(np.tile([[0.0, 1.0], [1.0, 0.0], [0.5, 0.5]], (100, 1))) == 0
    assert closed_curve(circle[:10]) == 0


def test_nearest_distances_equal_the_full_matrix_bit_for_bit():
    """The closed-curve test's nearest-neighbour distances (candidates by squared distance, hypot
    on those only) are exactly the minima of the full n × n matrix of np.hypot: random clouds,
    grids with exact ties and duplicate points, circles, points 1e-160 apart (squares underflow)."""
    from contactvib.steady.lyapunov import nearest_distances

    rng = np.random.default_rng(3)
    for trial in range(120):
        n = int(rng.integers(2, 700))
        p = [rng.random((n, 2)), rng.integers(0, 12, (n, 2)) / 11.0,
             np.column_stack([np.cos(t := 2.0 * math.pi * rng.random(n)), np.sin(t)]),
             rng.random((n, 2)) * 1e-160][trial % 4]
        d = np.hypot(p[:, None, 0] - p[None, :, 0], p[:, None, 1] - p[None, :, 1])
        np.fill_diagonal(d, np.inf)
        assert np.array_equal(nearest_distances(p).view(np.int64), d.min(axis=1).view(np.int64)), trial


def test_kaplan_yorke_of_the_flow():
    """D = j + Σλ/|λ_{j+1}| with the flow's zero exponent added; None unless λ1 > 0."""
    assert kaplan_yorke([-1.0, -2.0]) is None
    assert kaplan_yorke([0.0, -2.0]) is None
    assert kaplan_yorke([1.0, -4.0]) == pytest.approx(2.25)
    assert kaplan_yorke([1.0, 0.5, -0.5, -4.0]) == pytest.approx(4.25)
