"""Greenwood–Williamson contact (model/greenwood_williamson.py) against closed forms.

* F_3/2(0) = 2^(1/4) Γ(5/4) / sqrt(2π) exactly (rel 1e-10);
* the small-load limit: F_3/2(h) against its asymptotic series (6 terms) at h = 8 and 10 (rel
  2e-5 and 1e-6: the series' own truncation, measured 4.7e-6 and 3.4e-7), and the law F_s(y) far
  from the mean plane (first contact at 9 σ) against the series (rel 1e-4);
* the tabulated law in a ContactModel: y0 solves F_s(y0) = W by brentq on the quadrature itself
  (rel 1e-5: PCHIP between 400 rows), f_n0 = sqrt(F_s'(y0)/M)/2π with a central difference of the
  quadrature (rel 1e-3);
* the example table (examples/gw_table.csv) is what its script writes.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib.model import ParameterError
from contactvib.model.greenwood_williamson import GreenwoodWilliamson, f32, f32_asymptotic
from contactvib.model.laws import TableLaw

GW = GreenwoodWilliamson(sigma=0.5e-6, radius=50e-6, density=1e8, e_star=1.15e11)
S = 0.0009


def test_f32_at_the_mean_plane_is_exact():
    assert f32(0.0)[0] == pytest.approx(2 ** 0.25 * math.gamma(1.25) / math.sqrt(2 * math.pi), rel=1e-10)


@pytest.mark.parametrize("h, rtol", [(8.0, 2e-5), (10.0, 1e-6)])
def test_f32_small_load_limit(h, rtol):
    assert f32(h)[0] == pytest.approx(f32_asymptotic(h, 6)[0], rel=rtol)


def test_law_far_from_the_mean_plane_follows_the_series():
    gw = GreenwoodWilliamson(sigma=0.5e-6, radius=50e-6, density=1e8, e_star=1.15e11, first_contact_sigma=9.0)
    y = np.linspace(0.05, 1.0, 8) * gw.sigma
    c = 4.0 / 3.0 * gw.density * S * gw.e_star * math.sqrt(gw.radius) * gw.sigma ** 1.5
    series = c * (f32_asymptotic(9.0 - y / gw.sigma, 6) - f32_asymptotic(9.0, 6)[0])
    np.testing.assert_allclose(gw.load(y, S), series, rtol=1e-4)


def test_tabulated_law_gives_the_static_point_and_frequency():
    from scipy.optimize import brentq

    m = ContactModel(law=GW.table(S, 2e-6, 400), damping="hunt-crossley", alpha=34.4)
    y0 = brentq(lambda y: GW.load(np.array([y]), S)[0] - m.W, 1e-9, 2e-6, xtol=1e-18, rtol=1e-14)
    assert m.y0 == pytest.approx(y0, rel=1e-5)
    h = 1e-3 * y0
    k = (GW.load(np.array([y0 + h]), S)[0] - GW.load(np.array([y0 - h]), S)[0]) / (2 * h)
    assert m.f_n0 == pytest.approx(math.sqrt(k / m.M) / (2 * math.pi), rel=1e-3)
    assert 1400 < m.f_n0 < 1500 and 0.015 < m.zeta < 0.02  # the example's paper-like contact


def test_example_table_is_the_scripts_output():
    csv = Path(__file__).resolve().parents[2] / "examples" / "gw_table.csv"
    t = TableLaw.from_csv(csv)
    ref = GW.table(S, 2e-6, 400)
    np.testing.assert_allclose(t.deflection_m, ref.deflection_m, rtol=1e-13, atol=1e-22)
    np.testing.assert_allclose(t.load_n, ref.load_n, rtol=1e-13, atol=1e-22)


@pytest.mark.parametrize("kw, name", [({"sigma": -1e-6}, "sigma"), ({"radius": 0.0}, "radius"),
                                      ({"density": float("nan")}, "density"), ({"e_star": -1.0}, "e_star"),
                                      ({"first_contact_sigma": 0.0}, "first_contact_sigma")])
def test_bad_parameters_are_named(kw, name):
    args = dict(sigma=0.5e-6, radius=50e-6, density=1e8, e_star=1.15e11) | kw
    with pytest.raises(ParameterError) as e:
        GreenwoodWilliamson(**args)
    assert e.value.symbol == name
    with pytest.raises(ParameterError):
        GW.load(np.array([-1e-9]), S)
