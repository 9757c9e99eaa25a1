"""Harmonic balance: agreement with shooting where contact is kept, convergence in H where it
is lost, the AFT Jacobian, continuation through a fold with the stability change, bad input."""
import json

import numpy as np
import pytest

from contactvib import ContactModel, ParameterError
from contactvib.cli import main
from contactvib.frequency.harmonic_balance import (
    _AFT,
    _residual,
    coefficients_from_orbit,
    hb_continuation,
    hb_solve,
)
from contactvib.frequency.perturbation import perturbation_series
from contactvib.steady.orbits import describe_orbit, refine_orbit

MODEL = ContactModel()


def _shooting(exc, z):
    z, M, res = refine_orbit(exc, z, 1)
    return describe_orbit(exc, z, 1, monodromy=M, closure=res)


@pytest.mark.parametrize("fe,minima", [(287.0, 2), (360.0, 4), (371.0, 3)])
def test_hb_equals_shooting_where_contact_is_kept(fe, minima):
    """0.65 Q, H = 32: A_pp and |multipliers| equal the shooting orbit's to 1e-6 relative
    (measured ≤ 1.2e-11)."""
    exc = MODEL.excitation(0.65, fe)
    ref = _shooting(exc, perturbation_series(exc, terms=80).state)
    assert ref.minima_per_period == minima and not ref.loses_contact
    sol = hb_solve(exc, harmonics=32)
    assert not sol.loses_contact and sol.residual <= 1e-12
    assert sol.app_um == pytest.approx(ref.app_um, rel=1e-6)
    assert sol.ymin_um == pytest.approx(ref.ymin_um, rel=1e-6)
    assert np.sort(np.abs(sol.floquet_multipliers)) == pytest.approx(
        np.sort(np.abs(ref.floquet_multipliers)), rel=1e-6)
    assert sol.stable and sol.closure <= 1e-9


def test_hb_converges_with_harmonics_where_contact_is_lost():
    """Main resonance at 0.65 Q, 360 Hz (y_min ≈ −10 µm, 91 % of the period in flight): the
    error falls algebraically with H, not geometrically (the touch-down kink; measured 9.7e-4,
    7.7e-6, 6.6e-7, 2.5e-7 for H = 16, 32, 64, 128)."""
    exc = MODEL.excitation(0.65, 360.0)
    ref = _shooting(exc, [-45.6107, 0.5061])
    assert ref.loses_contact and ref.contact_loss_fraction > 0.9
    err = {}
    for H in (16, 32, 64, 128):
        sol = hb_solve(exc, harmonics=H, start=coefficients_from_orbit(exc, ref.state, harmonics=H), stability=False)
        assert sol.loses_contact
        err[H] = abs(sol.app_um - ref.app_um) / ref.app_um
    assert err[16] > 1e-4 and err[128] < 1e-6
    assert err[16] > err[32] > err[64] > err[128]


def test_aft_jacobian_matches_finite_differences():
    exc = MODEL.excitation(0.65, 742.0)  # an orbit with loss of contact
    H = 12
    aft = _AFT(H, 128)
    rng = np.random.default_rng(1)
    X = np.zeros(2 * H + 1)
    X[0], X[1], X[2] = 0.8, 1.2, 0.4
    X[3:] = 0.05 * rng.standard_normal(2 * H - 2)
    par = (MODEL.m2, MODEL.l, MODEL.damping_coefficient, exc.pa_over_q)
    R, J, dr = _residual(X, exc.r, par, aft)
    h = 1e-7
    Jfd = np.column_stack([(_residual(X + h * e, exc.r, par, aft, False)[0]
                            - _residual(X - h * e, exc.r, par, aft, False)[0]) / (2 * h)
                           for e in np.eye(X.size)])
    drfd = (_residual(X, exc.r + h, par, aft, False)[0]
            - _residual(X, exc.r - h, par, aft, False)[0]) / (2 * h)
    assert np.max(np.abs(J - Jfd)) <= 1e-5 * np.max(np.abs(J))
    assert np.max(np.abs(dr - drfd)) <= 1e-5 * np.max(np.abs(dr))


def test_continuation_passes_the_one_third_fold_and_stability_changes_there():
    """0.65 Q from 430 Hz up: the 1/3 resonance bends left; the branch turns at its largest
    f_e (≈ 461 Hz), comes back unstable (a real multiplier through +1) and leaves at 430 Hz."""
    b = hb_continuation(MODEL, pa_over_q=0.65, fmin_hz=430.0, fmax_hz=470.0, harmonics=24)
    assert "430" in b.stop_reason
    i = int(np.argmax(b.fe_hz))
    assert 455.0 < b.fe_hz[i] < 468.0
    assert b.stable[: i - 1].all() and not b.stable[i + 2:].any()
    assert b.app_um[-1] > b.app_um[0] * 2  # the upper, unstable side
    # a continuation point agrees with shooting started from it
    j = i // 2
    s = b.solutions[j]
    exc = MODEL.excitation(0.65, s.fe_hz)
    z = [s.coefficients[0] + s.coefficients[1::2].sum(),
         exc.r * (np.arange(1, 25) * s.coefficients[2::2]).sum()]
    ref = _shooting(exc, z)
    assert s.app_um == pytest.approx(ref.app_um, rel=1e-6)


def test_branch_stops_when_top_harmonics_hold_the_energy():
    b = hb_continuation(MODEL, pa_over_q=0.65, fmin_hz=900.0, fmax_hz=2000.0, harmonics=8, from_fmax=True)
    assert "harmonics" in b.stop_reason and b.loses_contact[-1]
    assert b.top_energy_fraction[-1] > 1e-8 and b.fe_hz.min() > 900.0


def test_bad_input(capsys, tmp_path):
    with pytest.raises(ParameterError, match="harmonics"):
        hb_solve(MODEL.excitation(0.5, 300.0), harmonics=0)
    with pytest.raises(ParameterError, match="fmax"):
        hb_continuation(MODEL, pa_over_q=0.5, fmin_hz=500.0, fmax_hz=400.0)
    for argv, msg in [(["--harmonics", "0"], "--harmonics (harmonics) = 0"),
                      (["--fmin", "2000", "--fmax", "300"], "--fmax (f_max) = 300: must be > --fmin"),
                      (["--fmin", "-1"], "--fmin (f_min) = -1"), (["--pa", "-0.5"], "--pa"),
                      (["--harmonics", "2.5"], "--harmonics")]:
        assert main(["hbm", *argv, "--out", str(tmp_path)]) == 2
        err = capsys.readouterr().err
        assert err.startswith("contactvib: error: ") and msg in err and err.count("\n") == 1


def test_cli_json(capsys, tmp_path):
    assert main(["hbm", "--pa", "0.1", "--harmonics", "12", "--fmin", "1700", "--fmax", "2000",
                 "--out", str(tmp_path), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["harmonics"] == 12 and len(d["branches"]) == 2
    pts = d["branches"][0]["points"]
    assert all(1700 <= p["fe_hz"] <= 2000 and p["stable"] and not p["loses_contact"] for p in pts)
    assert (tmp_path / "branch.json").exists() and list(tmp_path.glob("hbm_branch_*.png"))
