"""The one conversion between the kernels' nondimensional variables and the reported units.

The kernels integrate ``x = y / y0`` in ``τ = ω_n0 t`` (:mod:`contactvib.model.oscillator`);
results are reported as y [µm], ẏ [mm/s] and t [ms]::

    y [µm]    = y_e + x · y_um,   y_um      = y0 [m] · 1e6   (a position; a length: x · y_um)
    ẏ [mm/s]  = x' · ydot_mm_s,   ydot_mm_s = y0 [m] · ω_n0 [rad/s] · 1e3
    t [ms]    = τ  · t_ms,        t_ms      = 1e3 / ω_n0 [rad/s]

``y0`` is the contact's static deflection and ``y_e`` (``y_offset_um``) the contact law's
engagement point: 0 for a rough contact, which touches at y = 0; the gap of a clearance.

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
    y_offset_um : float
        Position y [µm] of the contact's engagement point (x = 0): 0 unless the law has a gap.
    """

    y_um: float
    ydot_mm_s: float
    t_ms: float
    y_offset_um: float = 0.0

    @classmethod
    def of(cls, y0: float, omega_n0: float, engagement_m: float = 0.0) -> Units:
        """The factors for static deflection ``y0`` [m], natural frequency ``omega_n0`` [rad/s]
        and the law's engagement point ``engagement_m`` [m]."""
        return cls(y_um=y0 * 1e6, ydot_mm_s=y0 * omega_n0 * 1e3, t_ms=1e3 / omega_n0,
                   y_offset_um=engagement_m * 1e6)

    def position_um(self, x):
        """Position y [µm] of the kernels' x (scalar or array): y_e + x · y_um."""
        if self.y_offset_um == 0.0:
            return x * self.y_um
        return x * self.y_um + self.y_offset_um

    @property
    def y_static_um(self) -> float:
        """Static equilibrium position [µm]: y_e + y0 (the static deflection y0 for y_e = 0)."""
        return self.y_offset_um + self.y_um

    def state(self, y_um: float, ydot_mm_s: float) -> tuple[float, float]:
        """Nondimensional state (x, x') of y = ``y_um`` µm, ẏ = ``ydot_mm_s`` mm/s.

        >>> from contactvib import ContactModel
        >>> u = ContactModel().units
        >>> x, xdot = u.state(2 * u.y_um, 0.0)  # twice the static deflection, at rest
        >>> round(x, 12), xdot
        (2.0, 0.0)
        """
        return (y_um - self.y_offset_um) / self.y_um, ydot_mm_s / self.ydot_mm_s
