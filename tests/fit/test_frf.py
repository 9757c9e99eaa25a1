"""Stepped-sine FRF fits against scipy references (tests/data/fit_*_frf.csv: up and down sweeps at
0.3 Q and 0.65 Q with their jumps, made by solve_ivp with located contact events), A_pp with 2 %
reading noise: the parameters within two reported standard errors, the fitted model's sweeps
jump where the data jump, and joint fits with a static curve."""

import numpy as np
import pytest
from reference import DATA, noisy_frf, truth, within

from contactvib.fitting import fit, static_data

OTHER_SETS = [n for n in ("a", "b", "c") if (DATA / f"fit_{n}_frf.csv").exists()]


def _jumps(d, app):
    """Per sweep the row after its largest step change of ln A_pp, where it exceeds 0.3 (a jump)."""
    out = []
    for rows in d.sweeps:
        steps = np.abs(np.diff(np.log(app[rows])))
        out.append(int(rows[np.argmax(steps) + 1]) if steps.max() > 0.3 else None)
    return out


@pytest.fixture(scope="module")
def paper_fit():
    model, true = truth("paper")
    data = noisy_frf("paper", 0.02, seed=1)
    return fit(frf=data, model=model, n_starts=2), data, model, true


def test_paper_parameters_recovered_from_up_and_down_sweeps(paper_fit):
    r, data, model, true = paper_fit
    assert r.converged
    errs = within(r, true)
    assert set(errs) == {"S_c_n", "m2", "S_h_n", "l"} and all(e < 2.0 for e in errs.values()), errs
    assert abs(r.value("f_n0_hz") - model.f_n0) < 2 * r.stderr("f_n0_hz")
    assert abs(r.value("zeta") - model.zeta) < 2 * r.stderr("zeta")
    assert r.value("m2") == pytest.approx(2.0, abs=0.15)
    assert r.residual_rms["frf"] == pytest.approx(0.02, rel=0.35)
    assert r.n_forward > 0 and r.time_s > 0


def test_fitted_model_jumps_where_the_sweeps_jump(paper_fit):
    r, data, _model, _true = paper_fit
    fitted = r.sets[0].predict([r.values], r.model)[0]
    measured = _jumps(data, data.app_um)
    assert sum(j is not None for j in measured) >= 2  # the data hold jumps (up sweeps at both levels)
    assert _jumps(data, fitted) == measured  # the model jumps at the same step of every sweep


@pytest.mark.slow
@pytest.mark.parametrize("name", OTHER_SETS)
def test_other_parameter_sets_recovered(name):
    model, true = truth(name)
    r = fit(frf=noisy_frf(name, 0.02, seed=3), model=model)
    errs = within(r, true)
    assert all(e < 2.0 for e in errs.values()), errs
    assert abs(r.value("f_n0_hz") - model.f_n0) < 2 * r.stderr("f_n0_hz")


@pytest.mark.slow
def test_joint_static_and_frf_weighs_each_set_by_its_noise():
    model, true = truth("paper")
    F = np.linspace(0.0, 8.0, 20)
    y = (F / true["S_c_n"]) ** 0.5 * 1e6
    y = y + np.random.default_rng(4).normal(0.0, 0.01 * y.max(), y.size)
    r = fit(static=static_data(F, y), frf=noisy_frf("paper", 0.02, seed=5), model=model, n_starts=0, n_refine=1)
    assert r.noise["static"] == pytest.approx(0.01 * y.max(), rel=0.5)
    assert r.noise["frf"] == pytest.approx(0.02, rel=0.5)
    errs = within(r, true)
    assert all(e < 2.0 for e in errs.values()), errs
    assert r.stderr("m2") < 0.05  # the static curve pins m2


@pytest.mark.parametrize("name", ["paper", *OTHER_SETS])
def test_stepped_sine_forward_model_agrees_with_scipy(name):
    """The forward model at the true parameters reproduces the scipy stepped-sine sweeps (each step
    from the previous step's state, jumps included): the paper's and set a's to 1e-5 of A_pp at
    every step; b and c at all steps but one to 1e-5, and that one (a step at a fold, where the
    start lies near the boundary of the two basins) to 0.3 % (b) or on the other branch (c, l = 0:
    the damping force jumps at contact, one step earlier)."""
    from contactvib.fitting import read_frf
    from contactvib.fitting.forward import FrfSet

    model, true = truth(name)
    d = read_frf(DATA / f"fit_{name}_frf.csv")
    a = FrfSet(d).predict([true], model)[0]
    rel = np.abs(a / d.app_um - 1.0)
    if name in ("paper", "a"):
        assert rel.max() < 1e-5, rel.max()
    else:
        assert np.count_nonzero(rel > 1e-5) <= 1 and (name == "b" or rel.max() < 3e-3), np.sort(rel)[-3:]


@pytest.mark.slow
def test_frf_stderr_agrees_with_the_spread_over_20_realisations():
    """20 noise realisations of the paper's sweeps: the median reported standard error of m2 and
    f_n0 against their spread (1.4826 × the median absolute deviation), within a factor of 2."""
    model, _true = truth("paper")
    fits = [fit(frf=noisy_frf("paper", 0.02, seed=100 + s), model=model, n_starts=2) for s in range(20)]
    for name in ("m2", "f_n0_hz"):
        vals = np.array([f.value(name) for f in fits])
        spread = 1.4826 * np.median(np.abs(vals - np.median(vals)))
        ratio = np.median([f.stderr(name) for f in fits]) / spread
        assert 0.5 < ratio < 2.0, (name, ratio, vals)
