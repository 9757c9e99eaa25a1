"""Fitting the contact parameters to measurements (``contactvib fit``).

:func:`fit` takes a static load–deflection curve, a free decay and/or stepped-sine sweeps
(:mod:`.data`), uses the package's own solvers as forward models (:mod:`.forward`) and returns a
:class:`FitResult` (:mod:`.results`) with standard errors, correlations and the fitted model.
"""

from ..errors import ComputationError
from .data import (
    DecayData,
    FrfData,
    StaticData,
    decay_data,
    frf_data,
    read_decay,
    read_frf,
    read_static,
    static_data,
)
from .results import FitResult
from .solver import fit

__all__ = ["DecayData", "FitResult", "FrfData", "StaticData", "decay_data", "fit", "frf_data",
           "read_decay", "read_frf", "read_static", "static_data"]

#: An alias of :class:`contactvib.ComputationError` (a failure at ``stage`` "fit").
FitError = ComputationError
