"""The clearance law (``contactvib/model/laws/clearance.py``) against independent references.

* closed form: with no damping and no forcing the slider bounces on the linear spring under
  gravity; its period is the contact arc of the linear oscillator about δ0 = W/k plus the free
  flight, T = 2 arccos(−δ0/A)/ω + 2 M ω sqrt(A² − δ0²)/W (A the amplitude about δ0, ω² = k/M);
* an independent scipy DOP853 integration with located contact events
  (:func:`contactvib.testing.integrate_contact`, which evaluates the law's own SI force, never
  the compiled kernels);
* the power law at m2 = 1 shifted by the gap, which under gravity alone is the same motion.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib.model import ParameterError
from contactvib.model.laws import ClearanceLaw, law_names
from contactvib.steady.simulate import simulate
from contactvib.testing import integrate_contact, model_ode

C_LIN = 2.037e10  # N/m³: f_n0 ≈ 1485 Hz with the paper's M and S
GAP_UM = 3.0


def _bouncing_period(m: ContactModel, A: float) -> float:
    """Closed-form period [s] of the undamped, unforced bounce of amplitude A [m] about δ0."""
    d0, k = m.y0, m.S * C_LIN
    w = math.sqrt(k / m.M)
    return 2.0 * math.acos(-d0 / A) / w + 2.0 * m.M * w * math.sqrt(A * A - d0 * d0) / m.W


def test_registered_with_its_parameters():
    assert "clearance" in law_names()
    law = ClearanceLaw(c_lin=C_LIN, gap_um=GAP_UM)
    assert law.engagement_m == pytest.approx(GAP_UM * 1e-6, rel=1e-15)
    assert float(law.force(1e-6, 1e-3)) == pytest.approx(1e-3 * C_LIN * 1e-6, rel=1e-15)
    assert float(law.force(0.0, 1e-3)) == 0.0 and float(law.force(-1e-6, 1e-3)) == 0.0
    m = ContactModel(law="clearance", law_params={"c_lin": C_LIN, "gap_um": GAP_UM})
    assert m.y0 == pytest.approx(m.W / (m.S * C_LIN), rel=1e-14)  # the contact's static deflection δ0
    assert m.f_n0 == pytest.approx(math.sqrt(m.S * C_LIN / m.M) / (2 * math.pi), rel=1e-14)
    assert m.units.y_static_um == pytest.approx(GAP_UM + m.y0 * 1e6, rel=1e-14)
    assert ContactModel(**m.parameters()) == m


def test_undamped_bounce_period_matches_the_closed_form():
    m = ContactModel(law="clearance", law_params={"c_lin": C_LIN, "gap_um": GAP_UM}, h_n=0.0)
    A = 3.0 * m.y0
    T = _bouncing_period(m, A)
    exc = m.excitation(0.0, 200.0)  # no force: the excitation only sets the time unit
    # the reference: scipy with located events, on the law's own SI force
    tr = integrate_contact(model_ode(m, exc), m.y0 + A, 0.0, 0.0, 4 * exc.period, rtol=1e-12)
    flights = [ta for contact, (ta, _tb), _ in tr.segments if not contact]
    assert len(flights) >= 15
    np.testing.assert_allclose(np.diff(flights), T, rtol=1e-10)
    # contactvib: the contact losses where y crosses the engagement point y = gap downwards
    h = simulate(exc, y_um=GAP_UM + (m.y0 + A) * 1e6, ydot_mm_s=0.0, n_periods=4, samples_per_period=20000, rtol=1e-12)
    d = h.y_um - GAP_UM
    i = np.flatnonzero((d[:-1] > 0.0) & (d[1:] <= 0.0))
    t = (h.t_ms[i] + (h.t_ms[i + 1] - h.t_ms[i]) * d[i] / (d[i] - d[i + 1])) * 1e-3
    np.testing.assert_allclose(np.diff(t), T, rtol=1e-7)  # linear interpolation of the samples
    assert np.array_equal(h.in_contact, d > 0.0)
    assert h.engagement_um == GAP_UM
    # and the whole trajectory against scipy's, to the integrators' tolerance
    ref = tr.sample(h.t_ms * 1e-3)
    assert np.max(np.abs(h.y_um - (GAP_UM + ref[0] * 1e6))) < 1e-8 * A * 1e6


def test_forced_attractors_are_the_shifted_power_law_and_periodic_under_scipy():
    clear = ContactModel(law="clearance", law_params={"c_lin": C_LIN, "gap_um": GAP_UM})
    power = ContactModel(c_n=C_LIN, m2=1.0)
    a = find_attractors(clear.excitation(0.65, 360.0))
    b = find_attractors(power.excitation(0.65, 360.0))
    assert len(a) == len(b) >= 3
    for x, y in zip(a, b):
        assert (x.period, x.minima_per_period) == (y.period, y.minima_per_period)
        assert x.app_um == pytest.approx(y.app_um, rel=1e-12)
        assert x.ymin_um == pytest.approx(y.ymin_um + GAP_UM, abs=1e-12)
        assert x.ymax_um == pytest.approx(y.ymax_um + GAP_UM, abs=1e-12)
        assert x.contact_loss_fraction == y.contact_loss_fraction
        assert x.loses_contact == (x.ymin_um < GAP_UM)
        np.testing.assert_allclose(np.abs(x.floquet_multipliers), np.abs(y.floquet_multipliers), rtol=1e-12)
    # every periodic attractor closes on itself under scipy (the law's SI force, located events)
    exc = clear.excitation(0.65, 360.0)
    u = clear.units
    for att in a:
        y_m, v_ms = att.state[0] * u.y_um * 1e-6, att.state[1] * u.ydot_mm_s * 1e-3
        tr = integrate_contact(model_ode(clear, exc), y_m, v_ms, 0.0, att.period * exc.period, rtol=1e-12)
        assert abs(tr.y - y_m) < 1e-6 * att.app_um * 1e-6
        assert abs(tr.ydot - v_ms) < 1e-6 * max(abs(v_ms), 1e-3)


@pytest.mark.parametrize("kw, symbol, allowed", [
    ({"gap_um": -1.0}, "gap_um", "must be in [0, 1e+6] um"),
    ({"c_lin": 0.0}, "c_lin", "must be > 0 N/m^3"),
    ({"gap": 1.0}, "gap", "unknown parameter of the clearance law; known: c_lin, gap_um"),
])
def test_bad_parameters_name_the_bounds(kw, symbol, allowed):
    with pytest.raises(ParameterError) as e:
        ContactModel(law="clearance", law_params=kw)
    assert e.value.symbol == symbol and allowed in str(e.value)


def test_command_line():
    run = [sys.executable, "-m", "contactvib", "attractors", "--law", "clearance", "--set", f"c_lin={C_LIN}",
           "--set", f"gap_um={GAP_UM}", "--pa", "0.65", "--fe", "360", "--starts", "64", "--json"]
    out = json.loads(subprocess.run(run, capture_output=True, text=True, check=True).stdout)
    assert out["model"]["law"] == "clearance" and out["model"]["law_params"]["gap_um"] == GAP_UM
    assert all(a["ymax_um"] > GAP_UM for a in out["attractors"])
    for bad, line in ((["--set", "gap_um=-1"], "--set gap_um (gap_um) = -1: must be in [0, 1e+6] um"),
                      (["--set", "c_n=1"], "--set c_n: a parameter of --law power, not of --law clearance")):
        r = subprocess.run([sys.executable, "-m", "contactvib", "attractors", "--law", "clearance", *bad],
                           capture_output=True, text=True)
        assert r.returncode == 2 and r.stderr.strip() == f"contactvib: error: {line}"


def test_every_command_takes_it(tmp_path):
    """resonance, continue and hbm on the clearance law: positions above the gap, contact loss
    where y < gap (the same rows as the power law at m2 = 1, shifted)."""
    import xarray as xr

    from contactvib.cli.main import main

    law = ["--law", "clearance", "--set", f"c_lin={C_LIN}", "--set", f"gap_um={GAP_UM}"]
    assert main(["resonance", *law, "--pa", "0.3", "--fmin", "1190", "--fmax", "1210", "--df", "10",
                 "--multistart-per-octave", "1", "--starts", "2", "--workers", "1", "--no-progress",
                 "--out", str(tmp_path / "res")]) == 0
    with xr.open_dataset(tmp_path / "res" / "resonance.nc") as ds:
        assert ds.attrs["engagement_um"] == GAP_UM
        assert np.all(ds["ymax_um"].values > GAP_UM)
        lost = ds["ymin_um"].values < GAP_UM
        assert np.array_equal(lost, ds["contact_loss_fraction"].values > 0.0)
    assert main(["continue", *law, "--pa", "0.3", "--from-fe", "1200", "--attractor", "0", "--fmin", "1100",
                 "--fmax", "1300", "--max-points", "30", "--out", str(tmp_path / "br")]) == 0
    branch, = (tmp_path / "br").glob("branch_*.nc")
    with xr.open_dataset(branch) as b:
        assert b.sizes["point"] >= 5 and np.all(b["ymax_um"].values > GAP_UM)
    assert main(["hbm", *law, "--pa", "0.1", "--fmin", "1000", "--fmax", "1100", "--out",
                 str(tmp_path / "hb")]) == 0
    assert list((tmp_path / "hb").glob("*.png"))
