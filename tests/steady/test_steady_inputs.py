"""Inputs and shared rules of the steady-state functions: excitation of the model, integer
counts, the public `simulate`, the one stability rule, the kernels' status messages."""
import numpy as np
import pytest

import contactvib
from contactvib import ContactModel, ParameterError, find_attractors
from contactvib._kernels.shooting import STABILITY_TOL, is_stable
from contactvib._kernels.status import MESSAGES, status_message

MODEL = ContactModel()


def test_simulate_is_the_function():
    from contactvib import simulate
    from contactvib.steady.simulate import simulate as sim

    assert callable(simulate) and simulate is sim and simulate is contactvib.simulate
    assert simulate.__module__ == "contactvib.steady.simulate"


def test_excitation_of_another_model_is_refused():
    """The deprecated form find_attractors(model, excitation) refuses an excitation of another
    model; the new form takes the model from the excitation."""
    other = MODEL.replace(M=0.3)
    with pytest.raises(ParameterError) as e, pytest.warns(DeprecationWarning):
        find_attractors(MODEL, other.excitation(0.65, 360.0), n_starts=4)
    assert e.value.symbol == "excitation" and "another model" in e.value.allowed
    assert "M" in e.value.allowed
    # an equal model (same parameters) is the same model
    with pytest.warns(DeprecationWarning):
        find_attractors(MODEL, ContactModel().excitation(0.65, 1930.0), n_starts=4, seeds=False)
    with pytest.raises(ParameterError, match="must be an Excitation"):
        find_attractors("x")


@pytest.mark.parametrize("kw, symbol", [({"n_starts": 16.7}, "n_starts"), ({"kmax": 2.5}, "kmax"),
                                        ({"seed": -1}, "seed"), ({"kmax": 65}, "kmax"),
                                        ({"max_periods": 10.5}, "max_periods"),
                                        ({"capture_tol": 0.2}, "capture_tol")])
def test_search_counts_must_be_integers(kw, symbol):
    with pytest.raises(ParameterError) as e:
        find_attractors(MODEL.excitation(0.65, 360.0), **kw)
    assert e.value.symbol == symbol


def test_simulate_counts_must_be_integers():
    from contactvib import simulate

    with pytest.raises(ParameterError, match="n_periods"):
        simulate(MODEL.excitation(0.5, 360.0), n_periods=2.5)


def test_stability_rule():
    assert STABILITY_TOL == 1e-6
    assert is_stable(1.0) and is_stable(1.0 + STABILITY_TOL) and is_stable(0.3)
    assert not is_stable(1.0 + 2 * STABILITY_TOL) and not is_stable(np.nan)
    assert type(is_stable(0.5)) is bool
    np.testing.assert_array_equal(is_stable(np.array([0.5, 1.0 + 1e-7, 1.1])), [True, True, False])


def test_attractors_found_are_stable():
    """The search keeps only orbits the stability rule calls stable."""
    res = find_attractors(MODEL.excitation(0.65, 1930.0), n_starts=32)
    mus = [a.floquet_abs_max for a in res if a.period is not None]
    assert mus and all(is_stable(mu) for mu in mus)


def test_status_messages():
    from contactvib._kernels import flow, settle, shooting, status, trace

    assert status_message(flow.STATUS_OK) == "ok"
    assert status_message(flow.STATUS_NONFINITE) == "non-finite state"
    assert status_message(shooting.STATUS_NEWTON_MAXITER) == "Newton shooting did not converge"
    assert status_message(status.STATUS_MAXITER) == "Newton did not converge"
    assert status_message(99) == "unknown status code 99"
    assert status_message(settle.SETTLE_CAPTURED, "settle") == "captured"
    assert status_message(trace.STOP_GRID_END, "stop") == "end of frequency grid"
    assert status_message(trace.ORIGIN_JUMP, "origin") == "jump"
    # the integration, Newton and corrector codes never collide
    codes = [c for (fam, c) in MESSAGES if fam == "status"]
    assert len(codes) == len(set(codes))
    assert all(isinstance(m, str) and m for m in MESSAGES.values())


def test_dataset_strings_are_unchanged():
    """Strings written into resonance datasets keep their text."""
    from contactvib.sweeps.dataset import STOP_REASONS

    assert STOP_REASONS == {0: "end of frequency grid", 1: "joined an attractor already traced this way",
                            2: "integration or Newton failure", 3: "attractor table full"}
    assert [status_message(c, "origin") for c in range(3)] == ["newton", "jump", "start"]
