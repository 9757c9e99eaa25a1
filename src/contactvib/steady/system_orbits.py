"""One operating point of a :class:`~contactvib.model.system.System`: time histories, the
stroboscopic map and its monodromy, periodic orbits by Newton shooting, mean contact forces.

The structure ``M q̈ + C q̇ + K q = f0 + b P(t) − Σ_i w_i F_i`` (``contactvib.model.system``) under
P(t) = P_a cos(2π f_e t) [N] is integrated by the compiled event-located DOP853 of
``contactvib._kernels.system_flow`` in its scaled form (``contactvib.model.system_kernel``);
states here are SI: z = (q, q̇) with q in m or rad, q̇ in m/s or rad/s, phase 0 where P(t) is
largest. A period-k orbit solves ``P^k(z) − z = 0``; Newton's method uses the monodromy
``∂P^k/∂z`` from the variational equation (with the saltation matrices at the switches), whose
eigenvalues are the orbit's Floquet multipliers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib._kernels import system_map as km
from contactvib._kernels.shooting import is_stable
from contactvib._kernels.status import STATUS_OK, STATUS_RECORD_FULL, status_message
from contactvib._kernels.system_flow import rec_width, system_arrays
from contactvib.errors import ComputationError
from contactvib.model import ParameterError, check_int, check_range
from contactvib.model.checks import KMAX_SEARCH_MAX, MEMORY_MAX, SHOOTING_RTOL_RANGE, check_memory
from contactvib.model.system import System, check_excitation, check_state
from contactvib.steady.transients import LONG_PERIOD_MAX

__all__ = ["SystemHistory", "PeriodMap", "SystemOrbit", "simulate_system", "period_map", "periodic_orbit",
           "mean_contact_forces", "DISPLAY_UNITS"]

#: Display units of a coordinate and of its rate, with the factor from SI, by coordinate unit.
DISPLAY_UNITS = {"m": ("um", 1e6, "mm/s", 1e3), "rad": ("urad", 1e6, "mrad/s", 1e3)}
#: Newton shooting: iterations, and the relative closure |P^k(z) − z|∞ / max(1, |z|∞) (scaled state).
NEWTON_MAX_ITER = 40
NEWTON_TOL = 1e-10
#: Largest initial step record (rows) per excitation period; doubled while the records overflow.
_RECORD_ROWS = 2048


@dataclass(frozen=True, eq=False)
class SystemHistory:
    """Time histories of a system.

    Attributes
    ----------
    t_ms : ndarray (T,)
        Time [ms].
    q : ndarray (n, T)
        Coordinates in display units (``q_units``: µm for "m", µrad for "rad").
    qdot : ndarray (n, T)
        Rates in display units (``qdot_units``: mm/s, mrad/s).
    forces_n : ndarray (m, T)
        Each contact's force [N] (0 out of contact).
    in_contact : ndarray of bool (m, T)
        Each contact's mode.
    coordinates, q_units, qdot_units, contacts : tuple of str
        Names and units of the rows.
    z_end : ndarray (2n,)
        The SI state (q, q̇) at the end.
    """

    t_ms: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    forces_n: np.ndarray
    in_contact: np.ndarray
    coordinates: tuple
    q_units: tuple
    qdot_units: tuple
    contacts: tuple
    z_end: np.ndarray


@dataclass(frozen=True, eq=False)
class PeriodMap:
    """The stroboscopic map after k periods: ``z`` = P^k(z0) (SI state (q, q̇), 2n) and its
    monodromy ``∂P^k/∂z0`` (2n × 2n, SI)."""

    z: np.ndarray
    monodromy: np.ndarray
    k: int


@dataclass(frozen=True, eq=False)
class SystemOrbit:
    """A period-k orbit of a system at phase 0.

    Attributes
    ----------
    z : ndarray (2n,)
        Orbit point (q, q̇) [SI].
    k : int
        Period [excitation periods].
    monodromy : ndarray (2n, 2n)
        ∂P^k/∂z at z [SI].
    floquet_multipliers : ndarray of complex (2n,)
        Eigenvalues of the monodromy, largest modulus first.
    stable : bool
        max |μ| ≤ 1 + STABILITY_TOL (``contactvib._kernels.shooting.is_stable``).
    closure : float
        Relative closure |P^k(z) − z|∞ / max(1, |z|∞) in the scaled state.
    iterations : int
        Newton iterations taken.
    """

    z: np.ndarray
    k: int
    monodromy: np.ndarray
    floquet_multipliers: np.ndarray
    stable: bool
    closure: float
    iterations: int


def _check_system(system) -> System:
    if not isinstance(system, System):
        raise ParameterError("system", system, "must be a contactvib.model.System")
    return system


def _arrays(system: System, pa_newton, fe_hz):
    pa, fe = check_excitation(pa_newton, fe_hz)
    form = system.kernel_form(pa, fe)
    sa = system_arrays(form.Kx, form.Cx, form.g0, form.gb, form.r, form.U, form.gam, form.Aw, form.rows)
    return sa, form


def _rtol(rtol) -> float:
    lo, hi = SHOOTING_RTOL_RANGE
    return check_range("rtol", rtol, lo, True, upper=hi)


def _fail(status: int, what: str):
    raise ComputationError(f"{what}: {status_message(status)}", stage="integration")


def _strobe(sa, x, k, rtol, with_jac):
    """k periods of the scaled state x; (x_end, Φ or None)."""
    n2 = x.size
    out_z = np.empty(n2)
    out_phi = np.empty((n2, n2)) if with_jac else np.empty((0, 0))
    st = km.strobe_map(sa, np.ascontiguousarray(x, dtype=float), int(k), rtol, rtol, out_z, out_phi)
    if st != STATUS_OK:
        _fail(st, f"the period map over {k} periods")
    return out_z, (out_phi if with_jac else None)


def period_map(system: System, pa_newton: float, fe_hz: float, z0, k: int = 1, *, rtol: float = 1e-12) -> PeriodMap:
    """The stroboscopic map P^k(z0) after ``k`` excitation periods and its monodromy (SI).

    Parameters
    ----------
    system : System
    pa_newton, fe_hz : float
        P_a [N] ≥ 0 and f_e [Hz] > 0 of P(t) = P_a cos(2π f_e t).
    z0 : array_like (2n,)
        (q, q̇) at phase 0 [m or rad, m/s or rad/s].
    k : int
        Periods (1..64, ``KMAX_SEARCH_MAX``).
    rtol : float
        Integrator tolerance (relative, and absolute in the scales L_j, L_j ω).
    """
    system = _check_system(system)
    sa, form = _arrays(system, pa_newton, fe_hz)
    z0 = check_state(system, z0)
    k = check_int("k", k, 1, KMAX_SEARCH_MAX)
    x, phi = _strobe(sa, form.scales.to_scaled(z0), k, _rtol(rtol), True)
    return PeriodMap(z=form.scales.to_si(x), monodromy=form.scales.monodromy_to_si(phi), k=k)


def periodic_orbit(system: System, pa_newton: float, fe_hz: float, z_guess, k: int = 1, *,
                   rtol: float = 1e-12, tol: float = NEWTON_TOL) -> SystemOrbit:
    """Newton shooting for a period-``k`` orbit (1 ≤ k ≤ ``LONG_PERIOD_MAX`` = 512, the search's
    long periods) from ``z_guess`` (SI (q, q̇) at phase 0).

    Solves P^k(z) − z = 0 in the scaled state with (Φ − I) dz = −(P^k(z) − z), steps larger than
    0.5 (relative to max(1, |z|∞)) damped to 0.5; converged when the relative closure ≤ ``tol``.
    ComputationError (stage "newton") if Newton's method fails (singular, diverging, no convergence)."""
    system = _check_system(system)
    sa, form = _arrays(system, pa_newton, fe_hz)
    k = check_int("k", k, 1, LONG_PERIOD_MAX)
    rtol = _rtol(rtol)
    tol = check_range("tol", tol, 0.0, False)
    sc = form.scales
    x = sc.to_scaled(check_state(system, z_guess, "z_guess"))
    n2 = x.size
    closure = math.inf
    for it in range(NEWTON_MAX_ITER + 1):
        px, phi = _strobe(sa, x, k, rtol, True)
        g = px - x
        scale = max(1.0, float(np.max(np.abs(x))))
        closure = float(np.max(np.abs(g))) / scale
        if closure <= tol:
            mu = np.linalg.eigvals(sc.monodromy_to_si(phi))
            mu = mu[np.argsort(-np.abs(mu), kind="stable")]
            return SystemOrbit(z=sc.to_si(x), k=k, monodromy=sc.monodromy_to_si(phi), floquet_multipliers=mu,
                               stable=bool(is_stable(float(np.max(np.abs(mu))))), closure=closure, iterations=it)
        try:
            dx = np.linalg.solve(phi - np.eye(n2), -g)
        except np.linalg.LinAlgError:
            raise ComputationError("Newton shooting: singular monodromy (a multiplier at 1)", stage="newton") from None
        step = float(np.max(np.abs(dx))) / scale
        if not math.isfinite(step) or step > 10.0:
            raise ComputationError(f"Newton shooting diverged (relative step {step:.3g})", stage="newton")
        x = x + (dx * (0.5 / step) if step > 0.5 else dx)
    raise ComputationError(f"Newton shooting did not converge in {NEWTON_MAX_ITER} iterations "
                           f"(relative closure {closure:.3g})", stage="newton")


def _records(sa, system, x, n_periods, rtol):
    """Step records of ``n_periods`` from the scaled state x: (rec, rows, x_end)."""
    m = len(system.contacts)
    width = rec_width(system.n, m)
    rows = _RECORD_ROWS * n_periods
    while True:
        per_period = width * 8.0 * rows / n_periods
        check_memory("n_periods", n_periods, rows * width * 8.0, max(1, int(MEMORY_MAX // per_period)))
        rec = np.empty((rows, width))
        out = np.empty(x.size)
        nrec, st = km.record_span(sa, np.ascontiguousarray(x), int(n_periods), rtol, rtol, rec, out)
        if st == STATUS_RECORD_FULL:
            rows = 2 * int(nrec)
            continue
        if st != STATUS_OK:
            _fail(st, "the time history")
        return rec, int(nrec), out


def simulate_system(system: System, pa_newton: float, fe_hz: float, q0=None, qdot0=None, n_periods: int = 20,
                    samples_per_period: int = 400, *, rtol: float = 1e-10) -> SystemHistory:
    """Time histories over ``n_periods`` excitation periods from (``q0``, ``qdot0``) [SI] at phase 0.

    ``q0`` defaults to the static state, ``qdot0`` to rest. Sampled from the integrator's dense
    output, ``samples_per_period`` points per period (the end point included); coordinates in
    µm or µrad, rates in mm/s or mrad/s, contact forces in N."""
    system = _check_system(system)
    sa, form = _arrays(system, pa_newton, fe_hz)
    n = system.n
    q0 = system.static_state() if q0 is None else q0
    qdot0 = np.zeros(n) if qdot0 is None else qdot0
    z0 = check_state(system, np.concatenate([np.ravel(q0), np.ravel(qdot0)]), "q0, qdot0")
    n_periods = check_int("n_periods", n_periods, 1)
    spp = check_int("samples_per_period", samples_per_period, 2)
    check_memory("n_periods", n_periods, 8.0 * n_periods * spp * (4 * n + 3 * len(system.contacts)),
                 int(MEMORY_MAX // (8 * spp * (4 * n + 3 * len(system.contacts)))))
    sc = form.scales
    rec, nrec, x_end = _records(sa, system, sc.to_scaled(z0), n_periods, _rtol(rtol))
    tau = np.linspace(0.0, n_periods * form.tau_period, n_periods * spp + 1)
    m = len(system.contacts)
    ys = np.empty((2 * n, tau.size))
    modes = np.zeros((m, tau.size), dtype=np.bool_)
    km.sample_records(rec, nrec, m, tau, ys, modes)
    f = np.empty((m, tau.size))
    km.element_forces(sa, ys, modes, f)
    z = sc.to_si(ys)
    for i, c in enumerate(system.contacts):  # a table's last row, a tabulated law's extent
        c.law.check_motion(float(np.max(system.directions[i] @ z[:n])) - c.engagement, sc.deflection[i],
                           f"the trajectory (contact {c.name})")
    qf = np.array([DISPLAY_UNITS[u][1] for u in system.units])[:, None]
    vf = np.array([DISPLAY_UNITS[u][3] for u in system.units])[:, None]
    return SystemHistory(
        t_ms=tau / sc.omega * 1e3, q=z[:n] * qf, qdot=z[n:] * vf, forces_n=f * sc.force[:, None], in_contact=modes,
        coordinates=system.coordinates, q_units=tuple(DISPLAY_UNITS[u][0] for u in system.units),
        qdot_units=tuple(DISPLAY_UNITS[u][2] for u in system.units),
        contacts=tuple(c.name for c in system.contacts), z_end=sc.to_si(x_end))


def mean_contact_forces(system: System, pa_newton: float, fe_hz: float, z0, n_periods: int = 1, *,
                        rtol: float = 1e-12) -> np.ndarray:
    """Each contact's mean force ⟨F_i⟩ [N] over ``n_periods`` from z0 (SI, phase 0): the integral
    over every integration step by 8-point Gauss–Legendre on the dense output (steps end on the
    switches, so each is smooth), divided by the span."""
    system = _check_system(system)
    sa, form = _arrays(system, pa_newton, fe_hz)
    z0 = check_state(system, z0)
    n_periods = check_int("n_periods", n_periods, 1)
    rec, nrec, _x = _records(sa, system, form.scales.to_scaled(z0), n_periods, _rtol(rtol))
    out = np.empty(len(system.contacts))
    km.mean_element_forces(sa, rec, nrec, out)
    return out * form.scales.force / (n_periods * form.tau_period)
