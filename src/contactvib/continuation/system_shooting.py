"""Pseudo-arclength continuation of the period-k orbits of a structure of n coordinates.

A period-k orbit of a :class:`~contactvib.model.system.System` under P(t) = P_a cos(2π f_e t)
[N] is a zero of ``G(x; q) = P^k(x; q) − x`` over the scaled state x = (x, x') of the compiled
form (2n components, :mod:`contactvib.model.system_kernel`), with q = f_e [Hz] or P_a [N]:
:class:`SystemOrbitProblem`, followed by the one continuation engine (:mod:`.engine`). Its
Jacobian ``[Φ − I | ∂P^k/∂q]`` takes the monodromy Φ from the variational equation with the
saltation matrices at the contact switches (:func:`contactvib._kernels.system_map.strobe_map`)
and ``∂P^k/∂q`` by the central difference ``(P^k(x; q + h) − P^k(x; q − h)) / 2h``,
``h = FD_STEP · |q|``.

Test functions of an accepted point, Φ's eigenvalues μ_1..μ_2n (the Floquet multipliers)::

    fold             det(Φ − I)                          a real multiplier through +1
    period doubling  det(Φ + I)                          a real multiplier through −1
    Neimark–Sacker   Π over complex pairs (|μ|² − 1)      a complex pair through |μ| = 1

A fold counts only where the parameter component of the branch tangent changes sign too. The
Neimark–Sacker test is NaN without a complex pair; a located zero counts only where the pair is
on the unit circle (| |μ| − 1 | ≤ LOCATED_TOL), which drops the jumps of the product where a pair
collides on the real axis; likewise a fold or period doubling counts only with a multiplier at +1
or −1. For n = 1 the three tests are those of :mod:`.bifurcations`.

Each accepted point is measured on MEASURE_SAMPLES samples per period (each coordinate's extrema
refined by the parabola through the extreme sample and its neighbours). A direction stops, besides
the engine's stops, above the amplitude bound, or where a period-k branch merges with a period-d
orbit: |P^d(x) − x| ≤ MERGE_TOL for a proper divisor d of k, or P^(k/2)(x) − x reversing while small
(the branch passed through a period doubling of the period-k/2 branch).

References
----------
Yu. A. Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., Springer (2004), Ch. 10.
R. I. Leine, N. van de Wouw, *Stability and Convergence of Mechanical Systems with Unilateral
Constraints*, Springer (2008), Ch. 7 (saltation matrices).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib._kernels import system_map as km
from contactvib._kernels.shooting import is_stable
from contactvib._kernels.status import STATUS_OK, status_message
from contactvib._kernels.system_flow import system_arrays
from contactvib.call_forms import renamed_fields
from contactvib.continuation.branch import Stop
from contactvib.continuation.engine import (
    Bound,
    EngineStop,
    Point,
    continue_branch,
    correct,
)
from contactvib.continuation.settings import BranchSettings
from contactvib.continuation.system_branch import SystemBranch, SystemOrbitRecord, SystemSpecialPoint
from contactvib.errors import ComputationError
from contactvib.model import ParameterError, check_int
from contactvib.model.checks import KMAX_SEARCH_MAX
from contactvib.model.system import System, check_excitation, check_state

__all__ = ["SystemContinuationSettings", "SystemOrbitProblem", "continue_system_orbit", "linear_seed",
           "system_tests", "SystemBranch", "SystemSpecialPoint", "SystemOrbitRecord", "FD_STEP", "LOCATED_TOL"]

#: Relative step of the central difference of ∂P^k/∂q.
FD_STEP = 1e-6
#: A located zero counts where a multiplier lies within this of +1 (fold), −1 (period doubling)
#: or a complex pair within this of |μ| = 1 (Neimark–Sacker); a sign change without it is a jump
#: of the test function (a pair colliding on the real axis, a multiplier through infinity). Loose:
#: at a grazing orbit a multiplier moves like the square root of the arclength.
LOCATED_TOL = 1e-3
#: A period-k orbit with |P^d(x) − x|∞ below this (relative to max(1, |x|∞)) for a proper divisor
#: d of k has merged with the period-d branch: the branch stops there.
MERGE_TOL = 1e-7
#: Samples per excitation period of the measured orbit.
MEASURE_SAMPLES = 512


@renamed_fields(app_max="app_max_um", pa_min="pa_min_newton", pa_max="pa_max_newton")
@dataclass(frozen=True)
class SystemContinuationSettings(BranchSettings):
    """Knobs of a system continuation (the fields it shares with
    :class:`~contactvib.continuation.shooting.ContinuationSettings`, same names, meaning and
    units, are checked by :class:`~contactvib.continuation.settings.BranchSettings`).

    Parameters
    ----------
    fmin_hz, fmax_hz : float
        Range of f_e [Hz] (stop when reached; 0 ≤ fmin_hz < fmax_hz).
    pa_min_newton, pa_max_newton : float
        Range of P_a [N] (for continuation in P_a; ``pa_min``, ``pa_max`` before 0.2.0, still
        accepted with a DeprecationWarning).
    ds, ds_min, ds_max : float
        Initial, smallest and largest pseudo-arclength step [relative units].
    max_points : int
        Points per direction, the start included (≥ 2).
    rtol : float
        Integrator tolerance (rtol = atol in the scaled state) of the shooting.
    tol : float
        Newton closure ``|P^k(x) − x|∞ / max(1, |x|∞)`` (scaled state).
    max_iter : int
        Newton iterations per correction.
    max_turn : float
        Largest angle [rad] between successive tangents before the step is halved.
    locate_tol : float
        Pseudo-arclength tolerance of the location of special points.
    max_failures : int
        Rejected steps per direction before the branch stops.
    app_max_um : float
        Amplitude bound [µm; µrad for a rotation]: a branch stops where the plotted coordinate's
        A_pp exceeds it (``app_max`` before 0.2.0, still accepted with a DeprecationWarning).
    """

    LEVEL_RANGE = ("pa_min_newton", "pa_max_newton", "N")
    FMIN_ZERO = True

    fmin_hz: float = 0.0
    fmax_hz: float = 1e6
    pa_min_newton: float = 0.0
    pa_max_newton: float = 1e9
    ds: float = 0.02
    ds_min: float = 1e-7
    ds_max: float = 0.1
    max_points: int = 1000
    rtol: float = 1e-11
    tol: float = 1e-9
    max_iter: int = 8
    max_turn: float = 0.35
    locate_tol: float = 1e-9
    max_failures: int = 100
    app_max_um: float = 1e15

    def __post_init__(self):
        for name, value in self.checked().items():
            object.__setattr__(self, name, value)

    def to_dict(self) -> dict:
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
                for k, v in self.__dict__.items()}


def system_tests(phi: np.ndarray) -> dict:
    """The fold, period-doubling and Neimark–Sacker test functions of a monodromy Φ (2n × 2n;
    module docstring)."""
    n2 = phi.shape[0]
    eye = np.eye(n2)
    mu = np.linalg.eigvals(phi)
    pairs = mu[mu.imag > 1e-12 * max(1.0, float(np.max(np.abs(mu))))]
    ns = float(np.prod(np.abs(pairs) ** 2 - 1.0)) if pairs.size else math.nan
    return {"fold": float(np.linalg.det(phi - eye)), "period-doubling": float(np.linalg.det(phi + eye)),
            "neimark-sacker": ns}


def _extrema(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Minimum and maximum of each row of a periodic sample, each refined by the vertex of the
    parabola through the extreme sample and its two neighbours (cyclic)."""
    def vertex(row, i):
        a, b, c = row[i - 1], row[i], row[(i + 1) % row.size]
        d = a - 2.0 * b + c
        return b if d == 0.0 else b - 0.125 * (c - a) ** 2 / d

    lo = np.array([vertex(r, int(np.argmin(r))) for r in q])
    hi = np.array([vertex(r, int(np.argmax(r))) for r in q])
    return np.minimum(lo, q.min(axis=1)), np.maximum(hi, q.max(axis=1))


def _same(a: SystemSpecialPoint, b: SystemSpecialPoint) -> bool:
    """One point located twice: a zero at the end of two brackets, or the same orbit met again as
    its copy shifted by some periods (a period-k branch that comes back over itself)."""
    return (a.type == b.type and abs(a.fe_hz - b.fe_hz) <= 1e-7 * abs(b.fe_hz)
            and abs(a.pa_newton - b.pa_newton) <= 1e-7 * max(abs(b.pa_newton), 1e-300))


def _sorted(mu: np.ndarray) -> np.ndarray:
    return mu[np.argsort(-np.abs(mu), kind="stable")]


class SystemOrbitProblem:
    """Period-k orbits of a system as a continuation problem (:mod:`.engine`).

    Unknowns ``u = (x (2n, scaled), q)`` with q = f_e [Hz] (``parameter="f_e"``) or P_a [N]
    (``"P_a"``); residual ``P^k(x; q) − x`` and Jacobian ``[Φ − I | ∂P^k/∂q]`` (module docstring;
    ``data`` = Φ); scaling ``1/max(1, |x|∞)`` of the state and ``1/|q|`` of the parameter.
    """

    test_names = ("fold", "period-doubling", "neimark-sacker")
    fold_tests = ("fold",)

    def __init__(self, system: System, pa_newton: float, fe_hz: float, k: int, parameter: str,
                 settings: SystemContinuationSettings, Q: float | None = None, coordinate: int = 0):
        self.system = system
        self.k = int(k)
        self.parameter = parameter
        self.pa, self.fe = float(pa_newton), float(fe_hz)
        self.s = settings
        self.Q = Q
        self.coordinate = int(coordinate)
        self.scales = system.kernel_form(1.0, 1.0).scales
        q0 = self.fe if parameter == "f_e" else self.pa
        self.q_floor = 1e-3 * abs(q0) if q0 != 0.0 else 1e-6
        if parameter == "f_e":
            self.bounds = (Bound(2 * system.n, settings.fmin_hz, settings.fmax_hz, "f_e"),)
        else:
            self.bounds = (Bound(2 * system.n, settings.pa_min_newton, settings.pa_max_newton, "P_a"),)
        self.prev_d = None  # P^(k/2)(x) − x at the last accepted point (even k)
        self.corrector = settings.corrector()
        self.steps = settings.step_control()

    # ------------------------------------------------------------------ helpers
    def excitation(self, q: float) -> tuple[float, float]:
        """(P_a [N], f_e [Hz]) at the parameter value q."""
        return (self.pa, q) if self.parameter == "f_e" else (q, self.fe)

    def _sa(self, q: float):
        pa, fe = self.excitation(q)
        f = self.system.kernel_form(pa, fe)
        return system_arrays(f.Kx, f.Cx, f.g0, f.gb, f.r, f.U, f.gam, f.Aw, f.rows)

    def _map(self, x, q, with_jac):
        n2 = x.size
        out = np.empty(n2)
        phi = np.empty((n2, n2)) if with_jac else np.empty((0, 0))
        st = km.strobe_map(self._sa(q), np.ascontiguousarray(x, dtype=float), self.k, self.s.rtol, self.s.rtol,
                           out, phi)
        return st, out, phi

    # ------------------------------------------------------------------ engine protocol
    def residual_jacobian(self, u):
        n2 = u.size - 1
        x, q = u[:n2], float(u[n2])
        st, px, phi = self._map(x, q, True)
        if st != STATUS_OK:
            return st, None, None, None
        h = FD_STEP * max(abs(q), self.q_floor)
        st1, p_hi, _ = self._map(x, q + h, False)
        st2, p_lo, _ = self._map(x, q - h, False)
        if st1 != STATUS_OK or st2 != STATUS_OK:
            return st1 if st1 != STATUS_OK else st2, None, None, None
        J = np.empty((n2, n2 + 1))
        J[:, :n2] = phi - np.eye(n2)
        J[:, n2] = (p_hi - p_lo) / (2.0 * h)
        return STATUS_OK, px - x, J, phi

    def residual_norm(self, u, G):
        return float(np.max(np.abs(G))) / max(1.0, float(np.max(np.abs(u[:-1]))))

    def weights(self, u):
        n2 = u.size - 1
        s = max(1.0, float(np.max(np.abs(u[:n2]))))
        w = np.full(u.size, 1.0 / s)
        w[n2] = 1.0 / max(abs(u[n2]), self.q_floor)
        return w

    def admissible(self, u):
        q = u[-1]
        return bool(np.all(np.isfinite(u))) and (q > 0.0 if self.parameter == "f_e" else q >= 0.0)

    def measure(self, u, J, phi, residual) -> SystemOrbitRecord | None:
        from contactvib.steady.system_orbits import simulate_system

        n = self.system.n
        pa, fe = self.excitation(float(u[-1]))
        z = self.scales.to_si(u[:-1])
        try:
            h = simulate_system(self.system, pa, fe, z[:n], z[n:], n_periods=self.k,
                                samples_per_period=MEASURE_SAMPLES, rtol=self.s.rtol)
        except (ComputationError, ParameterError):
            return None
        qmin, qmax = _extrema(h.q[:, :-1])
        return SystemOrbitRecord(fe, pa, _sorted(np.linalg.eigvals(phi)), qmax - qmin, qmin, qmax,
                                 (~h.in_contact[:, :-1]).mean(axis=1))

    def tests(self, pt: Point) -> dict:
        return system_tests(pt.data)

    def check(self, pt: Point):
        app = float(pt.record.app[self.coordinate])
        if app > self.s.app_max_um:
            return f"amplitude bound reached (A_pp = {app:.4g} > {self.s.app_max_um:g})"
        d = self.sub_period(pt.u)
        if d is not None:
            return (f"merges with the period-{d} branch (its orbit run {self.k // d} times) at "
                    f"f_e = {pt.record.fe_hz:.6g} Hz, P_a = {pt.record.pa_newton:.6g} N")
        return None

    def sub_period(self, u) -> int | None:
        """The least proper divisor d of k with |P^d(x) − x|∞ ≤ MERGE_TOL · max(1, |x|∞) (the
        period-k orbit has become a period-d one), else None."""
        x, q = u[:-1], float(u[-1])
        scale = max(1.0, float(np.max(np.abs(x))))
        for d in range(1, self.k):
            if self.k % d:
                continue
            out = np.empty(x.size)
            st = km.strobe_map(self._sa(q), np.ascontiguousarray(x, dtype=float), d, self.s.rtol, self.s.rtol,
                               out, np.empty((0, 0)))
            if st == STATUS_OK and float(np.max(np.abs(out - x))) <= MERGE_TOL * scale:
                return d
        return None

    def check_step(self, a: Point, b: Point):
        """For even k: P^(k/2)(x) − x reverses (by more than 150°) while small — the branch
        passed through the period-k/2 branch (a period doubling of it): stop there."""
        if self.k % 2:
            return None
        x, q = b.u[:-1], float(b.u[-1])
        out = np.empty(x.size)
        st = km.strobe_map(self._sa(q), np.ascontiguousarray(x, dtype=float), self.k // 2, self.s.rtol, self.s.rtol,
                           out, np.empty((0, 0)))
        d = out - x if st == STATUS_OK else None
        prev, self.prev_d = self.prev_d, d
        if d is None or prev is None:
            return None
        na, nb = float(np.linalg.norm(prev)), float(np.linalg.norm(d))
        small = min(na, nb) <= 0.2 * max(1.0, float(np.max(np.abs(x))))
        if small and float(np.dot(prev, d)) < -0.866 * na * nb:
            return (f"merges with the period-{self.k // 2} branch (period doubling near "
                    f"f_e = {b.record.fe_hz:.6g} Hz, P_a = {b.record.pa_newton:.6g} N)")
        return None

    def fix_q(self, u_guess):
        """Natural-parameter Newton at q = u_guess[-1]: (status, Point or None)."""
        e = np.zeros(u_guess.size)
        e[-1] = 1.0
        return correct(self, u_guess.copy(), u_guess.copy(), e, self.weights(u_guess), 0.0, self.corrector)

    # ------------------------------------------------------------------ runs and results
    def run(self, start: Point, t_dir, branch_id: str):
        """One direction: (points, specials, stop)."""
        self.prev_d = None
        out = continue_branch(self, start, t_dir, self.corrector, self.steps)
        specials = []
        for e in out.events:
            sp = self.special(e.kind, e.point, e.value,
                              (e.bracket[0].record.fe_hz, e.bracket[1].record.fe_hz), branch_id)
            if sp is not None:
                specials.append(sp)
        last = out.points[-1].record
        return out.points, specials, Stop(last.fe_hz, last.pa_newton, self.stop_text(out.stop), branch_id)

    @staticmethod
    def stop_text(stop: EngineStop) -> str:
        if stop.code == "max_points":
            return "maximum number of points reached"
        if stop.code == "max_failures":
            return f"step too small: {stop.failures} rejected steps (Newton or tangent failures)"
        if stop.code == "step_min":
            return f"step too small: Newton failure ({status_message(stop.status)})"
        if stop.code == "measure_failed":
            return "step too small: orbit record failed"
        if stop.code == "bound":
            name, side = stop.detail
            return f"{name} range reached ({side} bound)"
        if stop.code == "loop":
            return "closed branch (isola): back at its first point"
        return str(stop.detail)

    def special(self, kind, pt: Point, value, bracket, branch_id) -> SystemSpecialPoint | None:
        """The special point of a located event; None where no multiplier is there (within
        LOCATED_TOL of +1, −1 or the unit circle): a jump of the test function, not a zero."""
        r = pt.record
        mu = r.floquet_multipliers
        angle = math.nan
        if kind == "neimark-sacker":
            pairs = mu[mu.imag > 0.0]
            if not pairs.size:
                return None
            c = pairs[int(np.argmin(np.abs(np.abs(pairs) - 1.0)))]
            if abs(abs(c) - 1.0) > LOCATED_TOL:
                return None
            angle = float(np.angle(c)) / (2.0 * math.pi)
        elif np.min(np.abs(mu - (1.0 if kind == "fold" else -1.0))) > LOCATED_TOL:
            return None
        z = self.scales.to_si(pt.u[:-1])
        pq = r.pa_newton / self.Q if self.Q else math.nan
        return SystemSpecialPoint(type=kind, fe_hz=r.fe_hz, pa_over_q=pq, app_um=float(r.app[self.coordinate]),
                                  period=self.k, branch=branch_id, floquet_multipliers=mu, state=z,
                                  test_value=float(value), bracket=bracket,
                                  measures=self._dofs_and_contacts(r, z),
                                  pa_newton=r.pa_newton, angle_over_2pi=angle)

    def _dofs_and_contacts(self, r: SystemOrbitRecord, z) -> dict:
        """The ``dofs`` and ``contacts`` of the orbit (as ``attractors --system --json``)."""
        from contactvib.steady.results import dofs_and_contacts
        from contactvib.steady.system_attractors import orbit_columns

        try:
            cols, _minima = orbit_columns(self.system, r.pa_newton, r.fe_hz, z, self.k)
        except ComputationError:
            return {}
        return dofs_and_contacts(**cols)

    def branch(self, points, specials, stops, branch_id, settings=None) -> SystemBranch:
        """The points of one or two directions as a :class:`SystemBranch` (a special point met
        twice, :func:`_same`, kept once)."""
        unique = []
        for sp in specials:
            if not any(_same(sp, other) for other in unique):
                unique.append(sp)
        specials = unique
        n = len(points)
        u = np.array([p.u for p in points])
        rec = [p.record for p in points]
        mu = np.array([r.floquet_multipliers for r in rec], complex)
        arc = np.zeros(n)
        for i in range(1, n):
            arc[i] = arc[i - 1] + float(np.linalg.norm((u[i] - u[i - 1]) * self.weights(u[i - 1])))
        pa = np.array([r.pa_newton for r in rec])
        state = np.array([self.scales.to_si(x) for x in u[:, :-1]])
        sys_ = self.system
        from contactvib.steady.system_orbits import DISPLAY_UNITS

        return SystemBranch(
            branch=branch_id, period=self.k, parameter=self.parameter, fe_hz=np.array([r.fe_hz for r in rec]),
            pa_newton=pa, pa_over_q=pa / self.Q if self.Q else np.full(n, np.nan),
            app=np.array([r.app for r in rec]), qmin=np.array([r.qmin for r in rec]),
            qmax=np.array([r.qmax for r in rec]),
            contact_loss_fraction=np.array([r.contact_loss for r in rec]).reshape(n, len(sys_.contacts)),
            floquet_multipliers=mu, stable=is_stable(np.max(np.abs(mu), axis=1)), state=state, arclength=arc,
            coordinates=sys_.coordinates, units=tuple(DISPLAY_UNITS[x][0] for x in sys_.units),
            contacts=tuple(c.name for c in sys_.contacts), coordinate=self.coordinate,
            special=sorted(specials, key=lambda sp: sp.fe_hz if self.parameter == "f_e" else sp.pa_newton),
            stops=stops, settings=settings or {})


def linear_seed(system: System, pa_newton: float, fe_hz: float) -> np.ndarray:
    """The phase-0 state (q, q̇) [SI] of the steady response of the system linearised about its
    static state q_s: ``q = q_s + Re(X e^(iωt))``, ``(K_t − ω² M + iω C) X = b P_a``, with K_t the
    tangent stiffness there (a seed of Newton shooting below the contacts' amplitude)."""
    w = 2.0 * math.pi * float(fe_hz)
    qs = system.static_state()
    X = np.linalg.solve(system.tangent_stiffness(qs) - w * w * system.M + 1j * w * system.C,
                        system.b * float(pa_newton))
    return np.concatenate([qs + X.real, (1j * w * X).real])


def continue_system_orbit(system: System, pa_newton: float, fe_hz: float, z, period: int = 1, *,
                          parameter: str = "f_e", direction="both",
                          settings: SystemContinuationSettings | None = None, branch_id: str = "b0",
                          Q: float | None = None, coordinate: int = 0) -> SystemBranch:
    """Continue the period-``period`` orbit of ``system`` through the SI state ``z`` at
    P_a = ``pa_newton`` [N], f_e = ``fe_hz`` [Hz] in ``parameter`` ("f_e" or "P_a").

    Parameters
    ----------
    z : array_like (2n,)
        (q, q̇) [SI] at phase 0 near the orbit (refined by Newton shooting first).
    direction : {"both", "down", "up"}
        Decreasing, increasing parameter, or both (joined into one branch through the seed).
    Q : float, optional
        The force unit [N] of ``pa_over_q`` (the slide unit's M g); None: no Q.
    coordinate : int
        The coordinate whose A_pp the branch's ``app_um`` (and its figure) gives.

    Raises
    ------
    ParameterError
        Bad input (the seed's parameter outside the settings' range included).
    ComputationError
        The seed does not converge to a period-k orbit (``stage`` "continuation").
    """
    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a contactvib.model.System")
    settings = settings or SystemContinuationSettings()
    if not isinstance(settings, SystemContinuationSettings):
        raise ParameterError("settings", settings, "must be a SystemContinuationSettings")
    if parameter not in ("f_e", "P_a"):
        raise ParameterError("parameter", parameter, "must be 'f_e' or 'P_a'")
    if direction not in ("both", "down", "up"):
        raise ParameterError("direction", direction, "must be 'both', 'down' or 'up'")
    pa, fe = check_excitation(pa_newton, fe_hz)
    k = check_int("period", period, 1, KMAX_SEARCH_MAX)
    coordinate = check_int("coordinate", coordinate, 0, system.n - 1)
    z = check_state(system, z, "z")
    prob = SystemOrbitProblem(system, pa, fe, k, parameter, settings, Q, coordinate)
    q0 = fe if parameter == "f_e" else pa
    b = prob.bounds[0]
    if not (b.lo <= q0 <= b.hi):
        raise ParameterError(parameter, q0, f"seed must lie in the continuation range [{b.lo:g}, {b.hi:g}]")
    st, start = prob.fix_q(np.append(prob.scales.to_scaled(z), q0))
    if st != STATUS_OK:
        raise ComputationError(f"the seed does not converge to a period-{k} orbit at f_e = {fe:g} Hz, "
                               f"P_a = {pa:g} N ({status_message(st)})", stage="continuation")
    dirs = {"both": (-1, 1), "down": (-1,), "up": (1,)}[direction]
    parts = []
    e = np.zeros(start.u.size)
    for sgn in dirs:
        first = Point(start.u.copy(), start.J, start.data, start.residual, start.iterations)
        e[-1] = float(sgn)
        parts.append(prob.run(first, e.copy(), branch_id))
        if parts[-1][2].reason.startswith("closed branch"):
            break
    if len(parts) == 2:
        (pd_, sd, stop_d), (pu, su, stop_u) = parts
        points, specials, stops = pd_[::-1] + pu[1:], sd + su, [stop_d, stop_u]
    else:
        points, specials, stop = parts[0]
        stops = [stop]
    return prob.branch(points, specials, stops, branch_id, settings=settings.to_dict())
