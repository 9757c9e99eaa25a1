"""The oscillator: parameters, derived quantities, excitation, input checks (no kernels here)."""

from contactvib.model.oscillator import (PAPER_DEFAULTS, PARAMETER_UNITS, ZETA_MAX, ContactModel,
                                         Excitation, ParameterError, check_finite, check_range)

__all__ = ["ContactModel", "Excitation", "ParameterError", "PAPER_DEFAULTS", "PARAMETER_UNITS",
           "ZETA_MAX", "check_finite", "check_range"]
