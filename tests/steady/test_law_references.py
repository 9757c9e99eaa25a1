"""The contact-law and excitation families against independent references.

Every periodic attractor that :func:`find_attractors` reports for a law × excitation pair is
integrated again by scipy's DOP853 (rtol 1e-12) in SI units, with the contact events located and
the right-hand side switched there (:func:`contactvib.testing.integrate_contact`; the forces are
written in the helper from the model's parameters, the table law through scipy's own PCHIP), and
checked against exact identities of periodic motion:

* closure: the package's orbit point, converted to SI, comes back after k excitation periods
  (rel 1e-9 of the state scale; 1e-7 for the table law, whose PCHIP is only C¹ and costs both
  integrators accuracy at every knot), and not after fewer (minimal period);
* A_pp, y_min, y_max (rel 1e-8 of A_pp; table 1e-7), the strobe points, the minima count and the
  contact-loss fraction against the reference's located turning points and switches;
* mean contact force: over a period the slider's momentum returns, so ∫(F_s + F_d) dt = W k T,
  W = Q + F_pre (rel 1e-9 along the reference, 1e-7 from the package's own time history, 20,000
  samples a period, trapezoid rule);
* Liouville: the contact force is continuous at y = 0 (no saltation), so the product of the
  Floquet multipliers is exp(−∫ c_d(y) dt / M), c_d = S h_n y^l or α F_s(y) in contact
  (rel 1e-8); for Hunt–Crossley damping ∫ α F_s ẏ dt = α ∮ F_s dy = 0, so the product is
  exp(−α W k T / M) for every periodic orbit (rel 1e-9, no integration needed);
* base motion U equals the force M U (2π f_e)², a base acceleration A the force M A g_n: the
  same attractors, A_pp and strobe points to 1e-9 (relative).

The operating points are chosen where the attractors settle within a few hundred periods
(0.2–0.3 Q near 1000–1300 Hz), and each case has an orbit that loses contact.
"""

import math
import warnings

import numpy as np
import pytest

from contactvib import ContactModel, Excitation, attractor_history, find_attractors
from contactvib.model.laws import TableLaw
from contactvib.steady.attractors import UnsettledWarning
from contactvib.testing import integrate_contact, model_ode

PAPER = ContactModel()
G_N = 9.80665


def _table_csv(tmp_dir):
    """A 'measured' curve with non-uniform rows, through the CSV reader: F = S c_n y² (1 + y/1 µm)."""
    d_um = 3.0 * np.linspace(0.0, 1.0, 80) ** 1.5
    F = PAPER.S * PAPER.c_n * (d_um * 1e-6) ** 2 * (1.0 + d_um)
    path = tmp_dir / "table.csv"
    path.write_text("deflection_um,load_n\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(d_um, F)))
    return TableLaw.from_csv(path)


def _cases(tmp_dir):
    """id -> (model, excitation): each family once, the excitations on the power law with and
    without preload and on the exponential law."""
    pre = ContactModel(preload=1.0)
    expo = ContactModel(law="exponential")
    hc = ContactModel(damping="hunt-crossley")
    hc_exp = ContactModel(law="exponential", damping="hunt-crossley", preload=0.5)
    table = ContactModel(law=_table_csv(tmp_dir))
    table_hc = ContactModel(law=table.table, damping="hunt-crossley", alpha=25.0, preload=0.8)
    return {
        "power-preload-force": (pre, pre.excitation(0.3, 1300.0)),
        "exponential-force": (expo, expo.excitation(0.3, 1200.0)),
        "table-force": (table, table.excitation(0.3, 1200.0)),
        "hunt-crossley-force": (hc, hc.excitation(0.3, 1200.0)),
        "hunt-crossley-exponential-preload": (hc_exp, hc_exp.excitation(0.3, 1200.0)),
        "power-base-um": (PAPER, Excitation.base(PAPER, 1200.0, u_um=0.05)),
        "exponential-base-g": (expo, Excitation.base(expo, 1300.0, a_g=0.3)),
        "power-preload-harmonics": (pre, pre.excitation(0.2, 1000.0, harmonics=((2, 0.1, 30.0), (3, 0.05, -45.0)))),
        "table-hunt-crossley-preload-harmonics": (
            table_hc, table_hc.excitation(0.2, 1100.0, harmonics=((2, 0.08, -60.0), (4, 0.03, 90.0)))),
    }


CASE_IDS = ["power-preload-force", "exponential-force", "table-force", "hunt-crossley-force",
            "hunt-crossley-exponential-preload", "power-base-um", "exponential-base-g",
            "power-preload-harmonics", "table-hunt-crossley-preload-harmonics"]


@pytest.fixture(scope="module")
def searched(tmp_path_factory):
    """id -> (model, excitation, attractors): one search of 16 starts per case, shared."""
    cases = _cases(tmp_path_factory.mktemp("law"))
    out = {}
    for name, (m, exc) in cases.items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UnsettledWarning)  # the exponential law's slow bouncers
            res = find_attractors(exc, n_starts=16, seed=0)
        periodic = [a for a in res if a.period is not None]
        assert periodic, name
        out[name] = (m, exc, periodic)
    assert sorted(out) == sorted(CASE_IDS)
    return out


def _si_state(model, z):
    u = model.units
    return z[0] * u.y_um * 1e-6, z[1] * u.ydot_mm_s * 1e-3


def _reference(model, exc, a, n_periods=None, t0=0.0, z=None):
    """The scipy trajectory over the attractor's k periods (or ``n_periods``) from its state."""
    y, v = _si_state(model, a.state if z is None else z)
    k = a.period if n_periods is None else n_periods
    return integrate_contact(model_ode(model, exc), y, v, t0, t0 + k / exc.f_e, rtol=1e-12,
                             y_scale=model.y0, v_scale=model.y0 * model.omega_n0)


def _tol(name, tight, table):
    return table if name.startswith("table") else tight


@pytest.mark.parametrize("name", CASE_IDS)
def test_orbits_close_under_the_scipy_reference(searched, name):
    """Closure after k periods, not before; strobe points along the way."""
    m, exc, periodic = searched[name]
    tol = _tol(name, 1e-9, 1e-7)
    sy, sv = m.y0, m.y0 * m.omega_n0  # the state scale (x = 1, x' = 1)
    for a in periodic:
        y, v = _si_state(m, a.state)
        tr = _reference(m, exc, a)
        scale = max(1.0, abs(a.state).max())
        assert max(abs(tr.y - y) / sy, abs(tr.ydot - v) / sv) <= tol * scale, (a.period, a.app_um)
        T = 1.0 / exc.f_e
        pts = tr.sample(np.arange(a.period) * T)  # strobe points of the reference
        assert np.allclose(pts[0] * 1e6, a.strobe_y_um, rtol=0, atol=tol * scale * m.units.y_um)
        assert np.allclose(pts[1] * 1e3, a.strobe_ydot_mm_s, rtol=0, atol=tol * scale * m.units.ydot_mm_s)
        for j in range(1, a.period):  # minimal period
            assert max(abs(pts[0, j] - y) / sy, abs(pts[1, j] - v) / sv) > 1e-6 * scale


@pytest.mark.parametrize("name", CASE_IDS)
def test_orbit_measurements_match_the_scipy_reference(searched, name):
    """A_pp, y_min, y_max, minima count and contact-loss fraction from the located turning points
    and contact switches of the reference."""
    m, exc, periodic = searched[name]
    tol = _tol(name, 1e-8, 1e-7)
    assert any(a.loses_contact for a in periodic), "each case exercises the contact events"
    for a in periodic:
        tr = _reference(m, exc, a)
        app = (tr.ymax - tr.ymin) * 1e6
        assert a.app_um == pytest.approx(app, rel=tol)
        assert a.ymin_um == pytest.approx(tr.ymin * 1e6, abs=tol * app)
        assert a.ymax_um == pytest.approx(tr.ymax * 1e6, abs=tol * app)
        assert a.loses_contact == (tr.n_switches > 0) == (tr.ymin < 0.0)
        kT = a.period / exc.f_e
        assert a.contact_loss_fraction == pytest.approx(1.0 - tr.contact_time / kT, abs=1e-8)
        minima = sum(1 for t, _y, is_min in tr.turns if is_min and 0.0 < t < kT * (1 - 1e-12))
        assert a.minima_per_period == minima


@pytest.mark.parametrize("name", CASE_IDS)
def test_mean_contact_force_is_the_static_load(searched, name):
    """∫ (F_s + F_d) dt over k periods = W k T, W = Q + F_pre: along the reference (rel 1e-9)
    and from the package's own time history and spring force (rel 1e-7, trapezoid on 20,000
    samples a period)."""
    m, exc, periodic = searched[name]
    W = m.M * m.g + m.preload
    assert m.W == pytest.approx(W, rel=1e-15)
    for a in periodic:
        kT = a.period / exc.f_e
        tr = _reference(m, exc, a)
        assert tr.impulse / kT == pytest.approx(W, rel=1e-9)
        h = attractor_history(exc, a, n_periods=a.period, samples_per_period=20000)
        y, v, t = h.y_um * 1e-6, h.ydot_mm_s * 1e-3, h.t_ms * 1e-3
        Fs = -m.spring_force(y)  # the package's compiled spring force (0 in flight)
        rate = m.S * m.h_n * np.maximum(y, 0.0) ** m.l if m.damping == "power" else m.alpha * Fs
        Fc = np.where(y > 0.0, Fs + rate * v, 0.0)
        assert np.trapezoid(Fc, t) / (t[-1] - t[0]) == pytest.approx(W, rel=1e-7)


@pytest.mark.parametrize("name", CASE_IDS)
def test_liouville_floquet_determinant(searched, name):
    """Product of the Floquet multipliers = exp(−∫ c_d(y) dt / M) over the orbit (rel 1e-8)."""
    m, exc, periodic = searched[name]
    for a in periodic:
        tr = _reference(m, exc, a)
        det = np.prod(a.floquet_multipliers)
        assert abs(det.imag) <= 1e-12 * abs(det)
        assert det.real == pytest.approx(math.exp(-tr.damping_integral / m.M), rel=1e-8)


@pytest.mark.parametrize("name", ["hunt-crossley-force", "hunt-crossley-exponential-preload",
                                  "table-hunt-crossley-preload-harmonics"])
def test_hunt_crossley_determinant_closed_form(searched, name):
    """Hunt–Crossley damping: det = exp(−α W k T / M) for every periodic orbit (rel 1e-9)."""
    m, exc, periodic = searched[name]
    for a in periodic:
        kT = a.period / exc.f_e
        det = np.prod(a.floquet_multipliers).real
        assert det == pytest.approx(math.exp(-m.alpha * (m.M * m.g + m.preload) * kT / m.M), rel=1e-9)


def _same_sets(res_a, res_b, rtol):
    assert len(res_a) == len(res_b) > 0
    for a, b in zip(res_a, res_b):
        assert a.period == b.period and a.minima_per_period == b.minima_per_period
        assert a.app_um == pytest.approx(b.app_um, rel=rtol)
        scale = max(np.abs(b.strobe_y_um).max(), a.app_um)
        assert np.allclose(a.strobe_y_um, b.strobe_y_um, rtol=0, atol=rtol * scale)
        vscale = max(np.abs(b.strobe_ydot_mm_s).max(), 1e-300)
        assert np.allclose(a.strobe_ydot_mm_s, b.strobe_ydot_mm_s, rtol=0, atol=rtol * vscale)
        assert a.basin_fraction == b.basin_fraction


@pytest.mark.parametrize("law, f_e, u_um", [("power", 1200.0, 0.05), ("power", 360.0, 1.0),
                                            ("exponential", 1300.0, 0.04)])
def test_base_motion_equals_its_inertial_force(law, f_e, u_um):
    """Base motion U at f_e = force P_a = M U (2π f_e)² (A_pp and strobe points to 1e-9)."""
    m = ContactModel(law=law)
    base = Excitation.base(m, f_e, u_um=u_um)
    pa = m.M * u_um * 1e-6 * (2.0 * math.pi * f_e) ** 2 / (m.M * m.g)
    assert base.pa_over_q == pytest.approx(pa, rel=1e-14)
    assert base.P_a == pytest.approx(m.M * u_um * 1e-6 * (2.0 * math.pi * f_e) ** 2, rel=1e-14)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsettledWarning)
        res_b = find_attractors(base, n_starts=16)
        res_f = find_attractors(m.excitation(pa, f_e), n_starts=16)
    _same_sets(res_b, res_f, 1e-9)


@pytest.mark.parametrize("law, f_e, a_g", [("power", 1200.0, 0.3), ("exponential", 1300.0, 0.3)])
def test_base_acceleration_equals_its_inertial_force(law, f_e, a_g):
    """Base acceleration A [g] = force P_a = M A g_n (g_n = 9.80665 m/s²)."""
    m = ContactModel(law=law, preload=0.2)
    base = Excitation.base(m, f_e, a_g=a_g)
    pa = m.M * a_g * G_N / (m.M * m.g)
    assert base.pa_over_q == pytest.approx(pa, rel=1e-14)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsettledWarning)
        res_b = find_attractors(base, n_starts=16)
        res_f = find_attractors(m.excitation(pa, f_e), n_starts=16)
    _same_sets(res_b, res_f, 1e-9)


# ---------------------------------------------------------------------------------------------
# A table sampled from the power law reproduces the power law's attractors (README, 0.65 Q, 360 Hz)

#: ``contactvib attractors --pa 0.65 --fe 360`` (README): (period, minima, A_pp [µm]).
README_ORBITS = [(2, 1, 37.39), (1, 1, 11.436), (1, 2, 2.4027), (1, 3, 0.99929), (1, 4, 0.21522)]


def _power_table(n=1000, y_max=4e-6):
    return TableLaw.from_function(lambda y: PAPER.S * PAPER.c_n * y**PAPER.m2, y_max, n)


@pytest.fixture(scope="module")
def readme_power():
    exc = PAPER.excitation(0.65, 360.0)
    res = find_attractors(exc, n_starts=64, seed=0)
    assert [(a.period, a.minima_per_period) for a in res] == [(k, n) for k, n, _ in README_ORBITS]
    return res


def test_table_refines_the_readme_orbits(readme_power):
    """Each README orbit of the power law, refined under a 1000-row table of the same law up to
    4 µm: A_pp within 1e-3 of the README's printed value and within 1e-5 of the power law's,
    orbit point within 1e-4 of the state scale, same minima count."""
    from contactvib import describe_orbit, refine_orbit

    mt = ContactModel(law=_power_table())
    exc = mt.excitation(0.65, 360.0)
    for a, (k, n_min, app) in zip(readme_power, README_ORBITS):
        z, M, closure = refine_orbit(exc, a.state, a.period)
        assert closure <= 1e-10
        b = describe_orbit(exc, z, a.period, monodromy=M, closure=closure)
        assert (b.period, b.minima_per_period) == (k, n_min)
        assert b.app_um == pytest.approx(app, rel=1e-3)
        assert b.app_um == pytest.approx(a.app_um, rel=1e-5)
        assert np.max(np.abs(z - a.state)) <= 1e-4 * max(1.0, np.abs(a.state).max())
        assert b.floquet_abs_max < 1.0


def test_table_search_finds_the_readme_attractors():
    """The attractor search on the table law with the README's 512 starts (~15 s) lists the
    README's five attractors, A_pp within 1e-3, basins within 2 % absolute of the README's 4.88,
    42.19, 19.92, 4.69, 28.32 % (a few of the 512 starts lie on basin boundaries: observed
    differences up to 1 %)."""
    mt = ContactModel(law=_power_table())
    res = find_attractors(mt.excitation(0.65, 360.0), n_starts=512, seed=0)
    assert res.n_unsettled == 0 and res.n_failed == 0
    assert [(a.period, a.minima_per_period) for a in res] == [(k, n) for k, n, _ in README_ORBITS]
    for a, (_k, _n, app) in zip(res, README_ORBITS):
        assert a.app_um == pytest.approx(app, rel=1e-3)
    basins = [a.basin_fraction for a in res]
    assert basins == pytest.approx([0.0488, 0.4219, 0.1992, 0.0469, 0.2832], abs=0.02)


def test_motion_beyond_the_table_is_refused():
    """A trajectory that leaves the table's rows is refused (ParameterError naming the table)."""
    from contactvib import ParameterError, simulate

    mt = ContactModel(law=_power_table(200, y_max=0.6e-6))
    exc = mt.excitation(0.3, 1200.0)
    h = simulate(exc, y_um=0.5, n_periods=5)
    assert h.y_um.max() < 0.6
    with pytest.raises(ParameterError, match="beyond the table's last row") as e:
        simulate(exc, y_um=0.7, n_periods=5)
    assert e.value.symbol == "law_file"
