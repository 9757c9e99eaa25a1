"""Harmonic balance for every law family and excitation (not only the paper's power law under
one harmonic force).

References: the HB orbit's state at phase 0 integrated by scipy's DOP853 over one period (rtol
1e-12, located contact events, the forces written in contactvib.testing from the model's
parameters) must come back (rel 1e-9 of the state scale), and its A_pp must equal the shooting
attractor of :func:`find_attractors` (rel 1e-7: 32 harmonics of an orbit that stays in contact,
whose spectrum decays geometrically). The paper's law keeps its own residual (rel 1e-12 against
the generic one, on the same model)."""

import math

import numpy as np
import pytest

from contactvib import ContactModel, Excitation, find_attractors
from contactvib.frequency.harmonic_balance import HBSettings, _residual, hb_continuation, hb_solve
from contactvib.model import ParameterError
from contactvib.testing import integrate_contact, model_ode

F_E = 700.0


def _cases():
    power = ContactModel()
    return {
        "exponential": (ContactModel(law="exponential"), lambda m: m.excitation(0.1, F_E)),
        "hunt-crossley-preload": (ContactModel(damping="hunt-crossley", preload=1.0), lambda m: m.excitation(0.1, F_E)),
        "power-base-um": (power, lambda m: Excitation.base(m, F_E, u_um=0.05)),
        "exponential-base-g": (ContactModel(law="exponential", preload=0.3),
                               lambda m: Excitation.base(m, F_E, a_g=0.2)),
        "power-preload-harmonics": (ContactModel(preload=0.5),
                                    lambda m: m.excitation(0.1, F_E, harmonics=((2, 0.05, 30.0), (3, 0.02, -60.0)))),
    }


CASES = _cases()


@pytest.mark.parametrize("name", list(CASES))
def test_hb_orbit_is_the_scipy_orbit_and_the_attractor(name):
    m, make = CASES[name]
    exc = make(m)
    sol = hb_solve(exc, harmonics=32)
    assert not sol.loses_contact and sol.residual <= 1e-11
    X = sol.coefficients
    k = np.arange(1, 33)
    x0 = X[0] + X[1::2].sum()
    xd0 = exc.r * (k * X[2::2]).sum()  # d/dθ of b_k sin kθ at θ = 0, times r = dθ/dτ
    sy, sv = m.y0, m.y0 * m.omega_n0
    y, v = x0 * sy, xd0 * sv
    tr = integrate_contact(model_ode(m, exc), y, v, 0.0, 1.0 / exc.f_e, rtol=1e-12, y_scale=sy, v_scale=sv)
    assert max(abs(tr.y - y) / sy, abs(tr.ydot - v) / sv) <= 1e-9 * max(1.0, abs(x0))
    assert sol.app_um == pytest.approx((tr.ymax - tr.ymin) * 1e6, rel=1e-7)
    assert sol.closure <= 1e-10
    found = [a for a in find_attractors(exc, n_starts=16) if a.period == 1
             and abs(a.app_um - sol.app_um) <= 1e-3 * sol.app_um]
    assert len(found) == 1 and found[0].app_um == pytest.approx(sol.app_um, rel=1e-7)
    assert np.max(np.abs(sol.floquet_multipliers)) == pytest.approx(found[0].floquet_abs_max, rel=1e-6)


def test_paper_residual_equals_the_generic_one():
    """The paper's own residual and the generic one (full parameter vector) agree."""
    from contactvib._kernels import contact as kc
    from contactvib.frequency.aft import AFT

    m = ContactModel()
    exc = m.excitation(0.3, 900.0)
    short = (m.m2, m.l, m.damping_coefficient, 0.3)
    full = Excitation.base(m, 900.0, u_um=1e-30).kernel_parameters()  # the full layout, no force
    full[kc.P_EXCITATION] = kc.EXCITATION_FORCE
    full[3] = 0.3
    assert kc.is_paper_family(full[:5]) and full.size > 5
    aft = AFT(16, 128)
    X = hb_solve(exc, harmonics=16).coefficients
    for a, b in zip(_residual(X, exc.r, short, aft), _residual(X, exc.r, full, aft)):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-13)


def test_base_continuation_points_close_under_scipy():
    """An HB branch in f_e at constant U: every 25th point (stable or not) is a periodic orbit of
    the base-excited oscillator (scipy closure rel 1e-8 where the truncation is fine)."""
    m = ContactModel()
    U = 0.03
    b = hb_continuation(m, pa_over_q=U, fmin_hz=900.0, fmax_hz=1400.0, harmonics=32,
                        settings=HBSettings(stability=False), excitation="base-um")
    assert b.pa_over_q == U and len(b) > 50
    sy, sv = m.y0, m.y0 * m.omega_n0
    checked = 0
    for sol in b.solutions[::25]:
        if sol.loses_contact:
            continue
        X = sol.coefficients
        k = np.arange(1, X.size // 2 + 1)
        r = sol.fe_hz / m.f_n0
        x0, xd0 = X[0] + X[1::2].sum(), r * (k * X[2::2]).sum()
        exc = Excitation.base(m, sol.fe_hz, u_um=U)
        tr = integrate_contact(model_ode(m, exc), x0 * sy, xd0 * sv, 0.0, 1.0 / sol.fe_hz, rtol=1e-12,
                               y_scale=sy, v_scale=sv)
        assert max(abs(tr.y / sy - x0), abs(tr.ydot / sv - xd0)) <= 1e-8 * max(1.0, abs(x0)), sol.fe_hz
        checked += 1
    assert checked >= 3
    assert math.isfinite(b.app_um.max())


def test_force_harmonic_beyond_the_truncation_is_refused():
    m = ContactModel()
    with pytest.raises(ParameterError, match="harmonic 5"):
        hb_solve(m.excitation(0.1, F_E, harmonics=((5, 0.01, 0.0),)), harmonics=4)
    with pytest.raises(ParameterError, match="base motion"):
        hb_continuation(m, pa_over_q=0.03, fmin_hz=900.0, fmax_hz=1000.0, harmonics=8, excitation="base-um",
                        force_harmonics=((2, 0.1, 0.0),))


def test_table_law_sampled_from_the_power_law_gives_its_hb_orbit():
    """examples/power_law_table.csv (the paper's law on 301 rows, PCHIP): the HB orbit at 0.3 Q,
    900 Hz equals the power law's to the interpolation error (rel 1e-4; measured 2e-6)."""
    from pathlib import Path

    from contactvib.model.laws import TableLaw

    csv = Path(__file__).resolve().parents[2] / "examples" / "power_law_table.csv"
    table = ContactModel(law=TableLaw.from_csv(csv))
    power = ContactModel()
    a = hb_solve(table.excitation(0.3, 900.0), harmonics=32)
    b = hb_solve(power.excitation(0.3, 900.0), harmonics=32)
    assert a.app_um == pytest.approx(b.app_um, rel=1e-4)
