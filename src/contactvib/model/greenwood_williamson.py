"""Greenwood–Williamson rough contact with Gaussian summit heights, tabulated for the table law.

A nominally flat rough surface of area A carries η summits per m², each a sphere of radius R
with Hertzian load (4/3) E* R^(1/2) δ^(3/2), summit heights Gaussian with standard deviation σ;
at separation d between the mean summit plane and the flat (Greenwood & Williamson 1966)

    F(d) = (4/3) η A E* R^(1/2) σ^(3/2) F_3/2(d/σ),   F_3/2(h) = ∫_h^∞ (s − h)^(3/2) φ(s) ds,

φ the standard normal density. A Gaussian has no highest summit, so the deflection y is counted
from a chosen first-contact separation d0 = n σ (``first_contact_sigma`` n, default 4: 3e-5 of
the summits are above it): F_s(y) = F(d0 − y) − F(d0), so that the curve starts at (0, 0) as the
table law requires. F_3/2 is computed by adaptive quadrature (scipy ``quad``) on the rows of a
:class:`~contactvib.TableLaw` once, at start-up; far from the mean plane (h ≫ 1, the
small-load limit) it follows the asymptotic series

    F_3/2(h) ≈ φ(h) Σ_k (−1/2)^k / k! Γ(5/2 + 2k) h^−(5/2 + 2k)

(:func:`f32_asymptotic`), against which the quadrature is tested.

References: J. A. Greenwood, J. B. P. Williamson, Proc. R. Soc. A 295 (1966) 300–319.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib.model.checks import ParameterError, check_range

__all__ = ["GreenwoodWilliamson", "f32", "f32_asymptotic"]


def f32(h) -> np.ndarray:
    """F_3/2(h) = ∫_h^∞ (s − h)^(3/2) φ(s) ds [1] by adaptive quadrature (vectorised over h)."""
    from scipy.integrate import quad

    def one(hv):
        # u = s − h, and the Gaussian's decay scale: the integrand is negligible beyond u = 40
        val, _err = quad(lambda u: u ** 1.5 * math.exp(-0.5 * (u + hv) ** 2), 0.0, max(40.0, 40.0 - hv),
                         epsabs=0.0, epsrel=1e-12, limit=200)
        return val / math.sqrt(2.0 * math.pi)

    return np.array([one(float(v)) for v in np.atleast_1d(h)])


def f32_asymptotic(h, terms: int = 4) -> np.ndarray:
    """The asymptotic series of F_3/2 for h ≫ 1 (``terms`` terms): the small-load limit."""
    h = np.atleast_1d(np.asarray(h, float))
    s = sum((-0.5) ** k / math.factorial(k) * math.gamma(2.5 + 2 * k) * h ** -(2.5 + 2 * k) for k in range(terms))
    return np.exp(-0.5 * h * h) / math.sqrt(2.0 * math.pi) * s


@dataclass(frozen=True)
class GreenwoodWilliamson:
    """Greenwood–Williamson contact: summit height deviation ``sigma`` [m], summit radius
    ``radius`` [m], summit density ``density`` [1/m²], composite modulus ``e_star`` [Pa], and the
    first-contact separation in multiples of σ (``first_contact_sigma``, > 0)."""

    sigma: float
    radius: float
    density: float
    e_star: float
    first_contact_sigma: float = 4.0

    def __post_init__(self):
        for name, unit in (("sigma", "m"), ("radius", "m"), ("density", "1/m^2"), ("e_star", "Pa"),
                           ("first_contact_sigma", "sigma")):
            object.__setattr__(self, name, check_range(name, getattr(self, name), 0.0, False, unit))

    def load(self, y, area: float) -> np.ndarray:
        """Spring force F_s(y) = F(d0 − y) − F(d0) [N] at deflections ``y`` ≥ 0 [m] of a nominal
        contact area ``area`` [m²]."""
        area = check_range("area", area, 0.0, False, "m^2")
        y = np.asarray(y, float)
        if np.any(y < 0.0):
            raise ParameterError("y", float(y.min()), "deflections must be >= 0 m")
        c = 4.0 / 3.0 * self.density * area * self.e_star * math.sqrt(self.radius) * self.sigma ** 1.5
        n = self.first_contact_sigma
        return c * (f32(n - y.ravel() / self.sigma) - f32(n)[0]).reshape(y.shape)

    def table(self, area: float, y_max: float, n: int = 400):
        """The law as a :class:`~contactvib.TableLaw` on ``n`` rows from 0 to
        ``y_max`` [m] (the rows closer where the load grows fastest: uniform in y^(1/2))."""
        from contactvib.model.laws import TableLaw

        y_max = check_range("y_max", y_max, 0.0, False, "m")
        n = int(check_range("n", n, 4.0, True, "rows", upper=20000.0))
        d = y_max * np.linspace(0.0, 1.0, n) ** 2
        src = (f"Greenwood-Williamson (sigma = {self.sigma:.4g} m, R = {self.radius:.4g} m, eta = "
               f"{self.density:.4g} 1/m^2, E* = {self.e_star:.4g} Pa, d0 = {self.first_contact_sigma:g} sigma)")
        return TableLaw(d, self.load(d, area), source=src)
