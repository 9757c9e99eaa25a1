"""One pseudo-arclength continuation engine for every branch the package follows.

A *problem* (:class:`Problem`) is a map ``F: R^(n+1) → R^n`` of the unknowns ``u`` (state, then
the continuation parameter(s)) with its Jacobian, a scaling of the unknowns, measurements of an
accepted point and test functions; the engine does the rest, once for all problems (periodic
orbits by shooting in f_e or P_a, fold and period-doubling curves in the (f_e, P_a) plane,
harmonic balance in f_e). Equations of one step from the accepted point ``u_a``::

    F(u) = 0,        N(u) = τ · W (u − u_a) − Δs = 0          (pseudo-arclength hyperplane)

with ``W = diag(w)`` the problem's scaling and ``τ`` the unit tangent in scaled unknowns: the
null vector of ``F_u W⁻¹``, from the bordered system ``[F_u W⁻¹; τ_old] t = [0; 1]``.

* predictor: Euler, ``u_a + Δs W⁻¹ τ``;
* corrector: Newton on the bordered ``(n+1)×(n+1)`` system ``[F_u; τᵀW] d = −[F; N]``
  (:func:`correct`), converged when the problem's residual norm ≤ ``tol`` and ``|N| ≤ cons_tol``;
* step control (:class:`StepControl`): ``Δs`` multiplied by a factor chosen by the number of
  Jacobian evaluations of the last correction, halved after a failed correction or a tangent
  turning by more than ``max_turn``, optionally capped so that the parameter moves at most
  ``dq_max`` per step;
* events: a test function changing sign between two accepted points is located by the Illinois
  method (:func:`.bifurcations.locate_zero`) on the arclength σ ∈ (0, Δs), each trial point
  corrected back onto the branch on the hyperplane at σ; tests named in ``Problem.fold_tests``
  count only where the parameter component of the tangent changes sign too (a turning point);
* stops (:class:`EngineStop`): maximum number of points, step below ``ds_min``, too many
  rejected steps, a failed measurement at the smallest step, a bound of a parameter, a closed
  branch back at its first point, or a stop asked by the problem.

References
----------
E. L. Allgower, K. Georg, *Introduction to Numerical Continuation Methods*, SIAM (2003), Ch. 2.
H. B. Keller, *Lectures on Numerical Methods in Bifurcation Problems*, Springer (1987), Ch. 4.
R. Veltz, BifurcationKit.jl (2020): problems as residual + Jacobian + record, one engine.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from contactvib._kernels.continuation import bordered_newton_step, null_vector
from contactvib._kernels.status import (
    STATUS_DIVERGED,
    STATUS_MAXITER,
    STATUS_OK,
    STATUS_SINGULAR,
    STATUS_TANGENT_TURNED,
)
from contactvib.continuation.bifurcations import locate_zero

__all__ = ["Problem", "Point", "Event", "EngineStop", "CorrectorSettings", "StepControl",
           "Bound", "correct", "tangent", "continue_branch", "STATUS_OK", "STATUS_SINGULAR",
           "STATUS_DIVERGED", "STATUS_MAXITER", "STATUS_TURN"]

STATUS_TURN = STATUS_TANGENT_TURNED
#: problems with at most this many unknowns are solved by the compiled small dense solvers
SMALL = 8


@dataclass(frozen=True)
class Bound:
    """Range ``lo ≤ u[index] ≤ hi`` of one unknown; ``name`` for the stop message."""

    index: int
    lo: float
    hi: float
    name: str


class Problem(Protocol):
    """What the engine needs of a continuation problem (unknowns ``u``, size n + 1)."""

    #: names of the test functions returned by :meth:`tests`
    test_names: tuple
    #: tests that count only together with a turning point of the parameter (folds)
    fold_tests: tuple
    #: ranges of the unknowns (checked in order after each accepted step)
    bounds: tuple

    def residual_jacobian(self, u: np.ndarray) -> tuple:
        """``(status, F (n,), F_u (n, n+1), data)``; ``status`` 0 when evaluated, ``data`` any
        by-product kept with the point (e.g. the monodromy)."""

    # Optional fast path for small problems with a compiled residual:
    # ``residual_jacobian_step(u, bord, u_prev, ds, w) -> (status, F, F_u, data, res, N, step, u_new)``
    # evaluates the residual, its norm (as :meth:`residual_norm`) and the Jacobian and takes the
    # bordered Newton step in one compiled call (the arithmetic of
    # :func:`_kernels.continuation.bordered_newton_step`).

    def residual_norm(self, u: np.ndarray, F: np.ndarray) -> float:
        """Norm of F compared with :attr:`CorrectorSettings.tol`."""

    def weights(self, u: np.ndarray) -> np.ndarray:
        """Scaling ``w`` of the unknowns (arclength measured in ``w * u``)."""

    def admissible(self, u: np.ndarray) -> bool:
        """False when a Newton iterate left the domain (e.g. a frequency ≤ 0)."""

    def measure(self, u: np.ndarray, J: np.ndarray, data: Any, residual: float) -> Any:
        """Measurements of a converged point (returned as ``Point.record``), None on failure."""

    def tests(self, point: Point) -> dict:
        """Values of the test functions at a measured point (NaN: not defined there)."""

    def check(self, point: Point) -> str | None:
        """A problem-specific stop at an accepted point (its reason), or None."""

    def check_step(self, a: Point, b: Point) -> str | None:
        """A stop that rejects the new point ``b`` (reason), or None."""


@dataclass(frozen=True)
class CorrectorSettings:
    """Newton corrector: at most ``max_iter`` steps (``max_iter + 1`` Jacobians), at least
    ``min_iter``; converged when the residual norm ≤ ``tol`` and ``|N| ≤ cons_tol``; a scaled
    step ``max |w d|`` over ``max_step`` counts as divergence."""

    tol: float = 1e-10
    max_iter: int = 8
    min_iter: int = 0
    cons_tol: float = 1e-9
    max_step: float = 1.0


@dataclass(frozen=True)
class StepControl:
    """Adaptive pseudo-arclength step.

    ``growth``: ``((evaluations, factor), ...)`` in increasing evaluations: after a correction
    that took ≤ ``evaluations`` Jacobians the step is multiplied by ``factor`` (capped at
    ``ds_max``); otherwise divided by ``shrink`` (floored at ``ds_min``). A failed correction
    halves it. ``dq_max`` caps the change of the last unknown (the parameter) per step.
    """

    ds: float = 0.02
    ds_min: float = 1e-7
    ds_max: float = 0.15
    growth: tuple = ((2, 2.0), (3, 1.5), (5, 1.2))
    shrink: float = 1.5
    max_turn: float = math.pi
    max_failures: int = 1 << 30
    max_points: int = 2000
    dq_max: float = math.inf
    locate_tol: float = 1e-11
    locate: bool = True  # False: test-function sign changes are not located (no events)
    detect_loop: bool = False
    bound_action: str = "fix"  # "fix": corrected onto the bound, "append": kept, "drop": left out

    def next_ds(self, ds: float, evaluations: int) -> float:
        for n, g in self.growth:
            if evaluations <= n:
                return min(ds * g, self.ds_max)
        return max(ds / self.shrink, self.ds_min)


@dataclass
class Point:
    """An accepted (or located) point of a branch.

    Attributes
    ----------
    u : ndarray (n+1,)
        Unknowns.
    J : ndarray (n, n+1)
        Jacobian ``F_u`` there.
    data : any
        By-product of the residual (the problem's; e.g. the monodromy matrix).
    residual : float
        Residual norm at convergence.
    iterations : int
        Jacobian evaluations of its correction.
    record : any
        The problem's measurements (:meth:`Problem.measure`).
    tests : dict
        Test-function values.
    tangent : ndarray (n+1,) or None
        Unit tangent there in the scaled unknowns of the step that produced it, unscaled
        (``τ / w``), oriented along the branch.
    """

    u: np.ndarray
    J: np.ndarray
    data: Any
    residual: float
    iterations: int = 0
    record: Any = None
    tests: dict = field(default_factory=dict)
    tangent: np.ndarray | None = None


@dataclass(frozen=True)
class Event:
    """A located zero of test function ``kind`` between accepted points ``index`` and
    ``index + 1``."""

    kind: str
    index: int
    point: Point
    value: float
    bracket: tuple


@dataclass(frozen=True)
class EngineStop:
    """Why a direction ended: ``code`` in {"max_points", "step_min", "max_failures",
    "measure_failed", "bound", "loop", "problem", "rejected"}; ``status`` the last corrector
    status (step_min), ``detail`` the bound's ``(name, "lower"|"upper")`` or the problem's
    reason."""

    code: str
    status: int = 0
    detail: Any = None
    failures: int = 0


@dataclass
class Run:
    """Result of one direction: accepted points, located events, stop."""

    points: list
    events: list
    stop: EngineStop


def correct(problem: Problem, u_pred, u_prev, tau, w, ds, cs: CorrectorSettings):
    """Newton corrector onto ``F = 0`` on the hyperplane ``τ·W(u − u_prev) = ds``.

    ``ds = 0``, ``τ = e_q`` and ``u_prev = u_pred`` fix the parameter ``q`` (natural parameter).

    Returns
    -------
    status : int
        ``STATUS_OK``, the problem's status or ``STATUS_SINGULAR/DIVERGED/MAXITER``.
    point : Point or None
        The converged point (``record`` not yet measured).
    """
    u = np.array(u_pred, float)
    bord = tau * w
    small = u.size <= SMALL
    fused = small and hasattr(problem, "residual_jacobian_step")
    for it in range(cs.max_iter + 1):
        if fused:  # residual, its norm, Jacobian and the bordered step in one compiled call
            st, F, J, data, res, cons, step, u_new = problem.residual_jacobian_step(u, bord, u_prev, ds, w)
        else:
            st, F, J, data = problem.residual_jacobian(u)
        if st != STATUS_OK:
            return st, None
        if not fused:
            res = problem.residual_norm(u, F)
        if fused:
            pass
        elif small:  # N and the Newton step in one compiled call (the step unused if converged)
            u_new = np.empty(u.size)
            cons, step = bordered_newton_step(J, F, bord, u, u_prev, ds, w, u_new)
        else:
            cons = float(bord @ (u - u_prev)) - ds
        if it >= cs.min_iter and res <= cs.tol and abs(cons) <= cs.cons_tol:
            return STATUS_OK, Point(u, J, data, res, it + 1)
        if it == cs.max_iter:
            break
        if not small:
            try:
                d = np.linalg.solve(np.vstack([J, bord]), -np.append(F, cons))
            except np.linalg.LinAlgError:
                return STATUS_SINGULAR, None
            step = float(np.abs(d * w).max())
            u_new = u + d
        if step != step:  # NaN: singular
            return STATUS_SINGULAR, None
        if not math.isfinite(step) or step > cs.max_step:
            return STATUS_DIVERGED, None
        u = u_new
        if not problem.admissible(u):
            return STATUS_DIVERGED, None
    return STATUS_MAXITER, None


def tangent(J: np.ndarray, w: np.ndarray, direction: np.ndarray) -> np.ndarray | None:
    """Unit null vector of ``J W⁻¹`` (scaled unknowns) with a positive component along the unit
    vector ``direction``: ``[J W⁻¹; directionᵀ] t = [0; 1]``, normalised. None when singular."""
    n = J.shape[1]
    if n <= SMALL:
        t = np.empty(n)
        return t if null_vector(J, w, direction, t) else None
    A = np.empty((n, n))
    A[:-1] = J / w[None, :]
    A[-1] = direction
    rhs = np.zeros(n)
    rhs[-1] = 1.0
    try:
        t = np.linalg.solve(A, rhs)
    except np.linalg.LinAlgError:
        return None
    nrm = float(np.linalg.norm(t))
    if nrm == 0.0 or not math.isfinite(nrm):
        return None
    return t / nrm


def _unit(v):
    return v / np.linalg.norm(v)


class _Direction:
    """One direction of one branch (internal state of :func:`continue_branch`)."""

    def __init__(self, problem, cs, sc):
        self.p, self.cs, self.sc = problem, cs, sc

    def accept(self, pt: Point, t_unscaled) -> Point | None:
        rec = self.p.measure(pt.u, pt.J, pt.data, pt.residual)
        if rec is None:
            return None
        pt.record = rec
        pt.tangent = t_unscaled
        pt.tests = self.p.tests(pt)
        return pt

    def locate(self, kind, a: Point, b: Point, tau, w, ds):
        def f(sig):
            st, pt = correct(self.p, a.u + sig * tau / w, a.u, tau, w, sig, self.cs)
            if st != STATUS_OK:
                return None
            pt = self.accept(pt, a.tangent)
            if pt is None or not math.isfinite(pt.tests[kind]):
                return None
            return pt.tests[kind], pt

        found = locate_zero(f, 0.0, ds, a.tests[kind], b.tests[kind], self.sc.locate_tol)
        if found is None:
            return None
        return found[1], found[2]

    def crossings(self, a: Point, b: Point):
        q = a.u.size - 1
        turned = a.tangent[q] * b.tangent[q] < 0
        out = []
        for kind in self.p.test_names:
            fa, fb = a.tests[kind], b.tests[kind]
            if math.isfinite(fa) and math.isfinite(fb) and fa * fb < 0:
                if kind in self.p.fold_tests and not turned:
                    continue
                out.append(kind)
        return out

    def step(self, a: Point, tau, w, ds):
        """Predictor and corrector from ``a`` along the scaled unit tangent ``tau``; the new
        tangent, rejected (``STATUS_TURN``) when it turned by more than ``max_turn``."""
        st, b = correct(self.p, a.u + ds * tau / w, a.u, tau, w, ds, self.cs)
        if st != STATUS_OK:
            return st, None, None
        tau_new = tangent(b.J, w, tau)
        if tau_new is None:
            return STATUS_SINGULAR, None, None
        if (math.acos(min(1.0, float(np.dot(tau_new, tau)))) > self.sc.max_turn
                and ds > 2.0 * self.sc.ds_min):
            return STATUS_TURN, None, None
        return STATUS_OK, b, tau_new

    def stop_at_bound(self, points, events, b: Point, crossed) -> Run:
        """``b`` left a bound: events outside dropped, the last point by ``bound_action``."""
        bound, side = crossed
        events = [e for e in events if not _crossed(self.p.bounds, e.point.u)]
        if self.sc.bound_action == "fix":
            c = self.at_bound(points[-1], b, bound)
            if c is not None:
                points.append(c)
        elif self.sc.bound_action == "append":
            points.append(b)
        return Run(points, events, EngineStop("bound", detail=(bound.name, side)))

    def at_bound(self, a: Point, b: Point, bound: Bound):
        """The point on the bound between a and b, corrected at the fixed unknown."""
        lim = bound.lo if b.u[bound.index] < bound.lo else bound.hi
        i = bound.index
        frac = (lim - a.u[i]) / (b.u[i] - a.u[i])
        guess = a.u + frac * (b.u - a.u)
        guess[i] = lim
        e = np.zeros(a.u.size)
        e[i] = 1.0
        st, c = correct(self.p, guess, guess.copy(), e, self.p.weights(guess), 0.0, self.cs)
        if st != STATUS_OK:
            return None
        return self.accept(c, b.tangent)


def continue_branch(problem: Problem, start: Point, direction, cs: CorrectorSettings,
                    sc: StepControl) -> Run:
    """Follow the branch from the converged point ``start`` (``u``, ``J``, ``data`` set) along
    the unscaled ``direction`` (its tangent is oriented along it) until a stop.

    Returns
    -------
    Run
        ``points`` from ``start`` on, located ``events``, and the ``stop``.
    """
    eng = _Direction(problem, cs, sc)
    w = problem.weights(start.u)
    d0 = _unit(np.asarray(direction, float) * w)
    tau = tangent(start.J, w, d0)
    if tau is None:
        tau = d0
    p0 = eng.accept(start, tau / w)
    if p0 is None:
        return Run([start], [], EngineStop("measure_failed"))
    points, events = [p0], []
    t_start = p0.tangent.copy()
    ds, n_fail = sc.ds, 0
    why = problem.check(p0)
    if why is not None:
        return Run(points, events, EngineStop("problem", detail=why))
    while True:
        a = points[-1]
        if len(points) >= sc.max_points:
            return Run(points, events, EngineStop("max_points"))
        w = problem.weights(a.u)
        tau = _unit(a.tangent * w)
        if sc.dq_max < math.inf:
            ds = min(ds, sc.dq_max * w[-1] / max(abs(tau[-1]), 1e-300))
        st, b, tau_new = eng.step(a, tau, w, ds)
        if st != STATUS_OK:
            n_fail += 1
            ds *= 0.5
            if n_fail > sc.max_failures:
                return Run(points, events, EngineStop("max_failures", st, failures=n_fail))
            if ds < sc.ds_min:
                return Run(points, events, EngineStop("step_min", st, failures=n_fail))
            continue
        early = _crossed(problem.bounds, b.u) if sc.bound_action == "drop" else None
        if early is None and eng.accept(b, tau_new / w) is None:
            ds *= 0.5
            if ds < sc.ds_min:
                return Run(points, events, EngineStop("measure_failed"))
            continue
        if early is None:
            why = problem.check_step(a, b)
            if why is not None:
                return Run(points, events, EngineStop("rejected", detail=why))
            for kind in (eng.crossings(a, b) if sc.locate else ()):
                found = eng.locate(kind, a, b, tau, w, ds)
                if found is not None:
                    events.append(Event(kind, len(points) - 1, found[1], found[0], (a, b)))
        crossed = early or _crossed(problem.bounds, b.u)
        if crossed:
            return eng.stop_at_bound(points, events, b, crossed)
        points.append(b)
        if sc.detect_loop and _closed(points, t_start, problem, ds):
            return Run(points, events, EngineStop("loop"))
        why = problem.check(b)
        if why is not None:
            return Run(points, events, EngineStop("problem", detail=why))
        ds = sc.next_ds(ds, b.iterations)


def _crossed(bounds, u):
    """The first bound that ``u`` lies outside of, with the side ("lower"/"upper"), or None."""
    for bound in bounds:
        if u[bound.index] < bound.lo:
            return bound, "lower"
        if u[bound.index] > bound.hi:
            return bound, "upper"
    return None


def _closed(points, t_start, problem, ds) -> bool:
    """Back at the first point, passing it the way the branch left it (an isola's loop)."""
    if len(points) <= 8:
        return False
    b, a, first = points[-1], points[-2], points[0]
    wb = problem.weights(b.u)
    d0 = float(np.linalg.norm((b.u - first.u) * wb))
    same_way = float(np.dot(_unit(b.tangent * wb), _unit(t_start * wb))) > 0.9
    return (d0 < 1.5 * ds and same_way
            and float(np.linalg.norm((a.u - first.u) * wb)) >= d0)
