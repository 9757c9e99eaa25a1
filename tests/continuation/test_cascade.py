"""Period-doubling cascades (continuation/cascade.py) against independent references: scipy's
DOP853 with located contact events for the doubling itself, plain iteration of the map for the
periods on either side, and Feigenbaum's universal ratio for the cascade's geometry.

The cascade at 0.75 Q: the period-10 orbit found at 812 Hz (an attractor the box search calls
non-periodic: its period exceeds the search's kmax) doubles at 813.403, 815.197, 815.563,
815.641 Hz, ... (see docs/tutorials/cascades.md)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib.cli import main
from contactvib.continuation.cascade import FEIGENBAUM_DELTA, _Follower, follow_cascade, orbit_period
from contactvib.model import ParameterError
from contactvib.testing import integrate_contact, model_ode

PA = 0.75


@pytest.fixture(scope="module")
def model():
    return ContactModel()


@pytest.fixture(scope="module")
def period10(model):
    """The period-10 orbit at 812 Hz: (period, state) detected by iterating the map."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        atts = find_attractors(model.excitation(PA, 812.0))
    att = next(a for a in atts if 3.5 < a.app_um < 5.0)
    return orbit_period(model.excitation(PA, 812.0), state=att.state)


@pytest.fixture(scope="module")
def cascade(model, period10):
    k, z = period10
    return follow_cascade(model, pa_over_q=PA, fe_hz=812.0, state=z, period=k, max_doublings=4,
                          first_step_hz=0.1)


def test_the_long_period_is_detected_without_a_cap(period10):
    assert period10[0] == 10


def test_four_doublings_and_feigenbaum(cascade):
    assert cascade.periods == [10, 20, 40, 80]
    f = np.array(cascade.pd_fe_hz)
    assert np.all(np.diff(f) > 0) and 813.3 < f[0] < 813.5 and 815.1 < f[1] < 815.3
    assert len(cascade.delta) == 2
    # the ratios approach Feigenbaum's constant: the second within 0.5 % (it is 4.676)
    assert abs(cascade.delta[1] / FEIGENBAUM_DELTA - 1.0) < 5e-3
    assert abs(cascade.delta[0] / FEIGENBAUM_DELTA - 1.0) < 0.1
    d = cascade.to_dict()
    assert set(d) == {"pa_over_q", "periods", "pd_fe_hz", "delta", "stop"}


def test_periods_on_either_side_by_plain_iteration(model, cascade):
    z = cascade.states[0]
    f1, f2 = cascade.pd_fe_hz[:2]
    assert orbit_period(model.excitation(PA, f1 - 0.3), state=z)[0] == 10
    assert orbit_period(model.excitation(PA, f1 + 0.3), state=z)[0] == 20
    z2 = cascade.states[1]
    assert orbit_period(model.excitation(PA, f2 - 0.2), state=z2)[0] == 20
    assert orbit_period(model.excitation(PA, f2 + 0.15), state=z2)[0] == 40


def test_the_first_doubling_against_scipy(model, cascade):
    """On either side of f_1 (± 0.05 Hz) the kernel's period-10 orbit is a fixed point of scipy's
    period-10 map (to 1e-9), and scipy's finite-difference monodromy has a multiplier above −1
    before f_1 and below −1 after it (to 1e-6 of the kernel's)."""
    fol = _Follower(model, PA, 1e-12, 1e-10)
    f1 = cascade.pd_fe_hz[0]
    y0, w = model.y0, 2.0 * np.pi * model.f_n0
    lowest = []
    for df in (-0.05, 0.05):
        z, M = fol.orbit(f1 + df, cascade.states[0], 10)
        ode = model_ode(model, model.excitation(PA, f1 + df))
        T = 10.0 / (f1 + df)

        def P(zv, ode=ode, T=T):
            tr = integrate_contact(ode, zv[0] * y0, zv[1] * y0 * w, 0.0, T, rtol=1e-12)
            return np.array([tr.y / y0, tr.ydot / (y0 * w)])

        assert np.max(np.abs(P(z) - z)) < 1e-9 * max(1.0, np.max(np.abs(z)))
        J = np.empty((2, 2))
        for i in range(2):
            e = np.zeros(2)
            e[i] = 1e-6 * max(1.0, abs(z[i]))
            J[:, i] = (P(z + e) - P(z - e)) / (2.0 * e[i])
        mu_scipy = np.sort(np.linalg.eigvals(J).real)
        mu_kernel = np.sort(np.linalg.eigvals(M).real)
        assert np.allclose(mu_scipy, mu_kernel, atol=1e-6)
        lowest.append(mu_scipy[0])
    assert lowest[0] > -1.0 > lowest[1]


def test_bad_input(model, period10):
    k, z = period10
    with pytest.raises(ParameterError, match="direction"):
        follow_cascade(model, pa_over_q=PA, fe_hz=812.0, state=z, period=k, direction=0)
    with pytest.raises(ParameterError, match="period"):
        follow_cascade(model, pa_over_q=PA, fe_hz=812.0, state=z, period=0)


def test_cli_refuses_a_cascade_frequency_outside_the_range(capsys):
    assert main(["bifurcations", "--pa", "0.75", "--fmin", "790", "--fmax", "830", "--seed-fe", "812",
                 "--cascade-fe", "900"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("contactvib: error: --cascade-fe") and len(err[0]) <= 400
