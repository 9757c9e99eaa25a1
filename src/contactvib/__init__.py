"""contactvib: non-linear dynamics of contact oscillators (Kostek 2013).

The public API: :class:`ContactModel` (parameters, derived quantities), its
:meth:`ContactModel.excitation`, :func:`find_attractors`, :func:`simulate`,
:func:`attractor_history`, :func:`refine_orbit`, and the result types.
Heavy modules (numba kernels) are imported on first use.
"""
from .model import PAPER_DEFAULTS, ContactModel, Excitation, ParameterError

__all__ = ["ContactModel", "Excitation", "ParameterError", "PAPER_DEFAULTS", "find_attractors",
           "simulate", "attractor_history", "refine_orbit", "Attractor", "AttractorSet",
           "TimeHistory"]
__version__ = "0.1.0"

_LAZY = {
    "find_attractors": ("attractors", "find_attractors"),
    "simulate": ("simulate", "simulate"),
    "attractor_history": ("simulate", "attractor_history"),
    "refine_orbit": ("steady", "refine_orbit"),
    "Attractor": ("results", "Attractor"),
    "AttractorSet": ("results", "AttractorSet"),
    "TimeHistory": ("results", "TimeHistory"),
}


def __getattr__(name):
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(f".{module}", __name__), attr)
    raise AttributeError(f"module 'contactvib' has no attribute {name!r}")
