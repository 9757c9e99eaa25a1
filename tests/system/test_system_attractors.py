"""The multi-start search of a system (``steady.system_attractors``) and the commands
``contactvib attractors --system`` and ``contactvib simulate --system``.

The orbit the search finds on the 2-DOF file system (P_a = 2 N, f_e = 0.2 Hz: the stop is hit
once a period) is confirmed periodic by scipy with located events (``scipy_system``: solve_ivp
DOP853, rtol 1e-11): one period from its point returns to it to 1e-8 of the state's size
[measured 3e-11], with at least two switches of the stop."""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy_system import integrate_system

from contactvib.cli import main
from contactvib.model import ContactModel
from contactvib.model.rocking import rocking_system
from contactvib.model.system_file import load_system
from contactvib.steady.system_attractors import find_system_attractors
from contactvib.steady.system_orbits import period_map

EXAMPLE = Path(__file__).parents[2] / "examples" / "two_dof_stop.toml"
DOF_KEYS = {"name", "unit", "min", "max", "app", "h1"}
CONTACT_KEYS = {"name", "loses_contact", "contact_loss_fraction", "mean_force_n"}
ATTRACTOR_KEYS = {"period", "minima_per_period", "floquet_multipliers", "floquet_abs_max", "stable", "basin_fraction",
                  "dofs", "contacts"}


def _check_json(d: dict, n: int, m: int) -> None:
    assert len(d["natural_frequencies_hz"]) == n
    total = sum(a["basin_fraction"] for a in d["attractors"]) + d["n_unsettled"] / d["n_starts"]
    assert total + d["n_failed"] / d["n_starts"] == pytest.approx(1.0)
    for a in d["attractors"]:
        assert ATTRACTOR_KEYS <= set(a)
        assert len(a["floquet_multipliers"]) == 2 * n and all(len(mu) == 2 for mu in a["floquet_multipliers"])
        assert [set(x) for x in a["dofs"]] == [DOF_KEYS] * n and [set(c) for c in a["contacts"]] == [CONTACT_KEYS] * m
        assert a["stable"] == (a["floquet_abs_max"] <= 1.0 + 1e-6)
        # the Lyapunov keys: a periodic orbit's 2n exponents ln|mu_i| f_e / k, descending, exact
        assert a["attractor_type"] == "periodic" and a["kaplan_yorke_dimension"] is None
        mu = np.abs([complex(*m) for m in a["floquet_multipliers"]])
        expected = np.sort(np.log(mu) * d["fe_hz"] / a["period"])[::-1]
        np.testing.assert_allclose(a["lyapunov_per_s"], expected, rtol=1e-12)
        assert a["lyapunov_stderr_per_s"] == [0.0] * 2 * n


def test_the_file_system_orbit_is_periodic_in_scipy():
    s = load_system(EXAMPLE)
    r = find_system_attractors(s, 2.0, 0.2, n_starts=8)
    assert len(r) >= 1 and r.n_unsettled == 0
    a = r.attractors[0]
    z = a.orbit.z
    z_ref, _, switches = integrate_system(s, 2.0, 0.2, z, a.period / 0.2, atol_q=[1e-12, 1e-12])
    assert switches >= 2
    err = max(np.max(np.abs(z_ref[:2] - z[:2])) / np.max(np.abs(z[:2])),
              np.max(np.abs(z_ref[2:] - z[2:])) / np.max(np.abs(z[2:])))
    assert err < 1e-8
    d = r.to_dict()
    _check_json(d, 2, 1)
    # the stop engages beyond q1 = 1 m: the orbit reaches it, and its mean force is positive
    dofs, contact = d["attractors"][0]["dofs"], d["attractors"][0]["contacts"][0]
    assert dofs[0]["max"] > 1e6 and contact["loses_contact"] and contact["mean_force_n"] > 0.0


def test_the_rocking_unit_keeps_the_paper_small_orbit():
    """At 0.5 Q, 1300 Hz the paper's slider has a period-1 orbit of A_pp 0.650 µm (basin 81 % of
    its search); the unit at e = 0 has it with θ = 0, and the same heave range."""
    m = ContactModel()
    r = find_system_attractors(rocking_system(m), 0.5 * m.Q, 1300.0, n_starts=8)
    small = [a for a in r if a.period == 1]
    assert len(small) == 1
    d = small[0].to_dict()
    assert d["dofs"][0]["app"] == pytest.approx(0.64990, rel=1e-3) and d["dofs"][1]["app"] < 1e-6
    assert [c["mean_force_n"] for c in d["contacts"]] == pytest.approx([m.Q / 2] * 2, rel=1e-9)


def test_attractors_cli_json(capsys):
    rc = main(["attractors", "--system", "rocking", "--pa", "0.5", "--fe", "1300", "--set", "e=0.01", "--json",
               "--starts", "4"])
    out = capsys.readouterr().out
    d = json.loads(out)
    # none of 4 starts settles here (6 of 64 do): the JSON is printed, then exit status 1 as the slider's
    assert rc == (0 if d["attractors"] else 1)
    assert d["system"] == "rocking" and d["coordinates"] == ["y", "theta"] and d["n_starts"] == 4
    _check_json(d, 2, 2)


def test_attractors_cli_table(capsys):
    rc = main(["attractors", "--system", str(EXAMPLE), "--pa-newton", "2", "--fe", "0.2", "--starts", "4"])
    lines = capsys.readouterr().out.splitlines()
    assert rc == 0
    assert lines[0].startswith("system ") and "P_a = 2 N, f_e = 0.2 Hz" in lines[0]
    assert lines[1].startswith("linear modes: 0.09836, 0.2575 Hz")
    assert "q1 A_pp [um]" in lines[2] and lines[3].split()[:2] == ["0", "1"]


def test_simulate_cli(tmp_path, capsys):
    rc = main(["simulate", "--system", "rocking", "--pa", "0.5", "--fe", "1300", "--set", "e=0.01",
               "--from-state", "0.3,2", "0,0", "--periods", "5", "--out", str(tmp_path / "traj")])
    out = capsys.readouterr().out.split()
    assert rc == 0 and len(out) == 2 and all(Path(p).stat().st_size > 10_000 for p in out)
    rc = main(["simulate", "--system", str(EXAMPLE), "--pa-newton", "2", "--fe", "0.2", "--starts", "4",
               "--out", str(tmp_path / "att")])
    capsys.readouterr()
    assert rc == 0
    d = json.loads((tmp_path / "att" / "attractors.json").read_text())
    assert len(list((tmp_path / "att").glob("attractor*_forces.png"))) == len(d["attractors"]) >= 1


@pytest.mark.parametrize("args, words", [
    (["--system", "rocking", "--from-state", "0.3", "0"], "expected 2 positions"),
    (["--system", "rocking", "--base-um", "0.1"], "--base-um belongs to the paper's slider"),
    (["--system", "rocking", "--set", "a=-1"], "--set a"),
    (["--system", str(EXAMPLE), "--law", "exponential"], "--law"),
])
def test_simulate_cli_refusals(args, words, capsys, tmp_path):
    rc = main(["simulate", "--fe", "1300", *args, "--out", str(tmp_path)])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and len(err.splitlines()) == 1 and words in err, err


def test_the_rocking_orbits_come_in_mirror_pairs():
    """At 0.65 Q, 360 Hz the unit (e = 0) rocks on a period-1 orbit besides the paper's small one;
    its mirror image (θ → −θ: front and rear patch exchanged) is an orbit with the same
    multipliers, and each patch carries Q/2 on average."""
    m = ContactModel()
    s = rocking_system(m)
    r = find_system_attractors(s, 0.65 * m.Q, 360.0, n_starts=16)
    rocking = [a for a in r if a.to_dict()["dofs"][1]["app"] > 1.0 and a.attractor_type == "periodic"]
    assert rocking and all(a.period == 1 and a.stable for a in rocking)
    a = rocking[0]
    mirror = a.orbit.z * np.array([1.0, -1.0, 1.0, -1.0])
    pm = period_map(s, 0.65 * m.Q, 360.0, mirror, 1)
    size = np.array([m.y0, m.y0 / 0.05, m.y0 * m.omega_n0, m.y0 * m.omega_n0 / 0.05])
    assert np.max(np.abs(pm.z - mirror) / size) < 1e-9
    assert np.sort(np.abs(np.linalg.eigvals(pm.monodromy))) == pytest.approx(
        np.sort(np.abs(a.floquet_multipliers)), rel=1e-6)
    assert [c["mean_force_n"] for c in a.to_dict()["contacts"]] == pytest.approx([m.Q / 2] * 2, rel=1e-9)
