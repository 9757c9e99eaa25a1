"""The oscillator: parameters, derived quantities, excitation, units, input checks, the contact
law.

No kernels run here, except that :class:`PowerLaw` evaluates the compiled contact-law definition
(``contactvib._kernels.contact``, imported on first use).
"""

from contactvib.model.checks import (
                                     CAPTURE_TOL_MAX,
                                     EVOLUTION_ORDER_MAX,
                                     HARMONICS_MAX,
                                     KMAX_SEARCH_MAX,
                                     KMAX_SWEEP_MAX,
                                     MULTISTART_PER_OCTAVE_MAX,
                                     PA_NOTE,
                                     SHOOTING_RTOL_RANGE,
                                     WORKERS_MAX,
                                     ParameterError,
                                     check_choice,
                                     check_finite,
                                     check_frequency_range,
                                     check_int,
                                     check_pa_level,
                                     check_range,
)
from contactvib.model.contact_law import PowerLaw
from contactvib.model.excitation import (
    LEVEL_KINDS,
    LEVEL_TAGS,
    check_excitation,
    check_level_kind,
    excitation_at,
    level_text,
)
from contactvib.model.greenwood_williamson import GreenwoodWilliamson
from contactvib.model.laws import (
    ClearanceLaw,
    ExponentialLaw,
    LawParameter,
    PowerSpring,
    SpringLaw,
    TableLaw,
    law_class,
    law_names,
    register_law,
)
from contactvib.model.oscillator import PAPER_DEFAULTS, PARAMETER_UNITS, ZETA_MAX, ContactModel, Excitation
from contactvib.model.rocking import rocking_system
from contactvib.model.system import ContactElement, System
from contactvib.model.system_file import load_system
from contactvib.model.units import Units

__all__ = ["ContactModel", "System", "ContactElement", "rocking_system", "load_system",
           "Excitation", "ParameterError", "PowerLaw", "ExponentialLaw",
           "TableLaw", "ClearanceLaw", "PowerSpring", "SpringLaw", "LawParameter", "register_law", "law_names",
           "law_class", "PAPER_DEFAULTS", "PARAMETER_UNITS",
           "ZETA_MAX", "Units", "check_finite", "check_range", "check_int", "check_choice",
           "check_frequency_range", "check_pa_level", "PA_NOTE", "SHOOTING_RTOL_RANGE",
           "KMAX_SEARCH_MAX", "KMAX_SWEEP_MAX", "MULTISTART_PER_OCTAVE_MAX",
           "EVOLUTION_ORDER_MAX", "HARMONICS_MAX", "CAPTURE_TOL_MAX", "WORKERS_MAX",
           "LEVEL_KINDS", "LEVEL_TAGS", "check_excitation", "check_level_kind", "excitation_at", "level_text",
           "GreenwoodWilliamson"]
