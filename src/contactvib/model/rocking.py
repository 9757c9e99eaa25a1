"""The two-contact slide unit: a rigid slider that heaves and pitches on two rough patches.

A slider of mass M [kg] and moment of inertia J [kg m²] about its centre of mass rests on two
patches of area S/2 each at +a and −a [m] from the centre of mass. Its coordinates are the heave
y [m] (positive into the contacts) and the pitch θ [rad]; the patches deflect by
y1 = y + a θ and y2 = y − a θ and each follows the model's law with S/2 in place of S (its
damping too). Gravity Q = M g (plus the preload F_pre) acts at the centre of mass, the force
P(t) = P_a cos(2π f_e t) at the offset e [m]::

    M ÿ = Q + F_pre + P − F1 − F2
    J θ̈ = e P − a F1 + a F2

With e = 0 and θ = 0 the patches carry equal forces whose sum is the paper's contact force of
the heave y (Kostek 2013, Eq. 2.5): the paper's motions are motions of the unit, and their
stability against rocking is the question the pitch answers.
"""

from __future__ import annotations

from contactvib.model.checks import ParameterError, check_range
from contactvib.model.system import ContactElement, System

__all__ = ["rocking_system", "ROCKING_PARAMETERS", "ROCKING_CONTACTS"]

#: The unit's own parameters (``--set NAME=VALUE`` with ``--system rocking``) and their units.
ROCKING_PARAMETERS = {"a": "m", "J": "kg m^2", "e": "m"}
#: Names of the two patches: at +a and at −a from the centre of mass.
ROCKING_CONTACTS = ("front", "rear")


def rocking_system(model, a: float = 0.05, J: float | None = None, e: float = 0.0) -> System:
    """The slide unit of ``model`` (a :class:`~contactvib.ContactModel`) on two patches.

    Parameters
    ----------
    model : ContactModel
        Mass M, area S (split in halves), law, damping, g and preload of the slider.
    a : float
        Half the distance between the patches [m] (> 0).
    J : float, optional
        Moment of inertia about the centre of mass [kg m²] (> 0); default M (2a)²/12 (a uniform
        bar of length 2a).
    e : float
        Offset of the force from the centre of mass [m] (any sign; + towards the front patch).

    Returns
    -------
    System
        Coordinates ``("y", "theta")`` in ``("m", "rad")``, contacts ``front`` (direction (1, a))
        and ``rear`` ((1, −a)), f0 = (Q + F_pre, 0), force shape b = (1, e).
    """
    if not all(hasattr(model, name) for name in ("spring_law", "M", "W", "S", "damping")):
        raise ParameterError("model", model, "must be a ContactModel")
    a = check_range("a", a, 0.0, False, "m")
    J = model.M * (2.0 * a) ** 2 / 12.0 if J is None else check_range("J", J, 0.0, False, "kg m^2")
    e = check_range("e", e, None, True, "m")
    if model.damping == "hunt-crossley":
        damping = {"damping": "hunt-crossley", "alpha": model.alpha}
    else:
        damping = {"damping": "power", "h_n": model.h_n, "l": model.l}
    contacts = tuple(ContactElement(name, (1.0, s * a), model.S / 2.0, model.spring_law, **damping)
                     for name, s in zip(ROCKING_CONTACTS, (1.0, -1.0)))
    return System(M=[[model.M, 0.0], [0.0, J]], f0=[model.W, 0.0], b=[1.0, e], contacts=contacts,
                  coordinates=("y", "theta"), units=("m", "rad"))
