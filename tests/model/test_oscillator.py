"""Model parameters and derived quantities against closed forms and the paper (S2.1–S2.3)."""
import math

import numpy as np
import pytest

from contactvib import ContactModel, ParameterError
from contactvib.model import ZETA_MAX


def test_paper_static_deflection_and_natural_frequency():
    """S2.1, S2.2: y0 ≈ 0.2254 µm, f_n0 ≈ 1485.0 Hz for the paper's parameters."""
    m = ContactModel()
    assert m.Q == pytest.approx(0.2106 * 9.81, rel=1e-15)
    assert m.y0 * 1e6 == pytest.approx(0.2254, abs=5e-5)
    assert m.S * m.c_n * m.y0**m.m2 == pytest.approx(m.Q, rel=1e-13)
    assert m.f_n0 == pytest.approx(1485.0, abs=0.05)
    assert m.zeta == pytest.approx(0.018, abs=5e-4)


def test_linear_stiffness_is_derivative_of_spring_force():
    """k_lin equals −dF_s/dy at y0 (central difference)."""
    for m2 in (1.0, 1.5, 2.0, 3.0):
        m = ContactModel(m2=m2, c_n=1e16 if m2 != 1.0 else 1e10)
        dy = m.y0 * 1e-6
        fd = -(m.spring_force(m.y0 + dy) - m.spring_force(m.y0 - dy)) / (2 * dy)
        assert m.k_lin == pytest.approx(float(fd), rel=1e-8)
        assert m.omega_n0 == pytest.approx(math.sqrt(m.k_lin / m.M), rel=1e-14)
        assert m.conservative_force(m.y0) == pytest.approx(0.0, abs=1e-12 * m.Q)


def test_superharmonic_estimates():
    """S2.3: f_n0/m lies below f_n0 (Eq. 2.6)."""
    m = ContactModel()
    f = m.superharmonic_frequencies(6)
    assert np.allclose(f * np.arange(1, 7), m.f_n0)
    assert np.all(np.diff(f) < 0)


def test_kernel_parameters():
    m = ContactModel()
    e = m.excitation(0.65, 360.0)
    m2, l, c, p, r = e.kernel_parameters()
    assert (m2, l, p) == (2.0, 1.0, 0.65)
    assert c == pytest.approx(2 * m2 * m.zeta)
    assert r == pytest.approx(360.0 / m.f_n0)
    assert e.tau_period == pytest.approx(2 * math.pi / r)
    assert m.excitation(0.5, 100).P_a == pytest.approx(0.5 * m.Q)


@pytest.mark.parametrize("kw, symbol", [
    ({"M": -1.0}, "M"), ({"S": 0.0}, "S"), ({"m2": 0.5}, "m2"), ({"l": -1.0}, "l"),
    ({"h_n": -1.0}, "h_n"), ({"c_n": float("nan")}, "c_n"), ({"g": float("inf")}, "g"),
])
def test_bad_parameters_are_rejected(kw, symbol):
    with pytest.raises(ParameterError) as e:
        ContactModel(**kw)
    assert e.value.symbol == symbol


def test_overdamped_contact_is_rejected_with_the_largest_h_n():
    """The paper's h_n with l = 0 gives ζ = 8e4 (a stiff contact that explicit integration
    would crawl through): refused, naming h_n and the largest h_n allowed; ζ is linear in h_n,
    so that bound gives ζ = ZETA_MAX, and the h_n suggested for the paper's ζ gives 0.018."""
    with pytest.raises(ParameterError) as e:
        ContactModel(l=0.0)
    assert e.value.symbol == "h_n" and "zeta = 8.02e+04" in e.value.allowed
    h_max = float(e.value.allowed.split("h_n <= ")[1].split()[0])
    assert ContactModel(l=0.0, h_n=h_max * 0.999).zeta == pytest.approx(ZETA_MAX, rel=2e-3)
    h_paper = float(e.value.allowed.split("about ")[1].split()[0])
    assert ContactModel(l=0.0, h_n=h_paper).zeta == pytest.approx(ContactModel().zeta, rel=1e-2)


def test_bad_excitation_and_unknown_name():
    m = ContactModel()
    with pytest.raises(ParameterError, match="f_e"):
        m.excitation(0.5, -5)
    with pytest.raises(ParameterError, match="P_a/Q"):
        m.excitation(-0.1, 100)
    with pytest.raises(ParameterError, match="unknown"):
        ContactModel.from_overrides({"mass": 1.0})
    assert ContactModel.from_overrides({"m2": 1.5}).m2 == 1.5
