"""The System model: input checks (each error names its field), static state and linear modes
against closed forms, the scales of the compiled form, and the excitation/state checks of the
public functions."""

import math

import numpy as np
import pytest

from contactvib.model import ContactModel, ParameterError
from contactvib.model.laws import ClearanceLaw, ExponentialLaw, PowerSpring
from contactvib.model.system import ContactElement, System
from contactvib.steady.system_orbits import period_map, periodic_orbit, simulate_system

STOP = ClearanceLaw(c_lin=100.0, gap_um=1e6)


def element(**kw):
    args = {"name": "stop", "direction": (1.0, 0.0), "S": 1.0, "law": STOP, **kw}
    return ContactElement(**args)


def system(**kw):
    args = {"M": np.eye(2), "K": [[1.0, -1.0], [-1.0, 2.0]], "b": [0.0, 1.0], "contacts": [element()], **kw}
    return System(**args)


BAD = [
    ({"M": [[1.0, 0.0]]}, "M", "matrix"),
    ({"M": [[1.0, 0.5], [0.0, 1.0]]}, "M", "symmetric"),
    ({"M": [[1.0, 0.0], [0.0, -1.0]]}, "M", "positive definite"),
    ({"M": [[1.0, 0.0], [0.0, np.nan]]}, "M", "finite"),
    ({"K": np.eye(3)}, "K", "2x2"),
    ({"C": [[0.0, np.inf], [0.0, 0.0]]}, "C", "finite"),
    ({"f0": [1.0, 2.0, 3.0]}, "f0", "vector of 2"),
    ({"b": [np.nan, 1.0]}, "b", "finite"),
    ({"coordinates": ("x", "x")}, "coordinates", "distinct"),
    ({"units": ("m", "deg")}, "units", "rad"),
    ({"contacts": [element(direction=(0.0, 0.0))]}, "contacts[0].direction", "zero"),
    ({"contacts": [element(direction=(1.0, 0.0, 0.0))]}, "contacts[0].direction", "vector of 2"),
    ({"contacts": [element(direction=(np.nan, 1.0))]}, "contacts[0].direction", "finite"),
    ({"contacts": [element(S=-1.0)]}, "contacts[0].S", "> 0"),
    ({"contacts": [element(S=float("nan"))]}, "contacts[0].S", "finite"),
    ({"contacts": [element(law="no-such-law")]}, "contacts[0].law", "unknown law"),
    ({"contacts": [element(law=42)]}, "contacts[0].law", "SpringLaw"),
    ({"contacts": [element(damping="viscous")]}, "contacts[0].damping", "power"),
    ({"contacts": [element(h_n=-1.0)]}, "contacts[0].h_n", ">= 0"),
    ({"contacts": [element(l=11.0)]}, "contacts[0].l", "[0, 10]"),
    ({"contacts": [element(alpha=1.0)]}, "contacts[0].alpha", "Hunt-Crossley"),
    ({"contacts": [element(gap=-1e-6)]}, "contacts[0].gap", ">= 0"),
    ({"contacts": [element(), element()]}, "contacts", "distinct names"),
    ({"contacts": ["stop"]}, "contacts[0]", "ContactElement"),
]


@pytest.mark.parametrize("kw, field, words", BAD, ids=[f"{b[1]}-{b[2]}" for b in BAD])
def test_each_bad_input_names_its_field(kw, field, words):
    with pytest.raises(ParameterError) as e:
        system(**kw)
    assert e.value.symbol == field
    assert words in str(e.value)


def test_no_static_equilibrium_is_refused():
    # a free coordinate (no stiffness, no contact along it) under a load
    with pytest.raises(ParameterError) as e:
        System(M=np.eye(2), K=[[1.0, 0.0], [0.0, 0.0]], f0=[0.0, 1.0]).static_state()
    assert e.value.symbol == "f0"


def test_public_functions_check_their_inputs():
    s = system()
    for call, field in [
        (lambda: period_map(s, -1.0, 0.2, [0, 0, 0, 0]), "P_a"),
        (lambda: period_map(s, 1.0, 0.0, [0, 0, 0, 0]), "f_e"),
        (lambda: period_map(s, 1.0, 0.2, [0, 0, 0]), "z0"),
        (lambda: period_map(s, 1.0, 0.2, [0, 0, 0, np.nan]), "z0"),
        (lambda: period_map(s, 1.0, 0.2, [0, 0, 0, 0], 0), "k"),
        (lambda: period_map(s, 1.0, 0.2, [0, 0, 0, 0], rtol=1e-3), "rtol"),
        (lambda: periodic_orbit(s, 1.0, 0.2, [0, 0], 1), "z_guess"),
        (lambda: simulate_system(s, 1.0, 0.2, n_periods=0), "n_periods"),
        (lambda: simulate_system(s, 1.0, 0.2, samples_per_period=1), "samples_per_period"),
        (lambda: period_map("system", 1.0, 0.2, [0, 0, 0, 0]), "system"),
    ]:
        with pytest.raises(ParameterError) as e:
            call()
        assert e.value.symbol == field


def test_static_state_and_modes_of_the_clearance_example():
    s = system()
    assert s.static_state().tolist() == [0.0, 0.0]  # no load, the gap open
    w = np.sqrt(np.linalg.eigvalsh(np.array([[1.0, -1.0], [-1.0, 2.0]]))) / (2 * math.pi)
    np.testing.assert_allclose(s.linear_modes(), w, rtol=1e-12)
    # under a static load that closes the gap (1 m) the contact's stiffness 100 N/m counts
    s = system(f0=[150.0, 0.0])
    q = s.static_state()
    np.testing.assert_allclose(s.static_residual(q), 0.0, atol=1e-12 * 150.0)
    d = q[0] - 1.0
    assert d > 0 and s.contact_forces(q, [0.0, 0.0])[0] == pytest.approx(100.0 * d, rel=1e-12)
    w = np.sqrt(np.linalg.eigvalsh(np.array([[101.0, -1.0], [-1.0, 2.0]]))) / (2 * math.pi)
    np.testing.assert_allclose(s.linear_modes(), w, rtol=1e-12)


def test_rocking_unit_static_state_and_modes():
    """Two power-law contacts at ±a under gravity: each carries M g / 2, θ = 0; the vertical mode
    has 2 k_c, the rocking mode 2 k_c a² (k_c = m2 W/2 / y0)."""
    m, a, S, cn = 0.2106, 0.04, 0.00045, 4.52e16
    law = PowerSpring(c_n=cn, m2=2.0)
    J = m * a * a / 3.0
    s = System(M=np.diag([m, J]), f0=[m * 9.81, 0.0],
               contacts=[ContactElement("front", (1.0, a), S, law), ContactElement("rear", (1.0, -a), S, law)],
               coordinates=("y", "theta"), units=("m", "rad"))
    y0 = math.sqrt(m * 9.81 / 2 / (S * cn))
    q = s.static_state()
    assert q[0] == pytest.approx(y0, rel=1e-12) and abs(q[1]) < 1e-12 * y0 / a
    kc = 2.0 * S * cn * y0
    np.testing.assert_allclose(s.linear_modes(), [math.sqrt(2 * kc / m) / (2 * math.pi),
                                                  math.sqrt(2 * kc * a * a / J) / (2 * math.pi)], rtol=1e-12)
    sc = s.scales
    np.testing.assert_allclose(sc.length, [y0, y0 / a], rtol=1e-12)
    np.testing.assert_allclose(sc.force, [m * 9.81 / 2] * 2, rtol=1e-12)
    assert sc.omega == pytest.approx(2 * math.pi * s.linear_modes()[-1], rel=1e-12)


def test_single_dof_fields_and_a_law_by_name():
    m = ContactModel(damping="hunt-crossley", alpha=20.0, preload=0.3)
    s = System.single_dof(m)
    (c,) = s.contacts
    assert (c.damping, c.alpha, c.S, c.law) == ("hunt-crossley", 20.0, m.S, m.spring_law)
    assert s.M.tolist() == [[m.M]] and s.f0.tolist() == [m.W] and s.b.tolist() == [1.0]
    e = ContactElement("c", (1.0,), 1e-3, "exponential")
    System(M=[[1.0]], contacts=[e])
    assert isinstance(e.law, ExponentialLaw)
    with pytest.raises(ParameterError) as err:
        System.single_dof("paper")
    assert err.value.symbol == "model"


def test_a_gap_of_the_element_is_a_gap_of_the_law():
    """δ = w·q − (gap + the law's engagement point): a clearance of the element and the same
    clearance in the law give the same system (the same map, to rounding)."""
    from contactvib.steady.system_orbits import period_map

    def with_gap(law_gap_um, gap):
        return system(contacts=[element(law=ClearanceLaw(c_lin=100.0, gap_um=law_gap_um), gap=gap, h_n=0.5,
                                        l=0.0)])

    a, b = with_gap(1e6, 0.0), with_gap(0.0, 1.0)
    assert a.contacts[0].engagement == b.contacts[0].engagement == 1.0
    za = period_map(a, 2.0, 0.2, [0.5, 0.0, 0.0, 0.0], 2).z
    zb = period_map(b, 2.0, 0.2, [0.5, 0.0, 0.0, 0.0], 2).z
    np.testing.assert_allclose(za, zb, rtol=1e-13, atol=1e-13)
