"""The two-contact slide unit (``contactvib.model.rocking_system``) against the paper's slider.

With the force at the centre of mass (e = 0) and no pitch, the two patches (S/2 each at ±a)
carry equal forces whose sum is the paper's contact force of the heave: each periodic orbit of
the paper's model at 0.65 Q, 360 Hz (found and refined by the 1-DOF code, ``steady.orbits``) is
an orbit of the unit with θ = 0 and the same heave. Checked: the unit's period map closes on the
paper's orbit point to 2e-9 of the scales y0, y0 ω_n0 [measured ≤ 1e-10] and Newton shooting on the
unit lands on it to 1e-8 [≤ 1e-10]; its heave multipliers are the paper's to 1e-6 [≤ 3e-9]. The
pitch multipliers (the block of θ, θ̇ in the monodromy, decoupled at e = 0) say whether the
motion stays stable against rocking. Measured (largest |μ| of each block; the heave's equal the
paper's to ≤ 1e-10):

====== ====== ========= ============================== ==========================
period minima |μ| heave pitch multipliers              against rocking
====== ====== ========= ============================== ==========================
2      1      0.858     0.0092, 43.23                  unstable (divergent)
1      1      0.885     0.0275, 17.50                  unstable (divergent)
1      2      0.819     −0.0698, −4.315                unstable (flip: rocks at f_e/2)
1      3      0.751     −0.0208, −8.589                unstable (flip)
1      4      0.641     0.2208 ± 0.1368i (|μ| 0.260)   stable
====== ====== ========= ============================== ==========================

Only the small motion that keeps contact survives on the unit: the paper's large bouncing
orbits, lost contact and regained, rock.

The mean forces are exact identities (average the equations of motion over a period: ⟨ÿ⟩ =
⟨θ̈⟩ = ⟨P⟩ = 0): ⟨F1 + F2⟩ = Q and ⟨F1⟩ = ⟨F2⟩ = Q/2 on every periodic orbit, for any e (the
moment e P averages to 0); checked to 1e-9 relative [≤ 1e-12].
"""

import numpy as np
import pytest

from contactvib.model import ContactModel
from contactvib.model.rocking import rocking_system
from contactvib.steady.orbits import refine_orbit
from contactvib.steady.system_orbits import mean_contact_forces, period_map, periodic_orbit

#: The paper's attractors at 0.65 Q, 360 Hz (``contactvib attractors --pa 0.65 --fe 360``):
#: period and one stroboscopic point (y [µm], ẏ [mm/s]), refined below by the 1-DOF Newton.
PAPER_ORBITS = [(2, -31.70587665, -10.72010396), (1, -10.27873691, 1.06428416), (1, 0.76298575, -2.69977839),
                (1, -0.05752241, 1.14204546), (1, 0.29333685, -0.26267521)]
#: Largest pitch multiplier of each (the table of the module docstring).
PITCH_MU = [43.23, 17.50, 4.315, 8.589, 0.2597]


@pytest.fixture(scope="module")
def paper():
    m = ContactModel()
    exc = m.excitation(0.65, 360.0)
    orbits = []
    for k, y_um, v_mm_s in PAPER_ORBITS:
        x, xd = m.units.state(y_um, v_mm_s)
        z, M1, _ = refine_orbit(exc, np.array([x, xd]), k)
        orbits.append((k, np.array([z[0] * m.y0, z[1] * m.y0 * m.omega_n0]), M1))
    return m, orbits


def test_the_unit_at_rest_is_the_paper_slider():
    m = ContactModel()
    s = rocking_system(m)
    assert s.static_state() == pytest.approx([m.y0, 0.0], rel=1e-12, abs=1e-20)
    # heave at f_n0; pitch at sqrt(3) f_n0 for J = M (2a)^2 / 12 (k_pitch = a^2 k_lin, J = M a^2 / 3)
    assert s.linear_modes() == pytest.approx([m.f_n0, np.sqrt(3.0) * m.f_n0], rel=1e-10)
    assert s.contacts[0].S == s.contacts[1].S == m.S / 2 and s.b.tolist() == [1.0, 0.0]


@pytest.mark.parametrize("i", range(len(PAPER_ORBITS)))
def test_paper_orbits_are_orbits_of_the_unit(paper, i):
    m, orbits = paper
    k, (y, v), M1 = orbits[i]
    s = rocking_system(m)
    pa = 0.65 * m.Q
    z = np.array([y, 0.0, v, 0.0])
    size = np.array([m.y0, m.y0 / 0.05, m.y0 * m.omega_n0, m.y0 * m.omega_n0 / 0.05])
    pm = period_map(s, pa, 360.0, z, k)
    assert np.max(np.abs(pm.z - z) / size) < 2e-9
    orbit = periodic_orbit(s, pa, 360.0, z, k)
    assert np.max(np.abs(orbit.z - z) / size) < 1e-8
    heave = np.sort_complex(np.linalg.eigvals(orbit.monodromy[np.ix_([0, 2], [0, 2])]))
    assert heave == pytest.approx(np.sort_complex(np.linalg.eigvals(M1)), abs=1e-6)
    assert np.max(np.abs(orbit.monodromy[np.ix_([0, 2], [1, 3])])) < 1e-9 * np.max(np.abs(orbit.monodromy))
    pitch = np.linalg.eigvals(orbit.monodromy[np.ix_([1, 3], [1, 3])])
    assert np.max(np.abs(pitch)) == pytest.approx(PITCH_MU[i], rel=1e-3)
    assert orbit.stable == (np.max(np.abs(pitch)) < 1.0)


@pytest.mark.parametrize("i", range(len(PAPER_ORBITS)))
def test_mean_forces_on_the_paper_orbits(paper, i):
    m, orbits = paper
    k, (y, v), _ = orbits[i]
    f = mean_contact_forces(rocking_system(m), 0.65 * m.Q, 360.0, [y, 0.0, v, 0.0], k)
    assert f == pytest.approx([m.Q / 2, m.Q / 2], rel=1e-9)


def test_mean_forces_with_the_force_off_centre():
    """The period-1 orbit of the unit at 0.3 Q, 1000 Hz with e = 1 cm (it rocks): still
    ⟨F1⟩ = ⟨F2⟩ = Q/2."""
    m = ContactModel()
    s = rocking_system(m, e=0.01)
    k, (y, v) = 1, (m.y0, 0.0)
    z = np.array([y, 0.0, v, 0.0])
    for _ in range(100):  # settle near the stable period-1 orbit
        z = period_map(s, 0.3 * m.Q, 1000.0, z, k, rtol=1e-10).z
    orbit = periodic_orbit(s, 0.3 * m.Q, 1000.0, z, k)
    assert orbit.stable and abs(orbit.z[1]) > 1e-3 * m.y0 / 0.05
    f = mean_contact_forces(s, 0.3 * m.Q, 1000.0, orbit.z, k)
    assert f == pytest.approx([m.Q / 2, m.Q / 2], rel=1e-9)
