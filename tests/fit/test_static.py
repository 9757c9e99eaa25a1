"""Static load–deflection fits: the power law F = S c_n y^m2 recovered from synthetic curves with
additive deflection noise (2 % of the largest deflection), within two reported standard errors,
and the standard errors against the spread over 20 noise realisations (within a factor of 2)."""

import math

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib.fitting import fit, static_data

#: (S c_n [N/m^m2], m2): the paper's and three others (m2 in 1.3 .. 2.5)
CASES = [(0.0009 * 4.52e16, 2.0), (1.257e10, 1.5), (2.371e17, 2.5), (4.28e8, 1.3)]


def curve(Sc, m2, noise, seed, n=30, f_max=10.0):
    F = np.linspace(0.0, f_max, n)
    y = (F / Sc) ** (1.0 / m2) * 1e6
    rng = np.random.default_rng(seed)
    return F, y + rng.normal(0.0, noise * y.max(), n)


@pytest.mark.parametrize("Sc, m2", CASES)
def test_static_fit_recovers_the_power_law_within_two_stderr(Sc, m2):
    F, y = curve(Sc, m2, 0.02, seed=1)
    r = fit(static=static_data(F, y))
    assert r.converged
    assert set(r.parameters) == {"S_c_n", "m2"}
    assert abs(r.value("m2") - m2) < 2 * r.stderr("m2")
    # S c_n in log: its standard error is relative
    assert abs(math.log(r.value("S_c_n") / Sc)) < 2 * r.stderr("S_c_n") / r.value("S_c_n")
    y0 = (ContactModel().Q / Sc) ** (1 / m2) * 1e6
    assert abs(r.value("y0_um") - y0) < 2 * r.stderr("y0_um")
    assert r.residual_rms["static"] == pytest.approx(0.02 * y.max(), rel=0.4)


def test_static_stderr_agrees_with_the_spread_over_20_realisations():
    Sc, m2 = CASES[1]
    fits = [fit(static=static_data(*curve(Sc, m2, 0.02, seed=s))) for s in range(20)]
    m2s = np.array([f.value("m2") for f in fits])
    reported = np.median([f.stderr("m2") for f in fits])
    spread = np.std(m2s, ddof=1)
    assert 0.5 < reported / spread < 2.0
    y0s = np.array([f.value("y0_um") for f in fits])
    assert 0.5 < np.median([f.stderr("y0_um") for f in fits]) / np.std(y0s, ddof=1) < 2.0


def test_fixed_exponent_fits_only_the_coefficient():
    F, y = curve(CASES[0][0], 2.0, 0.01, seed=3)
    r = fit(static=static_data(F, y), fix={"m2": 2.0})
    assert list(r.parameters) == ["S_c_n"] and r.fixed["m2"] == 2.0
    assert r.value("S_c_n") == pytest.approx(CASES[0][0], rel=0.05)
