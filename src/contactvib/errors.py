"""The exceptions every part of contactvib shares (a leaf module: every package may import it).

Every exception that contactvib raises on purpose derives from :class:`ContactvibError`, so that
a caller can catch all of them with one ``except`` clause; each keeps its builtin base as well
(``ParameterError`` is a ``ValueError``, :class:`ComputationError` a ``RuntimeError``, ...), so
that code catching those keeps working. Two kinds matter to a caller: refused inputs
(:class:`~contactvib.ParameterError` and its kin, raised before any computation) and
computations that could not finish (:class:`ComputationError`, one class whose ``stage`` says
where). The exception is :class:`contactvib.interrupts.Interrupted`, a ``KeyboardInterrupt``:
Ctrl-C must not be caught by ``except Exception``.
"""

from __future__ import annotations

__all__ = ["ContactvibError", "ComputationError", "STAGES"]

#: The stages a computation can fail at (:attr:`ComputationError.stage`), with what each means.
STAGES = {
    "integration": "integrating the equation of motion (a step or an event failed)",
    "newton": "Newton shooting for a periodic orbit",
    "continuation": "the start or a branch switch of a pseudo-arclength continuation",
    "settle": "settling transients onto an attractor",
    "harmonic-balance": "the harmonic-balance Newton iteration",
    "friction": "the steady tangential motion under a normal attractor",
    "fit": "the least-squares fit to measurements",
}


class ContactvibError(Exception):
    """Base class of the exceptions raised by contactvib: refused inputs
    (:class:`~contactvib.ParameterError`), computations that cannot finish
    (:class:`~contactvib.ComputationError`) and datasets that cannot be read
    (:class:`~contactvib.DatasetError`). Its message is one line."""


class ComputationError(ContactvibError, RuntimeError):
    """A computation that could not finish: its inputs were accepted, but the numerics failed.

    Parameters
    ----------
    message : str
        One line: what failed and the numbers that say why.
    stage : str
        Where it failed, one of ``contactvib.errors.STAGES``: "integration", "newton", "continuation",
        "settle", "harmonic-balance", "friction" or "fit".
    result : object, optional
        The best result the computation reached, where it has one (the fit's best point, a
        :class:`~contactvib.FitResult`); None otherwise.

    Attributes
    ----------
    stage : str
        As given.
    result : object or None
        As given.
    """

    def __init__(self, message: str, *, stage: str, result=None):
        if stage not in STAGES:
            raise ValueError(f"stage must be one of {', '.join(STAGES)}; got {stage!r}")
        super().__init__(message)
        self.stage = stage
        self.result = result

    def __reduce__(self):  # picklable across process pools, keywords included
        return _rebuild, (self.args[0] if self.args else "", self.stage, self.result)


def _rebuild(message: str, stage: str, result) -> ComputationError:
    return ComputationError(message, stage=stage, result=result)
