"""One base class, :class:`contactvib.ContactvibError`, under every exception contactvib raises on
purpose; each keeps its builtin base (callers catching ValueError or RuntimeError keep working);
Ctrl-C (:class:`contactvib.interrupts.Interrupted`) stays a KeyboardInterrupt, out of reach of
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
    "ContinuationError": ("contactvib.continuation.shooting", RuntimeError),
    "InputError": ("contactvib.cli.errors", Exception),
    "RunInterrupted": ("contactvib.cli.errors", Exception),
    "FrictionError": ("contactvib.friction.tangential", RuntimeError),
    "BadInput": ("contactvib.explore.state", ValueError),
    "Stopped": ("contactvib.explore.state", Exception),
    "DatasetError": ("contactvib.sweeps.stored", ValueError),
    "DamagedDataset": ("contactvib.sweeps.stored", LookupError),
    "MissingLevel": ("contactvib.sweeps.stored", LookupError),
    "ResumeMismatch": ("contactvib.sweeps.resonance", ValueError),
    "OutputLocked": ("contactvib.sweeps.resonance", ValueError),
    "HBError": ("contactvib.frequency.hb_results", RuntimeError),
    "OrbitError": ("contactvib.steady.orbits", RuntimeError),
    "FitError": ("contactvib.fitting.solver", RuntimeError),
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
