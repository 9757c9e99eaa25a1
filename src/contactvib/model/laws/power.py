"""The power law of the paper: ``F_s = S c_n y^m2`` (Kostek 2013, Eq. 2.3), the default.

Its parameters are the model's own fields ``c_n`` and ``m2`` (``ContactModel(c_n=..., m2=...)``,
``--set c_n=... --set m2=...``), checked by the model; the compiled form is the kernels' power
spring, with the Taylor flow for integer exponents.
"""

from __future__ import annotations

import numpy as np

from contactvib.model.laws.contract import LawParameter, SpringLaw
from contactvib.model.laws.registry import register_law

__all__ = ["PowerSpring"]


@register_law
class PowerSpring(SpringLaw):
    """``F_s = S c_n y^m2`` [N] (y in m): the paper's spring (Eq. 2.3)."""

    name = "power"
    formula = "S c_n y^m2 (the paper's rough contact)"
    parameters = (
        LawParameter("c_n", "N/m^(2+m2)", 4.52e16, "stiffness coefficient"),
        LawParameter("m2", "1", 2.0, "stiffness exponent (2: the paper, 1.5: Hertz-like)", 1.0, True, 10.0),
    )
    taylor = True

    def static_deflection(self, W: float, S: float) -> float:
        """y0 [m] with F_s(y0) = W [N] on the nominal area S [m²]."""
        return (W / (S * self.c_n)) ** (1.0 / self.m2)

    def force(self, y, S: float):
        y = np.asarray(y, dtype=float)
        return np.where(y > 0.0, S * self.c_n * np.abs(y) ** self.m2, 0.0)

    def stiffness(self, y, S: float):
        y = np.asarray(y, dtype=float)
        return np.where(y > 0.0, self.m2 * S * self.c_n * np.abs(y) ** (self.m2 - 1.0), 0.0)

    def kernel_spring(self, y0: float, W: float, S: float):
        return self.compiled_power(self.m2)
