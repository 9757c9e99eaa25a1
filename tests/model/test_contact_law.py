"""One contact law, four users: the compiled right-hand side and Jacobian (DOP853 flow), the Taylor
recurrence, the harmonic-balance residual and the perturbation series are all built from the law
object and are checked here against each other, against a plain numpy formula and against scipy,
for m2 ∈ {1, 1.5, 2, 3} and l ∈ {0, 0.5, 1} (ζ = 0.018 for every law).

Tolerances: force and partials vs numpy 1e-14 relative (pow vs x·|x| round-off); Jacobian vs
central differences 1e-7; Taylor polynomial vs scipy (rtol 1e-13) 1e-11; HB and perturbation
orbit points are fixed points of scipy's one-period map to 1e-9, and agree with each other and
with the DOP853 kernel's period map to 1e-9.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from contactvib._kernels.flow import REC_WIDTH, STATUS_OK, advance, rhs
from contactvib._kernels.taylor import is_polynomial_law, series
from contactvib.frequency.harmonic_balance import hb_solve
from contactvib.frequency.perturbation import perturbation_series
from contactvib.model import ContactModel, PowerLaw
from contactvib.testing import scipy_in_contact

M2S = [1.0, 1.5, 2.0, 3.0]
LS = [0.0, 0.5, 1.0]
LAWS = [(m2, l) for m2 in M2S for l in LS]
ZETA = 0.018


def _model(m2, l):
    """A model with this law, y0 = 0.2 µm and the paper's ζ = 0.018 (h_n scaled for l)."""
    base = ContactModel()
    c_n = base.Q / (base.S * 2e-7 ** m2)
    probe = ContactModel(m2=m2, l=l, c_n=c_n, h_n=1.0)
    return ContactModel(m2=m2, l=l, c_n=c_n, h_n=ZETA / probe.zeta)


def _numpy_force(x, v, m2, l, c):
    """f, ∂f/∂x, ∂f/∂v of f = x^m2 + c x^l v for x > 0 (x > 0 assumed), written independently."""
    return (x ** m2 + c * x ** l * v, m2 * x ** (m2 - 1) + c * l * x ** (l - 1) * v, c * x ** l)


def _par(model, p=0.3, r=0.7):
    return np.array([model.m2, model.l, model.damping_coefficient, p, r])


@pytest.mark.parametrize("m2,l", LAWS)
def test_model_law_and_zeta(m2, l):
    model = _model(m2, l)
    assert model.power_law == PowerLaw(m2, l)
    assert model.zeta == pytest.approx(ZETA, rel=1e-12)
    y = np.array([-1e-7, 0.0, 1e-7, 3e-7])
    F = model.spring_force(y)
    assert F[:2].tolist() == [0.0, 0.0]
    assert np.allclose(F[2:], -model.S * model.c_n * y[2:] ** m2, rtol=1e-14, atol=0.0)


@pytest.mark.parametrize("m2,l", LAWS)
def test_kernel_rhs_law_and_numpy_agree(m2, l):
    """flow.rhs (contact and flight mode) = [1 + p cos rτ − f]/m2 with f from the law's
    vectorised force and from the plain formula; the law's partials = the formula's."""
    model = _model(m2, l)
    par = _par(model)
    c = par[2]
    rng = np.random.default_rng(7)
    x = rng.uniform(0.05, 3.0, 200)
    v = rng.uniform(-2.0, 2.0, 200)
    t = rng.uniform(0.0, 20.0, 200)
    f, fx, fv = model.power_law.force(x, v, c)
    g, gx, gv = _numpy_force(x, v, m2, l, c)
    for a, b in ((f, g), (fx, gx), (fv, gv)):
        assert np.allclose(a, b, rtol=1e-14, atol=1e-15)
    out = np.empty(2)
    for i in range(x.size):
        exc = 1.0 + par[3] * math.cos(par[4] * t[i])
        rhs(True, t[i], np.array([x[i], v[i]]), par, out)
        assert out[0] == v[i]
        assert out[1] == pytest.approx((exc - f[i]) / m2, rel=1e-14, abs=1e-14)
        rhs(False, t[i], np.array([-x[i], v[i]]), par, out)
        assert out[1] == exc / m2
    # flight (x ≤ 0): the law's force is zero, as harmonic balance needs it
    f0, fx0, fv0 = model.power_law.force(-x, v, c)
    assert not f0.any() and not fx0.any() and not fv0.any()
    assert model.power_law.force(0.0, 1.0, c)[0] == 0.0


@pytest.mark.parametrize("m2,l", LAWS)
def test_jacobian_is_the_derivative(m2, l):
    """The variational equation's Jacobian row (flow.rhs, n = 6, Φ = I) and the law's partials
    equal central differences of the right-hand side (relative 1e-7)."""
    model = _model(m2, l)
    par = _par(model)
    rng = np.random.default_rng(3)
    out = np.empty(6)
    o2 = np.empty(2)
    for x, v in zip(rng.uniform(0.2, 2.5, 20), rng.uniform(-1.5, 1.5, 20)):
        rhs(True, 0.4, np.array([x, v, 1.0, 0.0, 0.0, 1.0]), par, out)
        h = 1e-6
        num = []
        for dx, dv in ((h, 0.0), (0.0, h)):
            rhs(True, 0.4, np.array([x + dx, v + dv]), par, o2)
            ap = o2[1]
            rhs(True, 0.4, np.array([x - dx, v - dv]), par, o2)
            num.append((ap - o2[1]) / (2 * h))
        assert out[4] == pytest.approx(num[0], rel=1e-7, abs=1e-9)
        assert out[5] == pytest.approx(num[1], rel=1e-7, abs=1e-9)
        _, fx, fv = model.power_law.force(x, v, par[2])
        assert -fx / m2 == pytest.approx(out[4], rel=1e-15, abs=1e-16)
        assert -fv / m2 == pytest.approx(out[5], rel=1e-15, abs=1e-16)


@pytest.mark.parametrize("m2,l", [(m2, l) for m2, l in LAWS if m2 == int(m2) and l == int(l)])
def test_taylor_series_matches_scipy(m2, l):
    """The law's Taylor recurrence: V[1] is the right-hand side, and the order-24 polynomial at
    h = 0.1 equals scipy DOP853 (rtol 1e-13) on the contact-mode equation to 1e-11."""
    model = _model(m2, l)
    par = _par(model, p=0.5, r=0.9)
    assert is_polynomial_law(par)
    N = 24
    X, V = np.empty(N + 1), np.empty(N + 1)
    o2 = np.empty(2)
    for t0, x0, v0 in ((0.3, 1.2, -0.3), (2.0, 0.7, 0.4), (5.0, 1.9, 0.0)):
        series(True, t0, x0, v0, par, N, X, V)
        rhs(True, t0, np.array([x0, v0]), par, o2)
        assert X[1] == v0 and V[1] == pytest.approx(o2[1], rel=1e-14, abs=1e-15)
        h = 0.1
        sol = solve_ivp(lambda t, y: [y[1], (1 - y[0] ** m2 - par[2] * y[0] ** l * y[1]
                                             + par[3] * math.cos(par[4] * t)) / m2],
                        (t0, t0 + h), [x0, v0], method="DOP853", rtol=1e-13, atol=1e-13)
        xs = np.polyval(X[::-1], h)
        vs = np.polyval(V[::-1], h)
        assert xs == pytest.approx(sol.y[0, -1], abs=1e-11)
        assert vs == pytest.approx(sol.y[1, -1], abs=1e-11)


def _hb_point(sol, r):
    """(x, x') at phase 0 of an HB solution: x(θ) = a0 + Σ a_k cos kθ + b_k sin kθ."""
    X = sol.coefficients
    k = np.arange(1, (X.size - 1) // 2 + 1)
    return np.array([X[0] + X[1::2].sum(), r * (k * X[2::2]).sum()])


@pytest.mark.parametrize("m2,l", LAWS)
def test_hb_perturbation_and_flow_agree_with_scipy(m2, l):
    """At P_a = 0.1 Q, f_e = 0.7 f_n0 (contact kept): the HB solution (residual from the law's
    force) and the summed perturbation series (the law's Miller recurrence) give the same orbit
    point to 1e-9, it is a fixed point of scipy's one-period map to 1e-9 and of the DOP853
    kernel's (the law's compiled right-hand side) to 1e-9."""
    model = _model(m2, l)
    exc = model.excitation(0.1, 0.7 * model.f_n0)
    r = exc.r
    sol = hb_solve(exc, harmonics=24, stability=False)
    assert sol.residual < 1e-11 and not sol.loses_contact
    z_hb = _hb_point(sol, r)
    pert = perturbation_series(exc, terms=30, summation="plain")
    assert pert.valid
    z_ps = pert.state
    assert np.allclose(z_ps, z_hb, rtol=0.0, atol=1e-9)
    T = exc.tau_period
    par = exc.kernel_parameters()
    z_sp = scipy_in_contact(par, z_hb, T, rtol=1e-12)
    assert np.allclose(z_sp, z_hb, rtol=0.0, atol=1e-9)
    y = z_hb.copy()
    res = advance(y, 0.0, T, True, 0.01, par, 1e-12, 1e-12, np.empty((0, REC_WIDTH)), 0, 10**6)
    assert res[-1] == STATUS_OK and res[0]
    assert np.allclose(y, z_hb, rtol=0.0, atol=1e-9)
    # and the HB residual, re-evaluated on a fine grid with the plain formula, is small
    th = np.linspace(0.0, 2 * np.pi, 1001)
    X = sol.coefficients
    k = np.arange(1, (X.size - 1) // 2 + 1)[:, None]
    a, b = X[1::2, None], X[2::2, None]
    C, S = np.cos(k * th), np.sin(k * th)
    x = X[0] + (a * C + b * S).sum(0)
    xt = (k * (b * C - a * S)).sum(0)
    xtt = -(k * k * (a * C + b * S)).sum(0)
    f = _numpy_force(x, r * xt, m2, l, par[2])[0]
    resid = m2 * r * r * xtt + f - 1.0 - par[3] * np.cos(th)
    assert np.abs(resid).max() < 1e-10


def test_law_series_about_one_is_the_binomial_series():
    """Miller's recurrence from the law: with u = ε (one term), (1 + ε)^α has the binomial
    coefficients C(α, n), for the stiffness (m2) and damping (l) exponents."""
    law = PowerLaw(1.5, 0.5)
    N = 8
    u = np.zeros((N + 1, 3))
    u[1] = 1.0
    W = np.zeros((N + 1, 3))
    D = np.zeros((N + 1, 3))
    W[0] = D[0] = 1.0
    for n in range(1, N + 1):
        R, S = law.series_about_one(u, W, D, n)
        W[n] = law.m2 * u[n] + R
        D[n] = law.l * u[n] + S
    from scipy.special import binom

    n = np.arange(N + 1)
    assert np.allclose(W[:, 0], binom(1.5, n), rtol=1e-14, atol=1e-15)
    assert np.allclose(D[:, 0], binom(0.5, n), rtol=1e-14, atol=1e-15)
