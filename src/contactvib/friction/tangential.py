"""Friction under normal contact vibration at one operating point: the tangential motion driven
by the normal contact force R(t) of one normal attractor, to its periodic steady state.

The normal orbit (period k excitation periods) is recorded once (``steady.orbits.record``, the
7th-order step interpolants, steps ending on the contact events); the compiled tangential
integrator (:mod:`contactvib._kernels.friction`, :mod:`~contactvib._kernels.friction_period`)
goes through that record period after period from steady sliding without vibration (the drive
spring stretched by μ W, the slider at v_d, slipping) until its phase-0 state repeats after
j normal periods. Over those j periods the slider's mean velocity is v_d, so ⟨F_drive⟩ is the
mean friction force; the apparent friction coefficient over μ is

    friction_ratio = ⟨F_drive⟩ / (μ W),   W = Q + F_pre,

which is 1 without normal vibration (steady sliding at constant R = W): it is also the ratio to
the no-vibration value, and 1 − friction_ratio the friction reduction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels import friction as kf
from contactvib._kernels import friction_period as kp
from contactvib._kernels.contact import contact_force_array
from contactvib._kernels.flow import REC_H, REC_MODE, REC_T
from contactvib._kernels.orbit import sample_records
from contactvib._kernels.status import STATUS_INTERRUPTED, STATUS_OK, status_message
from contactvib.call_forms import old_form
from contactvib.errors import ComputationError
from contactvib.friction.model import FrictionModel
from contactvib.interrupts import new_stop_flag, run_interruptible
from contactvib.model import ContactModel, Excitation, ParameterError, check_excitation, check_int, check_range
from contactvib.steady.orbits import record
from contactvib.steady.results import Attractor

__all__ = ["FrictionResult", "FrictionHistory", "friction_at", "mean_limit"]

#: Integrator tolerance of the tangential motion.
RTOL = 1e-11
#: Distance of two phase-0 states, relative to the state plus its scale, at which the tangential
#: motion is periodic.
STEADY_TOL = 1e-9
#: Distance at which a settled run stops refining its steady state (or at its noise floor).
STEADY_TOL_FINE = 1e-13
#: Relative distance of z and P(z) at which a warm-started Newton run (``warm``, the sweeps'
#: friction columns) stops: the columns' relative accuracy.
WARM_TOL = 1e-6
#: Integrator tolerance of the tangential motion under a warm start (Newton to WARM_TOL).
WARM_RTOL = 1e-8
#: Integrator tolerance of the normal orbit's record under a warm start (1e-12 otherwise): its R(t)
#: to far below WARM_TOL, at 30 % fewer steps.
WARM_RECORD_RTOL = 1e-9
#: Drift [y0] per normal period below which a slider under a constant force is stuck (round-off).
STUCK_DRIFT = 1e-10
#: Largest tangential period searched [normal periods].
JMAX = 8
#: Gauss–Legendre nodes per normal step of :func:`mean_limit`.
_GL_NODES = 12


@dataclass
class FrictionHistory:
    """Time histories of the steady tangential motion over its period.

    Attributes
    ----------
    t_ms : ndarray
        Time [ms] from phase 0 of the excitation.
    normal_force_n : ndarray
        Normal contact force R [N] (0 in flight).
    friction_force_n : ndarray
        Tangential contact force F_t [N] on the contact (the slider feels −F_t).
    drive_force_n : ndarray
        Drive force k_d (v_d t − u) + c_d (v_d − u̇) [N].
    slip_velocity_mm_s : ndarray
        Velocity of the slip point [mm/s] (0 in stick; the slider's u̇ without compression).
    tangential_um : ndarray
        u − v_d t [µm], the slider behind the drive's end.
    mode : ndarray of str
        "stick", "slip" or "free" (no compression).
    """

    t_ms: np.ndarray
    normal_force_n: np.ndarray
    friction_force_n: np.ndarray
    drive_force_n: np.ndarray
    slip_velocity_mm_s: np.ndarray
    tangential_um: np.ndarray
    mode: np.ndarray


@dataclass
class FrictionResult:
    """The steady tangential motion under one normal attractor.

    Attributes
    ----------
    friction_ratio : float
        ⟨F_drive⟩ / (μ W) [1]: the apparent friction coefficient over μ, and its ratio to the
        no-vibration value (1); ``friction_reduction`` = 1 − friction_ratio.
    mu_apparent : float
        ⟨F_drive⟩ / W [1].
    mean_drive_force_n : float
        ⟨F_drive⟩ [N] over the steady period.
    limit_mean : float
        ⟨μ W (R⁺/W)^β⟩ / (μ W) [1]: the friction ratio of a contact that always slips forward
        (the limit of a fast drive); 1 for Coulomb friction when R ≥ 0 (⟨R⟩ = W), ≤ 1 under
        Hess & Soom (Jensen).
    stick_fraction, slip_fraction, free_fraction : float
        Fractions of the period in stick, in slip, and without compression (R ≤ 0: flight, or
        the damper pulling before a separation) [1].
    contact_loss_fraction : float
        Fraction of the period in flight, y < 0 [1] (the normal attractor's).
    tangential_app_um : float
        Peak-to-peak of u − v_d t over the period [µm] (the tangential oscillation; NaN under a
        force drive, where u drifts).
    mean_velocity_mm_s : float
        The slider's mean velocity [mm/s]: v_d under the velocity drive; under a constant force
        the creep that the vibration lets through (0: stuck), and then friction_ratio =
        (F_T − c_d · mean velocity) / (μ W).
    normal_period : int
        Period of the normal attractor [excitation periods].
    tangential_period : int
        Period of the tangential motion [normal periods] (0: not settled).
    settled : bool
        Whether the tangential motion became periodic within ``n_periods`` (if not, the means are
        over the second half of the run; their accuracy is that of a long-time average).
    n_periods : int
        Normal periods integrated.
    steady_distance : float
        Relative distance of the last two phase-0 states one tangential period apart [1].
    switches_per_period : float
        Located mode switches (stick, slip, free) per normal period.
    drive_work_uj, damper_dissipation_uj, slip_dissipation_uj, spring_work_uj : float
        Per steady period [µJ]: the drive's work (v_d ∫ F_drive dt, or F_T Δu), the damper's and the slip
        element's dissipation, and the work into the tangential spring (0 for a constant k_t; with
        k_t following the normal contact, what the neglected normal–tangential coupling exchanges).
    energy_residual : float
        (drive − damper − slip − spring) / drive work [1].
    friction : dict
        The FrictionModel's parameters.
    """

    friction_ratio: float
    mu_apparent: float
    mean_drive_force_n: float
    limit_mean: float
    stick_fraction: float
    slip_fraction: float
    free_fraction: float
    contact_loss_fraction: float
    tangential_app_um: float
    mean_velocity_mm_s: float
    normal_period: int
    tangential_period: int
    settled: bool
    n_periods: int
    steady_distance: float
    switches_per_period: float
    drive_work_uj: float
    damper_dissipation_uj: float
    slip_dissipation_uj: float
    spring_work_uj: float
    energy_residual: float
    friction: dict
    _run: tuple = field(default=(), repr=False, compare=False)

    @property
    def friction_reduction(self) -> float:
        """1 − friction_ratio [1]."""
        return 1.0 - self.friction_ratio

    def to_dict(self) -> dict:
        """The result as a JSON-ready dict (the CLI's per-attractor object)."""
        keys = [k for k in self.__dataclass_fields__ if not k.startswith("_")]
        d = {k: getattr(self, k) for k in keys}
        d["friction_reduction"] = self.friction_reduction
        return {k: (float(v) if isinstance(v, (np.floating, float)) else v) for k, v in d.items()}

    def history(self, samples_per_period: int = 2000) -> FrictionHistory:
        """R(t), F_t(t), the drive force, the slip velocity, u − v_d t and the mode over one steady
        period of the tangential motion (``samples_per_period`` per normal period)."""
        n = check_int("samples_per_period", samples_per_period, 16, 10**6)
        model, fm, rec, period, tpar, par, z0, mode, sigma, j = self._run
        ts = np.arange(j * n) * (period / n)
        st, so = kp.samples(rec, period, par, tpar, z0, mode, sigma, RTOL, fm.scales(model), j, ts)
        if st != STATUS_OK:
            raise ComputationError(f"tangential integration failed ({status_message(st)})", stage="friction")
        u, W = model.units, model.W
        w, v = so[:, kp.S_W], so[:, kp.S_V]
        names = np.array(["stick", "slip", "free"])
        return FrictionHistory(
            t_ms=ts * u.t_ms, normal_force_n=np.maximum(so[:, kp.S_R], 0.0) * W,
            friction_force_n=so[:, kp.S_F] * W,
            drive_force_n=(-tpar[kf.T_KD] * w - tpar[kf.T_CD] * v) * W,
            slip_velocity_mm_s=so[:, kp.S_SLIP] * u.ydot_mm_s, tangential_um=w * u.y_um,
            mode=names[so[:, kp.S_MODE].astype(int)])


def _normal_record(excitation: Excitation, attractor: Attractor, rtol: float | None = None):
    if attractor.period is None:
        raise ComputationError("a non-periodic normal attractor has no periodic R(t): friction is "
                               "computed for periodic attractors only", stage="friction")
    kw = {} if rtol is None else {"rtol": rtol}
    rec, _z, _tf = record(excitation, attractor.state, attractor.period, **kw)
    return rec, attractor.period * excitation.tau_period


def _normal_force(rec, par, tau):
    """r = R/W at sorted instants ``tau`` inside the record (0 in flight)."""
    x, v, contact = sample_records(rec, np.ascontiguousarray(tau, dtype=float))
    f, fx, fv = np.empty_like(x), np.empty_like(x), np.empty_like(x)
    contact_force_array(np.where(contact, np.maximum(x, 1e-300), 0.0), v, par, f, fx, fv)
    return np.where(contact, f, 0.0)


def _positive_parts(rec, par, i):
    """The sub-intervals [a, b] of contact step ``i`` where r > 0: its zeros (the damper pulling
    before a separation) bracketed on 65 points and located by bisection to 1e-15 of the step."""
    t0, h = rec[i, REC_T], rec[i, REC_H]
    th = np.linspace(0.0, 1.0, 65)
    pos = _normal_force(rec, par, t0 + h * np.clip(th, 1e-12, 1.0 - 1e-12)) > 0.0
    if pos.all():
        return [(t0, t0 + h)]
    cuts = [0.0]
    for k in np.nonzero(pos[1:] != pos[:-1])[0]:
        a, b = th[k], th[k + 1]
        while b - a > 1e-15:
            c = 0.5 * (a + b)
            if (_normal_force(rec, par, [t0 + h * c])[0] > 0.0) == pos[k]:
                a = c
            else:
                b = c
        cuts.append(0.5 * (a + b))
    cuts.append(1.0)
    mid = [0.5 * (cuts[q] + cuts[q + 1]) for q in range(len(cuts) - 1)]
    signs = _normal_force(rec, par, t0 + h * np.array(mid)) > 0.0
    return [(t0 + h * cuts[q], t0 + h * cuts[q + 1]) for q in range(len(mid)) if signs[q]]


def mean_limit(model: ContactModel, excitation: Excitation, attractor: Attractor, beta: float = 1.0) -> float:
    """⟨(R⁺/W)^β⟩ over the normal attractor's period [1], by Gauss–Legendre quadrature on each
    smooth piece of its record (R is smooth inside a step, the steps end on the contact events,
    and a step where R changes sign is cut at its zeros)."""
    beta = check_range("beta", beta, 0.0, False, "1", upper=1.0)
    rec, period = _normal_record(excitation, attractor)
    par = excitation.kernel_parameters()
    nodes, weights = np.polynomial.legendre.leggauss(_GL_NODES)
    total = 0.0
    for i in np.nonzero(rec[:, REC_MODE] > 0.5)[0]:
        for a, b in _positive_parts(rec, par, i):
            t = a + (b - a) * 0.5 * (nodes + 1.0)
            r = np.maximum(_normal_force(rec, par, t), 0.0)
            total += 0.5 * (b - a) * float(np.dot(weights, r ** beta))
    return total / period


def _start(rec, tpar, par):
    """Velocity drive: steady sliding without vibration, the drive spring stretched by μ W, the
    slider at v_d, slipping forward (free in flight). Force drive: the slider at rest, sticking
    with no tangential force."""
    if tpar[kf.T_KD] == 0.0:
        return np.zeros(3), kf.STICK, 1.0
    z0 = np.array([-tpar[kf.T_MU] / tpar[kf.T_KD], 0.0, tpar[kf.T_MU]])
    return z0, (kf.SLIP if rec[0, REC_MODE] > 0.5 else kf.FREE), 1.0


def _patience(tpar, period: float) -> int:
    """Periods without a halving of the steady distance after which the refinement stops: three
    decay times 2 M / c_d of the slider on its drive (at least 8; 50 without a damper)."""
    if tpar[kf.T_CD] <= 0.0:
        return 50
    return int(max(8, math.ceil(3.0 * 2.0 * tpar[kf.T_KAPPA] / tpar[kf.T_CD] / period)))


def auto_max_periods(model: ContactModel, fm: FrictionModel, period: float, tpar=None) -> int:
    """Default limit of normal periods: 60 decay times 2 M / c_d of the slider on its drive (what
    reaches the steady tolerance from a start error of order 1 with friction adding its own
    damping), at least 200, at most 20000; ten times that for a spring at rest (v_d = 0: the held
    slider creeps ever more slowly as the spring relaxes) (``tpar``: ``fm.kernel_parameters(model)``
    if known)."""
    tpar = fm.kernel_parameters(model) if tpar is None else tpar
    if tpar[kf.T_CD] <= 0.0:
        return 20000
    slow = 10.0 if fm.drive == "velocity" and fm.vd == 0.0 else 1.0  # a held slider's creep: slower
    return int(min(20000, max(200, math.ceil(slow * 60.0 * 2.0 * tpar[kf.T_KAPPA] / tpar[kf.T_CD] / period))))


def _newton(rec, par, tpar, scale, warm, k: int, fe_hz: float, cold):
    """The fixed point of the period map from ``warm``'s prediction at ``fe_hz`` [Hz] (or the
    ``cold`` start), ``warm``'s Jacobian kept when its period is ``k``, and the steady period from it in the layout of
    :func:`contactvib._kernels.friction_period.settle`'s outputs (n, j, distance, quad, times,
    wr, states, modes: one period); None if Newton does not converge."""
    from contactvib.friction.newton import newton_steady

    if warm.period != k:
        warm.jac = None
    start = cold if warm.z is None else (warm.predict(k, fe_hz), warm.mode, warm.sigma)
    got = newton_steady(rec, par, tpar, WARM_RTOL, scale, warm, *start, tol=WARM_TOL)
    if got is None:
        warm.jac = None
        return None
    z, mode, sigma, warm.jac, (pz, m1, s1, times, wr), _runs = got
    d = float(np.max(np.abs(pz[:3] - z) / (scale + np.abs(pz[:3]))))
    return (1, 1, d, pz[None, 3:].copy(), times[None, :], wr[None, :], np.vstack([z, pz[:3]]),
            np.array([[mode, int(sigma)], [m1, int(s1)]], np.int64))


@old_form("model", "excitation", "attractor", "friction")
def friction_at(excitation: Excitation, attractor: Attractor, *, friction: FrictionModel | None = None,
                max_periods: int | None = None, with_limit: bool = True, warm=None) -> FrictionResult:
    """The steady tangential motion (friction ratio, stick fraction, energies) under the normal
    attractor ``attractor`` at ``excitation`` (of its model, ``excitation.model``).

    Parameters
    ----------
    excitation, attractor
        The normal operating point and one of its periodic attractors (``find_attractors``).
    friction : FrictionModel
        Tangential parameters (default ``FrictionModel()``).
    max_periods : int or None
        Limit of normal periods to reach the steady state (None: ``auto_max_periods``).
        An unsettled run (a tangential motion that is not periodic with a period ≤ 8 normal
        periods, e.g. quasi-periodic stick–slip beating with the drive) is returned with
        ``settled = False`` and the means over the second half of its periods.
    with_limit : bool
        Compute ``limit_mean`` (a quadrature over the normal orbit; NaN when False: the dataset
        columns do without it).
    warm : contactvib.friction.newton.WarmStart or None
        Start from the (extrapolated) steady state of the neighbouring points of a branch
        (updated here to this one's) and find the fixed point of the period map by Newton's
        method (``contactvib.friction.newton.newton_steady``), to ``WARM_TOL`` (the
        tangential motion integrated at ``WARM_RTOL``, the normal orbit recorded at
        ``WARM_RECORD_RTOL``); the means are those of the period
        from the fixed point (the resonance sweeps' friction columns). Velocity drive only;
        where Newton does not converge the transient is settled from the warm state, to
        ``WARM_TOL``. None: the
        transient from steady sliding, refined to the integrator's noise floor.
    """
    model = check_excitation(excitation).model
    fm = FrictionModel() if friction is None else friction
    if not isinstance(fm, FrictionModel):
        raise ParameterError("friction", friction, "must be a FrictionModel")
    n_max = None if max_periods is None else check_int("max_periods", max_periods, 1, 10**6)
    rec, period = _normal_record(excitation, attractor, None if warm is None else WARM_RECORD_RTOL)
    tpar, par = fm.kernel_parameters(model), excitation.kernel_parameters()
    scale = fm.scales(model, tpar)
    z0, mode, sigma = _start(rec, tpar, par)
    got = None
    if warm is not None and fm.drive == "velocity":
        got = _newton(rec, par, tpar, scale, warm, attractor.period, excitation.f_e, (z0, mode, sigma))
        if got is None and warm.z is not None:
            z0, mode, sigma = warm.z, warm.mode, warm.sigma
    if got is not None:  # the fixed point and the steady period from it
        st, (n, j, dist, quad, times, wr, states, modes) = STATUS_OK, got
    else:
        n_max = auto_max_periods(model, fm, period, tpar) if n_max is None else n_max
        stop = new_stop_flag()  # Ctrl-C (or explore's stop) ends the kernel within one normal period
        # a warm start's fallback: to the columns' accuracy (WARM_TOL), not to the noise floor
        tols = (WARM_RTOL, WARM_TOL, WARM_TOL, 2) if warm is not None else \
            (RTOL, STEADY_TOL, STEADY_TOL_FINE, _patience(tpar, period))
        st, n, j, dist, quad, times, wr, states, modes = run_interruptible(
            kp.settle, rec, period, par, tpar, z0, mode, sigma, tols[0], scale, n_max, JMAX, tols[1], tols[2],
            tols[3], stop, stop=stop)
    if st == STATUS_INTERRUPTED:
        raise KeyboardInterrupt
    if st != STATUS_OK:
        raise ComputationError(f"tangential integration failed after {n} periods ({status_message(st)})",
                               stage="friction")
    jj = j if j > 0 else max(1, n // 2)  # unsettled (quasi-periodic stick-slip): the last half's mean
    sel = slice(n - jj, n)
    q = quad[sel].sum(axis=0)
    span = jj * period
    W, u = model.W, model.units
    energy = W * model.y0 * 1e6  # µJ per unit W y0
    ratio = q[0] / span / fm.mu
    drift = states[n, 0] - states[n - jj, 0]  # w over the window: 0 on a closed velocity-drive orbit
    force = fm.drive == "force"
    if force and abs(drift) <= STUCK_DRIFT * jj:  # stuck: the force never overcomes the contact
        drift = 0.0
    drive = tpar[kf.T_FT] * drift if force else tpar[kf.T_VD] * q[0]  # the drive's work
    tm = times[sel, :3].sum(axis=0) / span
    switches = times[sel, 3].sum() / jj
    jh = j if j > 0 else 1  # the history of an unsettled run: its last normal period
    if warm is not None:
        warm.push(states[n - jh], modes[n - jh, 0], modes[n - jh, 1], attractor.period, excitation.f_e)
    run = (model, fm, rec, period, tpar, par, states[n - jh].copy(), int(modes[n - jh, 0]),
           float(modes[n - jh, 1]), jh)
    return FrictionResult(
        friction_ratio=float(ratio), mu_apparent=float(ratio * fm.mu), mean_drive_force_n=float(ratio * fm.mu * W),
        limit_mean=mean_limit(model, excitation, attractor, fm.beta) if with_limit else math.nan,
        stick_fraction=float(tm[kf.STICK]), slip_fraction=float(tm[kf.SLIP]), free_fraction=float(tm[kf.FREE]),
        contact_loss_fraction=float(attractor.contact_loss_fraction),
        tangential_app_um=math.nan if force else float((wr[sel, 1].max() - wr[sel, 0].min()) * u.y_um),
        mean_velocity_mm_s=float((drift / span + tpar[kf.T_VD]) * u.ydot_mm_s),
        normal_period=int(attractor.period), tangential_period=int(j), settled=j > 0, n_periods=int(n),
        steady_distance=float(dist), switches_per_period=float(switches),
        drive_work_uj=float(drive * energy), damper_dissipation_uj=float(q[1] * energy),
        slip_dissipation_uj=float(q[2] * energy), spring_work_uj=float(q[3] * energy),
        energy_residual=float((drive - q[1] - q[2] - q[3]) / drive) if drive else math.nan,  # NaN: stuck
        friction=fm.parameters(), _run=run)
