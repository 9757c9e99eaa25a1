"""The system core's smaller promises: the flow map from any τ0 equals the stroboscopic map and
scipy, a linear structure's periodic orbit is its frequency response (closed form), the time
history's forces are the laws' own SI forces at its samples, the step records grow when full."""

import math

import numpy as np
import pytest
from scipy_system import integrate_system
from test_system_scipy import rocking_unit, two_dof

from contactvib._kernels import system_map as km
from contactvib._kernels.system_flow import system_arrays
from contactvib.model.system import System
from contactvib.steady import system_orbits
from contactvib.steady.system_orbits import period_map, periodic_orbit, simulate_system


def test_flow_map_from_any_start_time():
    """flow_map over [0, T] is the period map; over [τ0, τ1] it is scipy's from t0 = τ0/ω
    (to 1e-8 of the state's size [measured 8e-12])."""
    s = two_dof(h_n=0.5, l=0.0)
    pa, fe = 2.0, 0.2
    form = s.kernel_form(pa, fe)
    sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
    x0 = form.scales.to_scaled([0.5, 0.0, 0.0, 0.0])
    z, phi = np.empty(4), np.empty((4, 4))
    assert km.flow_map(sa, x0, 0.0, form.tau_period, 1e-12, 1e-12, z, phi) == 0
    pm = period_map(s, pa, fe, [0.5, 0.0, 0.0, 0.0], 1)
    np.testing.assert_allclose(form.scales.to_si(z), pm.z, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(form.scales.monodromy_to_si(phi), pm.monodromy, rtol=1e-12, atol=1e-12)
    # from τ0 = 0.3 T to 2.1 T: scipy from t0 = τ0/ω
    t0, t1 = 0.3 * form.tau_period, 2.1 * form.tau_period
    assert km.flow_map(sa, x0, t0, t1, 1e-12, 1e-12, z, np.empty((0, 0))) == 0
    om = form.scales.omega
    ref, _, switches = integrate_system(s, pa, fe, [0.5, 0.0, 0.0, 0.0], t1 / om, t0=t0 / om)
    assert switches >= 2
    assert np.max(np.abs(form.scales.to_si(z) - ref)) < 1e-8 * np.max(np.abs(ref))


def test_linear_structure_orbit_is_its_frequency_response():
    """No contact: the period-1 orbit is q(t) = Re(H b P_a e^{iωt}), H = (K − ω² M + iω C)⁻¹;
    its Floquet multipliers are e^{λT} of the free system's eigenvalues (to 1e-10 [measured 5e-13,
    2e-12])."""
    M, K, C, b = np.eye(2), np.array([[1.0, -1.0], [-1.0, 2.0]]), np.array([[0.03, -0.03], [-0.03, 0.06]]), \
        np.array([0.0, 1.0])
    s = System(M=M, K=K, C=C, b=b)
    pa, fe = 2.0, 0.2
    w = 2 * math.pi * fe
    H = np.linalg.solve(K - w * w * M + 1j * w * C, b * pa)
    orbit = periodic_orbit(s, pa, fe, np.zeros(4), 1)
    np.testing.assert_allclose(orbit.z, np.concatenate([H.real, (1j * w * H).real]), rtol=0, atol=1e-10)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-K, -C]])
    mu = np.exp(np.linalg.eigvals(A) / fe)
    np.testing.assert_allclose(np.sort_complex(orbit.floquet_multipliers), np.sort_complex(mu), rtol=0, atol=1e-10)
    assert orbit.stable


@pytest.mark.parametrize("make, pa, fe, z0", [(lambda: two_dof(damping="hunt-crossley", alpha=0.05), 2.0, 0.2,
                                               [0.5, 0.0, 0.0, 0.0]),
                                              (rocking_unit, 1.8, 700.0, [2.5e-7, 0.0, 0.0, 0.0])])
def test_time_history_forces_are_the_laws_own(make, pa, fe, z0):
    """Each sample's contact forces equal the laws' SI formulas at its state (rel 1e-9 of the
    largest force [measured 1e-15]), the modes are δ > 0, the end state is the period map's, the units are the
    display units."""
    s = make()
    n = s.n
    h = simulate_system(s, pa, fe, z0[:n], z0[n:], 2, 300, rtol=1e-12)
    unit = {"m": 1e-6, "rad": 1e-6}
    q = h.q * np.array([unit[u] for u in s.units])[:, None]
    v = h.qdot * np.array([1e-3 for _ in s.units])[:, None]
    F = np.array([s.contact_forces(q[:, j], v[:, j]) for j in range(q.shape[1])]).T
    assert np.max(np.abs(F - h.forces_n)) < 1e-9 * np.max(F)
    delta = s.directions @ q - np.array([c.engagement for c in s.contacts])[:, None]
    on = h.in_contact
    assert np.all(delta[on] > -1e-9 * np.max(np.abs(delta))) and np.all(delta[~on] < 1e-9 * np.max(np.abs(delta)))
    np.testing.assert_allclose(h.z_end, period_map(s, pa, fe, z0, 2, rtol=1e-12).z, rtol=1e-10,
                               atol=1e-10 * np.max(np.abs(h.z_end)))
    assert h.t_ms[-1] == pytest.approx(2e3 / fe, rel=1e-12)
    assert h.q_units == tuple("um" if u == "m" else "urad" for u in s.units)


def test_step_records_grow_when_full(monkeypatch):
    s = two_dof()
    ref = simulate_system(s, 2.0, 0.2, [0.5, 0.0], [0.0, 0.0], 2, 50)
    monkeypatch.setattr(system_orbits, "_RECORD_ROWS", 1)
    h = simulate_system(s, 2.0, 0.2, [0.5, 0.0], [0.0, 0.0], 2, 50)
    np.testing.assert_array_equal(h.q, ref.q)
