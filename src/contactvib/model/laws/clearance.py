"""The clearance law: a linear spring behind a gap, ``F_s = S c_lin δ⁺`` with ``δ = y − gap``.

The contact engages at ``y = gap`` (``gap_um`` [µm]); while ``δ ≤ 0`` nothing acts (the contact is
lost), and the damping law chosen beside it acts on δ while ``δ > 0``. ``c_lin`` [N/m³] is the
stiffness per unit nominal area, the power law's ``c_n`` at ``m2 = 1``, so the contact stiffness
is ``k = S c_lin`` [N/m]. Under gravity alone, in one coordinate, the motion is that of the power
law at ``m2 = 1`` shifted by the gap; in a structure without gravity the gap is what makes it
non-linear.

This file is the whole law: the registry finds it (a module of ``contactvib.model.laws``), and
``--law clearance --set c_lin=K --set gap_um=G`` works on every command.
"""

from __future__ import annotations

import numpy as np

from contactvib.model.laws.contract import LawParameter, SpringLaw
from contactvib.model.laws.registry import register_law

__all__ = ["ClearanceLaw"]


@register_law
class ClearanceLaw(SpringLaw):
    """``F_s = S c_lin (y − gap)⁺`` [N]: a linear spring that engages at y = gap.

    Parameters
    ----------
    c_lin : float
        Stiffness per unit nominal area [N/m³], > 0 (default: f_n0 ≈ 1485 Hz with the paper's
        M and S, as the paper's contact).
    gap_um : float
        Clearance [µm], ≥ 0, at most 1e6 µm (1 m).

    Examples
    --------
    >>> law = ClearanceLaw(c_lin=2e10, gap_um=1.0)
    >>> float(law.force(0.5e-6, 1e-3))  # δ = y − gap = 0.5 µm, on 1e-3 m²  [N]
    10.0
    """

    name = "clearance"
    formula = "S c_lin (y - gap)+ (a linear spring behind a clearance)"
    parameters = (
        LawParameter("c_lin", "N/m^3", 2.037e10, "stiffness per unit area (k = S c_lin)"),
        LawParameter("gap_um", "um", 0.0, "clearance: the contact engages at y = gap", 0.0, True, 1e6),
    )
    taylor = True

    @property
    def engagement_m(self) -> float:
        return self.gap_um * 1e-6

    def static_deflection(self, W: float, S: float) -> float:
        return W / (S * self.c_lin)

    def force(self, delta, S: float):
        d = np.asarray(delta, dtype=float)
        return np.where(d > 0.0, S * self.c_lin * d, 0.0)

    def stiffness(self, delta, S: float):
        d = np.asarray(delta, dtype=float)
        return np.where(d > 0.0, S * self.c_lin, 0.0)

    def contact_force(self, delta, S: float):
        return S * self.c_lin * float(delta)

    def kernel_spring(self, y0: float, W: float, S: float):
        # δ/δ0 with δ0 = W/(S c_lin): F_s/W = x, the compiled power spring at m2 = 1
        return self.compiled_power(1.0)
