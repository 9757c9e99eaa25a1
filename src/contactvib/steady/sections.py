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

from contactvib._kernels.describe import NP_LYAPUNOV, lyapunov_strobe
from contactvib._kernels.flow import REC_MODE, REC_T, REC_V, REC_X
from contactvib._kernels.orbit import record_steps, sample_records
from contactvib._kernels.status import STATUS_OK, status_message
from contactvib.errors import ComputationError
from contactvib.model import Excitation, check_excitation, check_int, check_range
from contactvib.model.checks import MEMORY_MAX, check_memory
from contactvib.steady.results import Attractor, AttractorSet

__all__ = ["largest_exponent", "trajectory_points", "TrajectoryPoints", "AttractorSection",
           "SectionSet", "poincare_sections", "check_section_periods", "SECTION_RTOL"]

#: Integrator tolerance of the sections (the reference test uses it against scipy at 1e-10).
SECTION_RTOL = 1e-10
#: Periods integrated per record (the step records of one chunk are held at once).
_CHUNK = 64
#: Initial step records per period (the buffer grows as needed).
_ROWS_PER_PERIOD = 512
#: Bytes per recorded period of a section (its points and impacts; generous).
_BYTES_PER_PERIOD = 256


def largest_exponent(excitation: Excitation, z, period: int | None = None, *, multipliers=None,
                     rtol: float = SECTION_RTOL) -> float:
    """λ1, the largest Lyapunov exponent of the stroboscopic map [1/excitation period].

    A period-k orbit (``period`` = k): λ1 = ln(max |μ|) / k, μ its Floquet ``multipliers`` (the
    eigenvalues of the k-period monodromy; without them the orbit is refined by Newton shooting
    from ``z``). Otherwise (``period`` None) the tangent-vector estimate of
    ``contactvib._kernels.describe.lyapunov_strobe`` over ``NP_LYAPUNOV`` (64) periods from
    ``z`` (Benettin et al. 1980). NaN where the integration fails.
    """
    z = np.asarray(z, float)
    if period is None:
        return float(lyapunov_strobe(z.copy(), excitation.kernel_parameters(), rtol, NP_LYAPUNOV))
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

    @property
    def loss_phase_fraction(self) -> np.ndarray:
        """Excitation phase at each contact loss [fraction of the period, 0..1)."""
        return self.loss_phase_rad / (2.0 * math.pi)

    @property
    def label(self) -> str:
        """``"period 3: 3 points"`` or ``"chaotic: 1000 points"``."""
        n = self.y_um.size
        what = f"period {self.period}" if self.period is not None else self.kind
        return f"{what}: {n} point{'s' if n != 1 else ''}"


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
                "attractor": s.index, "kind": s.kind, "period": s.period, "n_periods": s.n_periods,
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


def attractor_section(excitation: Excitation, attractor: Attractor, index: int = 0, *, n_periods: int = 1000,
                      rtol: float = SECTION_RTOL) -> AttractorSection:
    """The section and impact map of one ``attractor`` of ``excitation``: a period-k orbit over k
    periods from its state (its k points), a non-periodic attractor over ``n_periods``."""
    u = excitation.model.units
    n = attractor.period if attractor.period is not None else n_periods
    pts = trajectory_points(excitation, attractor.state, n, rtol=rtol)
    phase = np.mod(pts.loss_tau, excitation.tau_period) * excitation.r
    if attractor.period is not None:
        lam = largest_exponent(excitation, attractor.state, attractor.period,
                               multipliers=attractor.floquet_multipliers)
    else:
        lam = attractor.lyapunov_per_period if math.isfinite(attractor.lyapunov_per_period) else \
            largest_exponent(excitation, attractor.state)
    return AttractorSection(index=index, kind=attractor.kind, period=attractor.period, n_periods=n,
                            y_um=u.position_um(pts.strobe[:, 0]), ydot_mm_s=pts.strobe[:, 1] * u.ydot_mm_s,
                            loss_phase_rad=phase, loss_ydot_mm_s=pts.loss_v * u.ydot_mm_s, lambda1=float(lam))


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
