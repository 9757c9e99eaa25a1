"""Contact spring laws (SI) as plug-ins, and the damping families.

Every law keeps the paper's convention: the deflection ``δ = y − y_e`` (``y_e`` the law's
engagement point, 0 for a rough contact) is positive into the contact, the force acts only while
``δ > 0``, nothing acts in flight. The static point ``δ0`` solves ``F_s(δ0) = W = Q + F_pre``
(weight plus preload), the linear stiffness is ``k = F_s'(δ0)``.

* :class:`SpringLaw`, :class:`LawParameter` — the contract a law fulfils (``contract.py``);
* :func:`register_law`, :func:`law_names`, :func:`law_class` — the registry (``registry.py``):
  this package's modules and the entry-point group ``contactvib.laws``;
* the built-in laws, one module each: :class:`PowerSpring` (``power.py``, the paper's),
  :class:`ExponentialLaw` (``exponential.py``), :class:`TableLaw` (``table.py``, a measured
  curve), :class:`ClearanceLaw` (``clearance.py``, a linear spring behind a gap);
* the damping families ``power`` and ``hunt-crossley`` (``damping.py``).
"""

from contactvib.model.laws.clearance import ClearanceLaw
from contactvib.model.laws.contract import LawParameter, SpringLaw, tabulated_form
from contactvib.model.laws.damping import DAMPING_NAMES, DAMPING_PARAMETERS, HUNT_CROSSLEY_DEFAULT
from contactvib.model.laws.exponential import EXPONENTIAL_DEFAULTS, ExponentialLaw
from contactvib.model.laws.power import PowerSpring
from contactvib.model.laws.registry import (
    ENTRY_POINT_GROUP,
    law_class,
    law_names,
    law_parameter_names,
    register_law,
)
from contactvib.model.laws.table import TABLE_ROWS_MIN, TableLaw

__all__ = ["SpringLaw", "LawParameter", "register_law", "law_names", "law_class", "law_parameter_names",
           "tabulated_form", "ENTRY_POINT_GROUP", "PowerSpring", "ExponentialLaw", "TableLaw", "ClearanceLaw",
           "DAMPING_NAMES", "DAMPING_PARAMETERS", "TABLE_ROWS_MIN", "EXPONENTIAL_DEFAULTS",
           "HUNT_CROSSLEY_DEFAULT"]
