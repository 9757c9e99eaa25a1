"""Pseudo-arclength continuation of period-k orbits in f_e (or P_a), with stability and events.

A period-k orbit is a zero of ``G(z; q) = P^k(z; q) − z`` (stroboscopic map at phase 0, shooting
with the monodromy from the variational equations integrated through contact loss and
re-contact, :mod:`contactvib._kernels.continuation`). The branch through a seed is followed by
an Euler predictor along the tangent and a Newton corrector on the pseudo-arclength hyperplane,
in scaled unknowns (relative change of the state and of the parameter), with an adaptive step:
grown after easy corrections, halved after a failed one or a tangent turning by more than
``max_turn``. Every accepted point gets its Floquet multipliers (stability), its extrema over the
orbit (A_pp, y_min, y_max, from the dense output) and the test functions of
:mod:`.bifurcations`; sign changes are located on the branch.

A continuation never stops silently: each direction ends with a :class:`~.branch.Stop` that says
where and why (parameter bound reached, amplitude bound, step too small after Newton failures,
maximum number of points, merging onto the period-k/2 branch).

At a period doubling the branch of period 2k is entered (branch switching) along the
eigenvector ``e`` of the multiplier −1: the period-doubled branch leaves the period-2k
pitchfork tangent to ``(e, 0)``.

References
----------
E. J. Doedel, H. B. Keller, J. P. Kernévez, Numerical analysis and control of bifurcation
problems (I), *Int. J. Bifurcation and Chaos* 1 (1991) 493–520.
R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer (2010), Ch. 4, 7.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from contactvib._kernels.continuation import correct, orbit_range, tangent
from contactvib._kernels.flow import STATUS_OK
from contactvib._kernels.shooting import strobe_map
from contactvib.model import ContactModel, Excitation, ParameterError, check_range
from contactvib.continuation.bifurcations import fold_test, locate_zero, ns_test, pd_test
from contactvib.continuation.branch import Branch, SpecialPoint, Stop

__all__ = ["ContinuationSettings", "continue_orbit", "switch_period_doubling", "ContinuationError"]

_IP = {"f_e": 4, "P_a": 3}
_STATUS_TEXT = {1: "integrator step limit", 2: "integrator step too small", 5: "non-finite state",
                20: "singular Jacobian", 21: "Newton diverged", 22: "Newton did not converge"}


class ContinuationError(RuntimeError):
    """The seed orbit could not be refined (Newton shooting failed)."""


@dataclass(frozen=True)
class ContinuationSettings:
    """Knobs of a continuation run.

    Parameters
    ----------
    fmin, fmax : float
        Range of f_e [Hz] (stop when reached).
    pa_min, pa_max : float
        Range of P_a [Q] (stop when reached; for continuation in P_a).
    ds0, ds_min, ds_max : float
        Initial, smallest and largest pseudo-arclength step [relative units: 0.05 ≈ 5 %].
    max_points : int
        Points per direction.
    app_max_um : float
        Amplitude bound [µm]; the branch stops when A_pp exceeds it.
    rtol : float
        Integrator tolerance (rtol = atol) of the shooting.
    tol : float
        Newton closure ``|P^k(z) − z|∞ / max(1, |z|∞)``.
    max_iter : int
        Newton iterations per correction.
    max_turn : float
        Largest angle [rad] between successive tangents (scaled) before the step is halved.
    locate_tol : float
        Pseudo-arclength tolerance of the location of special points.
    max_failures : int
        Rejected steps per direction before the branch stops (a branch that keeps failing, e.g.
        a high-period orbit inside a chaotic band, would otherwise crawl on with tiny steps).
    """

    fmin: float = 30.0
    fmax: float = 2000.0
    pa_min: float = 0.0
    pa_max: float = 2.0
    ds0: float = 0.02
    ds_min: float = 1e-7
    ds_max: float = 0.15
    max_points: int = 2000
    app_max_um: float = 2000.0
    rtol: float = 1e-12
    tol: float = 1e-10
    max_iter: int = 8
    max_turn: float = 0.35
    locate_tol: float = 1e-11
    max_failures: int = 200

    def __post_init__(self):
        check_range("fmin", self.fmin, 0.0, False, "Hz")
        check_range("fmax", self.fmax, self.fmin, False, "Hz")
        check_range("pa_min", self.pa_min, 0.0, True)
        check_range("pa_max", self.pa_max, self.pa_min, False)
        check_range("ds_min", self.ds_min, 0.0, False)
        check_range("ds0", self.ds0, self.ds_min, True)
        check_range("ds_max", self.ds_max, self.ds0, True)
        check_range("max_points", self.max_points, 1, True)
        check_range("app_max_um", self.app_max_um, 0.0, False, "µm")
        check_range("rtol", self.rtol, 1e-15, True)
        if self.rtol > 1e-6:
            raise ParameterError("rtol", self.rtol, "must be <= 1e-6")
        check_range("tol", self.tol, 0.0, False)
        check_range("max_iter", self.max_iter, 1, True)
        check_range("max_turn", self.max_turn, 0.0, False, "rad")
        check_range("locate_tol", self.locate_tol, 0.0, False)
        check_range("max_failures", self.max_failures, 1, True)


#: Stop reason of a branch that closed on itself (an isola, or a loop through both directions).
ISOLA_STOP = "closed branch (isola): back at its first point"


def _weights(u: np.ndarray) -> np.ndarray:
    s = max(1.0, abs(u[0]), abs(u[1]))
    return np.array([1.0 / s, 1.0 / s, 1.0 / max(abs(u[2]), 1e-3)])


def _passes_zero(d_prev: np.ndarray, d: np.ndarray, z: np.ndarray) -> bool:
    """P^(k/2)(z) − z reverses (angle > 150°) while small: the branch went through zero."""
    na, nb = np.linalg.norm(d_prev), np.linalg.norm(d)
    if na == 0.0 or nb == 0.0:
        return True
    small = min(na, nb) <= 0.2 * max(1.0, float(np.max(np.abs(z))))
    return bool(small and float(np.dot(d_prev, d)) < -0.866 * na * nb)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


class _Engine:
    """One branch, one direction at a time (internal)."""

    def __init__(self, model: ContactModel, excitation: Excitation, k: int, parameter: str,
                 settings: ContinuationSettings, branch_id: str):
        self.model = model
        self.k = int(k)
        self.parameter = parameter
        self.ip = _IP[parameter]
        self.s = settings
        self.branch_id = branch_id
        self.par = excitation.kernel_parameters().copy()
        self.y_um = model.y0 * 1e6
        self.fn0 = model.f_n0
        if parameter == "f_e":
            self.qmin, self.qmax = settings.fmin / self.fn0, settings.fmax / self.fn0
        else:
            self.qmin, self.qmax = settings.pa_min, settings.pa_max
        self.J = np.empty((2, 3))
        self.M = np.empty((2, 2))

    # ------------------------------------------------------------------ helpers
    def fe_pa(self, u):
        par = self.par.copy()
        par[self.ip] = u[2]
        return par[4] * self.fn0, par[3]

    def correct(self, u_pred, u_prev, tau, w, ds):
        out_u = np.empty(3)
        J = np.empty((2, 3))
        M = np.empty((2, 2))
        st, its = correct(u_pred, u_prev, tau, w, ds, self.k, self.par, self.ip, self.s.rtol,
                          self.s.tol, self.s.max_iter, out_u, J, M)
        return st, its, out_u, J, M

    def fix_q(self, u_guess):
        """Natural-parameter Newton at q = u_guess[2]."""
        w = _weights(u_guess)
        tau = np.array([0.0, 0.0, 1.0])
        return self.correct(u_guess.copy(), u_guess.copy(), tau, w, 0.0)

    def measure(self, u, J, M):
        """Point record: multipliers, extrema, test functions."""
        par = self.par.copy()
        par[self.ip] = u[2]
        xmin, xmax, flight, n_min, st = orbit_range(u[:2].copy(), self.k, par, self.s.rtol)
        mu = np.linalg.eigvals(M)
        fe, pa = self.fe_pa(u)
        return {"u": u.copy(), "J": J.copy(), "M": M.copy(), "mu": mu, "xmin": xmin, "xmax": xmax,
                "flight": flight, "n_min": n_min, "fe": fe, "pa": pa,
                "fold": fold_test(M), "period-doubling": pd_test(M), "neimark-sacker": ns_test(M),
                "grazing": xmin, "ok": st == STATUS_OK}

    def sub_distance(self, u):
        """P^(k/2)(z) − z for even k (None otherwise): flips sign when a period-k branch
        passes through the period-doubling point of the period-k/2 branch."""
        if self.k % 2:
            return None
        par = self.par.copy()
        par[self.ip] = u[2]
        out = np.empty(2)
        st = strobe_map(u[:2].copy(), self.k // 2, par, self.s.rtol, self.s.rtol, out, np.empty((0, 0)))
        if st != STATUS_OK:
            return None
        return out - u[:2]

    def special(self, kind, pt, value, bracket):
        return SpecialPoint(type=kind, fe_hz=pt["fe"], pa_over_q=pt["pa"],
                            app_um=(pt["xmax"] - pt["xmin"]) * self.y_um, period=self.k,
                            branch=self.branch_id, multipliers=pt["mu"], state=pt["u"][:2].copy(),
                            test_value=float(value), bracket=bracket)

    def locate(self, kind, a, b, tau_a, w_a, ds):
        """Locate the zero of test ``kind`` between accepted points a (σ = 0) and b (σ = ds)."""
        fa, fb = a[kind], b[kind]

        def f(sig):
            st, _its, u, J, M = self.correct(a["u"] + sig * tau_a / w_a, a["u"], tau_a, w_a, sig)
            if st != STATUS_OK:
                return None
            pt = self.measure(u, J, M)
            val = pt[kind]
            if not math.isfinite(val):
                return None
            return val, pt

        found = locate_zero(f, 0.0, ds, fa, fb, self.s.locate_tol)
        if found is None:
            return None
        _s, val, pt = found
        return self.special(kind, pt, val, (a["fe"], b["fe"]))

    # ------------------------------------------------------------------ one direction
    def run(self, u0, J0, M0, t_dir, first_ds=None, merge_check=False):
        """Continue from the converged point ``u0`` along the unscaled direction ``t_dir``.

        Returns (points, specials, stop).
        """
        s = self.s
        p0 = self.measure(u0, J0, M0)
        points = [p0]
        specials = []
        w = _weights(u0)
        tau = np.empty(3)
        if tangent(J0, w, tau) == 0.0 or first_ds is not None:
            tau = _unit(t_dir * w)
        elif np.dot(tau, t_dir * w) < 0:
            tau = -tau
        t_u = tau / w  # unscaled direction, re-normalised in the scaled metric at each step
        t_start = t_u.copy()
        p0["tq"] = float(t_u[2])
        ds = first_ds if first_ds is not None else s.ds0
        prev_d = None
        merge_state = None
        stop = None
        n_fail = 0
        while stop is None:
            a = points[-1]
            if len(points) >= s.max_points:
                stop = "maximum number of points reached"
                break
            w = _weights(a["u"])
            tau = _unit(t_u * w)
            st, its, u, J, M = self.correct(a["u"] + ds * tau / w, a["u"], tau, w, ds)
            tau_new = np.empty(3)
            ok = st == STATUS_OK and tangent(J, w, tau_new) > 0.0
            if ok:
                if np.dot(tau_new, tau) < 0:
                    tau_new = -tau_new
                turn = math.acos(min(1.0, float(np.dot(tau_new, tau))))
                if turn > s.max_turn and ds > s.ds_min * 2:
                    ok = False
                    st = -1
            if not ok:
                n_fail += 1
                ds *= 0.5
                if n_fail > s.max_failures:
                    stop = f"step too small: {n_fail} rejected steps (Newton or tangent failures)"
                    break
                if ds < s.ds_min:
                    why = _STATUS_TEXT.get(st, "tangent turned too fast" if st == -1 else f"status {st}")
                    stop = f"step too small: Newton failure ({why})"
                continue
            b = self.measure(u, J, M)
            if not b["ok"]:
                ds *= 0.5
                if ds < s.ds_min:
                    stop = "step too small: orbit record failed"
                continue
            if merge_check:
                d = self.sub_distance(u)
                if d is not None and prev_d is not None and _passes_zero(prev_d, d, u[:2]):
                    stop = (f"merges with the period-{self.k // 2} branch "
                            f"(period doubling near f_e = {b['fe']:.6g} Hz)")
                    # the period-k/2 orbit there, for seeding that branch
                    za = a["u"][:2]
                    merge_state = 0.5 * (za + za + prev_d)
                    break
                prev_d = d
            # --- special points between a and b
            new = []
            b["tq"] = float(np.dot(tau_new / w, [0.0, 0.0, 1.0]))
            if a["tq"] * b["tq"] < 0 and a["fold"] * b["fold"] < 0:
                new.append("fold")
            for kind in ("period-doubling", "neimark-sacker", "grazing"):
                fa, fb = a[kind], b[kind]
                if math.isfinite(fa) and math.isfinite(fb) and fa * fb < 0:
                    new.append(kind)
            for kind in new:
                sp = self.locate(kind, a, b, tau, w, ds)
                if sp is not None:
                    specials.append((len(points) - 1, sp))
            # --- bounds
            q = u[2]
            if q < self.qmin or q > self.qmax:
                bound = self.qmin if q < self.qmin else self.qmax
                frac = (bound - a["u"][2]) / (q - a["u"][2])
                guess = a["u"] + frac * (u - a["u"])
                guess[2] = bound
                st2, _i, u2, J2, M2 = self.fix_q(guess)
                specials = [(i, sp) for i, sp in specials if self._inside(sp)]
                if st2 == STATUS_OK:
                    c = self.measure(u2, J2, M2)
                    c["tq"] = b["tq"]
                    points.append(c)
                name = "f_e" if self.parameter == "f_e" else "P_a"
                stop = f"{name} range reached ({'lower' if bound == self.qmin else 'upper'} bound)"
                break
            points.append(b)
            # --- a closed branch (isola) comes back to its first point: stop after one loop
            #     (close to it, and passing it in the direction the branch left it)
            if len(points) > 8:
                wb = _weights(u)
                d0 = float(np.linalg.norm((u - points[0]["u"]) * wb))
                same_way = float(np.dot(_unit(tau_new / w * wb), _unit(t_start * wb))) > 0.9
                if (d0 < 1.5 * ds and same_way
                        and float(np.linalg.norm((a["u"] - points[0]["u"]) * wb)) >= d0):
                    stop = ISOLA_STOP
                    break
            app = (b["xmax"] - b["xmin"]) * self.y_um
            if app > s.app_max_um:
                stop = f"amplitude bound reached (A_pp = {app:.4g} um > {s.app_max_um:g} um)"
                break
            t_u = tau_new / w
            if its <= 2:
                ds = min(ds * 2.0, s.ds_max)
            elif its <= 3:
                ds = min(ds * 1.5, s.ds_max)
            elif its <= 5:  # keep growing slowly: a step cut far down must not stay there
                ds = min(ds * 1.2, s.ds_max)
            else:
                ds = max(ds / 1.5, s.ds_min)
        last = points[-1]
        return points, [sp for _i, sp in specials], Stop(last["fe"], last["pa"], stop, self.branch_id,
                                                          merge_state)

    def _inside(self, sp):
        q = sp.fe_hz / self.fn0 if self.parameter == "f_e" else sp.pa_over_q
        return self.qmin <= q <= self.qmax

    # ------------------------------------------------------------------ assemble
    def branch(self, points, specials, stops, parent=None, settings=None) -> Branch:
        n = len(points)
        u = np.array([p["u"] for p in points]).reshape(n, 3)
        xmin = np.array([p["xmin"] for p in points])
        xmax = np.array([p["xmax"] for p in points])
        mu = np.array([p["mu"] for p in points], complex).reshape(n, 2)
        w = [_weights(p["u"]) for p in points]
        arc = np.zeros(n)
        for i in range(1, n):
            arc[i] = arc[i - 1] + float(np.linalg.norm((u[i] - u[i - 1]) * w[i - 1]))
        specials = sorted(specials, key=lambda sp: sp.fe_hz)
        return Branch(
            branch=self.branch_id, period=self.k, parameter=self.parameter,
            fe_hz=np.array([p["fe"] for p in points]), pa_over_q=np.array([p["pa"] for p in points]),
            app_um=(xmax - xmin) * self.y_um, ymin_um=xmin * self.y_um, ymax_um=xmax * self.y_um,
            multipliers=mu, stable=np.max(np.abs(mu), axis=1) < 1.0, state=u[:, :2].copy(),
            contact_loss_fraction=np.array([p["flight"] for p in points]),
            minima=np.array([p["n_min"] for p in points], int), arclength=arc,
            special=specials, stops=stops, parent=parent, fn0_hz=self.fn0, y0_um=self.y_um,
            settings=settings or {})


def _check_common(excitation, state, period, parameter, direction):
    if parameter not in _IP:
        raise ParameterError("parameter", parameter, "must be 'f_e' or 'P_a'")
    k = int(check_range("period", period, 1, True))
    if k != period:
        raise ParameterError("period", period, "must be an integer >= 1")
    if k > 64:
        raise ParameterError("period", period, "must be <= 64")
    if direction not in ("both", "down", "up", -1, 1):
        raise ParameterError("direction", direction, "must be 'both', 'down' or 'up'")
    z = np.asarray(state, float).reshape(-1)
    if z.shape != (2,) or not np.all(np.isfinite(z)):
        raise ParameterError("state", state, "must be two finite numbers (x = y/y0, x' = ẏ/(y0 ω_n0))")
    return k, z


def continue_orbit(model: ContactModel, excitation: Excitation, state, period: int,
                   parameter: str = "f_e", direction="both",
                   settings: ContinuationSettings | None = None, branch_id: str = "b0") -> Branch:
    """Continue the period-``period`` orbit through ``state`` at ``excitation``.

    Parameters
    ----------
    model, excitation
        The oscillator and the operating point of the seed.
    state : array_like (2,)
        Nondimensional orbit point (x = y/y0, x' = ẏ/(y0 ω_n0)) at phase 0, e.g.
        :attr:`Attractor.state`; refined by Newton shooting first.
    period : int
        Period k of the orbit [excitation periods].
    parameter : {"f_e", "P_a"}
        Continuation parameter.
    direction : {"both", "down", "up"}
        Decreasing, increasing parameter, or both (joined into one branch through the seed).
    settings : ContinuationSettings
    branch_id : str

    Returns
    -------
    Branch
        Points ordered along the branch, special points located on it, and one stop per
        direction.

    Raises
    ------
    ParameterError
        Bad input. The operating point must lie inside the settings' range.
    ContinuationError
        The seed does not converge to a period-k orbit.
    """
    settings = settings or ContinuationSettings()
    k, z = _check_common(excitation, state, period, parameter, direction)
    eng = _Engine(model, excitation, k, parameter, settings, branch_id)
    q0 = eng.par[eng.ip]
    if not (eng.qmin <= q0 <= eng.qmax):
        lo, hi = (settings.fmin, settings.fmax) if parameter == "f_e" else (settings.pa_min, settings.pa_max)
        val = excitation.f_e if parameter == "f_e" else excitation.pa_over_q
        raise ParameterError(parameter, val, f"seed must lie in the continuation range [{lo:g}, {hi:g}]")
    u0 = np.array([z[0], z[1], q0])
    st, _its, u, J, M = eng.fix_q(u0)
    if st != STATUS_OK:
        raise ContinuationError(f"the seed does not converge to a period-{k} orbit at "
                                f"f_e = {excitation.f_e:g} Hz ({_STATUS_TEXT.get(st, st)})")
    dirs = {"both": (-1, 1), "down": (-1,), "up": (1,), -1: (-1,), 1: (1,)}[direction]
    parts = []
    for sgn in dirs:
        parts.append(eng.run(u, J, M, np.array([0.0, 0.0, float(sgn)]), merge_check=k % 2 == 0))
        if parts[-1][2].reason == ISOLA_STOP:  # the loop is complete: no second direction
            break
    if len(parts) == 2:
        (pd_, sd, stop_d), (pu, su, stop_u) = parts
        points = pd_[::-1] + pu[1:]
        specials = sd + su
        stops = [stop_d, stop_u]
    else:
        points, specials, stop = parts[0]
        stops = [stop]
    return eng.branch(points, specials, stops, settings=asdict(settings))


def switch_period_doubling(model: ContactModel, special: SpecialPoint,
                           parameter: str = "f_e", settings: ContinuationSettings | None = None,
                           branch_id: str | None = None, ds: float = 0.01) -> Branch:
    """Branch switching at a period-doubling point onto the branch of period 2k.

    The period-2k orbits near the point are ``z* + ε e + O(ε²)`` (``e`` the eigenvector of the
    multiplier −1) at a parameter ``q* + O(ε²)``: the first point is corrected on the hyperplane
    through ``(z*, q*)`` normal to ``(e, 0)``, at a distance ``ds`` (scaled). The new branch is
    followed in one direction (its other half is the same orbits shifted by k periods) until it
    merges again with the period-k branch or another stop.

    Parameters
    ----------
    special : SpecialPoint
        A ``"period-doubling"`` point (from :func:`continue_orbit`).
    """
    if special.type != "period-doubling":
        raise ParameterError("special", special.type, "must be a period-doubling point")
    settings = settings or ContinuationSettings()
    exc = model.excitation(special.pa_over_q, special.fe_hz)
    k2 = 2 * int(special.period)
    bid = branch_id or f"{special.branch}.pd{special.fe_hz:.0f}"
    eng = _Engine(model, exc, k2, parameter, settings, bid)
    q_star = eng.par[eng.ip]
    # eigenvector of the multiplier closest to −1 (of the period-k monodromy)
    eng_k = _Engine(model, exc, int(special.period), parameter, settings, special.branch)
    st, _its, u_star, _J, M = eng_k.fix_q(np.array([special.state[0], special.state[1], q_star]))
    if st != STATUS_OK:
        raise ContinuationError("the period-doubling point could not be re-converged")
    vals, vecs = np.linalg.eig(M)
    e = np.real(vecs[:, int(np.argmin(np.abs(vals + 1.0)))])
    t_dir = np.array([e[0], e[1], 0.0])
    w = _weights(u_star)
    tau = _unit(t_dir * w)
    for _ in range(8):
        st, _its, u, J, M2 = eng.correct(u_star + ds * tau / w, u_star, tau, w, ds)
        if st == STATUS_OK:
            d = eng.sub_distance(u)
            if d is not None and np.max(np.abs(d)) / max(1.0, np.max(np.abs(u[:2]))) > 1e-3 * ds:
                break
        ds *= 0.5
    else:
        raise ContinuationError(f"no period-{k2} branch found at the period doubling "
                                f"f_e = {special.fe_hz:.6g} Hz")
    # direction of the first step away from the point along the new branch
    tn = np.empty(3)
    tangent(J, _weights(u), tn)
    tdir = tn / _weights(u)
    if np.dot(tdir * w, tau) < 0:
        tdir = -tdir
    points, specials, stop = eng.run(u, J, M2, tdir, merge_check=True)
    return eng.branch(points, specials, [stop], parent=special.branch, settings=asdict(settings))
