"""The paper's slider as the n = 1 system (``System.single_dof``) against the existing 1-DOF
kernels, and exact identities on its periodic orbits at 0.65 Q, 360 Hz.

* the static state and linear mode are y0 and f_n0 of the ContactModel (rel 1e-12);
* the stroboscopic map and its monodromy equal the 1-DOF kernel's (``_kernels.shooting.strobe_map``,
  converted to SI) from states in contact and in flight, over orbits that lose contact, to 1e-9 of
  the state's size [measured ≤ 4e-11; the monodromy ≤ 2e-10];
* a time history equals ``contactvib.simulate``'s to 1e-10 µm, 1e-10 mm/s [measured 1e-14 µm, 1e-13 mm/s];
* every attractor of ``find_attractors`` is found again by the system's Newton shooting from its
  state shifted by 1e-3 (relative): the orbit point to 1e-8 of y0 [measured ≤ 8e-10: the
  attractors' own refinement], the Floquet multipliers to 1e-6 [measured ≤ 1e-10];
* Liouville: det Φ = exp(−∫ c_d(y) dt / M) (scipy reference) to 1e-9 [measured ≤ 4e-12];
* mean force: averaging the equation over a period, ⟨F⟩ = M g exactly, to 1e-8 [measured ≤ 7e-12].

The clearance law with Hunt–Crossley damping and a preload, and the exponential law (power
damping), take the general path of the compiled law (the models beside the paper's).
"""

import numpy as np
import pytest
from scipy_system import integrate_system

from contactvib import ContactModel, find_attractors, simulate
from contactvib._kernels.shooting import strobe_map
from contactvib.model.system import ContactElement, System
from contactvib.steady.system_orbits import mean_contact_forces, period_map, periodic_orbit, simulate_system

PA, FE = 0.65, 360.0
MODELS = {"paper": ContactModel(),
          "clearance, hunt-crossley, preload": ContactModel(law="clearance", law_params={"c_lin": 2e10, "gap_um": 0.5},
                                                            damping="hunt-crossley", alpha=30.0, preload=0.5),
          "exponential": ContactModel(law="exponential")}


def _si(model, x):
    """Nondimensional (x, x') of the 1-DOF kernels → SI (y, ẏ)."""
    return np.array([model.spring_law.engagement_m + x[0] * model.y0, x[1] * model.y0 * model.omega_n0])


@pytest.mark.parametrize("name", MODELS)
def test_static_state_and_linear_mode_are_the_models(name):
    m = MODELS[name]
    s = System.single_dof(m)
    assert s.static_state()[0] == pytest.approx(m.spring_law.engagement_m + m.y0, rel=1e-12)
    assert s.linear_modes()[0] == pytest.approx(m.f_n0, rel=1e-12)
    assert s.coordinates == ("y",) and s.units == ("m",) and s.f0[0] == m.W


@pytest.mark.parametrize("name", MODELS)
@pytest.mark.parametrize("x0", [(1.3, 0.2), (-0.5, 1.0), (0.2, -2.0)])
def test_period_map_equals_the_one_dof_kernel(name, x0):
    m = MODELS[name]
    exc = m.excitation(PA, FE)
    s = System.single_dof(m)
    for k in (1, 3):
        oz, oM = np.empty(2), np.empty((2, 2))
        assert strobe_map(np.array(x0), k, exc.kernel_parameters(), 1e-12, 1e-12, oz, oM) == 0
        pm = period_map(s, exc.P_a, FE, _si(m, x0), k)
        z_ref = _si(m, oz)
        D = np.array([m.y0, m.y0 * m.omega_n0])
        assert np.max(np.abs(pm.z - z_ref) / D) < 1e-9 * max(1.0, np.max(np.abs(oz)))
        phi_ref = oM * D[:, None] / D[None, :]
        assert np.max(np.abs((pm.monodromy - phi_ref) * D[None, :] / D[:, None])) < 1e-9 * max(1.0, np.abs(oM).max())


def test_time_history_equals_simulate():
    m = MODELS["paper"]
    exc = m.excitation(PA, FE)
    ref = simulate(exc, y_um=0.1, ydot_mm_s=0.5, n_periods=3, samples_per_period=200, rtol=1e-12)
    h = simulate_system(System.single_dof(m), exc.P_a, FE, [0.1e-6], [0.5e-3], 3, 200, rtol=1e-12)
    assert h.q_units == ("um",) and h.qdot_units == ("mm/s",) and h.contacts == ("contact",)
    np.testing.assert_allclose(h.t_ms, ref.t_ms, rtol=1e-12)
    np.testing.assert_allclose(h.q[0], ref.y_um, rtol=0, atol=1e-10)
    np.testing.assert_allclose(h.qdot[0], ref.ydot_mm_s, rtol=0, atol=1e-10)
    assert np.array_equal(h.in_contact[0], ref.in_contact)
    F = h.forces_n[0]
    assert np.all(F[~h.in_contact[0]] == 0.0) and np.max(F) > m.Q


@pytest.fixture(scope="module")
def orbits():
    """(attractor, system orbit) pairs of the paper's model at 0.65 Q, 360 Hz."""
    m = MODELS["paper"]
    exc = m.excitation(PA, FE)
    s = System.single_dof(m)
    out = []
    for a in find_attractors(exc, n_starts=32):
        z = _si(m, a.state)
        o = periodic_orbit(s, exc.P_a, FE, z * (1.0 + 1e-3), a.period)
        out.append((a, z, o))
    assert len(out) >= 4 and any(a.loses_contact for a, _, _ in out)
    return out


def test_newton_finds_the_attractors_with_their_floquet_multipliers(orbits):
    for a, z, o in orbits:
        assert o.iterations >= 1 and o.stable
        D = np.array([MODELS["paper"].y0, MODELS["paper"].y0 * MODELS["paper"].omega_n0])
        assert np.max(np.abs(o.z - z) / D) < 1e-8 * max(1.0, np.max(np.abs(a.state)))
        np.testing.assert_allclose(np.sort_complex(o.floquet_multipliers), np.sort_complex(a.floquet_multipliers),
                                   rtol=0, atol=1e-6)


def test_liouville_on_the_periodic_orbits(orbits):
    m = MODELS["paper"]
    s = System.single_dof(m)
    for a, _z, o in orbits:
        z_ref, liouville, _ = integrate_system(s, PA * m.Q, FE, o.z, a.period / FE, atol_q=[1e-19])
        assert np.linalg.det(o.monodromy) == pytest.approx(np.exp(-liouville), rel=1e-9)
        D = np.array([m.y0, m.y0 * m.omega_n0])
        assert np.max(np.abs(z_ref - o.z) / D) < 1e-8 * max(1.0, np.max(np.abs(o.z / D)))  # scipy closes it too


def test_mean_contact_force_is_the_weight(orbits):
    m = MODELS["paper"]
    s = System.single_dof(m)
    for a, _z, o in orbits:
        F = mean_contact_forces(s, PA * m.Q, FE, o.z, a.period)
        assert F[0] == pytest.approx(m.Q, rel=1e-8)


def test_a_symmetric_slide_unit_is_the_paper_slider():
    """Two contacts at ±4 cm, half the paper's area each, under a vertical force only: θ stays 0,
    both contacts switch at the same instants (located as one event, the other at θ = 0 of the
    next step), and y follows the paper's slider: its map to 1e-9 of y0 [measured ≤ 4e-11], θ zero but
    for rounding [≤ 4e-12 y0/a]."""
    m = MODELS["paper"]
    a = 0.04
    law = m.spring_law
    unit = System(M=np.diag([m.M, m.M * a * a / 3.0]), f0=[m.Q, 0.0], b=[1.0, 0.0],
                  contacts=[ContactElement(name, (1.0, s * a), m.S / 2, law, h_n=m.h_n, l=m.l)
                            for name, s in (("front", 1), ("rear", -1))],
                  coordinates=("y", "theta"), units=("m", "rad"))
    exc = m.excitation(PA, FE)
    for x0 in [(1.3, 0.2), (-0.5, 1.0)]:
        oz, oM = np.empty(2), np.empty((2, 2))
        assert strobe_map(np.array(x0), 2, exc.kernel_parameters(), 1e-12, 1e-12, oz, oM) == 0
        y = _si(m, x0)
        pm = period_map(unit, exc.P_a, FE, [y[0], 0.0, y[1], 0.0], 2)
        D = np.array([m.y0, m.y0 * m.omega_n0])
        assert np.max(np.abs(pm.z[[0, 2]] - _si(m, oz)) / D) < 1e-9 * max(1.0, np.max(np.abs(oz)))
        assert abs(pm.z[1]) * a < 1e-9 * m.y0 and abs(pm.z[3]) * a < 1e-9 * m.y0 * m.omega_n0  # rounding only
        np.testing.assert_allclose(pm.monodromy[np.ix_([0, 2], [0, 2])] * D[None, :] / D[:, None], oM,
                                   rtol=0, atol=1e-8 * max(1.0, np.abs(oM).max()))
