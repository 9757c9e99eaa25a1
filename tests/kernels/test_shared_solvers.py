"""The kernels' shared numerical pieces against independent references.

* small dense solvers (:mod:`contactvib._kernels.linalg`) against ``numpy.linalg.solve``;
* the Illinois root finder (:mod:`contactvib._kernels.roots`) and its callers (dense-output and
  polynomial events, the continuation's ``locate_zero``) against ``scipy.optimize.brentq``;
* Newton on the period map (:func:`contactvib._kernels.shooting.newton_map`) on the linear
  oscillator, whose periodic orbit and monodromy are known in closed form, and on the paper's
  orbit against scipy's ``solve_ivp``;
* the stability rule |μ|max ≤ 1 + STABILITY_TOL, compiled and in Python.
"""

import math

import numpy as np
import pytest
from numba import njit
from scipy.linalg import expm
from scipy.optimize import brentq

from contactvib import ContactModel
from contactvib._kernels.flow import dense_root, dense_value
from contactvib._kernels.linalg import solve2, solve_dense
from contactvib._kernels.roots import illinois_root
from contactvib._kernels.series_roots import poly_root
from contactvib._kernels.shooting import (
    STABILITY_TOL,
    is_stable,
    newton_map,
    newton_orbit,
    stable_monodromy,
    stable_multipliers,
    strobe_map,
)
from contactvib._kernels.status import STATUS_NEWTON_MAXITER, STATUS_NEWTON_QUICK, STATUS_OK
from contactvib.continuation.bifurcations import locate_zero
from contactvib.testing import scipy_in_contact

RNG = np.random.default_rng(7)


# ---------------------------------------------------------------- linear solvers
@pytest.mark.parametrize("trial", range(20))
def test_solve2_equals_numpy(trial):
    A = RNG.normal(size=(2, 2))
    r = RNG.normal(size=2)
    ok, x0, x1 = solve2(A[0, 0], A[0, 1], A[1, 0], A[1, 1], r[0], r[1])
    assert ok
    np.testing.assert_allclose([x0, x1], np.linalg.solve(A, r), rtol=1e-10 * np.linalg.cond(A))


def test_solve2_refuses_singular_and_non_finite_systems():
    assert not solve2(1.0, 2.0, 2.0, 4.0, 1.0, 1.0)[0]
    assert not solve2(math.inf, 0.0, 0.0, 1.0, 1.0, 1.0)[0]
    assert not solve2(math.nan, 0.0, 0.0, 1.0, 1.0, 1.0)[0]


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 8])
def test_solve_dense_equals_numpy(n):
    for _ in range(10):
        A = RNG.normal(size=(n, n))
        y = RNG.normal(size=n)
        out = np.empty(n)
        assert solve_dense(A.copy(), y.copy(), out)
        np.testing.assert_allclose(out, np.linalg.solve(A, y), rtol=0, atol=1e-12 * np.linalg.cond(A))


def test_solve_dense_pivots_and_refuses_singular_systems():
    A = np.array([[0.0, 1.0, 2.0], [1.0, 0.0, 0.0], [0.0, 0.0, 3.0]])  # a zero first pivot
    y = np.array([5.0, 1.0, 3.0])
    out = np.empty(3)
    assert solve_dense(A.copy(), y.copy(), out)
    np.testing.assert_allclose(out, np.linalg.solve(A, y), rtol=1e-15)
    S = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]])
    assert not solve_dense(S, np.ones(3), np.empty(3))
    assert not solve_dense(np.array([[np.nan, 0.0], [0.0, 1.0]]), np.ones(2), np.empty(2))


# ---------------------------------------------------------------- root finding
@njit
def _cos_minus(x, args):
    return math.cos(x) - args[0] * x


@njit
def _cubic(x, args):
    return x * x * x - args[0]


@njit
def _exp_minus(x, args):
    return math.exp(args[0] * x) - args[1]


@njit
def _steep(x, args):
    return math.atan(args[0] * (x - args[1]))


@njit
def _root(f, args, a, b, xtol):
    return illinois_root(f, args, a, b, f(a, args), f(b, args), xtol, 200)


@pytest.mark.parametrize("f,args,a,b", [
    (_cos_minus, (1.0,), 0.0, 1.0), (_cubic, (2.0,), 0.0, 2.0), (_exp_minus, (3.0, 5.0), -1.0, 2.0),
    (_steep, (1e4, 0.3), 0.0, 1.0), (_cubic, (-1e-3,), -1.0, 0.5),
], ids=["cos", "cubic", "exp", "steep-atan", "small-root"])
def test_illinois_root_equals_brentq(f, args, a, b):
    ref = brentq(lambda x: f(x, args), a, b, xtol=1e-15, rtol=8.9e-16)
    x = _root(f, args, a, b, 4e-16)
    assert abs(x - ref) <= 4e-15 * max(1.0, abs(ref))
    # a looser tolerance stops earlier, still inside the bracket and near the root
    x_loose = _root(f, args, a, b, 1e-6)
    assert a < x_loose < b and abs(x_loose - ref) <= 1e-5


def test_polynomial_event_root_equals_brentq():
    # (s − 0.3)(s + 1)(s − 2) = s³ − 1.3 s² − 1.7 s + 0.6 on [0, 1]
    C = np.array([0.6, -1.7, -1.3, 1.0])
    s = poly_root(C, 3, 0, 0.0, 1.0)
    ref = brentq(lambda x: np.polyval(C[::-1], x), 0.0, 1.0, xtol=1e-16, rtol=8.9e-16)
    assert s == pytest.approx(0.3, abs=1e-15) and s == pytest.approx(ref, abs=1e-15)
    assert poly_root(C, 3, 0, 0.3, 1.0) == 0.3  # a root at an end is that end


@pytest.mark.parametrize("seed", range(8))
def test_dense_output_root_equals_brentq(seed):
    """Dense output of a step (any 7×2 coefficients are a polynomial in θ): where x crosses a
    level (the same root as brentq's, or another root of a polynomial with several)."""
    rng = np.random.default_rng(seed)
    F = rng.normal(scale=0.2, size=(7, 2))
    y = rng.normal(size=2)
    lo, hi = dense_value(F, y, 0.0, 0), dense_value(F, y, 1.0, 0)
    level = lo + 0.37 * (hi - lo)
    ref = brentq(lambda s: dense_value(F, y, s, 0) - level, 0.0, 1.0, xtol=1e-16, rtol=8.9e-16)
    th = dense_root(F, y, 0, level, 0.0, 1.0)
    assert 0.0 <= th <= 1.0
    assert abs(th - ref) <= 1e-14 or abs(dense_value(F, y, th, 0) - level) <= 1e-15 * max(1.0, abs(level))


def test_locate_zero_equals_brentq():
    f = lambda x: math.exp(x) - 3.0  # noqa: E731
    s, v, payload = locate_zero(lambda x: (f(x), "p"), 0.0, 2.0, f(0.0), f(2.0), 1e-13)
    assert s == pytest.approx(brentq(f, 0.0, 2.0, xtol=1e-15), abs=1e-12) and abs(v) < 1e-12
    assert payload == "p"
    # a trial point that cannot be evaluated is replaced by the midpoint
    fails = {"n": 0}

    def flaky(x):
        fails["n"] += 1
        return None if fails["n"] == 1 else (f(x), None)

    s2, _v, _p = locate_zero(flaky, 0.0, 2.0, f(0.0), f(2.0), 1e-13)
    assert s2 == pytest.approx(math.log(3.0), abs=1e-12)


# ---------------------------------------------------------------- Newton on the period map
def _linear_par(p=0.3, r=0.7, c=0.2):
    """m2 = 1, l = 0: x'' + c x' + x = 1 + p cos rτ, in contact throughout for small p."""
    return np.array([1.0, 0.0, c, p, r])


def _linear_orbit(par):
    """Closed form: x = 1 + Re(p e^{irτ} / (1 − r² + i c r)); monodromy exp(A T)."""
    _m2, _l, c, p, r = par
    H = p / (1.0 - r * r + 1j * c * r)
    z = np.array([1.0 + H.real, (1j * r * H).real])
    A = np.array([[0.0, 1.0], [-1.0, -c]])
    return z, expm(A * 2.0 * math.pi / r)


def test_newton_converges_to_the_linear_oscillators_orbit():
    par = _linear_par()
    z_exact, M_exact = _linear_orbit(par)
    oz, oM = np.empty(2), np.empty((2, 2))
    st, res, n = newton_map(np.array([1.05, 0.1]), 1, par, 1e-12, 1e-12, 1e-11, 10, 0.0, oz, oM)
    assert st == STATUS_OK and res <= 1e-11 and n <= 4  # a linear map: one step, then closure
    np.testing.assert_allclose(oz, z_exact, rtol=0, atol=1e-10)
    np.testing.assert_allclose(oM, M_exact, rtol=0, atol=1e-9)
    assert stable_monodromy(oM)
    # newton_orbit is newton_map with max_iter steps and no quick exit: the same numbers
    oz2, oM2 = np.empty(2), np.empty((2, 2))
    st2, res2 = newton_orbit(np.array([1.05, 0.1]), 1, par, 1e-12, 1e-12, 1e-11, 9, oz2, oM2)
    assert (st2, res2) == (st, res) and np.array_equal(oz2, oz) and np.array_equal(oM2, oM)


def test_newton_options_quick_exit_and_evaluation_cap():
    par = _linear_par()
    z_exact, _M = _linear_orbit(par)
    oz, oM = np.empty(2), np.empty((2, 2))
    # a start close enough that the first step is below the quick size: the stepped point back
    z0 = z_exact + np.array([2e-6, -1e-6])
    st, res, n = newton_map(z0, 1, par, 1e-12, 1e-12, 1e-14, 10, 3e-5, oz, oM)
    assert st == STATUS_NEWTON_QUICK and n == 1 and res > 1e-14
    assert np.max(np.abs(oz - z_exact)) < 1e-9  # the stepped point, not z0
    # one evaluation and no step after it: not converged
    st, res, n = newton_map(np.array([1.05, 0.1]), 1, par, 1e-12, 1e-12, 1e-11, 1, 0.0, oz, oM)
    assert st == STATUS_NEWTON_MAXITER and n == 1 and np.array_equal(oz, [1.05, 0.1])


def test_newton_on_the_papers_orbit_closes_under_scipy():
    """The paper's model at 0.2 Q, f_e = 0.6 f_n0 (in contact): the Newton orbit point returns to
    itself after one period of scipy's DOP853 at rtol 1e-12."""
    par = ContactModel().excitation(0.2, 0.6 * ContactModel().f_n0).kernel_parameters()
    oz, oM = np.empty(2), np.empty((2, 2))
    st, res = newton_orbit(np.array([1.0, 0.0]), 1, par, 1e-12, 1e-12, 1e-11, 12, oz, oM)
    assert st == STATUS_OK and res <= 1e-11
    z_end = scipy_in_contact(par, oz, 2.0 * math.pi / par[4])
    assert np.max(np.abs(z_end - oz)) <= 1e-9
    pz = np.empty(2)
    assert strobe_map(oz, 1, par, 1e-12, 1e-12, pz, np.empty((0, 0))) == STATUS_OK
    assert np.max(np.abs(pz - oz)) <= 1e-10


# ---------------------------------------------------------------- stability rule
def test_one_stability_rule_compiled_and_in_python():
    edge = 1.0 + STABILITY_TOL
    above = np.nextafter(edge, 2.0)
    for mu, want in [(0.5, True), (edge, True), (above, False), (math.nan, False), (math.inf, False)]:
        assert stable_multipliers(mu) is want or bool(stable_multipliers(mu)) == want
        assert is_stable(mu) is want
    arr = np.array([[0.5, edge], [above, math.nan]])
    np.testing.assert_array_equal(is_stable(arr), [[True, True], [False, False]])
    assert stable_monodromy(np.array([[0.0, 1.0], [-1.0, 0.0]]))  # rotation: |μ| = 1
    assert not stable_monodromy(np.array([[1.01, 0.0], [0.0, 0.2]]))
