"""The system core's compiled integrator against an independent scipy integration with located
events (``scipy_system``: solve_ivp DOP853, rtol 1e-11, a terminal event on every contact's
δ_i = 0, restarting in the new mode), and its monodromy against finite differences and
Liouville's formula.

Systems:

* the 2-DOF structure of the model-file example (M = I, K = [[1, −1], [−1, 2]],
  C = [[0.03, −0.03], [−0.03, 0.06]], b = [0, 1]) with one clearance contact on q1 (c_lin = 100
  N/m³, S = 1 m², gap 1 m), undamped, with power damping l = 0 (the force jumps at δ = 0: a
  saltation matrix) and with Hunt–Crossley damping;
* a slide unit that rocks on two rough contacts (the paper's law and damping, half the area each)
  under gravity, a force and a moment: coordinates y [m] and θ [rad], both contacts lost and
  regained every period.

Tolerances (measured errors in brackets): end states to 1e-8 of the state's size [≤ 3e-9, the
rocking unit; ≤ 4e-10 the 2-DOF]; monodromy against central differences of the map (step 1e-6 of
each scale, rtol 1e-13), in the scaled state, to 1e-6 [≤ 3e-8]; det Φ = exp(−∫ trace(M⁻¹ C(t)) dt)
to 1e-9 relative [≤ 2e-10]: the saltation matrices have determinant 1 (their jump has no position
part), so the identity holds across every switch. Without the saltation matrix the power-damped
(l = 0) case misses the finite differences by 6e-4.
"""

import math

import numpy as np
import pytest
from scipy_system import integrate_system

from contactvib.model.laws import ClearanceLaw, PowerSpring
from contactvib.model.system import ContactElement, System
from contactvib.steady.system_orbits import period_map, periodic_orbit

DAMPINGS = {"undamped": {}, "power l=0": {"h_n": 0.5, "l": 0.0}, "hunt-crossley": {"damping": "hunt-crossley",
                                                                                     "alpha": 0.05}}


def two_dof(**damping):
    """The model-file example: a clearance contact on q1, the force on q2."""
    return System(M=np.eye(2), K=[[1.0, -1.0], [-1.0, 2.0]], C=[[0.03, -0.03], [-0.03, 0.06]], b=[0.0, 1.0],
                  contacts=[ContactElement("stop", (1.0, 0.0), 1.0, ClearanceLaw(c_lin=100.0, gap_um=1e6),
                                           **damping)])


def rocking_unit():
    """A slide unit (0.2106 kg, half-length 4 cm) on two rough contacts at ±4 cm: (y, θ)."""
    m, a = 0.2106, 0.04
    law = PowerSpring(c_n=4.52e16, m2=2.0)
    contacts = [ContactElement(name, (1.0, s * a), 0.00045, law, h_n=3.5e11, l=1.0)
                for name, s in (("front", 1.0), ("rear", -1.0))]
    return System(M=np.diag([m, m * (2 * a) ** 2 / 12.0]), f0=[m * 9.81, 0.0], b=[1.0, 0.01],
                  contacts=contacts, coordinates=("y", "theta"), units=("m", "rad"))


#: (system, P_a [N], f_e [Hz], z0 [SI], periods, scipy's absolute tolerance on q)
CASES = {f"2dof {k}": (two_dof(**v), 2.0, 0.2, [0.5, 0.0, 0.0, 0.0], 3, [1e-12, 1e-12]) for k, v in DAMPINGS.items()}
CASES["rocking"] = (rocking_unit(), 1.8, 700.0, [2.5e-7, 0.0, 0.0, 0.0], 4, [1e-19, 1e-18])


def _state_error(a, b, system):
    """max |a − b| relative to the size of b, per kind (q and q̇ separately, each its own scale)."""
    n = system.n
    return max(np.max(np.abs(a[:n] - b[:n])) / np.max(np.abs(b[:n])),
               np.max(np.abs(a[n:] - b[n:])) / np.max(np.abs(b[n:])))


@pytest.mark.parametrize("case", CASES)
def test_end_state_and_liouville_against_scipy(case):
    system, pa, fe, z0, k, atol_q = CASES[case]
    pm = period_map(system, pa, fe, z0, k, rtol=1e-12)
    z_ref, liouville, switches = integrate_system(system, pa, fe, z0, k / fe, atol_q=atol_q)
    assert switches >= 2 * k if case == "rocking" else switches >= 4
    assert _state_error(pm.z, z_ref, system) < 1e-8
    assert np.linalg.det(pm.monodromy) == pytest.approx(math.exp(-liouville), rel=1e-9)


@pytest.mark.parametrize("case", CASES)
def test_monodromy_against_finite_differences(case):
    system, pa, fe, z0, k, _ = CASES[case]
    z0 = np.array(z0)
    phi = period_map(system, pa, fe, z0, k, rtol=1e-13).monodromy
    d = system.scales.state * 1e-6  # steps of 1e-6 of each component's scale
    fd = np.empty_like(phi)
    for j in range(z0.size):
        e = np.zeros_like(z0)
        e[j] = d[j]
        fd[:, j] = (period_map(system, pa, fe, z0 + e, k, rtol=1e-13).z
                    - period_map(system, pa, fe, z0 - e, k, rtol=1e-13).z) / (2 * d[j])
    D = system.scales.state
    scaled = (phi - fd) * D[None, :] / D[:, None]  # in the scaled state, where entries are O(1)
    assert np.max(np.abs(scaled)) < 1e-6 * max(1.0, np.max(np.abs(phi * D[None, :] / D[:, None])))


@pytest.mark.parametrize("damping", ["power l=0", "hunt-crossley"])
def test_periodic_orbit_of_the_clearance_system(damping):
    """Newton shooting from a settled state: a period-1 orbit with contact, its closure by scipy,
    Liouville's formula along it and stability of the attractor it was settled on."""
    system = two_dof(**DAMPINGS[damping])
    pa, fe = 2.0, 0.2
    z = period_map(system, pa, fe, [0.5, 0.0, 0.0, 0.0], 60, rtol=1e-10).z  # settle for 60 periods
    orbit = periodic_orbit(system, pa, fe, z, 1)
    z_ref, liouville, switches = integrate_system(system, pa, fe, orbit.z, 1 / fe)
    assert switches == 2
    assert _state_error(z_ref, orbit.z, system) < 1e-8
    assert np.prod(orbit.floquet_multipliers).real == pytest.approx(math.exp(-liouville), rel=1e-9)
    assert orbit.stable and np.max(np.abs(orbit.floquet_multipliers)) < 1.0
