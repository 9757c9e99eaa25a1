"""Stroboscopic Poincaré sections and impact maps of the attractors at one operating point.

The stroboscopic section of an attractor is the sequence of states (y, ẏ) at t = k/f_e,
k = 0, 1, …, N − 1, integrated from the attractor's state at phase 0; a period-k orbit gives its k
distinct points, a non-periodic attractor a cloud (chaos) or a closed curve (quasi-periodic
motion). The impact map is the sequence of states at each contact loss (the instants where the
deflection y returns to the contact's engagement point from inside the contact): the excitation's
phase φ = 2π f_e t mod 2π there and the velocity ẏ at the loss. Both come from the step records
of the compiled DOP853 flow (``contactvib._kernels.flow``), whose contact switches are located
on the dense output and land the step exactly on them.

λ1, the largest Lyapunov exponent of the stroboscopic map [1/excitation period], is
``largest_exponent``: the one place it is computed for the sections and the orbit diagram.

Units: y [µm], ẏ [mm/s], phase [rad] and [fraction of the period], λ1 [1/period].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels.flow import REC_MODE, REC_T, REC_V, REC_X
from contactvib._kernels.orbit import record_steps, sample_records
from contactvib._kernels.shooting import is_stable, strobe_map
from contactvib._kernels.status import STATUS_OK, status_message
from contactvib.errors import ComputationError
from contactvib.model import Excitation, check_excitation, check_int, check_range
from contactvib.model.checks import MEMORY_MAX, check_memory
from contactvib.steady.results import Attractor, AttractorSet

__all__ = ["largest_exponent", "trajectory_points", "TrajectoryPoints", "AttractorSection", "SectionSet",
           "poincare_sections", "check_section_periods", "repeating_period", "stable_orbit_in", "SECTION_RTOL",
           "SECTION_PERIOD_TOL"]

#: Integrator tolerance of the sections (the reference test uses it against scipy at 1e-10).
SECTION_RTOL = 1e-10
#: Periods integrated per record (the step records of one chunk are held at once).
_CHUNK = 64
#: Initial step records per period (the buffer grows as needed).
_ROWS_PER_PERIOD = 512
#: Periods of the Benettin run that gives a non-periodic attractor's λ1 (10 batches).
LAMBDA_PERIODS = 1000
#: Bytes per recorded period of a section (its points and impacts; generous).
_BYTES_PER_PERIOD = 256


def largest_exponent(excitation: Excitation, z, period: int | None = None, *, multipliers=None,
                     rtol: float = SECTION_RTOL) -> float:
    """λ1, the largest Lyapunov exponent of the stroboscopic map [1/excitation period].

    A period-k orbit (``period`` = k): λ1 = ln(max |μ|) / k, μ its Floquet ``multipliers`` (the
    eigenvalues of the k-period monodromy; without them the orbit is refined by Newton shooting
    from ``z``). Otherwise (``period`` None) the largest exponent of the spectrum by Benettin's
    method over :data:`LAMBDA_PERIODS` periods from ``z`` (:func:`contactvib.steady.lyapunov.benettin`,
    the attractor search's own estimate), per excitation period. NaN where the integration fails.
    """
    z = np.asarray(z, float)
    if period is None:
        from contactvib.errors import ComputationError
        from contactvib.steady.lyapunov import benettin

        try:
            spec = benettin(excitation, z, LAMBDA_PERIODS, 10, 0, rtol, with_trace=False)
        except ComputationError:
            return math.nan
        return float(spec.exponents_per_s[0]) / excitation.f_e
    if multipliers is None or np.size(multipliers) == 0:
        from contactvib.steady.orbits import refine_orbit

        _z, monodromy, _res = refine_orbit(excitation, z, period)
        multipliers = np.linalg.eigvals(monodromy)
    mu = float(np.max(np.abs(multipliers)))
    return math.log(mu) / period if mu > 0.0 else -math.inf


@dataclass(frozen=True)
class TrajectoryPoints:
    """Stroboscopic points and contact losses of a trajectory (nondimensional, as the kernels').

    Attributes
    ----------
    strobe : ndarray (n, 2)
        (x, x') at τ = kT, k = 0..n − 1 (T = 2π/r, the excitation period).
    loss_tau : ndarray
        Instants of the contact losses [τ] from the start (x reaches 0 from x > 0).
    loss_v : ndarray
        x' at each loss [y0 ω_n0] (≤ 0: leaving the contact).
    z_end : ndarray (2,)
        State at τ = nT.
    """

    strobe: np.ndarray
    loss_tau: np.ndarray
    loss_v: np.ndarray
    z_end: np.ndarray


def _losses(rec: np.ndarray):
    """Contact losses of step records: a row in flight that starts on x = 0 after a row in
    contact (the flow lands a step on each located switch and starts the next one there)."""
    if rec.shape[0] < 2:
        return np.empty(0), np.empty(0)
    mode = rec[:, REC_MODE] > 0.5
    at = np.flatnonzero(mode[:-1] & ~mode[1:] & (rec[1:, REC_X] == 0.0)) + 1
    return rec[at, REC_T].copy(), rec[at, REC_V].copy()


def trajectory_points(excitation: Excitation, z, n_periods: int, *, rtol: float = SECTION_RTOL) -> TrajectoryPoints:
    """Integrate ``n_periods`` from the nondimensional state ``z`` at phase 0 and keep the
    stroboscopic points and the contact losses (``TrajectoryPoints``); records of at most
    64 periods are held at once."""
    par = excitation.kernel_parameters()
    T = excitation.tau_period
    cur = np.asarray(z, float).copy()
    strobe, taus, vs = [], [], []
    done = 0
    while done < n_periods:
        n = min(_CHUNK, n_periods - done)
        rec, z_end, _tf, _ne, st = record_steps(cur, 0.0, np.int64(n), par, rtol, _ROWS_PER_PERIOD * n, 0)
        if st != STATUS_OK:
            raise ComputationError(f"integration failed after {done} periods ({status_message(st)})",
                                   stage="integration")
        pts = np.empty((n, 2))
        pts[0] = cur
        if n > 1:
            xs, v, _c = sample_records(rec, np.arange(1, n) * T)
            pts[1:, 0], pts[1:, 1] = xs, v
        strobe.append(pts)
        t, v = _losses(rec)
        taus.append(t + done * T)
        vs.append(v)
        cur = np.asarray(z_end, float).copy()
        done += n
    return TrajectoryPoints(np.vstack(strobe), np.concatenate(taus), np.concatenate(vs), cur)


def repeating_period(strobe: np.ndarray, kmax: int, tol: float) -> int | None:
    """The smallest k ≤ kmax with the strobe points (n, 2) repeating after k periods to ``tol``
    (relative to max(1, |points|∞)), or None."""
    n = strobe.shape[0]
    scale = max(1.0, float(np.max(np.abs(strobe))))
    for k in range(1, min(kmax, n - 1) + 1):
        if float(np.max(np.abs(strobe[k:] - strobe[:-k]))) <= tol * scale:
            return k
    return None


def _stable_newton(excitation: Excitation, z, k: int):
    """The stable period-k orbit that Newton shooting reaches from ``z``: (z, multipliers), or None."""
    from contactvib.steady.orbits import refine_orbit

    try:
        z_orb, M, _res = refine_orbit(excitation, z, k)
    except ComputationError:
        return None
    mu = np.linalg.eigvals(M)
    return (z_orb, mu) if is_stable(float(np.max(np.abs(mu)))) else None


def _minimal_period(strobe: np.ndarray, k: int, tol: float = 1e-7) -> int:
    """The smallest divisor d of k with the orbit's strobe point d equal to point 0 (relative ``tol``)."""
    scale = max(1.0, float(np.max(np.abs(strobe))))
    for d in range(1, k):
        if k % d == 0 and float(np.max(np.abs(strobe[d] - strobe[0]))) <= tol * scale:
            return d
    return k


def _monodromy(excitation: Excitation, z, k: int, rtol: float) -> np.ndarray:
    M = np.empty((2, 2))
    st = strobe_map(np.asarray(z, float).copy(), np.int64(k), excitation.kernel_parameters(), rtol, rtol,
                    np.empty(2), M)
    return M if st == STATUS_OK else np.full((2, 2), np.nan)


def stable_orbit_in(excitation: Excitation, pts: TrajectoryPoints, kmax: int, tol: float, rtol: float = SECTION_RTOL):
    """The stable periodic orbit that a recorded trajectory ``pts`` approaches: its points repeat
    after k ≤ kmax periods to ``tol`` (:func:`repeating_period`), Newton shooting on P^k from the
    last state converges (closure 1e-10) to a stable orbit, described by its minimal period d | k.
    Returns ``(d, z, multipliers, TrajectoryPoints over d periods)`` or None."""
    k = repeating_period(pts.strobe, kmax, tol)
    orbit = _stable_newton(excitation, pts.z_end, k) if k is not None else None
    if orbit is None:
        return None
    z_orb, mu = orbit
    one = trajectory_points(excitation, z_orb, k, rtol=rtol)
    d = _minimal_period(one.strobe, k)
    if d < k:  # Newton on P^k reached an orbit of period d, a divisor of k: describe it as such
        mu = np.linalg.eigvals(_monodromy(excitation, z_orb, d, rtol))
        one = trajectory_points(excitation, z_orb, d, rtol=rtol)
    return d, z_orb, mu, one


@dataclass(frozen=True)
class AttractorSection:
    """The stroboscopic section and impact map of one attractor.

    Attributes
    ----------
    index : int
        The attractor's number in the search's list (largest A_pp first).
    kind : str
        ``"periodic"``, ``"chaotic"``, ``"quasi-periodic"`` or ``"non-periodic"``.
    period : int or None
        Minimal period [excitation periods] (None: non-periodic).
    n_periods : int
        Excitation periods integrated (a period-k orbit: k).
    y_um, ydot_mm_s : ndarray
        The section's points: y [µm] and ẏ [mm/s] at t = k/f_e, in time order (a period-k orbit:
        its k points, starting at the attractor's state).
    loss_phase_rad : ndarray
        Excitation phase 2π f_e t mod 2π at each contact loss [rad] (impact map).
    loss_ydot_mm_s : ndarray
        ẏ at each contact loss [mm/s] (≤ 0: leaving the contact).
    lambda1 : float
        Largest Lyapunov exponent of the stroboscopic map [1/excitation period] (``largest_exponent``).
    search_kind : str
        The search's kind where the section found a stable periodic orbit that the search
        (periods up to its kmax) had classified as non-periodic; "" otherwise.
    """

    index: int
    kind: str
    period: int | None
    n_periods: int
    y_um: np.ndarray
    ydot_mm_s: np.ndarray
    loss_phase_rad: np.ndarray
    loss_ydot_mm_s: np.ndarray
    lambda1: float
    search_kind: str = ""

    @property
    def loss_phase_fraction(self) -> np.ndarray:
        """Excitation phase at each contact loss [fraction of the period, 0..1)."""
        return self.loss_phase_rad / (2.0 * math.pi)

    @property
    def label(self) -> str:
        """``"period 3: 3 points"``, ``"chaotic: 1000 points"`` or ``"period 12: 12 points (the search:
        chaotic)"``."""
        n = self.y_um.size
        what = f"period {self.period}" if self.period is not None else self.kind
        note = f" (the search: {self.search_kind})" if self.search_kind else ""
        return f"{what}: {n} point{'s' if n != 1 else ''}{note}"


@dataclass(frozen=True)
class SectionSet:
    """The sections of every attractor at one operating point.

    Attributes
    ----------
    sections : list of AttractorSection
    fe_hz, pa_over_q : float
        Excitation frequency [Hz] and amplitude [Q].
    y0_um, fn0_hz : float
        Static deflection [µm] and linear natural frequency [Hz] of the model.
    n_periods : int
        Periods integrated per non-periodic attractor.
    level : str
        The excitation level as titles write it (``"P_a = 0.75 Q"``).
    """

    sections: list
    fe_hz: float
    pa_over_q: float
    y0_um: float
    fn0_hz: float
    n_periods: int
    level: str = ""
    units: dict = field(default_factory=lambda: {
        "y_um": "um", "ydot_mm_s": "mm/s", "phase_rad": "rad", "phase_frac": "1 (fraction of the period)",
        "v_loss_mm_s": "mm/s", "lambda1": "1/excitation period", "fe_hz": "Hz", "pa_over_q": "Q = M g"})

    def __len__(self):
        return len(self.sections)

    def __iter__(self):
        return iter(self.sections)

    def __getitem__(self, i):
        return self.sections[i]

    def rows(self, impacts: bool = False) -> list[dict]:
        """One dict per point (section points; with ``impacts`` the impact-map points after them):
        attractor, kind, period (0: non-periodic), k, y_um, ydot_mm_s, phase_rad, phase_frac,
        v_loss_mm_s (NaN where not of that map)."""
        out = []
        for s in self.sections:
            for k, (y, v) in enumerate(zip(s.y_um, s.ydot_mm_s)):
                out.append({"attractor": s.index, "kind": s.kind, "map": "section", "period": s.period or 0,
                            "k": k, "y_um": y, "ydot_mm_s": v, "phase_rad": math.nan, "phase_frac": math.nan,
                            "v_loss_mm_s": math.nan})
            if impacts:
                for k, (ph, v) in enumerate(zip(s.loss_phase_rad, s.loss_ydot_mm_s)):
                    out.append({"attractor": s.index, "kind": s.kind, "map": "impact", "period": s.period or 0,
                                "k": k, "y_um": math.nan, "ydot_mm_s": math.nan, "phase_rad": ph,
                                "phase_frac": ph / (2.0 * math.pi), "v_loss_mm_s": v})
        return out

    def to_csv(self, path, impacts: bool = False):
        """Write ``rows()`` as CSV with a ``#`` header of the operating point and the units."""
        cols = ["attractor", "kind", "map", "period", "k", "y_um", "ydot_mm_s", "phase_rad", "phase_frac",
                "v_loss_mm_s"]
        lines = [f"# contactvib section: {self.level}, f_e = {self.fe_hz:g} Hz; stroboscopic points at "
                 f"t = k/f_e (map = section) and contact losses (map = impact)",
                 "# units: y_um [um], ydot_mm_s [mm/s], phase_rad [rad], phase_frac [fraction of the "
                 "excitation period], v_loss_mm_s [mm/s], period [excitation periods, 0: non-periodic]",
                 ",".join(cols)]
        for r in self.rows(impacts):
            lines.append(",".join(_cell(r[c]) for c in cols))
        with open(path, "w", encoding="utf-8") as fh:
            fh.write("\n".join(lines) + "\n")
        return path

    def to_dict(self, impacts: bool = False) -> dict:
        """JSON form: the operating point, the units, and per attractor its points."""
        return {
            "fe_hz": self.fe_hz, "pa_over_q": self.pa_over_q, "y0_um": self.y0_um, "fn0_hz": self.fn0_hz,
            "n_periods": self.n_periods, "units": dict(self.units),
            "attractors": [{
                "attractor": s.index, "kind": s.kind, "search_kind": s.search_kind or None, "period": s.period,
                "n_periods": s.n_periods,
                "lambda1": s.lambda1, "y_um": s.y_um.tolist(), "ydot_mm_s": s.ydot_mm_s.tolist(),
                **({"phase_rad": s.loss_phase_rad.tolist(), "v_loss_mm_s": s.loss_ydot_mm_s.tolist()}
                   if impacts else {})} for s in self.sections],
        }


def _cell(v) -> str:
    if isinstance(v, (float, np.floating)):
        return "" if math.isnan(v) else repr(float(v))
    return str(v)


def check_section_periods(n_periods) -> int:
    """``n_periods`` of ``poincare_sections``: an integer ≥ 1 whose points fit in memory."""
    n = check_int("n_periods", n_periods, 1)
    check_memory("n_periods", n, float(n) * _BYTES_PER_PERIOD, MEMORY_MAX // _BYTES_PER_PERIOD)
    return n


#: Relative repetition of a non-periodic attractor's strobe points (the second half of its
#: section) below which the section tries a periodic orbit by Newton shooting.
SECTION_PERIOD_TOL = 1e-6


def attractor_section(excitation: Excitation, attractor: Attractor, index: int = 0, *, n_periods: int = 1000,
                      rtol: float = SECTION_RTOL) -> AttractorSection:
    """The section and impact map of one ``attractor`` of ``excitation``: a period-k orbit over k
    periods from its state (its k points), a non-periodic attractor over ``n_periods``.

    A non-periodic attractor whose strobe points repeat after k ≤ n_periods/4 periods (to
    :data:`SECTION_PERIOD_TOL` over the second half) and that Newton shooting refines to a stable
    period-k orbit (a period beyond the search's kmax) is drawn as that orbit: its k points, λ1 from
    its Floquet multipliers, ``search_kind`` the search's verdict."""
    u = excitation.model.units
    n = attractor.period if attractor.period is not None else n_periods
    pts = trajectory_points(excitation, attractor.state, n, rtol=rtol)
    period, kind, search_kind = attractor.period, attractor.kind, ""
    if period is not None:
        lam = largest_exponent(excitation, attractor.state, period, multipliers=attractor.floquet_multipliers)
    else:
        tail = TrajectoryPoints(pts.strobe[n // 2:], pts.loss_tau, pts.loss_v, pts.z_end)
        orbit = stable_orbit_in(excitation, tail, n // 4, SECTION_PERIOD_TOL, rtol) if n >= 8 else None
        if orbit is not None:
            period, z_orb, mu, pts = orbit
            kind, search_kind, n = "periodic", attractor.kind, period
            lam = largest_exponent(excitation, z_orb, period, multipliers=mu)
        else:
            lam = attractor.lyapunov_per_period if math.isfinite(attractor.lyapunov_per_period) else \
                largest_exponent(excitation, attractor.state)
    phase = np.mod(pts.loss_tau, excitation.tau_period) * excitation.r
    return AttractorSection(index=index, kind=kind, period=period, n_periods=n,
                            y_um=u.position_um(pts.strobe[:, 0]), ydot_mm_s=pts.strobe[:, 1] * u.ydot_mm_s,
                            loss_phase_rad=phase, loss_ydot_mm_s=pts.loss_v * u.ydot_mm_s, lambda1=float(lam),
                            search_kind=search_kind)


def poincare_sections(excitation: Excitation, attractors: AttractorSet | None = None, *, n_periods: int = 1000,
                      rtol: float = SECTION_RTOL) -> SectionSet:
    """Stroboscopic sections and impact maps of the attractors at ``excitation``.

    Parameters
    ----------
    excitation : Excitation
        The operating point.
    attractors : AttractorSet or None
        Its attractors (:func:`contactvib.find_attractors`; None: searched with the defaults).
    n_periods : int
        Excitation periods integrated per non-periodic attractor (≥ 1); a period-k orbit is
        integrated over its k periods.
    rtol : float
        Integrator tolerance.

    Returns
    -------
    SectionSet
    """
    model = check_excitation(excitation).model
    n_periods = check_section_periods(n_periods)
    rtol = check_range("rtol", rtol, 0.0, False)
    if attractors is None:
        from contactvib.steady.attractors import find_attractors

        attractors = find_attractors(excitation)
    sections = [attractor_section(excitation, a, i, n_periods=n_periods, rtol=rtol)
                for i, a in enumerate(attractors)]
    sym, val, unit = excitation.level
    level = f"{'P_a' if sym == 'P_a/Q' else sym} = {val:g} {'µm' if unit == 'um' else unit}"
    return SectionSet(sections=sections, fe_hz=excitation.f_e, pa_over_q=excitation.pa_over_q,
                      y0_um=model.units.y_um, fn0_hz=model.f_n0, n_periods=n_periods, level=level)
