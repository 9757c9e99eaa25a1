"""The base of contactvib's exceptions (a leaf module: every package may import it).

Every exception that contactvib raises on purpose derives from :class:`ContactvibError`, so that
a caller can catch all of them with one ``except`` clause; each keeps its builtin base as well
(``ParameterError`` is a ``ValueError``, ``OrbitError`` a ``RuntimeError``, ...), so that code
catching those keeps working. The exception is :class:`contactvib.interrupts.Interrupted`, a
``KeyboardInterrupt``: Ctrl-C must not be caught by ``except Exception``.
"""

from __future__ import annotations

__all__ = ["ContactvibError"]


class ContactvibError(Exception):
    """Base class of the exceptions raised by contactvib: refused inputs
    (:class:`~contactvib.ParameterError`), computations that cannot finish
    (:class:`~contactvib.OrbitError`, :class:`~contactvib.ContinuationError`, ...) and datasets
    that cannot be read (:class:`~contactvib.DatasetError`). Its message is one line."""
