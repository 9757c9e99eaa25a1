"""Friction under normal contact vibration: the tangential motion of the slider driven
along the slideway, with a Jenkins contact (tangential stiffness and Coulomb slip) whose slip limit
follows the normal contact force R(t) of a normal attractor.

:class:`FrictionModel` (model.py) holds the tangential parameters; :func:`friction_at`
(tangential.py) integrates the tangential motion to its steady state and returns a
:class:`FrictionResult`.
"""

from contactvib.errors import ComputationError
from contactvib.friction.model import MINDLIN_RATIO, FrictionModel
from contactvib.friction.tangential import FrictionHistory, FrictionResult, friction_at, mean_limit

__all__ = ["MINDLIN_RATIO", "FrictionModel", "FrictionHistory", "FrictionResult",
           "friction_at", "mean_limit"]

#: An alias of :class:`contactvib.ComputationError` (a failure at ``stage`` "friction").
FrictionError = ComputationError
