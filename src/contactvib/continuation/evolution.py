"""Evolution of a 1/m resonance: two-parameter continuation of its folds and period doublings.

One-parameter continuation in f_e at a ladder of amplitudes P_a (:func:`.diagram.bifurcation_diagram`
seeded near f_n0/m) gives the folds and period doublings of the period-1 branches; those of the
1/m resonance are the ones whose orbit has m minima per period (the paper's S4.7). Each is then
followed in the (f_e, P_a) plane by pseudo-arclength continuation of the minimally extended
system (unknowns ``U = (x, x', r, p)``)::

    P(z; r, p) − z = 0,     h(z; r, p) = 0,     h = det(M − I) (fold) or det(M + I) (period doubling)

with ``∂h/∂U`` by central differences of the monodromy. The fold curve of a resonance peak has a
cusp where the peak starts to bend (its lowest P_a); the lowest P_a of a period-doubling curve is
where the first period doubling appears.

References
----------
W. Govaerts, *Numerical Methods for Bifurcations of Dynamical Equilibria*, SIAM (2000), Ch. 4.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels.continuation import orbit_range, residual_jacobian
from contactvib._kernels.shooting import strobe_map
from contactvib._kernels.status import STATUS_OK
from contactvib.call_forms import old_form
from contactvib.continuation.bifurcations import fold_test, pd_test
from contactvib.continuation.engine import (
    Bound,
    CorrectorSettings,
    Point,
    StepControl,
    continue_branch,
    correct,
)
from contactvib.continuation.shooting import ContinuationSettings
from contactvib.model import EVOLUTION_ORDER_MAX, ContactModel, ParameterError, check_int, check_range

__all__ = ["evolution", "EvolutionResult", "Curve", "continue_codim1", "Codim1Problem"]

_H = {"fold": fold_test, "period-doubling": pd_test}


@dataclass
class Curve:
    """A fold or period-doubling curve in the (f_e, P_a) plane."""

    type: str
    fe_hz: np.ndarray
    pa_over_q: np.ndarray
    app_um: np.ndarray
    stops: list = field(default_factory=list)


@dataclass
class EvolutionResult:
    """Fold and period-doubling curves of the 1/m resonance, and the one-parameter points.

    Attributes
    ----------
    order : int
        m of the 1/m resonance.
    curves : list of Curve
    points : list of SpecialPoint
        Folds and period doublings of the 1/m resonance found by one-parameter continuation at
        each level of P_a (they must lie on the curves: an independent check).
    extremes : dict
        ``{"fold onset": (f_e [Hz], P_a [Q]), "period-doubling onset": (...)}``: lowest P_a of
        the curves (absent when no such curve was found).
    levels : ndarray
        The P_a levels [Q] of the one-parameter runs.
    """

    order: int
    curves: list
    points: list
    extremes: dict
    levels: np.ndarray

    def to_dict(self) -> dict:
        return {"order": self.order, "levels_pa_over_q": [float(p) for p in self.levels],
                "extremes": {k: {"fe_hz": float(f), "pa_over_q": float(p)} for k, (f, p) in self.extremes.items()},
                "points": [s.to_dict() for s in self.points],
                "curves": [{"type": c.type, "fe_hz": [float(v) for v in c.fe_hz],
                            "pa_over_q": [float(v) for v in c.pa_over_q],
                            "stops": c.stops} for c in self.curves]}

    def to_json(self, **kw) -> str:
        return json.dumps(self.to_dict(), **kw)


def _w(U):
    s = max(1.0, abs(U[0]), abs(U[1]))
    return np.array([1 / s, 1 / s, 1 / max(abs(U[2]), 1e-3), 1 / max(abs(U[3]), 1e-3)])


class Codim1Problem:
    """The minimally extended system of a fold or period doubling as a continuation problem.

    Unknowns ``U = (x, x', r, p)``; residual ``(P(z; r, p) − z, h(z; r, p))`` with
    ``h = det(M − I)`` (fold) or ``det(M + I)`` (period doubling); Jacobian ``[M − I | ∂P/∂r |
    ∂P/∂p]`` (:func:`contactvib._kernels.continuation.residual_jacobian`, ∂P/∂p by central
    differences) with ``∂h/∂U`` by central differences of the monodromy. Convergence: relative
    closure ≤ tol and ``|h| ≤ 1e-9`` (the residual norm weights h by ``tol / 1e-9``). Stops at
    the P_a and f_e bounds (the point outside is kept). Measurement: A_pp [µm] of the orbit.
    """

    test_names = ()
    fold_tests = ()
    h_tol = 1e-9

    def __init__(self, model: ContactModel, par0, kind, rtol, pa_range, fe_range, tol=1e-10):
        self.par = par0.copy()
        self.par0 = par0.copy()
        self.kind = kind
        self.h = _H[kind]
        self.rtol = rtol
        self.tol = tol
        self.y_um = model.units.y_um
        fn0 = model.f_n0
        self.bounds = (Bound(3, pa_range[0], pa_range[1], "P_a"),
                       Bound(2, fe_range[0] / fn0, fe_range[1] / fn0, "f_e"))

    def residual_jacobian(self, U):
        par = self.par
        par[4], par[3] = U[2], U[3]
        G = np.empty(2)
        J = np.empty((2, 3))
        M = np.empty((2, 2))
        st = residual_jacobian(U[:3].copy(), 1, par, 4, self.rtol, G, J, M)
        if st != STATUS_OK:
            return st, None, None, None
        Gp = self._dG_dp(U)
        dh = self._dh(U)
        if Gp is None or dh is None:
            return 1, None, None, None
        par[4], par[3] = U[2], U[3]
        Jf = np.zeros((3, 4))
        Jf[:2, :3] = J
        Jf[:2, 3] = Gp
        Jf[2] = dh
        return STATUS_OK, np.array([G[0], G[1], self.h(M)]), Jf, M

    def _dG_dp(self, U):
        """∂P/∂p by central differences."""
        par = self.par
        hp = 1e-5 * max(abs(U[3]), 1e-3)
        outs = []
        for sgn in (1, -1):
            par[3] = U[3] + sgn * hp
            o = np.empty(2)
            if strobe_map(U[:2].copy(), 1, par, self.rtol, self.rtol, o, np.empty((0, 0))) != STATUS_OK:
                return None
            outs.append(o)
        par[3] = U[3]
        return (outs[0] - outs[1]) / (2 * hp)

    def _dh(self, U):
        """∂h/∂U by central differences of the monodromy."""
        par = self.par
        dh = np.empty(4)
        for i in range(4):
            step = 1e-6 * max(1.0, abs(U[i])) if i < 2 else 1e-6 * max(abs(U[i]), 1e-3)
            vals = []
            for sgn in (1, -1):
                V = U.copy()
                V[i] += sgn * step
                par[4], par[3] = V[2], V[3]
                o = np.empty(2)
                MM = np.empty((2, 2))
                if strobe_map(V[:2].copy(), 1, par, self.rtol, self.rtol, o, MM) != STATUS_OK:
                    return None
                vals.append(self.h(MM))
            dh[i] = (vals[0] - vals[1]) / (2 * step)
        return dh

    def residual_norm(self, U, F):
        sc = max(1.0, abs(U[0]), abs(U[1]))
        return max(max(abs(F[0]), abs(F[1])) / sc, abs(F[2]) * self.tol / self.h_tol)

    def weights(self, U):
        return _w(U)

    def admissible(self, U):
        return U[2] > 0 and U[3] >= 0

    def measure(self, U, J, M, residual):
        """A_pp [µm] of the orbit (NaN when its record fails)."""
        par = self.par0.copy()
        par[4], par[3] = U[2], U[3]
        xmin, xmax, _f, _n, st = orbit_range(U[:2].copy(), 1, par, self.rtol)
        return (xmax - xmin) * self.y_um if st == STATUS_OK else math.nan

    def tests(self, pt):
        return {}

    def check(self, pt):
        return None

    def check_step(self, a, b):
        return None


def continue_codim1(model: ContactModel, kind: str, fe_hz: float, pa_over_q: float, state, *,
                    pa_range: tuple, f_range: tuple = (30.0, 2000.0), ds: float = 0.02,
                    ds_max: float = 0.1, max_points: int = 300, rtol: float = 1e-11,
                    max_iter: int = 9) -> Curve:
    """Follow a fold or period-doubling point of a period-1 branch in the (f_e, P_a) plane.

    ``pa_range`` = (P_a min, P_a max) [Q] and ``f_range`` = (f_min, f_max) [Hz] bound the curve.

    Both directions from the point (:func:`.engine.continue_branch` on :class:`Codim1Problem`,
    step ×1.5 after every accepted step); stops at the P_a and f_e bounds, after ``max_points``
    per direction, or when the step falls below 1e-6 (Newton failure).
    """
    if kind not in _H:
        raise ParameterError("kind", kind, "must be 'fold' or 'period-doubling'")
    par0 = model.excitation(pa_over_q, fe_hz).kernel_parameters()
    if par0[3] != pa_over_q:
        raise ParameterError("F_pre", model.preload, "the evolution in (f_e, P_a) is written for P_a in units of "
                                                     "Q without a preload")
    prob = Codim1Problem(model, par0, kind, rtol, tuple(pa_range), tuple(f_range))
    cs = CorrectorSettings(tol=prob.tol, max_iter=check_int("max_iter", max_iter, 1), cons_tol=1e-9, max_step=0.5)
    sc = StepControl(ds=ds, ds_min=1e-6, ds_max=ds_max, growth=((1 << 30, 1.5),),
                     max_points=max_points, bound_action="append")
    fn0 = model.f_n0
    U0 = np.array([state[0], state[1], fe_hz / fn0, pa_over_q])
    # converge the point on the hyperplane P_a = const
    st, start = correct(prob, U0, U0, np.array([0, 0, 0, 1.0]), _w(U0), 0.0, cs)
    if st != STATUS_OK:
        return Curve(kind, np.array([fe_hz]), np.array([pa_over_q]), np.array([np.nan]),
                     ["the point did not converge"])
    halves, stops = [], []
    for sgn in (1.0, -1.0):
        first = Point(start.u.copy(), start.J, start.data, start.residual)
        run = continue_branch(prob, first, np.array([0.0, 0.0, 0.0, sgn]), cs, sc)
        halves.append(run.points)
        stops.append(_STOP_TEXT.get(run.stop.code, "") or f"{run.stop.detail[0]} range reached")
    pts = halves[1][::-1] + halves[0][1:]
    P = np.array([p.u for p in pts])
    return Curve(kind, P[:, 2] * fn0, P[:, 3], np.array([p.record for p in pts]), stops)


_STOP_TEXT = {"max_points": "maximum number of points reached",
              "step_min": "step too small: Newton failure", "bound": ""}


def _minima(model, sp):
    exc = model.excitation(sp.pa_over_q, sp.fe_hz)
    return orbit_range(np.asarray(sp.state, float), 1, exc.kernel_parameters(), 1e-11)[3]


@old_form("model", "order")
def evolution(model: ContactModel, *, order: int, pa_min: float = 0.3, pa_max: float = 0.9,
              n_levels: int = 7, seed_fe=None, settings: ContinuationSettings | None = None,
              max_points: int = 300, log=None) -> EvolutionResult:
    """Folds and period doublings of the 1/``order`` resonance in the (f_e, P_a) plane.

    Parameters
    ----------
    order : int
        m ≥ 1 of the 1/m resonance (near f_n0/m).
    pa_min, pa_max : float
        Range of P_a [Q].
    n_levels : int
        Amplitude levels of the one-parameter runs (≥ 2).
    seed_fe : sequence of float, optional
        Seed frequencies [Hz] of the attractor searches (default: f_n0/m × (0.45, 0.7, 0.9, 1.1)
        and f_n0/(m + 1) × 0.9).
    """
    from contactvib.continuation.diagram import bifurcation_diagram

    m = check_int("order", order, 1, EVOLUTION_ORDER_MAX)
    pa_min = check_range("pa_min", pa_min, 0.0, False)
    pa_max = check_range("pa_max", pa_max, pa_min, False)
    n_levels = check_int("n_levels", n_levels, 2)
    settings = settings or ContinuationSettings(fmin_hz=30.0, fmax_hz=2000.0, max_points=600)
    log = log or (lambda msg: None)
    fn0 = model.f_n0
    if seed_fe is None:
        seed_fe = [fn0 / m * s for s in (0.45, 0.7, 0.9, 1.1)] + [0.9 * fn0 / (m + 1)]
        seed_fe = [f for f in seed_fe if settings.fmin_hz <= f <= settings.fmax_hz]
    levels = np.linspace(pa_min, pa_max, n_levels)
    points = []
    first = {}
    for p in levels:
        bs = bifurcation_diagram(model, pa_over_q=float(p), seed_fe=seed_fe, settings=settings, switch=False)
        found = [sp for b in bs if b.period == 1 for sp in b.special
                 if sp.type in _H and _minima(model, sp) == m]
        # de-duplicate (the same point on a branch reached from two seeds)
        uniq = []
        for sp in sorted(found, key=lambda s: s.fe_hz):
            if not any(u.type == sp.type and abs(u.fe_hz - sp.fe_hz) < 1e-6 * sp.fe_hz for u in uniq):
                uniq.append(sp)
        log(f"P_a = {p:.3g} Q: " + (", ".join(f"{s.type} {s.fe_hz:.5g} Hz" for s in uniq) or "none"))
        points.extend(uniq)
        for sp in uniq:
            first.setdefault(sp.type, [])
            if not first[sp.type] or first[sp.type][0].pa_over_q == sp.pa_over_q:
                first[sp.type].append(sp)
    curves = []
    for kind, sps in first.items():
        for sp in sps:
            if any(c.type == kind and _near_curve(c, sp) for c in curves):
                continue
            c = continue_codim1(model, kind, sp.fe_hz, sp.pa_over_q, sp.state, pa_range=(pa_min, pa_max),
                                f_range=(settings.fmin_hz, settings.fmax_hz), max_points=max_points)
            log(f"{kind} curve from {sp.fe_hz:.5g} Hz: {len(c.fe_hz)} points, stops: {c.stops}")
            curves.append(c)
    extremes = {}
    for kind, name in (("fold", "fold onset"), ("period-doubling", "period-doubling onset")):
        cs = [c for c in curves if c.type == kind and c.fe_hz.size > 1]
        if cs:
            c = min(cs, key=lambda c: np.nanmin(c.pa_over_q))
            i = int(np.nanargmin(c.pa_over_q))
            extremes[name] = (float(c.fe_hz[i]), float(c.pa_over_q[i]))
    return EvolutionResult(m, curves, points, extremes, levels)


def _near_curve(c: Curve, sp, rel=1e-2) -> bool:
    """True when the curve crosses the level P_a of ``sp`` within ``rel`` of its f_e."""
    d = c.pa_over_q - sp.pa_over_q
    for i in np.nonzero(d[:-1] * d[1:] <= 0)[0]:
        a = 0.0 if d[i] == d[i + 1] else d[i] / (d[i] - d[i + 1])
        f = c.fe_hz[i] + a * (c.fe_hz[i + 1] - c.fe_hz[i])
        if abs(f - sp.fe_hz) <= rel * sp.fe_hz:
            return True
    return False
