"""contactvib: non-linear dynamics of contact oscillators (Kostek 2013)."""
from .model import ContactModel, Excitation, ParameterError, PAPER_DEFAULTS

__all__ = ["ContactModel", "Excitation", "ParameterError", "PAPER_DEFAULTS"]
__version__ = "0.1.0"
