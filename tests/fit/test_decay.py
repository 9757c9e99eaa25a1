"""Free-decay fits against scipy references (tests/data/fit_*_decay.csv, 2 % additive noise): every
parameter within two reported standard errors; the standard errors against the spread over 20
noise realisations (slow)."""

import numpy as np
import pytest
from reference import DATA, noisy_decay, truth, within

from contactvib.fitting import fit

SETS = [n for n in ("paper", "a", "b", "c") if (DATA / f"fit_{n}_decay.csv").exists()]


@pytest.mark.parametrize("name", SETS)
def test_decay_fit_recovers_the_parameters_within_two_stderr(name):
    model, true = truth(name)
    r = fit(decay=noisy_decay(name, 0.02, seed=1), model=model, n_starts=4)
    assert r.converged
    errs = within(r, true)
    assert set(errs) == {"S_c_n", "m2", "S_h_n", "l"}
    assert all(e < 2.0 for e in errs.values()), errs
    assert abs(r.value("f_n0_hz") - model.f_n0) < 2 * r.stderr("f_n0_hz")
    assert abs(r.value("zeta") - model.zeta) < 2 * r.stderr("zeta")
    assert r.residual_rms["decay"] == pytest.approx(0.02 * np.abs(r.sets[0].data.values).max(), rel=0.2)


def test_decay_with_known_exponents_fits_the_products_only():
    model, true = truth("paper")
    r = fit(decay=noisy_decay("paper", 0.01, seed=2), model=model, fix={"m2": 2.0, "l": 1.0}, n_starts=0)
    assert set(r.parameters) == {"S_c_n", "S_h_n", "y_init_um", "v_init_mm_s"}
    assert all(e < 2.0 for e in within(r, true).values())
    assert any("Only the products" in s for s in r.identifiability)


@pytest.mark.slow
def test_decay_stderr_agrees_with_the_spread_over_20_realisations():
    """The spread is 1.4826 × the median absolute deviation (the standard deviation of a normal
    sample, robust to an outlier): l and ζ trade off along a curved valley, and in one of these
    20 realisations (seed 18) the fit ends in a second minimum at l = 0.21 whose cost is within
    1.5 of the one at l = 1 (the local standard error, 0.08, does not see it), which alone
    doubles the plain standard deviation of l (0.20 against 0.10 without it)."""
    model, true = truth("paper")
    fits = [fit(decay=noisy_decay("paper", 0.02, seed=s), model=model, n_starts=0) for s in range(20)]
    for name in ("m2", "l", "f_n0_hz", "zeta"):
        vals = np.array([f.value(name) for f in fits])
        spread = 1.4826 * np.median(np.abs(vals - np.median(vals)))
        ratio = np.median([f.stderr(name) for f in fits]) / spread
        assert 0.5 < ratio < 2.0, (name, ratio)


def test_acceleration_record_gives_f_n0_and_zeta():
    """An accelerometer's decay (t_ms, a_ms2): the acceleration of the scipy reference trajectory,
    (W − F_c(y, ẏ))/M in contact and g in flight, + 2 % noise."""
    import math

    from contactvib.fitting import decay_data
    from contactvib.testing import integrate_contact, model_ode

    model, true = truth("paper")
    ode = model_ode(model, model.excitation(0.0, 1000.0))
    t = np.linspace(0.0, 12.0 / model.f_n0, 600)
    tr = integrate_contact(ode, 1.8 * model.y0, 0.0, 0.0, float(t[-1]), rtol=1e-11, y_scale=model.y0,
                           v_scale=model.y0 * model.omega_n0)
    y, v = tr.sample(t)
    a = np.array([(ode.W - (ode.contact_force(yi, vi) if yi > 0 else 0.0)) / ode.M for yi, vi in zip(y, v)])
    a = a + np.random.default_rng(7).normal(0.0, 0.02 * np.abs(a).max(), a.size)
    r = fit(decay=decay_data(t * 1e3, a, kind="a_ms2"), model=model, n_starts=2)
    assert r.converged
    assert abs(r.value("f_n0_hz") - model.f_n0) < 2 * r.stderr("f_n0_hz")
    assert abs(r.value("zeta") - model.zeta) < 2 * r.stderr("zeta")
    assert math.isfinite(r.residual_rms["decay"])


def test_joint_static_and_decay_weighs_each_set_by_its_noise():
    """A static curve (1 % of its largest deflection) and a decay (2 %) in one fit: each set's
    noise level is estimated from its residuals, and the static curve pins m2."""
    from contactvib.fitting import static_data

    model, true = truth("paper")
    F = np.linspace(0.0, 8.0, 20)
    y = (F / true["S_c_n"]) ** 0.5 * 1e6
    y = y + np.random.default_rng(4).normal(0.0, 0.01 * y.max(), y.size)
    decay = noisy_decay("paper", 0.02, seed=6)
    r = fit(static=static_data(F, y), decay=decay, model=model, n_starts=0)
    assert r.noise["static"] == pytest.approx(0.01 * y.max(), rel=0.4)
    assert r.noise["decay"] == pytest.approx(0.02 * np.abs(decay.values).max(), rel=0.3)
    assert all(e < 2.0 for e in within(r, true).values()), within(r, true)
    assert set(r.residual_rms) == {"static", "decay"}


def test_the_answer_does_not_depend_on_the_model_given_or_the_seed():
    """The starts come from the data (a grid around f_n0 from the zero crossings, ζ, m2, l, plus
    random ones): another model's c_n, h_n, m2, l and another seed give the same optimum."""
    model, _true = truth("paper")
    data = noisy_decay("paper", 0.02, seed=9)
    r1 = fit(decay=data, model=model, n_starts=4, seed=0)
    r2 = fit(decay=data, model=model.replace(c_n=1e14, m2=1.5, h_n=1e8, l=0.5), n_starts=4, seed=5)
    for name in ("m2", "l", "f_n0_hz", "zeta"):
        assert r1.value(name) == pytest.approx(r2.value(name), rel=1e-4, abs=1e-5), name
