"""The one conversion between the kernels' nondimensional variables and the reported units.

The kernels integrate ``x = y / y0`` in ``τ = ω_n0 t`` (:mod:`contactvib.model.oscillator`);
results are reported as y [µm], ẏ [mm/s] and t [ms]::

    y [µm]    = x  · y_um,        y_um      = y0 [m] · 1e6
    ẏ [mm/s]  = x' · ydot_mm_s,   ydot_mm_s = y0 [m] · ω_n0 [rad/s] · 1e3
    t [ms]    = τ  · t_ms,        t_ms      = 1e3 / ω_n0 [rad/s]

Get the factors of a model from :attr:`ContactModel.units <contactvib.model.ContactModel.units>`.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Units"]


@dataclass(frozen=True)
class Units:
    """Scale factors from nondimensional kernel variables to reported units.

    Parameters
    ----------
    y_um : float
        Micrometres per unit of x = y/y0: y0 · 1e6 [µm].
    ydot_mm_s : float
        Millimetres per second per unit of x' = dx/dτ: y0 ω_n0 · 1e3 [mm/s].
    t_ms : float
        Milliseconds per unit of τ = ω_n0 t: 1e3 / ω_n0 [ms].
    """

    y_um: float
    ydot_mm_s: float
    t_ms: float

    @classmethod
    def of(cls, y0: float, omega_n0: float) -> Units:
        """The factors for static deflection ``y0`` [m] and natural frequency ``omega_n0`` [rad/s]."""
        return cls(y_um=y0 * 1e6, ydot_mm_s=y0 * omega_n0 * 1e3, t_ms=1e3 / omega_n0)

    def state(self, y_um: float, ydot_mm_s: float) -> tuple[float, float]:
        """Nondimensional state (x, x') of y = ``y_um`` µm, ẏ = ``ydot_mm_s`` mm/s.

        >>> from contactvib import ContactModel
        >>> u = ContactModel().units
        >>> x, xdot = u.state(2 * u.y_um, 0.0)  # twice the static deflection, at rest
        >>> round(x, 12), xdot
        (2.0, 0.0)
        """
        return y_um / self.y_um, ydot_mm_s / self.ydot_mm_s
