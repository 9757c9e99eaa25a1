"""Periodic orbits: shooting, pseudo-arclength continuation, Floquet stability, bifurcations.

Public names: :func:`continue_orbit`, :func:`switch_period_doubling`, :func:`continue_attractors`,
:func:`bifurcation_diagram`, :func:`evolution`, :class:`ContinuationSettings`, :class:`Branch`,
:class:`BranchSet`, :class:`SpecialPoint`, :class:`Stop`.
"""

from .branch import Branch, BranchSet, SpecialPoint, Stop
from .continuation import ContinuationError, ContinuationSettings, continue_orbit, switch_period_doubling

__all__ = ["Branch", "BranchSet", "SpecialPoint", "Stop", "ContinuationError",
           "ContinuationSettings", "continue_orbit", "switch_period_doubling",
           "continue_attractors", "bifurcation_diagram", "evolution", "EvolutionResult"]


def __getattr__(name):
    if name in ("continue_attractors", "bifurcation_diagram"):
        from . import diagram

        return getattr(diagram, name)
    if name in ("evolution", "EvolutionResult"):
        from . import evolution as _ev

        return getattr(_ev, name)
    raise AttributeError(f"module 'contactvib.periodic' has no attribute {name!r}")
