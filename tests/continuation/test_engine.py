"""The one continuation engine on analytic problems, the problems' Jacobians against finite
differences, and branch files in the new and the old naming scheme."""

import math

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib.continuation.engine import (
    Bound,
    CorrectorSettings,
    Point,
    StepControl,
    continue_branch,
    correct,
    tangent,
)

MODEL = ContactModel()


class Analytic:
    """F(u) = 0 for u = (x, λ) given as callables; test function ``fold`` = ∂F/∂x."""

    test_names = ("fold", "sign")
    fold_tests = ("fold",)

    def __init__(self, F, dF, bounds=(), stop_at=None):
        self.F, self.dF, self.bounds, self.stop_at = F, dF, bounds, stop_at
        self.evaluations = 0

    def residual_jacobian(self, u):
        self.evaluations += 1
        return 0, np.array([self.F(u)]), np.array([self.dF(u)]), None

    def residual_norm(self, u, F):
        return abs(float(F[0]))

    def weights(self, u):
        return np.ones(2)

    def admissible(self, u):
        return True

    def measure(self, u, J, data, residual):
        return {"x": float(u[0]), "lam": float(u[1])}

    def tests(self, pt):
        # "sign" changes sign at x = 0.5 but is no fold: located without a turning point
        return {"fold": float(pt.J[0, 0]), "sign": float(pt.u[0] - 0.5)}

    def check(self, pt):
        if self.stop_at is not None and pt.u[0] > self.stop_at:
            return "past the stop"
        return None

    def check_step(self, a, b):
        return None


def _start(prob, u):
    st, F, J, data = prob.residual_jacobian(np.asarray(u, float))
    assert st == 0
    return Point(np.asarray(u, float), J, data, abs(float(F[0])))


PARABOLA = dict(F=lambda u: u[0] ** 2 + u[1], dF=lambda u: np.array([2.0 * u[0], 1.0]))
CS = CorrectorSettings(tol=1e-13, max_iter=10)


def test_fold_of_the_parabola_located_inside_its_bracket():
    """x² + λ = 0 from (−1, −1) with λ increasing: the fold at (0, 0) is located to the
    tolerance, between the two accepted points that bracket it; the 'sign' test at x = 0.5
    (no turning point) is located too; the branch stops at the λ bound."""
    prob = Analytic(**PARABOLA, bounds=(Bound(1, -2.0, 2.0, "lambda"),))
    sc = StepControl(ds=0.05, ds_max=0.2, locate_tol=1e-13)
    run = continue_branch(prob, _start(prob, [-1.0, -1.0]), [0.0, 1.0], CS, sc)
    assert run.stop.code == "bound" and run.stop.detail == ("lambda", "lower")
    folds = [e for e in run.events if e.kind == "fold"]
    assert len(folds) == 1
    f = folds[0]
    assert abs(f.point.u[0]) < 1e-12 and abs(f.point.u[1]) < 1e-12
    a, b = f.bracket
    assert a.u[0] < f.point.u[0] < b.u[0]
    assert a is run.points[f.index] and b is run.points[f.index + 1]
    # the tangent's λ-component changed sign across the bracket (a turning point)
    assert a.tangent[1] * b.tangent[1] < 0
    signs = [e for e in run.events if e.kind == "sign"]
    assert len(signs) == 1 and abs(signs[0].point.u[0] - 0.5) < 1e-12
    # every accepted point lies on the parabola, and the last one on the bound
    u = np.array([p.u for p in run.points])
    assert np.max(np.abs(u[:, 0] ** 2 + u[:, 1])) < 1e-12
    assert u[-1, 1] == pytest.approx(-2.0, abs=1e-14) and u[-1, 0] > 0
    # a fold test changing sign where the branch does not turn is not a fold
    prob.fold_tests = ("fold", "sign")
    run = continue_branch(prob, _start(prob, [-1.0, -1.0]), [0.0, 1.0], CS, sc)
    assert [e.kind for e in run.events] == ["fold"]


def test_two_folds_of_the_cubic():
    """x³ − x − λ = 0 followed in x: two folds of λ at x = ±1/√3 (∂F/∂x = 3x² − 1 = 0),
    located; stop at the x bound."""
    prob = Analytic(F=lambda u: u[0] ** 3 - u[0] - u[1],
                    dF=lambda u: np.array([3.0 * u[0] ** 2 - 1.0, -1.0]),
                    bounds=(Bound(0, -1.5, 1.5, "x"),))
    run = continue_branch(prob, _start(prob, [-1.5, -1.875]), [1.0, 0.0], CS,
                          StepControl(ds=0.05, ds_max=0.1, locate_tol=1e-13))
    folds = sorted(e.point.u[0] for e in run.events if e.kind == "fold")
    assert np.allclose(folds, [-1 / math.sqrt(3), 1 / math.sqrt(3)], atol=1e-12)
    assert run.stop.code == "bound" and run.stop.detail == ("x", "upper")


def test_circle_closes_after_one_loop_and_problem_stops():
    circle = dict(F=lambda u: u[0] ** 2 + u[1] ** 2 - 1.0,
                  dF=lambda u: np.array([2.0 * u[0], 2.0 * u[1]]))
    prob = Analytic(**circle)
    sc = StepControl(ds=0.1, ds_max=0.2, detect_loop=True)
    run = continue_branch(prob, _start(prob, [1.0, 0.0]), [0.0, 1.0], CS, sc)
    assert run.stop.code == "loop"
    ang = np.unwrap([math.atan2(p.u[1], p.u[0]) for p in run.points])
    assert 2 * math.pi - 0.5 < ang[-1] <= 2 * math.pi + 0.3
    assert np.all(np.diff(ang) > 0)
    # the two folds of λ on the circle, at (0, ±1); and the problem's own stop
    folds = sorted((e.point.u[1], e.point.u[0]) for e in run.events if e.kind == "fold")
    np.testing.assert_allclose(folds, [(-1.0, 0.0), (1.0, 0.0)], atol=1e-9)
    run2 = continue_branch(Analytic(**circle, stop_at=0.9), _start(prob, [0.0, -1.0]),
                           [1.0, 0.0], CS, StepControl(ds=0.1))
    assert run2.stop.code == "problem" and run2.stop.detail == "past the stop"
    assert run2.points[-1].u[0] > 0.9


def test_step_control_and_max_points():
    sc = StepControl(ds=0.02, ds_min=1e-7, ds_max=0.15)  # the shooting engine's rule
    assert sc.next_ds(0.02, 2) == 0.04 and sc.next_ds(0.02, 3) == pytest.approx(0.03)
    assert sc.next_ds(0.02, 5) == pytest.approx(0.024) and sc.next_ds(0.02, 6) == 0.02 / 1.5
    assert sc.next_ds(0.14, 1) == 0.15 and sc.next_ds(1e-7, 9) == 1e-7
    hb = StepControl(ds=0.02, ds_max=0.5, growth=((4, 1.5),), shrink=1.0)
    assert hb.next_ds(0.02, 4) == pytest.approx(0.03) and hb.next_ds(0.02, 5) == 0.02
    prob = Analytic(**PARABOLA)
    run = continue_branch(prob, _start(prob, [-1.0, -1.0]), [0.0, 1.0], CS,
                          StepControl(ds=0.01, growth=(), shrink=1.0, max_points=7))
    assert run.stop.code == "max_points" and len(run.points) == 7
    arc = np.linalg.norm(np.diff([p.u for p in run.points], axis=0), axis=1)
    np.testing.assert_allclose(arc, 0.01, rtol=1e-3)  # constant step, chord ≈ arclength


def test_dq_max_caps_the_parameter_step():
    prob = Analytic(F=lambda u: u[0] - 2.0 * u[1], dF=lambda u: np.array([1.0, -2.0]))
    run = continue_branch(prob, _start(prob, [0.0, 0.0]), [0.0, 1.0], CS,
                          StepControl(ds=1.0, ds_max=1.0, dq_max=0.01, max_points=5))
    dlam = np.diff([p.u[1] for p in run.points])
    np.testing.assert_allclose(dlam, 0.01, rtol=1e-12)


def test_corrector_fixes_the_parameter_and_reports_failures():
    prob = Analytic(**PARABOLA)
    e = np.array([0.0, 1.0])
    st, pt = correct(prob, np.array([-1.3, -1.0]), np.array([-1.3, -1.0]), e, np.ones(2), 0.0, CS)
    assert st == 0 and pt.u[1] == -1.0 and pt.u[0] == pytest.approx(-1.0, abs=1e-13)
    # λ = 1: no real x, Newton fails (singular or diverged or iterations)
    st, pt = correct(prob, np.array([0.0, 1.0]), np.array([0.0, 1.0]), e, np.ones(2), 0.0, CS)
    assert st in (20, 21, 22) and pt is None
    t = tangent(np.array([[2.0, 1.0]]), np.ones(2), np.array([0.0, 1.0]))
    np.testing.assert_allclose(t, np.array([-1.0, 2.0]) / math.sqrt(5))


def _fd_jacobian(prob, u, steps):
    J = np.empty((prob.residual_jacobian(u)[1].size, u.size))
    for i, h in enumerate(steps):
        up, um = u.copy(), u.copy()
        up[i] += h
        um[i] -= h
        J[:, i] = (prob.residual_jacobian(up)[1] - prob.residual_jacobian(um)[1]) / (2 * h)
    return J


def test_orbit_problem_jacobian_matches_finite_differences():
    from contactvib.continuation.shooting import ContinuationSettings, OrbitProblem
    from contactvib.steady.orbits import refine_orbit

    exc = MODEL.excitation(0.65, 1930.0)
    for parameter, q in (("f_e", exc.r), ("P_a", exc.pa_over_q)):
        prob = OrbitProblem(MODEL, exc, 1, parameter, ContinuationSettings(rtol=1e-13))
        z, _M, _r = refine_orbit(exc, [1.0, 0.0], 1)
        u = np.array([z[0] + 1e-3, z[1] - 1e-3, q])
        st, _F, J, M = prob.residual_jacobian(u)
        assert st == 0
        np.testing.assert_allclose(J, _fd_jacobian(prob, u, [1e-6, 1e-6, 1e-6 * q]),
                                   rtol=1e-5, atol=1e-6)
        np.testing.assert_allclose(J[:, :2], M - np.eye(2))


def test_codim1_problem_jacobian_matches_finite_differences():
    from contactvib.continuation.evolution import Codim1Problem

    exc = MODEL.excitation(0.65, 1000.0)
    prob = Codim1Problem(MODEL, exc.kernel_parameters(), "fold", 1e-13, (0.0, 2.0), (30, 2000))
    u = np.array([1.1, 0.2, exc.r, 0.65])
    st, F, J, _M = prob.residual_jacobian(u)
    assert st == 0 and F.shape == (3,) and J.shape == (3, 4)
    np.testing.assert_allclose(J, _fd_jacobian(prob, u, [1e-5, 1e-5, 1e-5, 1e-5]),
                               rtol=1e-4, atol=1e-5)


def test_hb_problem_jacobian_matches_finite_differences():
    from contactvib.frequency.aft import AFT
    from contactvib.frequency.harmonic_balance import HBProblem

    H = 8
    prob = HBProblem(MODEL, 0.65, AFT(H, 64), (300.0, 2000.0), 1e-8, False)
    rng = np.random.default_rng(1)
    u = np.concatenate([[1.0], 0.3 * rng.standard_normal(2 * H) / np.repeat(np.arange(1, H + 1), 2) ** 2,
                        [0.4]])
    st, _F, J, _d = prob.residual_jacobian(u)
    assert st == 0 and J.shape == (2 * H + 1, 2 * H + 2)
    np.testing.assert_allclose(J, _fd_jacobian(prob, u, [1e-7] * u.size), rtol=1e-5, atol=1e-6)


def test_branch_file_roundtrip_new_and_old_names(tmp_path):
    from contactvib import ContinuationSettings, continue_orbit, find_attractors
    from contactvib.continuation.branch import _OLD_NAMES, Branch

    exc = MODEL.excitation(0.65, 1930.0)
    a = [a for a in find_attractors(exc) if a.period == 1][0]
    b = continue_orbit(exc, a.state, 1, direction="down", settings=ContinuationSettings(fmin_hz=1500, fmax_hz=2000))
    ds = b.to_xarray()
    assert set(_OLD_NAMES) <= set(ds.data_vars) and not set(_OLD_NAMES.values()) & set(ds.data_vars)
    b.to_netcdf(tmp_path / "new.nc")
    ds.rename(_OLD_NAMES).to_netcdf(tmp_path / "old.nc")
    for name in ("new.nc", "old.nc"):
        r = Branch.from_netcdf(tmp_path / name)
        for col in ("fe_hz", "pa_over_q", "app_um", "ymin_um", "ymax_um", "floquet_multipliers",
                    "stable", "state", "contact_loss_fraction", "minima_per_period", "arclength"):
            np.testing.assert_array_equal(getattr(r, col), getattr(b, col), err_msg=col)
        assert (r.branch, r.period, r.parameter, r.fn0_hz) == (b.branch, b.period, b.parameter, b.fn0_hz)
        assert [s.to_dict() for s in r.stops] == [s.to_dict() for s in b.stops]
        assert [s.to_dict() for s in r.special] == [s.to_dict() for s in b.special]
        assert r.settings == b.settings
