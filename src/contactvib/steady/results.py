"""Result objects with units: time histories, attractors and attractor sets.

Conventions: ``y`` [µm] positive downwards (contact deflection for y > 0, a gap for y < 0),
``ẏ`` [mm/s], time [ms] or [s] as each field says, frequencies [Hz], forces as multiples of
Q = M g.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["TimeHistory", "Attractor", "AttractorSet", "dofs_and_contacts", "lyapunov_fields",
           "kaplan_yorke_dimension", "DOF_NAMES", "DOF_UNITS",
           "CONTACT_NAMES"]

#: The model's coordinates (degrees of freedom) as results list them, and their display units:
#: the paper's oscillator has one, the contact deflection y [µm].
DOF_NAMES = ("y",)
DOF_UNITS = ("um",)
#: The model's contact elements as results list them: the paper's oscillator has one.
CONTACT_NAMES = ("contact",)


def _number(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def dofs_and_contacts(*, dof_name, dof_unit, dof_min, dof_max, dof_app, dof_h1, contact_name,
                      contact_loses_contact, contact_loss_frac, contact_mean_force_n) -> dict:
    """The ``dofs`` and ``contacts`` lists of one steady state in the JSON contract.

    The one builder of these lists: :meth:`Attractor.to_dict` and the dataset query
    (:func:`contactvib.attractors_at`) both pass their columns here, named as the dataset's
    variables (``docs/formats.md``).

    Parameters
    ----------
    dof_name, dof_unit : sequence of str, length n
        Each coordinate's name and display unit (the paper's model: ``("y",)``, ``("um",)``).
    dof_min, dof_max, dof_app, dof_h1 : sequence of float, length n
        Each coordinate's minimum, maximum, peak-to-peak amplitude and one-sided amplitude of
        its component at f_e, in its display unit.
    contact_name : sequence of str, one per contact element
    contact_loses_contact : sequence of bool
        Whether the element opens somewhere on the motion.
    contact_loss_frac : sequence of float
        Fraction of the period with the element open [1].
    contact_mean_force_n : sequence of float
        Time average of the element's contact force over the motion [N] (NaN: not known).

    Returns
    -------
    dict
        ``{"dofs": [{"name", "unit", "min", "max", "app", "h1"}, ...],
        "contacts": [{"name", "loses_contact", "contact_loss_fraction", "mean_force_n"}, ...]}``;
        a value that is not finite is ``None``.
    """
    dofs = [{"name": str(n), "unit": str(u), "min": _number(lo), "max": _number(hi), "app": _number(a),
             "h1": _number(h)}
            for n, u, lo, hi, a, h in zip(dof_name, dof_unit, dof_min, dof_max, dof_app, dof_h1, strict=True)]
    contacts = [{"name": str(n), "loses_contact": bool(lc), "contact_loss_fraction": _number(fr),
                 "mean_force_n": _number(fm)}
                for n, lc, fr, fm in zip(contact_name, contact_loses_contact, contact_loss_frac,
                                         contact_mean_force_n, strict=True)]
    return {"dofs": dofs, "contacts": contacts}


def kaplan_yorke_dimension(exponents) -> float | None:
    """Kaplan–Yorke dimension of the flow's attractor from the map's exponents, the flow's zero
    exponent added: D = j + Σ_{i≤j} λ_i / |λ_{j+1}|, j the last index with a non-negative partial
    sum; None unless λ1 > 0."""
    lam = np.sort(np.asarray(exponents, float))[::-1]
    if lam.size == 0 or not lam[0] > 0.0:
        return None
    lam = np.sort(np.append(lam, 0.0))[::-1]
    partial = np.cumsum(lam)
    j = int(np.flatnonzero(partial >= 0.0)[-1]) + 1
    if j >= lam.size:
        return float(lam.size)
    return float(j + partial[j - 1] / abs(lam[j]))


def lyapunov_fields(attractor_type: str, exponents, stderr) -> dict:
    """The Lyapunov keys of an attractor in the JSON contract: ``attractor_type``,
    ``lyapunov_per_s`` (descending), ``lyapunov_stderr_per_s``, ``kaplan_yorke_dimension``
    (None unless λ1 > 0); non-finite values None."""
    return {"attractor_type": attractor_type,
            "lyapunov_per_s": [_number(v) for v in exponents],
            "lyapunov_stderr_per_s": [_number(v) for v in stderr],
            "kaplan_yorke_dimension": kaplan_yorke_dimension(exponents)}


@dataclass(frozen=True)
class TimeHistory:
    """Samples of a trajectory.

    Attributes
    ----------
    t_ms : ndarray
        Time [ms] from the start of the record (phase 0 of the excitation at t = 0).
    y_um : ndarray
        Displacement y [µm] (y > y_e contact deflection, y < y_e gap; y_e = 0 but for a law with
        a clearance).
    ydot_mm_s : ndarray
        Velocity ẏ [mm/s].
    in_contact : ndarray of bool
        True where y > y_e (the contact's deflection is positive).
    y0_um : float
        Static equilibrium position [µm] (the static deflection for y_e = 0).
    engagement_um : float
        y_e [µm], where the contact engages (0 but for a law with a clearance).
    fe_hz : float
        Excitation frequency [Hz].
    pa_over_q : float
        Excitation amplitude [Q] (under base motion, its inertial force's).
    base_um : ndarray or None
        Base displacement u(t) [µm] along y under base motion (None under a force).
    level : str
        The excitation level as titles write it ("P_a = 0.65 Q", "U = 0.05 µm").
    """

    t_ms: np.ndarray
    y_um: np.ndarray
    ydot_mm_s: np.ndarray
    in_contact: np.ndarray
    y0_um: float
    fe_hz: float
    pa_over_q: float
    base_um: np.ndarray | None = None
    level: str = ""
    engagement_um: float = 0.0

    @property
    def slider_um(self) -> np.ndarray:
        """The slider's absolute displacement s = y + u along y [µm] (= y under a force)."""
        return self.y_um if self.base_um is None else self.y_um + self.base_um


@dataclass(frozen=True)
class Attractor:
    """A stable steady state at one (P_a, f_e), periodic or not.

    Attributes
    ----------
    period : int or None
        Minimal period in excitation periods (None: non-periodic).
    kind : str
        ``"periodic"``, or for a proven non-periodic attractor ``"chaotic"`` (λ1 above 3 standard
        errors of its Benettin estimate) or ``"quasi-periodic"`` (``|λ1|`` within 3 standard errors
        and a stroboscopic section on a closed curve); ``"non-periodic"`` when not classified.
    minima_per_period : int or None
        Local minima of y(t) over the whole period-k orbit, counted cyclically.
    app_um, ymin_um, ymax_um : float
        Peak-to-peak amplitude y_max − y_min and the extrema [µm].
    loses_contact : bool
        Whether y < 0 somewhere on the orbit.
    contact_loss_fraction : float
        Fraction of the orbit's period spent with y < 0 [1].
    basin_fraction : float
        Fraction of the random start box that converged here [1] (0: found only by the
        physics-derived seeds, below the box sampling's resolution).
    floquet_multipliers : ndarray of complex
        The 2n eigenvalues of the period-k monodromy matrix (n = 1 coordinate: two), empty for
        non-periodic.
    strobe_y_um, strobe_ydot_mm_s : ndarray
        Stroboscopic points at phase 0 of the excitation, in orbit order.
    extrema_t_ms, extrema_y_um, extrema_is_min : ndarray
        Local extrema over one orbit period (non-periodic: over the recorded span).
    closure : float
        Relative closure ``|P^k(z) − z|∞ / max(1, |z|∞)`` of the refined orbit (inf if non-periodic).
    hits : int
        Number of starts (box and seeds) that reached it.
    state : ndarray
        Nondimensional orbit point (x = y/y0, x' = ẏ/(y0 ω_n0)) at phase 0, for reuse.
    lyapunov_per_period : float
        Largest Lyapunov exponent of the stroboscopic map [1/excitation period] of a
        non-periodic attractor, λ1/f_e of ``lyapunov_per_s`` (NaN for periodic orbits).
    slider_app_um : float or None
        Under base motion u(t): peak-to-peak amplitude [µm] of the slider's absolute displacement
        s = y + u over the orbit (what an accelerometer on the slider integrates to); None under
        a force, where s = y.
    h1_um : float
        One-sided amplitude [µm] of the f_e component of y(t) (the dataset's ``harmonics_um`` at
        j = period; non-periodic: over the recorded span), NaN where not measured.
    mean_contact_force_n : float
        Time average [N] of the contact force S c_n y^m2 + S h_n y^l ẏ (y > 0; the law's F_s + F_d)
        over the orbit's period (non-periodic: the recorded span), integrated along the orbit; for
        a periodic orbit it equals the static load W = Q + F_pre (the mean of the equation of
        motion). NaN where not measured.

    lyapunov_per_s, lyapunov_stderr_per_s : ndarray
        The Lyapunov spectrum of the period map [1/s], descending, and the standard error of each
        (``contactvib.steady.lyapunov``): ln ``|μ_i|`` / (k T) of a periodic orbit (standard errors 0),
        Benettin's batch means of a non-periodic attractor; empty where not computed.

    ``attractor_type`` and ``kaplan_yorke_dimension`` derive from them. ``dofs`` and ``contacts``
    of the JSON contract come from :meth:`dof_columns` through ``dofs_and_contacts``.
    """

    period: int | None
    kind: str
    minima_per_period: int | None
    app_um: float
    ymin_um: float
    ymax_um: float
    loses_contact: bool
    contact_loss_fraction: float
    basin_fraction: float
    floquet_multipliers: np.ndarray
    strobe_y_um: np.ndarray
    strobe_ydot_mm_s: np.ndarray
    extrema_t_ms: np.ndarray
    extrema_y_um: np.ndarray
    extrema_is_min: np.ndarray
    closure: float
    hits: int
    state: np.ndarray = field(repr=False)
    lyapunov_per_period: float = math.nan
    slider_app_um: float | None = None
    h1_um: float = math.nan
    mean_contact_force_n: float = math.nan
    lyapunov_per_s: np.ndarray = field(default_factory=lambda: np.empty(0))
    lyapunov_stderr_per_s: np.ndarray = field(default_factory=lambda: np.empty(0))

    @property
    def attractor_type(self) -> str:
        """"periodic", "quasi-periodic" or "chaotic" (the type the search earned: ``kind``)."""
        return "periodic" if self.period is not None else self.kind

    @property
    def kaplan_yorke_dimension(self) -> float | None:
        """Kaplan–Yorke dimension of the attractor in (y, ẏ, phase) where λ1 > 0, else None
        (``contactvib.steady.lyapunov.kaplan_yorke``)."""
        return kaplan_yorke_dimension(self.lyapunov_per_s)

    def dof_columns(self) -> dict:
        """The columns of ``dofs_and_contacts`` for this attractor (one coordinate y [µm], one
        contact), named as the dataset's per-point variables."""
        return {"dof_name": DOF_NAMES, "dof_unit": DOF_UNITS, "dof_min": [self.ymin_um],
                "dof_max": [self.ymax_um], "dof_app": [self.app_um], "dof_h1": [self.h1_um],
                "contact_name": CONTACT_NAMES, "contact_loses_contact": [self.loses_contact],
                "contact_loss_frac": [self.contact_loss_fraction],
                "contact_mean_force_n": [self.mean_contact_force_n]}

    @property
    def floquet_abs_max(self) -> float | None:
        """Largest ``|Floquet multiplier|`` [1] (None if non-periodic)."""
        if self.floquet_multipliers.size == 0:
            return None
        return float(np.max(np.abs(self.floquet_multipliers)))

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib attractors --json`` for this attractor."""
        d = {
            "period": self.period,
            "kind": self.kind,
            "minima_per_period": self.minima_per_period,
            "app_um": float(self.app_um),
            "ymin_um": float(self.ymin_um),
            "ymax_um": float(self.ymax_um),
            "loses_contact": bool(self.loses_contact),
            "contact_loss_fraction": float(self.contact_loss_fraction),
            "basin_fraction": float(self.basin_fraction),
            "floquet_abs_max": self.floquet_abs_max,
            "floquet_multipliers": [[float(m.real), float(m.imag)] for m in self.floquet_multipliers],
            "closure": float(self.closure) if np.isfinite(self.closure) else None,
            "lyapunov_per_period": (float(self.lyapunov_per_period)
                                    if math.isfinite(self.lyapunov_per_period) else None),
            "hits": int(self.hits),
            **lyapunov_fields(self.attractor_type, self.lyapunov_per_s, self.lyapunov_stderr_per_s),
            "strobe_points": [
                {"y_um": float(a), "ydot_mm_s": float(b)}
                for a, b in zip(self.strobe_y_um, self.strobe_ydot_mm_s)
            ],
            "extrema": [
                {"t_ms": float(t), "y_um": float(y), "type": "min" if m else "max"}
                for t, y, m in zip(self.extrema_t_ms, self.extrema_y_um, self.extrema_is_min)
            ],
        }
        if self.slider_app_um is not None:
            d["slider_app_um"] = float(self.slider_app_um)
        d.update(dofs_and_contacts(**self.dof_columns()))
        return d


@dataclass(frozen=True)
class AttractorSet:
    """All attractors found at one operating point, sorted by A_pp, largest first.

    Attributes
    ----------
    attractors : list of Attractor
    fn0_hz, y0_um : float
        Linear natural frequency [Hz] and static deflection [µm] of the model.
    pa_over_q, fe_hz : float
        Excitation amplitude [Q] and frequency [Hz].
    n_box, n_seeds : int
        Random starts in the box and physics-derived seeds.
    n_failed : int
        Starts that neither converged nor stayed bounded (integration failure).
    settings : dict
        Search settings used.
    n_unsettled : int
        Starts (box and seeds) that found no period within ``max_periods`` and whose strobe
        cloud is not a proven non-periodic attractor: still in a transient, not counted.
    unsettled_fraction : float
        Share of the box starts among them [1]; the basin fractions add up to 1 minus this
        (and the failed box starts).
    unsettled_reasons : dict
        The unsettled starts by the reason of the search's verdict ("free flight: no contact",
        "still converging", "strobe cloud still drifting", ...); the counts add up to
        ``n_unsettled``.
    model, excitation : dict
        What produced the result: the model's parameters (``ContactModel.parameters``, with the
        law, its parameters and a table's content hash) and ``Excitation.describe()``.
    """

    attractors: list
    fn0_hz: float
    y0_um: float
    pa_over_q: float
    fe_hz: float
    n_box: int
    n_seeds: int
    n_failed: int
    settings: dict
    n_unsettled: int = 0
    unsettled_fraction: float = 0.0
    model: dict | None = None
    unsettled_reasons: dict = field(default_factory=dict)
    excitation: dict | None = None

    def __len__(self):
        return len(self.attractors)

    def __iter__(self):
        return iter(self.attractors)

    def __getitem__(self, i):
        return self.attractors[i]

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib attractors --json``."""
        return {
            "fn0_hz": float(self.fn0_hz),
            "y0_um": float(self.y0_um),
            "pa_over_q": float(self.pa_over_q),
            "fe_hz": float(self.fe_hz),
            "n_box": int(self.n_box),
            "n_seeds": int(self.n_seeds),
            "n_failed": int(self.n_failed),
            "n_unsettled": int(self.n_unsettled),
            "unsettled_fraction": float(self.unsettled_fraction),
            "unsettled_reasons": {str(k): int(v) for k, v in self.unsettled_reasons.items()},
            "max_periods": int(self.settings.get("max_periods", 0)),
            "units": {"y": "um (positive = contact deflection)", "ydot": "mm/s", "t": "ms",
                      "f": "Hz", "P_a": "Q = M g"},
            "attractors": [a.to_dict() for a in self.attractors],
            **({"model": self.model} if self.model is not None else {}),
            **({"excitation": self.excitation} if self.excitation is not None else {}),
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), **kwargs)
