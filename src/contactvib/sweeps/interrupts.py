"""Clean interrupts of long runs: Ctrl-C (SIGINT) between kernel calls, workers that end with
their parent.

A KeyboardInterrupt must not be raised while a compiled kernel runs: the parallel kernels
(``prange``, e.g. ``settle_known_many``) call back into Python (``_numba_unpickle``) and an
exception raised there by the default SIGINT handler comes out as ``SystemError:
CPUDispatcher(...) returned a result with an exception set`` (or worse). Levels that run in the
main thread therefore run under :func:`deferred_sigint`: SIGINT only sets a flag, and
:func:`check_interrupt`, called wherever Python regains control between kernel calls (every
trace and multi-start frequency of :mod:`contactvib.sweeps.sweep`, every level), raises the
KeyboardInterrupt there.

Worker processes ignore SIGINT (the parent handles it and terminates them) and end when their
parent dies, even by SIGKILL (:func:`end_with_parent`).
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from contextlib import contextmanager
from pathlib import Path

__all__ = ["Interrupted", "deferred_sigint", "check_interrupt", "end_with_parent"]


class Interrupted(KeyboardInterrupt):
    """A run stopped by SIGINT after its workers were stopped and its lock released.

    Attributes
    ----------
    n_kept : int
        Finished levels whose chunks are in ``chunks`` (``resume=True`` reuses them).
    chunks : Path or None
        The chunks folder ``OUT/.chunks``; None for a run without an output folder.
    """

    def __init__(self, n_kept: int, chunks: Path | None):
        self.n_kept, self.chunks = int(n_kept), (None if chunks is None else Path(chunks))
        super().__init__(self.summary("resume=True"))

    def summary(self, resume: str = "--resume") -> str:
        """``interrupted: 3 levels kept in OUT/.chunks; rerun with <resume>`` (just
        ``interrupted`` without an output folder)."""
        if self.chunks is None:
            return "interrupted"
        levels = "level" if self.n_kept == 1 else "levels"
        return f"interrupted: {self.n_kept} {levels} kept in {self.chunks}; rerun with {resume}"


_PENDING = threading.Event()  # SIGINT received under deferred_sigint, not yet raised


def _note_sigint(signum, frame):
    _PENDING.set()


def check_interrupt() -> None:
    """Raise KeyboardInterrupt if SIGINT arrived under :func:`deferred_sigint` (call it where no
    kernel runs)."""
    if _PENDING.is_set():
        _PENDING.clear()
        raise KeyboardInterrupt


@contextmanager
def deferred_sigint():
    """Within: SIGINT sets a flag that :func:`check_interrupt` raises (and, if nothing did, the
    exit of this block). Only in the main thread and while SIGINT has Python's default handler;
    otherwise (another handler installed, a thread) nothing changes."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    _PENDING.clear()
    signal.signal(signal.SIGINT, _note_sigint)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    check_interrupt()


def _prctl_pdeathsig(sig: int) -> bool:
    """Linux: have the kernel send ``sig`` to this process when its parent ends."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(1, int(sig), 0, 0, 0) == 0  # PR_SET_PDEATHSIG = 1
    except (OSError, AttributeError):
        return False


def _watch_parent(parent: int) -> None:
    import time

    while os.getppid() == parent:
        time.sleep(1.0)
    os._exit(1)


def end_with_parent(parent: int) -> None:
    """Make this (worker) process end when process ``parent`` does: ``PR_SET_PDEATHSIG``
    (SIGTERM) on Linux, else a daemon thread that polls the parent id once a second."""
    if _prctl_pdeathsig(signal.SIGTERM):
        if os.getppid() != parent:  # the parent died before prctl took effect
            os._exit(1)
        return
    threading.Thread(target=_watch_parent, args=(parent,), daemon=True,
                     name="contactvib-parent-watch").start()
