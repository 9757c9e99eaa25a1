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
from contactvib._kernels.flow import STATUS_OK
from contactvib._kernels.shooting import strobe_map
from contactvib.model import ContactModel, ParameterError, check_range
from contactvib.continuation.bifurcations import fold_test, pd_test
from contactvib.continuation.shooting import ContinuationSettings

__all__ = ["evolution", "EvolutionResult", "Curve", "continue_codim1"]

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


class _Codim1:
    def __init__(self, par0, kind, rtol):
        self.par = par0.copy()
        self.kind = kind
        self.h = _H[kind]
        self.rtol = rtol

    def F_J(self, U):
        par = self.par
        par[4], par[3] = U[2], U[3]
        G = np.empty(2)
        J = np.empty((2, 3))
        M = np.empty((2, 2))
        st = residual_jacobian(U[:3].copy(), 1, par, 4, self.rtol, G, J, M)
        if st != STATUS_OK:
            return None
        # ∂G/∂p by central differences
        hp = 1e-5 * max(abs(U[3]), 1e-3)
        outs = []
        for sgn in (1, -1):
            par[3] = U[3] + sgn * hp
            o = np.empty(2)
            if strobe_map(U[:2].copy(), 1, par, self.rtol, self.rtol, o, np.empty((0, 0))) != STATUS_OK:
                return None
            outs.append(o)
        par[3] = U[3]
        Gp = (outs[0] - outs[1]) / (2 * hp)
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
        par[4], par[3] = U[2], U[3]
        Fv = np.array([G[0], G[1], self.h(M)])
        Jf = np.zeros((3, 4))
        Jf[:2, :3] = J
        Jf[:2, 3] = Gp
        Jf[2] = dh
        return Fv, Jf, M

    def correct(self, Upred, U0, tau, w, ds, max_iter=10, tol=1e-10):
        U = Upred.copy()
        for _ in range(max_iter):
            out = self.F_J(U)
            if out is None:
                return None
            Fv, Jf, M = out
            cons = float(np.dot(tau, w * (U - U0)) - ds)
            sc = max(1.0, abs(U[0]), abs(U[1]))
            if max(abs(Fv[0]), abs(Fv[1])) / sc <= tol and abs(Fv[2]) <= 1e-9 and abs(cons) < 1e-9:
                return U, Jf, M
            A = np.vstack([Jf, tau * w])
            try:
                d = np.linalg.solve(A, -np.concatenate([Fv, [cons]]))
            except np.linalg.LinAlgError:
                return None
            if not np.all(np.isfinite(d)) or np.max(np.abs(d * w)) > 0.5:
                return None
            U = U + d
            if U[2] <= 0 or U[3] < 0:
                return None
        return None


def _null(Jf, w):
    Js = Jf / w[None, :]
    _u, _s, vt = np.linalg.svd(Js)
    return vt[-1]


def continue_codim1(model: ContactModel, kind: str, fe_hz: float, pa_over_q: float, state,
                    pa_min: float, pa_max: float, fmin: float = 30.0, fmax: float = 2000.0,
                    ds0: float = 0.02, ds_max: float = 0.1, max_points: int = 300,
                    rtol: float = 1e-11) -> Curve:
    """Follow a fold or period-doubling point of a period-1 branch in the (f_e, P_a) plane.

    Both directions from the point; stops at the P_a and f_e bounds, after ``max_points`` per
    direction, or when the step falls below 1e-6 (Newton failure).
    """
    if kind not in _H:
        raise ParameterError("kind", kind, "must be 'fold' or 'period-doubling'")
    par0 = model.excitation(pa_over_q, fe_hz).kernel_parameters()
    eng = _Codim1(par0, kind, rtol)
    fn0 = model.f_n0
    U0 = np.array([state[0], state[1], fe_hz / fn0, pa_over_q])
    w = _w(U0)
    # converge the point on the hyperplane P_a = const
    out = eng.correct(U0, U0, np.array([0, 0, 0, 1.0]), w, 0.0)
    if out is None:
        return Curve(kind, np.array([fe_hz]), np.array([pa_over_q]), np.array([np.nan]),
                     ["the point did not converge"])
    U0, J0, _M = out
    halves = []
    stops = []
    for sgn in (1.0, -1.0):
        U, J = U0.copy(), J0
        tprev = None
        pts = [U.copy()]
        ds = ds0
        reason = "maximum number of points reached"
        while len(pts) < max_points:
            w = _w(U)
            t = _null(J, w)
            if tprev is None:
                t = t * (sgn if t[3] >= 0 else -sgn)
            elif np.dot(t, tprev * w) < 0:
                t = -t
            res = eng.correct(U + ds * t / w, U, t, w, ds)
            if res is None:
                ds *= 0.5
                if ds < 1e-6:
                    reason = "step too small: Newton failure"
                    break
                continue
            U, J, _M = res
            tprev = t / w
            tprev = tprev / np.linalg.norm(tprev * _w(U))
            pts.append(U.copy())
            if not (pa_min <= U[3] <= pa_max):
                reason = "P_a range reached"
                break
            if not (fmin <= U[2] * fn0 <= fmax):
                reason = "f_e range reached"
                break
            ds = min(ds * 1.5, ds_max)
        halves.append(pts)
        stops.append(reason)
    pts = halves[1][::-1] + halves[0][1:]
    P = np.array(pts)
    app = []
    y_um = model.y0 * 1e6
    for U in P:
        par = par0.copy()
        par[4], par[3] = U[2], U[3]
        xmin, xmax, _f, _n, st = orbit_range(U[:2].copy(), 1, par, rtol)
        app.append((xmax - xmin) * y_um if st == STATUS_OK else math.nan)
    return Curve(kind, P[:, 2] * fn0, P[:, 3], np.array(app), stops)


def _minima(model, sp):
    exc = model.excitation(sp.pa_over_q, sp.fe_hz)
    return orbit_range(np.asarray(sp.state, float), 1, exc.kernel_parameters(), 1e-11)[3]


def evolution(model: ContactModel, order: int, pa_min: float = 0.3, pa_max: float = 0.9,
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

    m = int(check_range("order", order, 1, True))
    if m != order or m > 8:
        raise ParameterError("order", order, "must be an integer in 1..8")
    pa_min = check_range("pa_min", pa_min, 0.0, False)
    pa_max = check_range("pa_max", pa_max, pa_min, False)
    n_levels = int(check_range("n_levels", n_levels, 2, True))
    settings = settings or ContinuationSettings(fmin=30.0, fmax=2000.0, max_points=600)
    log = log or (lambda msg: None)
    fn0 = model.f_n0
    if seed_fe is None:
        seed_fe = [fn0 / m * s for s in (0.45, 0.7, 0.9, 1.1)] + [0.9 * fn0 / (m + 1)]
        seed_fe = [f for f in seed_fe if settings.fmin <= f <= settings.fmax]
    levels = np.linspace(pa_min, pa_max, n_levels)
    points = []
    first = {}
    for p in levels:
        bs = bifurcation_diagram(model, float(p), seed_fe, settings, switch=False)
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
            c = continue_codim1(model, kind, sp.fe_hz, sp.pa_over_q, sp.state, pa_min, pa_max,
                                settings.fmin, settings.fmax, max_points=max_points)
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
