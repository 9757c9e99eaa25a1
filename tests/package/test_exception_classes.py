"""One base class, :class:`contactvib.ContactvibError`, under every exception contactvib raises on
purpose; each keeps its builtin base (callers catching ValueError or RuntimeError keep working);
one class for every computation that fails, :class:`contactvib.ComputationError`, whose ``stage``
says where; Ctrl-C (:class:`contactvib.interrupts.Interrupted`) stays a KeyboardInterrupt, out of reach of
``except Exception``."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

from contactvib import ContactvibError

SRC = Path(__file__).resolve().parents[2] / "src" / "contactvib"

#: name -> (module, builtin base it keeps)
EXPECTED = {
    "ParameterError": ("contactvib.model.checks", ValueError),
    "InputError": ("contactvib.cli.errors", Exception),
    "RunInterrupted": ("contactvib.cli.errors", Exception),
    "BadInput": ("contactvib.explore.state", ValueError),
    "Stopped": ("contactvib.explore.state", Exception),
    "DatasetError": ("contactvib.sweeps.stored", ValueError),
    "DamagedDataset": ("contactvib.sweeps.stored", LookupError),
    "MissingLevel": ("contactvib.sweeps.stored", LookupError),
    "ResumeMismatch": ("contactvib.sweeps.resonance", ValueError),
    "OutputLocked": ("contactvib.sweeps.resonance", ValueError),
    "ComputationError": ("contactvib.errors", RuntimeError),
}


def _exception_classes():
    """(module, class name) of every class defined in src/contactvib that derives from an
    exception (found by its bases' names), warnings excepted."""
    for path in sorted(SRC.rglob("*.py")):
        module = ".".join(path.relative_to(SRC.parent).with_suffix("").parts).removesuffix(".__init__")
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ClassDef):
                bases = [ast.unparse(b) for b in node.bases]
                if any(b.endswith(("Error", "Exception", "Interrupt", "Mismatch", "Locked", "Dataset",
                                   "Input")) for b in bases):
                    yield module, node.name


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_every_exception_is_a_contactvib_error_and_keeps_its_builtin_base(name):
    module, builtin = EXPECTED[name]
    cls = getattr(importlib.import_module(module), name)
    assert issubclass(cls, ContactvibError) and issubclass(cls, builtin)


def test_no_exception_class_is_left_out():
    found = {(m, n) for m, n in _exception_classes()}
    expected = {(m, n) for n, (m, _) in EXPECTED.items()} | {("contactvib.interrupts", "Interrupted"),
                                                              ("contactvib.errors", "ContactvibError")}
    assert found == expected, "a new exception class: derive it from ContactvibError and list it here"


def test_ctrl_c_is_not_an_exception_and_there_is_one_dataset_error():
    from contactvib.explore.dataset_view import DatasetError as ViewError
    from contactvib.interrupts import Interrupted
    from contactvib.sweeps.film import DatasetError as FilmError

    assert issubclass(Interrupted, KeyboardInterrupt) and not issubclass(Interrupted, Exception)
    assert FilmError is ViewError is importlib.import_module("contactvib").DatasetError
    from contactvib import ContactModel

    with pytest.raises(ContactvibError, match="must be a ContactModel"):
        ContactModel.excitation("paper", 0.6, 360)


def test_one_class_for_failed_computations_with_its_stage():
    from contactvib import ComputationError, ContactModel, refine_orbit
    from contactvib.errors import STAGES

    assert issubclass(ComputationError, ContactvibError) and issubclass(ComputationError, RuntimeError)
    exc = ContactModel().excitation(0.65, 360.0)
    with pytest.raises(ComputationError, match="Newton shooting for a period-1 orbit failed") as failed:
        refine_orbit(exc, [1e3, 1e3], 1, max_iter=1)
    assert failed.value.stage == "newton" and failed.value.result is None
    assert "\n" not in str(failed.value)
    with pytest.raises(ValueError, match="stage"):
        ComputationError("x", stage="nowhere")
    assert {"newton", "continuation", "settle", "harmonic-balance", "friction", "fit"} <= set(STAGES)


def test_the_former_names_are_aliases_outside_all():
    import pickle

    import contactvib
    import contactvib.fitting
    import contactvib.friction
    from contactvib import ComputationError

    for name in ("OrbitError", "ContinuationError", "HBError", "FitError", "FrictionError"):
        assert getattr(contactvib, name) is ComputationError and name not in contactvib.__all__
    assert contactvib.fitting.FitError is contactvib.friction.FrictionError is ComputationError
    assert "FitError" not in contactvib.fitting.__all__ and "FrictionError" not in contactvib.friction.__all__
    again = pickle.loads(pickle.dumps(ComputationError("no fit", stage="fit", result=3)))
    assert (str(again), again.stage, again.result) == ("no fit", "fit", 3)
