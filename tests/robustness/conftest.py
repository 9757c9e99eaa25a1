"""Fixtures of the robustness tests: the computations of every command replaced by a stub, so
that a test drives the command line in-process and sees where the checks end and the work would
begin."""

import pytest

#: The computations the commands start (after their inputs and output folder are checked).
COMPUTATIONS = [
    "contactvib.steady.attractors.find_attractors",
    "contactvib.steady.attractors.start_box",
    "contactvib.steady.simulate.simulate",
    "contactvib.steady.lyapunov.lyapunov_spectrum",
    "contactvib.steady.lyapunov.system_lyapunov_spectrum",
    "contactvib.steady.basins.basins",
    "contactvib.steady.system_basins.system_basins",
    "contactvib.steady.orbit_diagram.orbit_diagram",
    "contactvib.sweeps.resonance.resonance_dataset",
    "contactvib.sweeps.system_resonance.system_resonance_dataset",
    "contactvib.sweeps.paper.reproduce_paper",
    "contactvib.sweeps.film.animate",
    "contactvib.continuation.diagram.continue_attractors",
    "contactvib.continuation.diagram.bifurcation_diagram",
    "contactvib.continuation.evolution.evolution",
    "contactvib.frequency.harmonic_balance.hb_continuation",
    "contactvib.frequency.system_hb.system_hb_continuation",
    "contactvib.continuation.cascade.cascades_at",
    "contactvib.frequency.perturbation.perturbation_series",
    "contactvib.sweeps.regimes.evolution_curves",
    "contactvib.sweeps.regimes.regime_maps",
    "contactvib.fitting.solver.fit",
    "contactvib.explore.server.serve",  # the explore server: never started by these tests
]


class ComputationStarted(Exception):
    """Raised by the stubs: the command accepted its inputs and would start computing."""


@pytest.fixture
def no_computation(monkeypatch):
    """Every computation of :data:`COMPUTATIONS` replaced by a stub raising
    :class:`ComputationStarted` (naming the computation); returns that exception class."""
    for target in COMPUTATIONS:
        def stub(*args, _target=target, **kwargs):
            raise ComputationStarted(_target)

        monkeypatch.setattr(target, stub)
    return ComputationStarted
