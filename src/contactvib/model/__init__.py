"""The oscillator: parameters, derived quantities, excitation, input checks, the contact law.

No kernels run here, except that :class:`PowerLaw` evaluates the compiled contact-law definition
(``contactvib._kernels.contact``, imported on first use).
"""

from contactvib.model.contact_law import PowerLaw
from contactvib.model.oscillator import (PAPER_DEFAULTS, PARAMETER_UNITS, ZETA_MAX, ContactModel,
                                         Excitation, ParameterError, check_finite, check_range)

__all__ = ["ContactModel", "Excitation", "ParameterError", "PowerLaw", "PAPER_DEFAULTS",
           "PARAMETER_UNITS", "ZETA_MAX", "check_finite", "check_range"]
