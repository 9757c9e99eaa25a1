"""Pseudo-arclength continuation of period-k orbits in f_e (or P_a), with stability and events.

A period-k orbit is a zero of ``G(z; q) = P^k(z; q) − z`` (stroboscopic map at phase 0, shooting
with the monodromy from the variational equations integrated through contact loss and
re-contact, :mod:`contactvib._kernels.continuation`): :class:`OrbitProblem`. The branch
through a seed is followed by the one continuation engine (:mod:`.engine`: Euler predictor along
the tangent, bordered Newton corrector on the pseudo-arclength hyperplane, in scaled unknowns —
relative change of the state and of the parameter — and an adaptive step: grown after easy
corrections, halved after a failed one or a tangent turning by more than ``max_turn``). Every
accepted point gets its Floquet multipliers (stability), its extrema over the orbit (A_pp,
y_min, y_max, from the dense output) and the test functions of
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

from dataclasses import asdict, dataclass, replace

import numpy as np

from contactvib._kernels.continuation import orbit_range, residual_jacobian, residual_jacobian_step
from contactvib._kernels.shooting import is_stable, strobe_map
from contactvib._kernels.status import STATUS_OK, status_message
from contactvib.call_forms import old_form
from contactvib.continuation.bifurcations import fold_test, ns_test, pd_test
from contactvib.continuation.branch import Branch, SpecialPoint, Stop
from contactvib.continuation.engine import (
    Bound,
    EngineStop,
    Point,
    continue_branch,
    correct,
)
from contactvib.continuation.settings import BranchSettings
from contactvib.errors import ComputationError
from contactvib.model import (
    ContactModel,
    Excitation,
    ParameterError,
    check_choice,
    check_excitation,
    check_level_kind,
    check_range,
    excitation_at,
)

__all__ = ["ContinuationSettings", "continue_orbit", "switch_period_doubling",
           "OrbitProblem", "OrbitRecord"]

_IP = {"f_e": 4, "P_a": 3}


@dataclass(frozen=True)
class ContinuationSettings(BranchSettings):
    """Knobs of a continuation run (the fields it shares with
    ``contactvib.continuation.system_shooting.SystemContinuationSettings`` are checked by
    ``contactvib.continuation.settings.BranchSettings``).

    Parameters
    ----------
    fmin_hz, fmax_hz : float
        Range of f_e [Hz] (stop when reached).
    pa_min, pa_max : float
        Range of P_a [Q] (stop when reached; for continuation in P_a).
    ds, ds_min, ds_max : float
        Initial, smallest and largest pseudo-arclength step [relative units: 0.05 ≈ 5 %].
    max_points : int
        Points per direction, the start included (≥ ``BRANCH_POINTS_MIN``).
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
    locate : bool
        Locate the special points (folds, doublings, Neimark–Sacker, grazing). False leaves them
        out and changes no branch point: for callers that need only each point's stability (the
        sweep's post-pass, ``contactvib.sweeps.unstable_parts``).
    max_failures : int
        Rejected steps per direction before the branch stops (a branch that keeps failing, e.g.
        a high-period orbit inside a chaotic band, would otherwise crawl on with tiny steps).
    excitation : str
        What the level of a continuation in f_e holds (:data:`contactvib.model.LEVEL_KINDS`):
        "force" (P_a/Q), "base-um" (base displacement U [µm], the inertial force growing with
        f_e²) or "base-g" (base acceleration A [g]); the branch's ``pa_over_q`` then holds U or A.
    """

    fmin_hz: float = 30.0
    fmax_hz: float = 2000.0
    pa_min: float = 0.0
    pa_max: float = 2.0
    ds: float = 0.02
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
    locate: bool = True
    excitation: str = "force"

    def excitation_at(self, model: ContactModel, level: float, f_e: float) -> Excitation:
        """The excitation at ``level`` and f_e [Hz] (:func:`contactvib.model.excitation_at`)."""
        return excitation_at(model, level, f_e, self.excitation)

    def __post_init__(self):
        # the shared fields checked by BranchSettings, each against the checked values before it,
        # and stored as checked (a number given as text is a float, a count an int)
        v = self.checked()
        v["locate"] = bool(check_choice("locate", self.locate, (True, False)))
        v["excitation"] = check_level_kind(self.excitation)
        for name, value in v.items():
            object.__setattr__(self, name, value)


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


@dataclass(frozen=True)
class OrbitRecord:
    """Measurements of one periodic orbit on a branch (:meth:`OrbitProblem.measure`).

    ``xmin``, ``xmax``: extrema of x = y/y0 over the orbit [y0]; ``flight``: fraction of the
    period with x ≤ 0; ``minima_per_period``: local minima of x over the period-k orbit;
    ``floquet_multipliers``: eigenvalues of the monodromy matrix M.
    """

    fe_hz: float
    pa_over_q: float
    floquet_multipliers: np.ndarray
    xmin: float
    xmax: float
    flight: float
    minima_per_period: int


class OrbitProblem:
    """Period-k orbits of the stroboscopic map as a continuation problem (:mod:`.engine`).

    Unknowns ``u = (x, x', q)``, residual ``G(u) = P^k(z; q) − z`` and Jacobian
    ``[M − I | ∂P^k/∂q]`` from :func:`contactvib._kernels.continuation.residual_jacobian`
    (``data`` = the monodromy M), scaling ``1/max(1, |x|, |x'|)`` for the state and ``1/|q|`` for
    the parameter, test functions of :mod:`.bifurcations`, stops at the amplitude bound and (with
    ``merge_check``) where a period-k branch merges onto the period-k/2 branch.
    """

    test_names = ("fold", "period-doubling", "neimark-sacker", "grazing")
    fold_tests = ("fold",)

    def __init__(self, model: ContactModel, excitation: Excitation, k: int, parameter: str,
                 settings: ContinuationSettings, merge_check: bool = False):
        self.k = int(k)
        self.parameter = parameter
        self.ip = _IP[parameter]
        self.s = settings
        self.par = excitation.kernel_parameters().copy()
        if self.ip == 3 and self.par[3] != excitation.pa_over_q:
            raise ParameterError("parameter", parameter, "continuation in P_a is written for a force in units of "
                                 "Q (no preload, no base motion); continue in f_e instead")
        self.level = excitation.level[1]  # recorded with each point of a branch in f_e
        self.y_um = model.units.y_um
        self.position_um = model.units.position_um
        self.excitation = excitation
        self.fn0 = model.f_n0
        if parameter == "f_e":
            lo, hi = settings.fmin_hz / self.fn0, settings.fmax_hz / self.fn0
        else:
            lo, hi = settings.pa_min, settings.pa_max
        self.bounds = (Bound(2, lo, hi, parameter),)
        self.merge_check = merge_check
        self.prev_d = None
        self.merge_state = None
        self.corrector = settings.corrector()
        self.steps = settings.step_control()

    # ------------------------------------------------------------------ engine protocol
    def residual_jacobian(self, u):
        G, J, M = np.empty(2), np.empty((2, 3)), np.empty((2, 2))
        st = residual_jacobian(u, self.k, self.par, self.ip, self.s.rtol, G, J, M)
        return st, G, J, M

    def residual_jacobian_step(self, u, bord, u_prev, ds, w):
        """:meth:`residual_jacobian`, :meth:`residual_norm` and the engine's bordered Newton step
        in one compiled call (the optional fast path of the engine's problem protocol)."""
        st, res, cons, step, G, J, M, u_new = residual_jacobian_step(
            u, self.k, self.par, self.ip, self.s.rtol, bord, u_prev, ds, w)
        return st, G, J, M, res, cons, step, u_new

    def residual_norm(self, u, G):
        return max(abs(G[0]), abs(G[1])) / max(1.0, abs(u[0]), abs(u[1]))

    def weights(self, u):
        return _weights(u)

    def admissible(self, u):
        return self.ip != 4 or u[2] > 0.0

    def measure(self, u, J, M, residual) -> OrbitRecord | None:
        par = self.par.copy()
        par[self.ip] = u[2]
        xmin, xmax, flight, n_min, st = orbit_range(u[:2].copy(), self.k, par, self.s.rtol)
        if st != STATUS_OK:
            return None
        return OrbitRecord(par[4] * self.fn0, par[3] if self.ip == 3 else self.level, np.linalg.eigvals(M),
                           xmin, xmax, flight,
                           n_min)

    def tests(self, pt: Point) -> dict:
        M = pt.data
        return {"fold": fold_test(M), "period-doubling": pd_test(M), "neimark-sacker": ns_test(M),
                "grazing": pt.record.xmin}

    def check(self, pt: Point):
        app = (pt.record.xmax - pt.record.xmin) * self.y_um
        if app > self.s.app_max_um:
            return f"amplitude bound reached (A_pp = {app:.4g} um > {self.s.app_max_um:g} um)"
        return None

    def check_step(self, a: Point, b: Point):
        if not self.merge_check:
            return None
        d = self.sub_distance(b.u)
        if d is not None and self.prev_d is not None and _passes_zero(self.prev_d, d, b.u[:2]):
            za = a.u[:2]
            self.merge_state = 0.5 * (za + za + self.prev_d)  # the period-k/2 orbit, a seed
            return (f"merges with the period-{self.k // 2} branch "
                    f"(period doubling near f_e = {b.record.fe_hz:.6g} Hz)")
        self.prev_d = d
        return None

    # ------------------------------------------------------------------ helpers
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

    def fix_q(self, u_guess):
        """Natural-parameter Newton at q = u_guess[2]: (status, Point or None)."""
        return correct(self, u_guess.copy(), u_guess.copy(), np.array([0.0, 0.0, 1.0]),
                       _weights(u_guess), 0.0, self.corrector)

    def run(self, start: Point, t_dir, branch_id: str):
        """One direction: (points, specials, stop)."""
        self.prev_d, self.merge_state = None, None
        out = continue_branch(self, start, t_dir, self.corrector, self.steps)
        specials = [self.special(e.kind, e.point, e.value, (e.bracket[0].record.fe_hz,
                                                            e.bracket[1].record.fe_hz), branch_id)
                    for e in out.events]
        last = out.points[-1].record
        return out.points, specials, Stop(last.fe_hz, last.pa_over_q, self.stop_text(out.stop),
                                          branch_id, self.merge_state)

    def stop_text(self, stop: EngineStop) -> str:
        if stop.code == "max_points":
            return "maximum number of points reached"
        if stop.code == "max_failures":
            return f"step too small: {stop.failures} rejected steps (Newton or tangent failures)"
        if stop.code == "step_min":
            why = status_message(stop.status)
            return f"step too small: Newton failure ({why})"
        if stop.code == "measure_failed":
            return "step too small: orbit record failed"
        if stop.code == "bound":
            name, side = stop.detail
            return f"{name} range reached ({side} bound)"
        if stop.code == "loop":
            return ISOLA_STOP
        return str(stop.detail)

    def special(self, kind, pt: Point, value, bracket, branch_id) -> SpecialPoint:
        r = pt.record
        return SpecialPoint(type=kind, fe_hz=r.fe_hz, pa_over_q=r.pa_over_q,
                            app_um=(r.xmax - r.xmin) * self.y_um, period=self.k, branch=branch_id,
                            floquet_multipliers=r.floquet_multipliers, state=pt.u[:2].copy(),
                            test_value=float(value), bracket=bracket,
                            measures=self._dofs_and_contacts(r, pt.u[:2].copy()))

    def _dofs_and_contacts(self, r, state) -> dict:
        """The ``dofs`` and ``contacts`` of the orbit at a special point (its first harmonic and
        mean contact forces measured along the orbit, :func:`contactvib.steady.orbits.describe_orbit`)."""
        from contactvib.steady.orbits import describe_orbit

        exc = replace(self.excitation, f_e=r.fe_hz) if self.ip == 4 else \
            replace(self.excitation, f_e=r.fe_hz, pa_over_q=r.pa_over_q)
        d = describe_orbit(exc, state, self.k).to_dict()
        return {"dofs": d["dofs"], "contacts": d["contacts"]}

    def branch(self, points, specials, stops, branch_id, parent=None, settings=None) -> Branch:
        """The points of one or two directions as a :class:`~.branch.Branch`."""
        n = len(points)
        u = np.array([p.u for p in points]).reshape(n, 3)
        rec = [p.record for p in points]
        xmin = np.array([r.xmin for r in rec])
        xmax = np.array([r.xmax for r in rec])
        mu = np.array([r.floquet_multipliers for r in rec], complex).reshape(n, 2)
        arc = np.zeros(n)
        for i in range(1, n):
            arc[i] = arc[i - 1] + float(np.linalg.norm((u[i] - u[i - 1]) * _weights(u[i - 1])))
        return Branch(
            branch=branch_id, period=self.k, parameter=self.parameter,
            fe_hz=np.array([r.fe_hz for r in rec]), pa_over_q=np.array([r.pa_over_q for r in rec]),
            app_um=(xmax - xmin) * self.y_um, ymin_um=self.position_um(xmin), ymax_um=self.position_um(xmax),
            floquet_multipliers=mu, stable=is_stable(np.max(np.abs(mu), axis=1)), state=u[:, :2].copy(),
            contact_loss_fraction=np.array([r.flight for r in rec]),
            minima_per_period=np.array([r.minima_per_period for r in rec], int), arclength=arc,
            special=sorted(specials, key=lambda sp: sp.fe_hz), stops=stops, parent=parent,
            fn0_hz=self.fn0, y0_um=self.y_um, settings=settings or {})


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
    try:
        z = np.asarray(state, float).reshape(-1)
    except (TypeError, ValueError):
        z = np.array([np.nan])
    if z.shape != (2,) or not np.all(np.isfinite(z)):
        raise ParameterError("state", state, "must be two finite numbers (x = y/y0, x' = ẏ/(y0 ω_n0))")
    return k, z


@old_form("model", "excitation", "state", "period", "parameter", "direction", "settings", "branch_id")
def continue_orbit(excitation: Excitation, state, period: int, *, parameter: str = "f_e", direction="both",
                   settings: ContinuationSettings | None = None, branch_id: str = "b0") -> Branch:
    """Continue the period-``period`` orbit through ``state`` at ``excitation``.

    Parameters
    ----------
    excitation : Excitation
        The operating point of the seed (with its model, ``excitation.model``).
    state : array_like (2,)
        Nondimensional orbit point (x = y/y0, x' = ẏ/(y0 ω_n0)) at phase 0, e.g.
        ``Attractor.state``; refined by Newton shooting first.
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
    ComputationError
        The seed does not converge to a period-k orbit (``stage`` "continuation").
    """
    model = check_excitation(excitation).model
    settings = settings or ContinuationSettings()
    if not isinstance(settings, ContinuationSettings):
        raise ParameterError("settings", settings, "must be a ContinuationSettings")
    k, z = _check_common(excitation, state, period, parameter, direction)
    prob = OrbitProblem(model, excitation, k, parameter, settings, merge_check=k % 2 == 0)
    q0 = prob.par[prob.ip]
    bound = prob.bounds[0]
    if not (bound.lo <= q0 <= bound.hi):
        lo, hi = (settings.fmin_hz, settings.fmax_hz) if parameter == "f_e" else (settings.pa_min, settings.pa_max)
        val = excitation.f_e if parameter == "f_e" else excitation.pa_over_q
        raise ParameterError(parameter, val, f"seed must lie in the continuation range [{lo:g}, {hi:g}]")
    st, start = prob.fix_q(np.array([z[0], z[1], q0]))
    if st != STATUS_OK:
        raise ComputationError(f"the seed does not converge to a period-{k} orbit at "
                               f"f_e = {excitation.f_e:g} Hz ({status_message(st)})", stage="continuation")
    dirs = {"both": (-1, 1), "down": (-1,), "up": (1,), -1: (-1,), 1: (1,)}[direction]
    parts = []
    for sgn in dirs:
        first = Point(start.u.copy(), start.J, start.data, start.residual, start.iterations)
        parts.append(prob.run(first, np.array([0.0, 0.0, float(sgn)]), branch_id))
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
    return prob.branch(points, specials, stops, branch_id, settings=asdict(settings))


@old_form("model", "special", "parameter", "settings", "branch_id", "ds")
def switch_period_doubling(model: ContactModel, special: SpecialPoint, *, parameter: str = "f_e",
                           settings: ContinuationSettings | None = None, branch_id: str | None = None,
                           ds: float = 0.01) -> Branch:
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
    exc = settings.excitation_at(model, special.pa_over_q, special.fe_hz)
    k2 = 2 * int(special.period)
    bid = branch_id or f"{special.branch}.pd{special.fe_hz:.0f}"
    prob = OrbitProblem(model, exc, k2, parameter, settings, merge_check=True)
    q_star = prob.par[prob.ip]
    # eigenvector of the multiplier closest to −1 (of the period-k monodromy)
    prob_k = OrbitProblem(model, exc, int(special.period), parameter, settings)
    st, pk = prob_k.fix_q(np.array([special.state[0], special.state[1], q_star]))
    if st != STATUS_OK:
        raise ComputationError("the period-doubling point could not be re-converged", stage="continuation")
    u_star = pk.u
    vals, vecs = np.linalg.eig(pk.data)
    e = np.real(vecs[:, int(np.argmin(np.abs(vals + 1.0)))])
    t_dir = np.array([e[0], e[1], 0.0])
    w = _weights(u_star)
    tau = t_dir * w / np.linalg.norm(t_dir * w)
    for _ in range(8):
        st, pt = correct(prob, u_star + ds * tau / w, u_star, tau, w, ds, prob.corrector)
        if st == STATUS_OK:
            d = prob.sub_distance(pt.u)
            if d is not None and np.max(np.abs(d)) / max(1.0, np.max(np.abs(pt.u[:2]))) > 1e-3 * ds:
                break
        ds *= 0.5
    else:
        raise ComputationError(f"no period-{k2} branch found at the period doubling "
                               f"f_e = {special.fe_hz:.6g} Hz", stage="continuation")
    # the first step leaves the point along the new branch, away from (z*, q*) along (e, 0)
    points, specials, stop = prob.run(pt, t_dir, bid)
    return prob.branch(points, specials, [stop], bid, parent=special.branch,
                       settings=asdict(settings))
