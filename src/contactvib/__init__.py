"""contactvib: non-linear dynamics of contact oscillators (Kostek 2013).

The public API: every verb and result type is importable from here, e.g.
``from contactvib import ContactModel, find_attractors, simulate``. Heavy modules (numba kernels,
matplotlib) are imported on first use of a name that needs them.

Verbs: :func:`find_attractors`, :func:`basins`, :func:`poincare_sections`, :func:`orbit_diagram`,
:func:`simulate`, :func:`attractor_history`,
:func:`refine_orbit`, :func:`describe_orbit`, :func:`continue_orbit`,
:func:`continue_attractors`, :func:`switch_period_doubling`, :func:`bifurcation_diagram`,
:func:`evolution`, :func:`perturbation_series`, :func:`perturbation_curve`, :func:`hb_solve`,
:func:`hb_continuation`, :func:`trace_level`, :func:`resonance_dataset`,
:func:`open_resonance` (a stored dataset, :class:`ResonanceData`), :func:`attractors_at`,
:func:`check_completeness`,
:func:`reproduce_paper`, :func:`regime_maps`, :func:`animate`,
:func:`friction_at`, :func:`lyapunov_spectrum` (:class:`LyapunovSpectrum`).
"""

__version__ = "0.1.0"

#: public name -> (module, attribute); the module is imported on first access
_LAZY = {
    # the model (lazy too: ``import contactvib`` stays cheap for the console script)
    **{name: ("contactvib.model", name) for name in ("ContactModel", "Excitation", "ExponentialLaw", "TableLaw",
                                                      "GreenwoodWilliamson", "ParameterError", "PAPER_DEFAULTS")},
    "ContactvibError": ("contactvib.errors", "ContactvibError"),
    "ComputationError": ("contactvib.errors", "ComputationError"),
    # fitting to measurements
    "fit": ("contactvib.fitting.solver", "fit"),
    "FitResult": ("contactvib.fitting.results", "FitResult"),
    # steady states
    "find_attractors": ("contactvib.steady.attractors", "find_attractors"),
    "lyapunov_spectrum": ("contactvib.steady.lyapunov", "lyapunov_spectrum"),
    "LyapunovSpectrum": ("contactvib.steady.lyapunov", "LyapunovSpectrum"),
    "simulate": ("contactvib.steady.simulate", "simulate"),
    "attractor_history": ("contactvib.steady.simulate", "attractor_history"),
    "basins": ("contactvib.steady.basins", "basins"),
    "BasinMap": ("contactvib.steady.basins", "BasinMap"),
    "poincare_sections": ("contactvib.steady.sections", "poincare_sections"),
    "SectionSet": ("contactvib.steady.sections", "SectionSet"),
    "orbit_diagram": ("contactvib.steady.orbit_diagram", "orbit_diagram"),
    "OrbitDiagramSettings": ("contactvib.steady.orbit_diagram", "OrbitDiagramSettings"),
    "refine_orbit": ("contactvib.steady.orbits", "refine_orbit"),
    "describe_orbit": ("contactvib.steady.orbits", "describe_orbit"),
    "Attractor": ("contactvib.steady.results", "Attractor"),
    "AttractorSet": ("contactvib.steady.results", "AttractorSet"),
    "TimeHistory": ("contactvib.steady.results", "TimeHistory"),
    # continuation
    "continue_orbit": ("contactvib.continuation.shooting", "continue_orbit"),
    "switch_period_doubling": ("contactvib.continuation.shooting", "switch_period_doubling"),
    "ContinuationSettings": ("contactvib.continuation.shooting", "ContinuationSettings"),
    "continue_attractors": ("contactvib.continuation.diagram", "continue_attractors"),
    "bifurcation_diagram": ("contactvib.continuation.diagram", "bifurcation_diagram"),
    "evolution": ("contactvib.continuation.evolution", "evolution"),
    "EvolutionResult": ("contactvib.continuation.evolution", "EvolutionResult"),
    "Curve": ("contactvib.continuation.evolution", "Curve"),
    "follow_cascade": ("contactvib.continuation.cascade", "follow_cascade"),
    "cascades_at": ("contactvib.continuation.cascade", "cascades_at"),
    "orbit_period": ("contactvib.continuation.cascade", "orbit_period"),
    "Cascade": ("contactvib.continuation.cascade", "Cascade"),
    "regime_maps": ("contactvib.sweeps.regimes", "regime_maps"),
    "MapCurve": ("contactvib.sweeps.regimes", "MapCurve"),
    "Branch": ("contactvib.continuation.branch", "Branch"),
    "BranchSet": ("contactvib.continuation.branch", "BranchSet"),
    "SpecialPoint": ("contactvib.continuation.branch", "SpecialPoint"),
    "Stop": ("contactvib.continuation.branch", "Stop"),
    # frequency domain
    "perturbation_series": ("contactvib.frequency.perturbation", "perturbation_series"),
    "perturbation_curve": ("contactvib.frequency.perturbation", "perturbation_curve"),
    "PerturbationResult": ("contactvib.frequency.perturbation", "PerturbationResult"),
    "hb_solve": ("contactvib.frequency.harmonic_balance", "hb_solve"),
    "hb_continuation": ("contactvib.frequency.harmonic_balance", "hb_continuation"),
    "HBSolution": ("contactvib.frequency.harmonic_balance", "HBSolution"),
    "HBBranch": ("contactvib.frequency.harmonic_balance", "HBBranch"),
    "HBSettings": ("contactvib.frequency.harmonic_balance", "HBSettings"),
    "coefficients_from_orbit": ("contactvib.frequency.harmonic_balance", "coefficients_from_orbit"),
    # sweeps and the paper
    "SweepSettings": ("contactvib.sweeps.sweep", "SweepSettings"),
    "trace_level": ("contactvib.sweeps.sweep", "trace_level"),
    "resonance_dataset": ("contactvib.sweeps.resonance", "resonance_dataset"),
    "open_resonance": ("contactvib.sweeps.stored", "open_resonance"),
    "ResonanceData": ("contactvib.sweeps.stored", "ResonanceData"),
    "attractors_at": ("contactvib.sweeps.stored", "attractors_at"),
    "check_completeness": ("contactvib.sweeps.completeness", "check_completeness"),
    "reproduce_paper": ("contactvib.sweeps.paper", "reproduce_paper"),
    "PaperResult": ("contactvib.sweeps.paper", "PaperResult"),
    "animate": ("contactvib.sweeps.film", "animate"),
    "FilmResult": ("contactvib.sweeps.film", "FilmResult"),
    "open_levels": ("contactvib.sweeps.film", "open_levels"),
    "DatasetError": ("contactvib.sweeps.stored", "DatasetError"),
    "MissingLevel": ("contactvib.sweeps.stored", "MissingLevel"),
    # friction under normal contact vibration
    "friction_at": ("contactvib.friction.tangential", "friction_at"),
    "FrictionModel": ("contactvib.friction.model", "FrictionModel"),
    "FrictionResult": ("contactvib.friction.tangential", "FrictionResult"),
    "FrictionHistory": ("contactvib.friction.tangential", "FrictionHistory"),
}

__all__ = ["__version__", *_LAZY]

#: Aliases of :class:`ComputationError` (``stage`` says where a computation failed), importable
#: but not listed in ``__all__``: one class is documented, not five names for it.
_ALIASES = {name: ("contactvib.errors", "ComputationError")
            for name in ("OrbitError", "ContinuationError", "HBError", "FitError", "FrictionError")}


def __getattr__(name):
    if name in _LAZY or name in _ALIASES:
        import importlib

        module, attr = _LAZY.get(name) or _ALIASES[name]
        value = getattr(importlib.import_module(module), attr)
        globals()[name] = value  # later lookups, and the submodule attribute, give the function
        return value
    raise AttributeError(f"module 'contactvib' has no attribute {name!r}")


def __dir__():
    return sorted(__all__)
