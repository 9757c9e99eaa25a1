"""The fields every shooting continuation's settings share, checked in one place.

:class:`BranchSettings` is the base of :class:`~contactvib.continuation.shooting.ContinuationSettings`
(the slider, P_a in units of Q) and
:class:`~contactvib.continuation.system_shooting.SystemContinuationSettings` (a System, P_a in N).
Both hold the same fields with the same meaning and unit, checked by :meth:`BranchSettings.checked`
in this order (each against the checked values before it)::

    fmin_hz > 0 (≥ 0 where FMIN_ZERO)   fmax_hz > fmin_hz                                [Hz]
    level range: lower ≥ 0, upper > lower                                  [Q or N, LEVEL_RANGE]
    ds_min > 0,  ds ≥ ds_min,  ds_max ≥ ds                                   [relative units]
    max_points ≥ BRANCH_POINTS_MIN   app_max_um > 0 [µm]   rtol in SHOOTING_RTOL_RANGE
    tol > 0   max_iter ≥ 1   max_turn > 0 [rad]   locate_tol > 0   max_failures ≥ 1

(the steps and the Newton corrector by :func:`check_steps` and :func:`check_newton`, which
:class:`~contactvib.frequency.harmonic_balance.HBSettings` uses too), and give the one engine's
corrector (:meth:`BranchSettings.corrector`) and step control
(:meth:`BranchSettings.step_control`) the same way.
"""

from __future__ import annotations

from contactvib.continuation.engine import CorrectorSettings, StepControl
from contactvib.model import check_int, check_range
from contactvib.model.checks import SHOOTING_RTOL_RANGE

__all__ = ["BranchSettings", "BRANCH_POINTS_MIN", "check_steps", "check_newton"]

#: Smallest ``max_points``: a direction of a branch is its start and at least one step.
BRANCH_POINTS_MIN = 2


def check_steps(ds, ds_min, ds_max) -> dict:
    """The pseudo-arclength steps of any continuation checked [relative units]:
    ``0 < ds_min ≤ ds ≤ ds_max``, by name as floats."""
    v = {"ds_min": check_range("ds_min", ds_min, 0.0, False)}
    v["ds"] = check_range("ds", ds, v["ds_min"], True, lower_name="ds_min")
    v["ds_max"] = check_range("ds_max", ds_max, v["ds"], True, lower_name="ds")
    return v


def check_newton(tol, max_iter) -> dict:
    """The Newton corrector of any continuation checked: ``tol > 0`` (the problem's residual
    norm), ``max_iter ≥ 1`` iterations, by name."""
    return {"tol": check_range("tol", tol, 0.0, False), "max_iter": check_int("max_iter", max_iter, 1)}


class BranchSettings:
    """Base of the frozen settings dataclasses of a shooting continuation (module docstring).

    A subclass declares the shared fields (its own defaults) and names its level range:
    ``LEVEL_RANGE`` = (lower field, upper field, unit) of P_a, ``FMIN_ZERO`` whether
    ``fmin_hz = 0`` is allowed. Its ``__post_init__`` stores :meth:`checked` (plus its own fields).
    """

    LEVEL_RANGE = ("pa_min", "pa_max", "")
    FMIN_ZERO = False

    def checked(self) -> dict:
        """The shared fields checked (module docstring), by name, as floats and ints."""
        lo, hi, unit = self.LEVEL_RANGE
        v = {"fmin_hz": check_range("fmin_hz", self.fmin_hz, 0.0, self.FMIN_ZERO, "Hz")}
        v["fmax_hz"] = check_range("fmax_hz", self.fmax_hz, v["fmin_hz"], False, "Hz", lower_name="fmin_hz")
        v[lo] = check_range(lo, getattr(self, lo), 0.0, True, unit)
        v[hi] = check_range(hi, getattr(self, hi), v[lo], False, unit, lower_name=lo)
        v.update(check_steps(self.ds, self.ds_min, self.ds_max))
        v["max_points"] = check_int("max_points", self.max_points, BRANCH_POINTS_MIN)
        v["app_max_um"] = check_range("app_max_um", self.app_max_um, 0.0, False, "µm")
        v["rtol"] = check_range("rtol", self.rtol, SHOOTING_RTOL_RANGE[0], True, upper=SHOOTING_RTOL_RANGE[1])
        v.update(check_newton(self.tol, self.max_iter))
        v["max_turn"] = check_range("max_turn", self.max_turn, 0.0, False, "rad")
        v["locate_tol"] = check_range("locate_tol", self.locate_tol, 0.0, False)
        v["max_failures"] = check_int("max_failures", self.max_failures, 1)
        return v

    def corrector(self) -> CorrectorSettings:
        """Newton on the bordered system: ``max_iter`` steps to ``tol``, |N| ≤ 1e-9, a scaled
        step over 1 counted as divergence."""
        return CorrectorSettings(tol=self.tol, max_iter=self.max_iter, cons_tol=1e-9, max_step=1.0)

    def step_control(self) -> StepControl:
        """The adaptive step from ``ds`` in [``ds_min``, ``ds_max``], at most ``max_points`` per
        direction and ``max_failures`` rejected steps, closed branches detected, a bound reached
        corrected onto it; special points located unless a ``locate`` field says False."""
        return StepControl(ds=self.ds, ds_min=self.ds_min, ds_max=self.ds_max, max_turn=self.max_turn,
                           max_failures=self.max_failures, max_points=self.max_points,
                           locate_tol=self.locate_tol, locate=getattr(self, "locate", True),
                           detect_loop=True, bound_action="fix")
