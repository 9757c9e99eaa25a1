"""Harmonic balance of a System (frequency/system_hb.py) against independent references: the
linear response in closed form, the single-DOF harmonic balance of the paper's model (another
formulation), Newton shooting on the compiled flow (the orbit and its multipliers), and the
exact period averages of the rocking unit's contact forces."""

from __future__ import annotations

import json

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib.cli import main
from contactvib.frequency.harmonic_balance import hb_solve
from contactvib.frequency.system_hb import system_hb_continuation, system_hb_solve
from contactvib.model import ParameterError
from contactvib.model.rocking import rocking_system
from contactvib.model.system import System
from contactvib.model.system_file import load_system
from contactvib.steady.system_orbits import periodic_orbit

STOP = "examples/two_dof_stop.toml"


@pytest.fixture(scope="module")
def stop():
    return load_system(STOP)


def test_linear_response_when_the_stop_never_engages(stop):
    """P_a = 1 mN keeps q1 far below the 1 m gap: the system is linear, its response one harmonic,
    (K − ω² M + iω C) A = b P_a, to 1e-10."""
    for fe in (0.05, 0.0984, 0.2575, 0.4):
        sol = system_hb_solve(stop, 1e-3, fe, harmonics=3, stability=False)
        w = 2 * np.pi * fe
        A = np.linalg.solve(np.array(stop.K) - w * w * np.array(stop.M) + 1j * w * np.array(stop.C), 1e-3 * stop.b)
        assert np.allclose(sol.coefficients[:, 1], A.real, rtol=1e-10, atol=1e-16)
        assert np.allclose(sol.coefficients[:, 2], -A.imag, rtol=1e-10, atol=1e-16)
        assert np.allclose(sol.q_h1, np.abs(A) * 1e6, rtol=1e-10)
        assert np.max(np.abs(sol.coefficients[:, 3:])) < 1e-14 and sol.mean_force_n[0] == 0.0
        assert sol.loses_contact[0] and sol.contact_loss_fraction[0] == 1.0  # the stop stays open


def test_single_dof_system_equals_the_papers_harmonic_balance():
    """The paper's slider as the n = 1 system: the same orbit as the single-DOF harmonic balance
    (nondimensional, another code path), A_pp to 1e-9."""
    model = ContactModel()
    system = System.single_dof(model)
    for pa, fe in ((0.3, 1000.0), (0.3, 1200.0)):
        ref = hb_solve(model.excitation(pa, fe), harmonics=16, n_time=256, stability=False)
        sol = system_hb_solve(system, pa * model.Q, fe, harmonics=16, n_time=256, stability=False)
        assert sol.q_app[0] == pytest.approx(ref.app_um, rel=1e-9)
        assert sol.q_min[0] == pytest.approx(ref.ymin_um, rel=1e-9, abs=1e-9 * ref.app_um)
        assert sol.mean_force_n[0] == pytest.approx(model.Q, rel=1e-9)  # ⟨F⟩ = Q on a periodic orbit


def test_rocking_mean_forces_are_half_the_weight_each():
    """⟨F1⟩ = ⟨F2⟩ = Q/2 for the rocking unit, exactly (the period average of both equations),
    also with the force off-centre."""
    model = ContactModel()
    system = rocking_system(model, e=0.01)
    sol = system_hb_solve(system, 0.3 * model.Q, 1000.0, harmonics=16, stability=False)
    assert sol.residual < 1e-10
    assert np.allclose(sol.mean_force_n, model.Q / 2, rtol=1e-9)
    assert sol.q_app[1] > 0.0  # the off-centre force pitches the unit


def test_orbit_and_multipliers_against_shooting(stop):
    """On the 2-DOF stop's resonance (the stop closing for a small part of the period) the HB orbit
    point is the shooting orbit to 2e-4 of its size at H = 32 (its rates to 2e-2), and its stability verdict is the
    shooting orbit's: all |μ| < 1 at 0.085 Hz, a complex pair outside the unit circle at 0.095 Hz
    (past the Neimark–Sacker point near 0.0926 Hz). Each start is the last point of one HB branch
    from 0.03 Hz before it first passes f_e."""
    branch = system_hb_continuation(stop, 0.1, fmin_hz=0.03, fmax_hz=0.095, harmonics=32, stability=False,
                                    energy_tol=1e-2).solutions
    for fe, unstable in ((0.085, False), (0.095, True)):
        first_past = next((i for i, b in enumerate(branch) if b.fe_hz > fe), len(branch))
        sol = system_hb_solve(stop, 0.1, fe, harmonics=32, start=branch[first_past - 1])
        c = sol.coefficients
        k = np.arange(1, 33)
        z = np.concatenate([c[:, 0] + c[:, 1::2].sum(axis=1), 2 * np.pi * fe * (k * c[:, 2::2]).sum(axis=1)])
        orb = periodic_orbit(stop, 0.1, fe, z)
        q, v = np.abs(orb.z[:2]).max(), np.abs(orb.z[2:]).max()
        assert np.max(np.abs(orb.z[:2] - z[:2])) < 2e-4 * q  # positions
        assert np.max(np.abs(orb.z[2:] - z[2:])) < 2e-2 * v  # rates: the derivative converges slower in H
        assert sol.stable is (not unstable) and orb.stable is (not unstable)
        if unstable:
            mu = orb.floquet_multipliers[0]
            assert abs(mu) > 1.0 and abs(mu.imag) > 0.1


def test_bad_input(stop):
    with pytest.raises(ParameterError, match="system"):
        system_hb_solve("rocking", 0.1, 0.1)
    with pytest.raises(ParameterError, match="harmonics"):
        system_hb_solve(stop, 0.1, 0.1, harmonics=0)
    with pytest.raises(ParameterError, match="fmax_hz"):
        system_hb_continuation(stop, 0.1, fmin_hz=0.3, fmax_hz=0.2)


def test_cli_hbm_system(tmp_path, capsys):
    out = tmp_path / "hb"
    assert main(["hbm", "--system", STOP, "--pa-newton", "0.1", "--fmin", "0.2", "--fmax", "0.3",
                 "--harmonics", "8", "--plot", "q2", "--measure", "h1", "--out", str(out), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["system"] == STOP and d["coordinates"] == ["q1", "q2"] and d["harmonics"] == 8
    p = d["points"][0]
    assert {"fe_hz", "pa_newton", "stable", "floquet_multipliers", "dofs", "contacts"} <= set(p)
    assert len(p["floquet_multipliers"]) == 4 and [x["name"] for x in p["dofs"]] == ["q1", "q2"]
    assert (out / "hbm_two_dof_stop_pa0.1N_H8_q2_h1.png").exists()


@pytest.mark.parametrize("args, needle", [
    (["--system", STOP, "--pa", "0.5", "--fmin", "0.1", "--fmax", "0.2"], "defines no Q"),
    (["--system", STOP, "--pa-newton", "0.1", "--fmin", "0.1", "--fmax", "0.2", "--plot", "q9"], "--plot q9"),
    (["--system", STOP, "--pa-newton", "0.1", "--fmin", "0.3", "--fmax", "0.2"], "--fmax"),
    (["--pa-newton", "0.1"], "--pa-newton: an option of --system only"),
])
def test_cli_hbm_system_bad_input(args, needle, tmp_path, capsys):
    assert main(["hbm", *args, "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0] and len(err[0]) <= 400


def test_special_points_agree_with_the_shooting_continuation(stop):
    """The stability changes of the HB branch (H = 24) lie at the special points that the shooting
    continuation locates (continuation/system_shooting.py, checked against scipy there): the first
    Neimark–Sacker point 0.092612 Hz, the period doubling 0.117581 Hz and the lower fold 0.103998 Hz,
    to 2e-3 of f_e (the truncation where the stop closes for under 1 % of the period)."""
    from contactvib.plotting.system import crossing_kind

    br = system_hb_continuation(stop, 0.1, fmin_hz=0.085, fmax_hz=0.125, harmonics=24, energy_tol=1e-2)
    st = br.stable
    found = [(crossing_kind(br.solutions[i].floquet_multipliers, br.solutions[i + 1].floquet_multipliers),
              0.5 * (br.fe_hz[i] + br.fe_hz[i + 1])) for i in np.where(st[1:] != st[:-1])[0]]
    for kind, f_ref in (("Neimark–Sacker", 0.092612), ("period doubling", 0.117581), ("fold", 0.103998)):
        assert any(k == kind and abs(f - f_ref) < 2e-3 * f_ref for k, f in found), (kind, found)
