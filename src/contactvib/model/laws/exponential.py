"""The exponential law ``F_s = S c_e (exp(y/λ) − 1)``: rough surfaces with exponentially
distributed asperity heights; ``k = (W + S c_e)/λ``. Compiled as the kernels' exponential spring,
with its own Taylor recurrence.
"""

from __future__ import annotations

import math

import numpy as np

from contactvib.model.laws.contract import LawParameter, SpringLaw
from contactvib.model.laws.registry import register_law

__all__ = ["ExponentialLaw", "EXPONENTIAL_DEFAULTS"]

#: Default exponential law: chosen so that with the paper's M, g, S its static deflection and
#: linear natural frequency are those of the paper's power law to 1 % (y0 0.2254 µm, f_n0 1485 Hz).
EXPONENTIAL_DEFAULTS = {"c_e": 584.0, "lam": 0.1413e-6}


@register_law
class ExponentialLaw(SpringLaw):
    """``F_s = S c_e (exp(y/λ) − 1)`` [N]: exponentially distributed asperity heights.

    Parameters
    ----------
    c_e : float
        Pressure coefficient [N/m²], > 0.
    lam : float
        Decay length λ [m], > 0 (of the order of the asperity heights' standard deviation).
    """

    name = "exponential"
    formula = "S c_e (exp(y/lam) - 1) (exponentially distributed asperities)"
    parameters = (
        LawParameter("c_e", "N/m^2", EXPONENTIAL_DEFAULTS["c_e"], "pressure coefficient"),
        LawParameter("lam", "m", EXPONENTIAL_DEFAULTS["lam"], "decay length (about the asperity heights' rms)"),
    )
    taylor = True

    def static_deflection(self, W: float, S: float) -> float:
        return self.lam * math.log1p(W / (S * self.c_e))

    def force(self, y, S: float):
        y = np.asarray(y, dtype=float)
        return np.where(y > 0.0, S * self.c_e * np.expm1(np.maximum(y, 0.0) / self.lam), 0.0)

    def stiffness(self, y, S: float):
        y = np.asarray(y, dtype=float)
        return np.where(y > 0.0, S * self.c_e / self.lam * np.exp(np.maximum(y, 0.0) / self.lam), 0.0)

    def kernel_spring(self, y0: float, W: float, S: float):
        return self.compiled_exponential(y0 / self.lam, S * self.c_e / W)
