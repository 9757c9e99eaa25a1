"""∂P^k/∂r of the stroboscopic map from the sensitivity equation (:func:`strobe_map_dr`), the
continuation's parameter column, against central differences of scipy's map (DOP853 at rtol
1e-13 with located contact switches) and, for the excitations scipy is not written for here,
against central differences of the kernel's own map at rtol 1e-13."""

import math

import numpy as np
import pytest

from contactvib._kernels.continuation import IP_RATIO, residual_jacobian
from contactvib._kernels.shooting import strobe_map, strobe_map_dr
from contactvib.model import ContactModel, excitation_at
from contactvib.testing import integrate_modes, power_law_rhs

#: Relative step of the reference differences: their truncation error is ~1e-8 relative here.
H_REL = 1e-6


def _scipy_map(par, z, k):
    """P^k(z) by scipy: k periods T = 2π/r, each from τ = 0 (the force's phase)."""
    f_contact, f_flight = power_law_rhs(par)
    s = np.array(z, float)
    for _ in range(k):
        s = integrate_modes(f_contact, f_flight, s, 0.0, 2.0 * math.pi / par[4], rtol=1e-13, atol=1e-13).y
    return s


def _sensitivity(par, z, k, rtol=1e-12):
    pz, M, dr = np.empty(2), np.empty((2, 2)), np.empty(2)
    assert strobe_map_dr(np.array(z, float), k, par.copy(), rtol, rtol, pz, M, dr) == 0
    return pz, M, dr


@pytest.mark.parametrize("pa, fe, z, k", [
    (0.3, 1000.0, (0.5, 0.1), 1),     # in contact throughout
    (0.9, 244.0, (1.0, 0.0), 3),      # flights and impacts (the saltation acts on s)
    (0.65, 1300.0, (2.0, 1.0), 2),
])
def test_sensitivity_matches_scipy_differences(pa, fe, z, k):
    par = ContactModel().excitation(pa, fe).kernel_parameters()
    _pz, _M, dr = _sensitivity(par, z, k)
    h = H_REL * par[4]
    up, down = par.copy(), par.copy()
    up[4] += h
    down[4] -= h
    ref = (_scipy_map(up, z, k) - _scipy_map(down, z, k)) / (2.0 * h)
    # scipy's noise (1e-13 / 1e-6) and the differences' truncation: well below 1e-6 relative; the
    # former column (central differences at 1e-5 r) was 2.3e-6 off at 244 Hz
    assert np.max(np.abs(dr - ref)) <= 1e-6 * np.max(np.abs(ref))


@pytest.mark.parametrize("kind, level", [("base-um", 0.05), ("base-g", 0.5)])
def test_sensitivity_of_base_excitation_matches_differences(kind, level):
    par = excitation_at(ContactModel(), level, 700.0, kind).kernel_parameters()
    z = np.array([1.0, 0.0])
    _pz, _M, dr = _sensitivity(par, z, 2)
    h = H_REL * par[4]
    ends = []
    for sign in (1.0, -1.0):
        p = par.copy()
        p[4] += sign * h
        out = np.empty(2)
        assert strobe_map(z, 2, p, 1e-13, 1e-13, out, np.empty((0, 0))) == 0
        ends.append(out)
    ref = (ends[0] - ends[1]) / (2.0 * h)
    assert np.max(np.abs(dr - ref)) <= 1e-6 * np.max(np.abs(ref))


def test_state_and_monodromy_as_without_the_sensitivity():
    """The extra equations change the step sequence only within the tolerance."""
    par = ContactModel().excitation(0.9, 244.0).kernel_parameters()
    z = np.array([1.0, 0.0])
    pz, M, _dr = _sensitivity(par, z, 3)
    pz6, M6 = np.empty(2), np.empty((2, 2))
    assert strobe_map(z, 3, par.copy(), 1e-12, 1e-12, pz6, M6) == 0
    assert np.max(np.abs(pz - pz6)) <= 1e-9 * max(1.0, np.max(np.abs(pz6)))
    assert np.max(np.abs(M - M6)) <= 1e-7 * np.max(np.abs(M6))


def test_residual_jacobian_uses_the_sensitivity_column():
    par = ContactModel().excitation(0.9, 244.0).kernel_parameters()
    u = np.array([1.0, 0.0, par[4]])
    G, J, M = np.empty(2), np.empty((2, 3)), np.empty((2, 2))
    assert residual_jacobian(u, 3, par.copy(), IP_RATIO, 1e-12, G, J, M) == 0
    pz, M_ref, dr = _sensitivity(par, u[:2], 3)
    assert np.allclose(G, pz - u[:2], rtol=0, atol=1e-12)
    assert np.array_equal(J[:, 2], dr)
    assert np.array_equal(J[:, :2], M_ref - np.eye(2))
