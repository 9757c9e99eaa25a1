"""The verdict of the n-DOF attractor search (``steady.system_attractors``): a start without a
period ≤ kmax is periodic with a long period, chaotic, quasi-periodic or unsettled with a reason,
as in the 1-DOF search (``steady.transients.search_verdict``).

References and tolerances:

* the torus of ``examples/self_excited_stop.toml`` (P_a = 0.05 N, f_e = 0.12 Hz; a negatively
  damped coordinate behind a damped stop): ``|λ1|`` ≤ 3 standard errors [measured 6.5e-5 ± 1.1e-4
  1/s over 2000 periods]; the sum of the four exponents equals the damping average
  −⟨tr M⁻¹C(t)⟩ integrated on the dense output within 3 of its standard errors + 1e-10
  [measured 9e-12], and that average equals −tr(M⁻¹C) − S h_n · (contact fraction) (l = 0: a
  constant contact damping rate) to 1e-9; an independent solve_ivp run (DOP853, rtol 1e-11, the
  stop's switches located as events, ``contactvib.testing.integrate_system``) from another start
  reaches the same closed curve (``same_cloud``: median distances below 5 % of its extent) and its
  Liouville integral gives the same sum within 5e-4 1/s (0.6 %; 128 periods).
* ``examples/two_dof_stop.toml`` at 0.1 N: chaotic at 0.0955 Hz (λ1 > 3 standard errors; the
  long Benettin run of the lyapunov tests: +0.0114 ± 0.0003 1/s), the sum of the exponents
  −tr(M⁻¹C) = −0.09 1/s (the stop is undamped) to 1e-9; at 0.095 Hz the periodic attractors of
  the search without the verdict are kept bit for bit, the starts it left unsettled settle on a
  stable orbit of period 10 > kmax.
* a linear undamped structure whose stop is never reached: every start unsettled, "free flight:
  no contact".
* a growing mode (negative damping) that no contact acts on: refused in one line, exit 2.
"""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.model.system_file import load_system
from contactvib.steady.lyapunov import SIGMA_FACTOR, closed_curve, system_lyapunov_spectrum
from contactvib.steady.system_attractors import find_system_attractors
from contactvib.steady.system_verdict import strobe_projection
from contactvib.steady.transients import same_cloud
from contactvib.testing import integrate_system

EXAMPLES = Path(__file__).parents[2] / "examples"
TORUS = EXAMPLES / "self_excited_stop.toml"
STOP = EXAMPLES / "two_dof_stop.toml"


def _arrays(system, pa, fe):
    from contactvib._kernels.system_flow import system_arrays

    f = system.kernel_form(pa, fe)
    return system_arrays(f.Kx, f.Cx, f.g0, f.gb, f.r, f.U, f.gam, f.Aw, f.rows), f.scales


@pytest.fixture(scope="module")
def torus():
    s = load_system(TORUS)
    return s, find_system_attractors(s, 0.05, 0.12, n_starts=4)


def test_the_torus_is_labelled_quasi_periodic(torus):
    s, r = torus
    assert len(r) == 1 and r.n_unsettled == 0 and r.n_failed == 0
    a = r.attractors[0]
    assert a.attractor_type == "quasi-periodic" and a.hits == 4 and a.basin_fraction == 1.0
    lam, se = a.lyapunov_per_s, a.lyapunov_stderr_per_s
    assert abs(lam[0]) <= SIGMA_FACTOR * se[0]
    assert np.all(lam[1:] < -SIGMA_FACTOR * se[1:])  # attracting in the other three directions
    sa, sc = _arrays(s, 0.05, 0.12)
    assert closed_curve(strobe_projection(sa, np.array([sc.to_scaled(p) for p in a.strobe]))) == 1
    d = r.to_dict()["attractors"][0]
    assert d["attractor_type"] == "quasi-periodic" and d["period"] is None and d["kaplan_yorke_dimension"] is None
    assert len(d["lyapunov_per_s"]) == 4 and d["lyapunov_per_s"] == sorted(d["lyapunov_per_s"], reverse=True)
    assert d["contacts"][0]["loses_contact"] and d["dofs"][0]["max"] > 1e6  # q1 reaches the stop at 1 m


def test_the_torus_exponents_sum_to_the_damping_average(torus):
    s, r = torus
    spec = system_lyapunov_spectrum(s, 0.05, 0.12, r.attractors[0], periods=2000, batches=10, with_trace=True)
    assert abs(spec.exponents_per_s[0]) <= SIGMA_FACTOR * spec.stderr_per_s[0]
    assert abs(spec.sum_per_s - spec.damping_average_per_s) <= 3.0 * spec.damping_stderr_per_s + 1e-10
    c = s.contacts[0]
    w = np.asarray(c.direction, float)
    Minv = np.linalg.inv(s.M)
    closed_form = -np.trace(Minv @ s.C) - (w @ Minv @ w) * c.S * c.h_n * spec.contact_fraction
    assert spec.damping_average_per_s == pytest.approx(closed_form, abs=1e-9)
    assert 0.05 < spec.contact_fraction < 0.5


def test_scipy_reaches_the_same_closed_curve(torus):
    s, r = torus
    fe, T = 0.12, 1.0 / 0.12
    sa, sc = _arrays(s, 0.05, fe)
    z = np.array([0.0, 0.5, 0.3, 0.0])  # not a start of the search
    n_transient, n_kept = 150, 128
    pts, liouville = [], 0.0
    for j in range(n_transient + n_kept):
        z, li, _ = integrate_system(s, 0.05, fe, z, (j + 1) * T, rtol=1e-11, t0=j * T)
        if j >= n_transient:
            pts.append(sc.to_scaled(z))
            liouville += li
    ref = strobe_projection(sa, np.array(pts))
    cloud = strobe_projection(sa, np.array([sc.to_scaled(p) for p in r.attractors[0].strobe]))
    assert same_cloud(cloud, ref) and closed_curve(ref) == 1
    # Liouville along the scipy run: Σλ = −⟨tr M⁻¹C(t)⟩
    assert -liouville / (n_kept * T) == pytest.approx(float(np.sum(r.attractors[0].lyapunov_per_s)), abs=5e-4)


def test_the_chaotic_attractor_at_0_0955_hz():
    s = load_system(STOP)
    r = find_system_attractors(s, 0.1, 0.0955, n_starts=4)
    assert len(r) == 1 and r.n_unsettled == 0
    a = r.attractors[0]
    assert a.attractor_type == "chaotic" and a.hits == 4 and a.orbit is None
    assert a.lyapunov_per_s[0] > SIGMA_FACTOR * a.lyapunov_stderr_per_s[0]
    assert float(np.sum(a.lyapunov_per_s)) == pytest.approx(-0.09, abs=1e-9)  # −tr M⁻¹C, the stop undamped
    d = r.to_dict()["attractors"][0]
    assert d["attractor_type"] == "chaotic" and 2.0 < d["kaplan_yorke_dimension"] < 3.0
    assert d["floquet_multipliers"] is None and len(d["lyapunov_stderr_per_s"]) == 4


def test_the_periodic_attractors_are_kept_and_long_periods_found():
    s = load_system(STOP)
    old = find_system_attractors(s, 0.1, 0.095, n_starts=8, nonperiodic=False)
    new = find_system_attractors(s, 0.1, 0.095, n_starts=8)
    assert [a.period for a in old] == [6] and old.n_unsettled == 5
    assert old.unsettled_reasons == {"no period <= kmax": 5}
    six = [a for a in new if a.period == 6]
    assert len(six) == 1 and six[0].hits == old.attractors[0].hits
    assert np.array_equal(six[0].orbit.z, old.attractors[0].orbit.z)
    assert six[0].to_dict() == old.attractors[0].to_dict()
    ten = [a for a in new if a.period == 10]
    assert len(ten) == 1 and ten[0].hits == 5 and ten[0].stable and ten[0].orbit.closure < 1e-9
    assert new.n_unsettled == 0 and new.unsettled_reasons == {}


def test_a_free_flight_is_unsettled_with_its_reason(tmp_path):
    f = tmp_path / "free.toml"
    f.write_text('[system]\ncoordinates = ["q1"]\nmass = [[1.0]]\nstiffness = [[1.0]]\nforce_shape = [1.0]\n'
                 '[[contact]]\nname = "far"\ndirection = [1.0]\nlaw = "clearance"\nc_lin = 10.0\n'
                 'gap_um = 1.0e6\n')
    r = find_system_attractors(load_system(f), 0.01, 0.1 * math.sqrt(2.0), n_starts=2, kmax=2, max_periods=20)
    assert len(r) == 0 and r.n_unsettled == 2
    assert r.unsettled_reasons == {"free flight: no contact": 2}
    assert r.to_dict()["unsettled_reasons"] == {"free flight: no contact": 2}


def test_the_command_prints_the_type(capsys):
    rc = main(["attractors", "--system", str(TORUS), "--pa-newton", "0.05", "--fe", "0.12", "--starts", "2",
               "--json"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert [a["attractor_type"] for a in d["attractors"]] == ["quasi-periodic"]
    assert d["unsettled_reasons"] == {} and d["attractors"][0]["period"] is None


NEGATIVE = {  # a growing mode that no contact can limit: refused before any output
    "no contact": '[system]\ncoordinates = ["q1"]\nmass = [[1.0]]\nstiffness = [[1.0]]\ndamping = [[-0.02]]\n'
                  'force_shape = [1.0]\n',
    "a contact off the growing mode": '[system]\ncoordinates = ["q1", "q2"]\nmass = [[1.0, 0.0], [0.0, 1.0]]\n'
                                      'stiffness = [[1.0, 0.0], [0.0, 1.5]]\ndamping = [[0.05, 0.0], [0.0, -0.02]]\n'
                                      'force_shape = [1.0, 0.0]\n[[contact]]\nname = "stop"\ndirection = [1.0, 0.0]\n'
                                      'law = "clearance"\nc_lin = 10.0\ngap_um = 1.0e6\n',
}


@pytest.mark.parametrize("case", list(NEGATIVE))
def test_an_unbounded_negatively_damped_system_is_one_line(tmp_path, capsys, case):
    f = tmp_path / "neg.toml"
    f.write_text(NEGATIVE[case])
    rc = main(["attractors", "--system", str(f), "--pa-newton", "0.1", "--fe", "0.1"])
    assert rc == 2
    out = capsys.readouterr()
    assert out.out == ""
    lines = out.err.strip().splitlines()
    assert len(lines) == 1 and len(lines[0]) <= 400 and "--system (system.damping)" in lines[0]
    assert "grows without bound" in lines[0]
