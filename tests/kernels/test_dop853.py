"""The shared DOP853 pieces (:mod:`contactvib._kernels.dop853`) that the normal flow and the
friction kernel step with: the tableau is SciPy's, a step built from them has order 8 and its
dense output order 7 on a linear oscillator with a known solution, the error norm takes one
absolute tolerance or one per component alike, and the controller's factors stay in bounds."""

import math

import numpy as np
import pytest
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as scipy_co

from contactvib._kernels import dop853 as d


def test_the_tableau_is_scipys():
    for name in ("A", "B", "C", "E3", "E5", "D"):
        assert np.array_equal(getattr(d, name), getattr(scipy_co, name)), name


@njit
def _f(t, y, out):
    """x'' + x = cos(2t): a forced linear oscillator."""
    out[0] = y[1]
    out[1] = -y[0] + math.cos(2.0 * t)


@njit
def _fixed_steps(y0, t_end, n_steps, theta):
    """n_steps DOP853 steps from the shared pieces; the state at t_end, the dense output at
    fraction ``theta`` of the last step and the error norm of the last step."""
    K = np.empty((17, 2))
    y = y0.copy()
    ynew = np.empty(2)
    F = np.empty((7, 2))
    h = t_end / n_steps
    t = 0.0
    err = 0.0
    dense = np.empty(2)
    for _ in range(n_steps):
        _f(t, y, K[0])
        for s in range(1, 12):
            d.stage_state(K, y, h, s, 2, K[16])
            _f(t + d.C[s] * h, K[16], K[s])
        d.solution(K, y, h, 2, ynew)
        _f(t + h, ynew, K[12])
        err = d.error_norm(K, y, ynew, h, 2, 1e-12, 1e-12)
        for s in range(13, 16):
            d.stage_state(K, y, h, s, 2, K[16])
            _f(t + d.C[s] * h, K[16], K[s])
        d.interpolant(K, y, ynew, h, 2, F)
        dense[0] = d.dense_value(F, y, theta, 0)
        dense[1] = d.dense_value(F, y, theta, 1)
        y[:] = ynew
        t += h
    return y, dense, err


def _exact(t):
    """x(0) = 1, x'(0) = 0: x = (4/3) cos t − (1/3) cos 2t."""
    return np.array([4.0 / 3.0 * np.cos(t) - np.cos(2.0 * t) / 3.0,
                     -4.0 / 3.0 * np.sin(t) + 2.0 / 3.0 * np.sin(2.0 * t)])


def test_a_step_of_the_shared_pieces_has_order_8_and_its_dense_output_order_7():
    y0 = np.array([1.0, 0.0])
    T = 3.0
    ns = np.array([6, 8, 12, 16])
    err_end, err_dense = [], []
    for n in ns:
        y, dense, _ = _fixed_steps(y0, T, n, 0.37)
        err_end.append(np.abs(y - _exact(T)).max())
        err_dense.append(np.abs(dense - _exact(T - (1 - 0.37) * T / n)).max())
    slope = np.polyfit(np.log(T / ns), np.log(err_end), 1)[0]
    slope_dense = np.polyfit(np.log(T / ns), np.log(err_dense), 1)[0]
    assert slope == pytest.approx(8.0, abs=0.4)
    assert slope_dense > 6.6  # the interpolant's local error, order 7 + 1 (over one step)


@njit
def _norms(K, y, ynew, h, atol, atol_vec, rtol):
    return d.error_norm(K, y, ynew, h, 3, atol, rtol), d.error_norm(K, y, ynew, h, 3, atol_vec, rtol)


def test_the_error_norm_takes_one_tolerance_or_one_per_component():
    rng = np.random.default_rng(3)
    for _ in range(20):
        K = rng.normal(size=(17, 3))
        y, ynew = rng.normal(size=3), rng.normal(size=3)
        atol = 10.0 ** rng.uniform(-12, -6)
        one, each = _norms(K, y, ynew, 0.1, atol, np.full(3, atol), 1e-9)
        assert one == each  # bit for bit
    # Hairer's ERR by hand
    K = rng.normal(size=(17, 3))
    y, ynew = rng.normal(size=3), rng.normal(size=3)
    atol = np.array([1e-9, 1e-8, 1e-7])
    sc = atol + 1e-8 * np.maximum(np.abs(y), np.abs(ynew))
    e5 = np.sum((d.E5 @ K[:13] / sc) ** 2)
    e3 = np.sum((d.E3 @ K[:13] / sc) ** 2)
    by_hand = 0.1 * e5 / np.sqrt((e5 + 0.01 * e3) * 3)
    assert _norms(K, y, ynew, 0.1, 1e-9, atol, 1e-8)[1] == pytest.approx(by_hand, rel=1e-13)


def test_the_controller_factor_is_bounded():
    for err in np.concatenate([[0.0, 1.0, math.inf, math.nan], 10.0 ** np.linspace(-12, 6, 50)]):
        for rejected in (False, True):
            f = d.step_factor(err, rejected)
            assert d.MIN_FACTOR <= f <= d.MAX_FACTOR
            if not err < 1.0:
                assert f < 1.0  # a rejected step shrinks
            elif rejected:
                assert f <= 1.0  # no growth right after a rejection
    assert d.step_factor(0.0, False) == d.MAX_FACTOR
    assert d.step_factor(math.nan, False) == d.MIN_FACTOR
