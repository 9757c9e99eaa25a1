"""Least-squares fit of the contact parameters to measurements (``contactvib fit``).

The objective is the sum over data sets k of Σ_i (r_ki / σ_k)², r_k the residuals of set k's
forward model (:mod:`.forward`) and σ_k its noise level: first a guess (2 % of the set's range;
3 % in ln A_pp), then, with more than one set, re-estimated from the set's residuals at the
optimum and the fit run again from there, so that each set weighs by its own noise.

The fit's coordinates are ln f_n0, m2, ln ζ, l (and a decay's initial state) in place of
S·c_n, m2, S·h_n, l: dynamic data fix f_n0 and ζ first and best, and in these coordinates the
exponents are nearly uncorrelated with them, where log S·c_n and m2 (log S·h_n and l) are
correlated to 0.9999 and the solver crawls along the valley. Bounds are boxes in m2, l, f_n0,
ζ. A fixed S·c_n (S·h_n) replaces ln f_n0 (ln ζ) by the fixed product.

Multi-start: candidates on a grid around the data's own estimates (f_n0 from the peak or the
zero crossings, ζ; integer exponents, so that they run on the Taylor flow) plus random ones
are all evaluated at once (numba threads), and the best few are refined by
:func:`scipy.optimize.least_squares` (trust-region reflective, ``x_scale='jac'``) with a
forward-difference Jacobian whose columns are again evaluated at once.

The covariance is s² (JᵀJ)⁻¹ at the optimum, J the Jacobian of the weighted residuals and
s² = Σ(r/σ)² / (n − p) the residual variance (Gauss–Newton; the standard errors of a linearised
model, exact as the noise goes to zero). Derived quantities (f_n0, y0, ζ) get theirs by the
delta method.

References
----------
Bates, D. M. & Watts, D. G., *Nonlinear Regression Analysis and Its Applications* (Wiley, 1988), Ch. 2.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from contactvib.errors import ComputationError
from contactvib.model import ContactModel, ParameterError

from .forward import CONTACT_NAMES, LOG_NAMES, UNITS, guess_contact, make_model, make_set
from .results import FitResult

#: Default bounds, by the name a user gives them (f_n0 [Hz] and zeta stand for S_c_n and S_h_n).
DEFAULT_BOUNDS = {"f_n0_hz": (1e-3, 1e9), "m2": (1.0, 5.0), "zeta": (1e-6, 100.0), "l": (0.0, 3.0),
                  "y_init_um": (-np.inf, np.inf), "v_init_mm_s": (-np.inf, np.inf)}
#: The fit's coordinate of each parameter, and the name its bounds are given by.
COORD = {"S_c_n": "ln_f_n0", "S_h_n": "ln_zeta"}
BOUND_NAME = {"ln_f_n0": "f_n0_hz", "ln_zeta": "zeta"}
NUISANCE = ("y_init_um", "v_init_mm_s")
#: A set whose best residual RMS exceeds this share of its data's RMS is not reached by the model.
UNREACHED = {"static": 0.3, "decay": 0.5, "frf": 0.4}
#: Cycles of a decay fitted in the successive stages (None: the whole record).
DECAY_WINDOWS = (4, 10, None)
#: Finite-difference step of the Jacobian in the fit's coordinates: a sweep's A_pp is accurate to
#: ~1e-8..1e-6 (settle and Newton tolerances, warm or cold starts), so 1e-5 made Jacobian columns
#: wrong by up to 150 %; 1e-3 keeps their error below 1 % and its own truncation error as small.
FD_STEP = 1e-3


def _coords_of(p: dict, base: ContactModel) -> dict:
    """The fit's coordinates of the physical parameters ``p``."""
    y0 = (base.Q / p["S_c_n"]) ** (1.0 / p["m2"])
    w = math.sqrt(p["m2"] * base.g / y0)
    zeta = p["S_h_n"] * y0 ** p["l"] / (2.0 * base.M * w)
    return {**p, "ln_f_n0": math.log(w / (2 * math.pi)), "ln_zeta": math.log(zeta)}


@dataclass
class _Problem:
    sets: list
    base: ContactModel
    free: list
    fixed: dict
    lo: np.ndarray
    hi: np.ndarray
    sigma: dict
    progress: object = None
    n_forward: int = 0

    def params(self, u) -> dict:
        """Physical parameters (S_c_n, m2, S_h_n, l, nuisances) of the coordinates ``u``."""
        c = dict(zip(self.free, (float(x) for x in u)))
        p = {**self.fixed, **{k: v for k, v in c.items() if k not in BOUND_NAME}}
        m2, base = p["m2"], self.base
        if "ln_f_n0" in c:
            w = 2.0 * math.pi * math.exp(min(c["ln_f_n0"], 700.0))
            y0 = m2 * base.g / (w * w)
            p["S_c_n"] = base.Q / y0**m2
        else:
            y0 = (base.Q / p["S_c_n"]) ** (1.0 / m2)
            w = math.sqrt(m2 * base.g / y0)
        if "ln_zeta" in c:
            p["S_h_n"] = 2.0 * math.exp(min(c["ln_zeta"], 700.0)) * base.M * w / y0 ** p["l"]
        return p

    def raw(self, U, warm: bool = False) -> list:
        """Unweighted residuals of every set for each row of ``U``: list of float64[K, n_k].
        ``warm``: sweeps start every step from the orbits of the last single-point evaluation."""
        plist = [self.params(u) for u in np.atleast_2d(U)]
        self.n_forward += len(plist)
        if self.progress is not None:
            self.progress.update(len(plist))
        return [s.residuals(plist, self.base, warm=s.last_states) if warm and s.kind == "frf"
                else s.residuals(plist, self.base) for s in self.sets]

    def weighted(self, U, warm: bool = False) -> np.ndarray:
        return np.hstack([r / self.sigma[s.kind] for r, s in zip(self.raw(U, warm), self.sets)])

    def fun(self, u) -> np.ndarray:
        """Weighted residuals at one point (kept for the Jacobian at the same point)."""
        r = self.weighted(np.asarray(u)[None, :])[0]
        self._last = (np.array(u, float), r)
        return r

    def jac(self, u) -> np.ndarray:
        """Forward differences, every column at once (and f(u) again unless just computed); a
        sweep's columns start every step from the orbit that f(u)'s sweep reached there (the
        same attractor, continued: the derivative along the branch, in a few periods a step)."""
        u = np.asarray(u, float)
        h = np.where(u + FD_STEP <= self.hi, FD_STEP, -FD_STEP)
        steps = [u + np.eye(len(u))[j] * h[j] for j in range(len(u))]
        last = getattr(self, "_last", None)
        if last is None or not np.array_equal(last[0], u):
            self.fun(u)
        r0, R = self._last[1], self.weighted(np.vstack(steps), warm=True)
        return ((R - r0) / h[:, None]).T


def _starts(prob: _Problem, seed: int, n_random: int) -> np.ndarray:
    """Candidate starts in the fit's coordinates: a grid around the data's estimates plus random."""
    kinds = {s.kind: s for s in prob.sets}
    base = prob.base
    g = {"S_c_n": 1e13, "m2": 2.0, "S_h_n": 1e5, "l": 1.0}
    if "static" in kinds:
        g.update(kinds["static"].log_log_guess())
    # integer exponents where a forward solve is dear (sweeps run on the Taylor flow then);
    # f_n0 and zeta matter most. A decay's phase wraps over its cycles: a fine grid in f_n0.
    m2s = [prob.fixed.get("m2", g["m2"] if "static" in kinds else 2.0)]
    ls = [prob.fixed.get("l", 1.0)]
    zetas = (0.008, 0.02, 0.05)
    f_guesses = []
    if "static" in kinds:  # the static curve fixes y0, hence f_n0 (y0 ω_n0² = m2 g)
        y0 = (base.Q / g["S_c_n"]) ** (1.0 / g["m2"])
        f_guesses = [math.sqrt(g["m2"] * base.g / y0) / (2 * math.pi)]
    elif "frf" in kinds:
        fp = kinds["frf"].peak_frequency()
        f_guesses = [fp * c for c in (1.05, 1.2, 1.4)]
    if "decay" in kinds and "frf" not in kinds:
        fd = f_guesses[0] if f_guesses else kinds["decay"].frequency_guess()
        f_guesses = [fd * c for c in (np.linspace(0.97, 1.03, 3) if "static" in kinds else np.linspace(0.85, 1.25, 17))]
        zetas = (0.004, 0.01, 0.02, 0.04, 0.08)
        if "m2" not in prob.fixed and "static" not in kinds:
            m2s = [1.5, 2.0, 2.5]
        if "l" not in prob.fixed:
            ls = [0.5, 1.0]
    grid = []
    if len(kinds) > 1 or "static" not in kinds:
        for f in f_guesses:
            for m2 in m2s:
                for zeta in zetas:
                    for l in ls:
                        grid.append(guess_contact(f, m2, zeta, l, base))
    else:
        grid.append(dict(g))
    rows = []
    for c in grid:
        p = {**g, **c}
        if "decay" in kinds:
            p.update(kinds["decay"].initial_guess({**prob.fixed, **p}, base))
        c = _coords_of({**p, **{k: v for k, v in prob.fixed.items() if k in CONTACT_NAMES}}, base)
        rows.append([c[n] for n in prob.free])
    U = np.clip(np.array(rows, float), prob.lo, prob.hi)
    if n_random > 0:
        rng = np.random.default_rng(seed)
        c = np.median(U, axis=0)
        span = np.array([{"ln_f_n0": 0.15, "ln_zeta": 0.7, "m2": 0.0, "l": 0.0}.get(n, 0.3 * abs(x) + 1e-3)
                         for n, x in zip(prob.free, c)])
        R = c + rng.uniform(-1, 1, (n_random, len(c))) * span
        U = np.vstack([U, np.clip(R, prob.lo, prob.hi)])
    return U


def _covariance(J: np.ndarray, cost: float, n: int) -> np.ndarray:
    p = J.shape[1]
    s2 = 2.0 * cost / max(n - p, 1)
    return s2 * np.linalg.pinv(J.T @ J, rcond=1e-12)


def _physical(prob: _Problem, u: np.ndarray, cov: np.ndarray) -> dict:
    """The fitted physical parameters with standard errors (delta method from the coordinates)."""
    names = [n for n in CONTACT_NAMES if COORD.get(n, n) in prob.free] + [n for n in prob.free if n in UNITS
                                                                          and n not in CONTACT_NAMES]

    def values(uu):
        p = prob.params(uu)
        return np.array([math.log(p[n]) if n in LOG_NAMES else p[n] for n in names])
    v0 = values(u)
    G = np.empty((len(names), len(u)))
    for j in range(len(u)):
        e = np.zeros(len(u))
        e[j] = 1e-7 * max(1.0, abs(u[j]))
        G[:, j] = (values(u + e) - v0) / e[j]
    se = np.sqrt(np.maximum(np.diag(G @ cov @ G.T), 0.0))
    out = {}
    for n, v, s in zip(names, v0, se):
        val = math.exp(v) if n in LOG_NAMES else float(v)
        out[n] = {"value": val, "stderr": val * s if n in LOG_NAMES else float(s), "unit": UNITS[n]}
    return out


def _derived(prob: _Problem, u: np.ndarray, cov: np.ndarray) -> dict:
    def values(uu):
        m = make_model(prob.params(uu), prob.base)
        return np.array([m.f_n0, m.y0 * 1e6, m.zeta])
    v0 = values(u)
    G = np.empty((3, len(u)))
    for j in range(len(u)):
        e = np.zeros(len(u))
        e[j] = 1e-7 * max(1.0, abs(u[j]))
        G[:, j] = (values(u + e) - v0) / e[j]
    se = np.sqrt(np.maximum(np.diag(G @ cov @ G.T), 0.0))
    names = ("f_n0_hz", "y0_um", "zeta") if any(s.kind != "static" for s in prob.sets) else ("f_n0_hz", "y0_um")
    return {name: {"value": float(v), "stderr": float(s), "unit": unit}
            for name, v, s, unit in zip(names, v0, se, ("Hz", "um", "1"))}


def _identifiability(prob: _Problem, values: dict, corr: np.ndarray, u: np.ndarray) -> list:
    kinds = [s.kind for s in prob.sets]
    out = []
    for n, x, lo, hi in zip(prob.free, u, prob.lo, prob.hi):
        if min(abs(x - lo), abs(x - hi)) < 1e-6 * max(1.0, abs(x)):
            name = BOUND_NAME.get(n, n)
            out.append(f"{name} ended on its bound ({math.exp(x) if n in BOUND_NAME else x:.6g}): the data pull "
                       "beyond it, and its standard error describes the bounded fit only; widen --bounds.")
    if any(k != "static" for k in kinds):
        out.append(f"Only the products S_c_n = S c_n and S_h_n = S h_n are identifiable from dynamic data "
                   f"(S = {prob.base.S:g} m^2 is taken as given: c_n = S_c_n/S, h_n = S_h_n/S).")
    for n in ("m2", "l"):
        if n in values and values[n]["stderr"] > 0.25:
            out.append(f"{n} is poorly determined by these data (stderr {values[n]['stderr']:.2g}): only "
                       "amplitude-dependent data fix m2 and l (a single small-amplitude test determines only f_n0 "
                       "and zeta); add larger amplitudes, another force level or a static curve, or fix it.")
    for i, a in enumerate(prob.free):
        for j in range(i):
            if abs(corr[i, j]) > 0.995 and {a, prob.free[j]}.isdisjoint(NUISANCE):
                out.append(f"{prob.free[j]} and {a} are strongly correlated (rho = {corr[i, j]:.4f}): the data fix "
                           "a combination of them better than each.")
    return out


def _refine(prob: _Problem, u0: np.ndarray, max_nfev: int):
    from scipy.optimize import least_squares

    return least_squares(prob.fun, u0, jac=prob.jac, bounds=(prob.lo, prob.hi),
                         x_scale="jac", method="trf", max_nfev=max_nfev, xtol=1e-8, ftol=1e-8, gtol=1e-8)


def _setup(data_sets, model, fix, bounds):
    sets = [make_set(d) for d in data_sets]
    base = model if model is not None else ContactModel()
    fix = {k: float(v) for k, v in (fix or {}).items()}
    for k in fix:
        if k not in CONTACT_NAMES + ("y_init_um", "v_init_mm_s"):
            raise ParameterError(k, fix[k], f"unknown fit parameter; known: {', '.join(CONTACT_NAMES)}")
    used = [n for n in CONTACT_NAMES if any(n in s.uses for s in sets)]
    fixed = {n: fix.get(n, {"S_c_n": base.S * base.c_n, "m2": base.m2, "S_h_n": base.S * base.h_n,
                            "l": base.l}[n]) for n in CONTACT_NAMES if n not in used or n in fix}
    free = [COORD.get(n, n) for n in used if n not in fix] + [n for s in sets for n in s.nuisance if n not in fix]
    fixed.update({n: v for n, v in fix.items() if n not in CONTACT_NAMES})
    b = dict(DEFAULT_BOUNDS)
    for n, (lo, hi) in (bounds or {}).items():
        if n not in b:
            raise ParameterError(n, f"{lo}:{hi}", f"no bounds for this name; bounds are given for {', '.join(b)}")
        lo, hi = float(lo), float(hi)
        if not lo < hi or (n in ("f_n0_hz", "zeta") and lo <= 0):
            raise ParameterError(n, f"{lo:g}:{hi:g}", "bounds must be lower < upper"
                                 + (" with lower > 0" if n in ("f_n0_hz", "zeta") else ""))
        b[n] = (lo, hi)
    lo = np.array([math.log(b[BOUND_NAME[n]][0]) if n in BOUND_NAME else b[n][0] for n in free])
    hi = np.array([math.log(b[BOUND_NAME[n]][1]) if n in BOUND_NAME else b[n][1] for n in free])
    n_total = sum(s.n for s in sets)
    if n_total <= len(free):
        raise ParameterError("data", n_total, f"points: fewer than the {len(free) + 1} needed to fit "
                                              f"{len(free)} parameters ({', '.join(free)}) with an error estimate")
    sigma = {s.kind: s.noise_guess() for s in sets}
    return _Problem(sets, base, free, fixed, lo, hi, sigma)


def fit(*, static=None, decay=None, frf=None, model: ContactModel | None = None, fix: dict | None = None,
        bounds: dict | None = None, n_starts: int = 8, n_refine: int | None = None, seed: int = 0,
        max_nfev: int = 60, progress: bool = False) -> FitResult:
    """Fit the contact parameters to one or more measurements by least squares.

    Parameters
    ----------
    static, decay, frf : path or data object, optional
        A static load–deflection curve, a free decay, stepped-sine sweeps (files as in
        ``contactvib.fitting.data``, or :class:`~contactvib.fitting.StaticData`,
        :class:`~contactvib.fitting.DecayData`, :class:`~contactvib.fitting.FrfData`).
    model : ContactModel, optional
        Gives M, g, S (and the values of parameters the data do not determine); the paper's by default.
    fix : dict, optional
        Parameters held at a known value (``S_c_n``, ``m2``, ``S_h_n``, ``l``).
    bounds : dict, optional
        name -> (lower, upper) in the physical parameter (defaults ``DEFAULT_BOUNDS``).
    n_starts : int
        Random candidate starts added to the grid of estimated ones.
    n_refine : int, optional
        Best candidates refined by least squares (default: 1 with a sweep, whose forward solve is
        dear; 4 for a decay alone, whose cost has many minima; 2 otherwise).
    max_nfev : int
        Iterations allowed to each least-squares run.
    progress : bool
        Show a tqdm bar of the forward solves on stderr.

    Returns
    -------
    FitResult

    Raises
    ------
    ParameterError
        Bad data or options; a data set that no parameter set inside the bounds reaches.
    ComputationError
        The solver did not converge (``stage`` "fit"; its ``result`` is the best point found).
    """
    from tqdm import tqdm

    from .data import load

    t0 = time.perf_counter()
    given = [(k, v) for k, v in (("static", static), ("decay", decay), ("frf", frf)) if v is not None]
    if not given:
        raise ParameterError("data", "none", "give at least one of static, decay, frf")
    data = [load(k, v) if isinstance(v, (str, bytes)) or hasattr(v, "__fspath__") else v for k, v in given]
    prob = _setup(data, model, fix, bounds)
    decays = [s for s in prob.sets if s.kind == "decay"]
    with tqdm(unit="solve", desc="fit", disable=not progress, leave=False) as bar:
        prob.progress = bar
        U = _starts(prob, seed, n_starts)
        found = []
        for stage, cycles in enumerate(DECAY_WINDOWS if decays else [None]):
            for s in decays:  # a decay's phase wraps over its cycles: fit the first few first
                s.window_ms = None if cycles is None else cycles * 1e3 / s.frequency_guess()
            if stage == 0:
                costs = [0.5 * float(np.sum(r**2)) for r in np.atleast_2d(prob.weighted(U))]
                # a decay is cheap: refine more candidates (its cost surface has many minima)
                if n_refine is None:  # a sweep's solve is dear; a decay's cost surface has many minima
                    n_refine = 1 if any(s.kind == "frf" for s in prob.sets) else (4 if decays else 2)
                n = max(1, n_refine)
                found = [_refine(prob, U[i], max_nfev) for i in np.argsort(costs)[:n]]
            else:
                found = [_refine(prob, res.x, max_nfev) for res in sorted(found, key=lambda r: r.cost)[:2]]
        best = min(found, key=lambda r: r.cost)
        if len(prob.sets) > 1:  # each set weighed by its own noise level, then refit
            raw = prob.raw(best.x)
            for s, r in zip(prob.sets, raw):
                prob.sigma[s.kind] = float(np.sqrt(np.mean(r[0] ** 2))) or prob.sigma[s.kind]
            best = _refine(prob, best.x, max_nfev)
        J = prob.jac(best.x)
    return _result(prob, best, J, t0, len(U))


def _result(prob: _Problem, best, J, t0: float, n_starts: int) -> FitResult:
    u = best.x
    n = sum(s.n for s in prob.sets)
    cov = _covariance(J, best.cost, n)
    se_u = np.sqrt(np.maximum(np.diag(cov), 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se_u, se_u)
    p = prob.params(u)
    values = _physical(prob, u, cov)
    raw = prob.raw(u[None, :])
    rms = {s.kind: float(np.sqrt(np.mean(r[0] ** 2))) for s, r in zip(prob.sets, raw)}
    fitted = make_model(p, prob.base)
    result = FitResult(
        parameters=values, fixed={k: v for k, v in prob.fixed.items()}, derived=_derived(prob, u, cov),
        names=[n.replace("_", " ", 1) if n in BOUND_NAME else n for n in prob.free], correlation=corr,
        residual_rms=rms, noise=dict(prob.sigma), n_forward=prob.n_forward, time_s=time.perf_counter() - t0,
        converged=bool(best.status > 0), message=str(best.message),
        identifiability=_identifiability(prob, values, corr, u),
        model=fitted, n_starts=n_starts, cost=float(best.cost), sets=prob.sets, values=p)
    for s in prob.sets:
        scale = float(np.sqrt(np.mean(np.log(s.data.app_um) ** 2))) if s.kind == "frf" else float(
            np.sqrt(np.mean((s.data.deflection_um if s.kind == "static" else s.data.values) ** 2)))
        far = rms[s.kind] / scale if s.kind != "frf" else rms[s.kind]
        if far > UNREACHED[s.kind]:
            raise ParameterError(s.kind, s.data.source,
                                 f"no parameter set inside the bounds reaches these data: the best fit stays "
                                 f"{100 * far:.0f} % (RMS{' of ln A_pp' if s.kind == 'frf' else ''}) away from them")
    if not result.converged:
        raise ComputationError(f"the fit did not converge ({best.message}); best point: "
                               + ", ".join(f"{k} = {v['value']:.6g}" for k, v in values.items()),
                               stage="fit", result=result)
    return result
