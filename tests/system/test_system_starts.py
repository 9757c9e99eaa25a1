"""Where a system's search starts (``steady.system_starts``): the ballistic seeds fly free for
whole excitation periods under the static load, and reach large orbits the box cannot.

Independent check: scipy (``scipy_system``: solve_ivp with located contact events, no force)
from the seed of a one-period flight (speed fraction 1, phase 0) of the rocking unit (no linear
stiffness or damping: a ballistic flight) makes its first contact switch at t = T to 1e-6 of T,
back at the touching position."""

from pathlib import Path

import numpy as np
from scipy_system import integrate_system

from contactvib.model import ContactModel
from contactvib.model.rocking import rocking_system
from contactvib.model.system_file import load_system
from contactvib.steady.system_attractors import find_system_attractors
from contactvib.steady.system_starts import SEED_PHASES, SEED_SPEEDS, seed_states

EXAMPLE = Path(__file__).parents[2] / "examples" / "two_dof_stop.toml"


def test_the_one_period_seed_lands_after_one_period_in_scipy():
    m = ContactModel()
    s = rocking_system(m)
    fe = 1300.0
    form = s.kernel_form(0.0, fe)
    X = seed_states(s, form, fe)
    # flights of 1 and 2 periods, 3 speeds, 4 phases, less the seeds that have landed already
    landed = sum(1 for j in (1, 2) for sp in SEED_SPEEDS for ph in SEED_PHASES if ph >= sp * j)
    assert X.shape == (2 * len(SEED_SPEEDS) * len(SEED_PHASES) - landed, 4)
    seeds_si = np.array([form.scales.to_si(x) for x in X])
    z0 = np.array([0.0, 0.0, -m.g / fe / 2.0, 0.0])  # j = 1, s = 1, phase 0: take-off at -g T/2
    assert np.min(np.max(np.abs(seeds_si - z0) / np.array([1e-6, 1e-6, 1e-3, 1e-3]), axis=1)) < 1e-9
    z, _, switches = integrate_system(s, 0.0, fe, z0, 0.999 / fe, rtol=1e-12, liouville=False)
    assert switches == 0 and z[0] < 0.0  # still in flight, above the touching position
    z, _, switches = integrate_system(s, 0.0, fe, z0, 1.001 / fe, rtol=1e-12, liouville=False)
    assert switches >= 1 and z[0] > 0.0  # landed in between: at t = T


def test_no_seeds_without_a_static_load():
    s = load_system(EXAMPLE)
    assert seed_states(s, s.kernel_form(0.1, 0.1), 0.1).shape == (0, 4)


def test_seeds_reach_the_large_orbits_that_the_box_misses():
    """Rocking unit (e = 0), 0.65 Q, 200 Hz: the box finds the small period-1 orbit only; the
    seeds add a period-2 orbit of about 35 µm heave (basin 0: no box start reaches it), which one
    period-2 of scipy at rtol 1e-10 confirms to 1e-6 of its size [measured 6e-8; the compiled
    period map agrees with itself to 1e-10 over rtol 1e-9..1e-13, while scipy's reference at
    rtol ≤ 1e-11 settles 2e-5 away in the pitch, with overflowing trial steps at the stiff
    re-contacts: the reference's limit here]."""
    m = ContactModel()
    s = rocking_system(m)
    pa, fe = 0.65 * m.Q, 200.0
    box = find_system_attractors(s, pa, fe, n_starts=8, seeds=False, nonperiodic=False)
    both = find_system_attractors(s, pa, fe, n_starts=8, nonperiodic=False)
    assert max(a.to_dict()["dofs"][0]["app"] for a in box) < 1.0
    large = [a for a in both if a.to_dict()["dofs"][0]["app"] > 10.0]
    assert large and all(a.basin_fraction == 0.0 for a in large) and both.settings["n_seeds"] > 0
    a = large[0]
    with np.errstate(over="ignore", invalid="ignore"):
        z, _, switches = integrate_system(s, pa, fe, a.orbit.z, a.period / fe, rtol=1e-10, liouville=False)
    assert switches >= 2
    err = np.max(np.abs(z - a.orbit.z) / np.abs(a.strobe).max(axis=0))
    assert err < 1e-6


def test_cli_no_seeds(capsys):
    import json

    from contactvib.cli import main

    counts = []
    for extra in ([], ["--no-seeds"]):
        rc = main(["attractors", "--system", "rocking", "--pa", "0.65", "--fe", "200", "--starts", "4", "--json",
                   *extra])
        d = json.loads(capsys.readouterr().out)
        assert rc == 0
        counts.append(d["n_seeds"])
    assert counts[0] > 0 and counts[1] == 0
