"""Clean interrupts of long runs: Ctrl-C (SIGINT) never inside numba, kernels that stop on
request, workers that end with their parent.

A numba kernel holds the interpreter until it returns, so a SIGINT would wait for it (seconds to
hours on legal input). :func:`run_interruptible` runs a kernel compiled with ``nogil=True`` in a
helper thread while the main thread waits; on Ctrl-C it sets the kernel's ``stop`` flag
(int64[1], read by the kernel after every excitation period), waits for the kernel to return and
re-raises the KeyboardInterrupt, typically within milliseconds (the attractor search uses it).

A KeyboardInterrupt must not be raised inside numba: compiled kernels call back into Python
(boxing typed records through ``_numba_unpickle``, in ``settle_known_many`` for one), and so
does the compiler (llvmlite's object-cache call-back); an exception raised there by the default
SIGINT handler comes out as ``SystemError: CPUDispatcher(...) returned a result with an
exception set``, as "Exception ignored" noise, or worse.
:func:`contactvib.sweeps.resonance.resonance_dataset` (and the CLI's sweep commands, figures
included) therefore run under :func:`deferred_sigint`: SIGINT raises KeyboardInterrupt at once
where only Python code is on the stack (a kernel that is running returns first), but while
numba or llvmlite code is on the stack it only sets a flag, which :func:`check_interrupt` raises
wherever Python regains control between kernel calls (every trace and multi-start frequency of
:mod:`contactvib.sweeps.sweep`, every level, every 0.2 s while waiting for the workers).

Worker processes ignore SIGINT (the parent handles it and terminates them) and end when their
parent dies, even by SIGKILL (:func:`end_with_parent`).

Another thread stops a run through a stop flag (:func:`stop_scope`, ``contactvib explore``): the
kernels that take a stop flag (:func:`new_stop_flag`) return within one period, and
:func:`check_interrupt` raises KeyboardInterrupt between the kernel calls of a sweep.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from contextlib import contextmanager
from pathlib import Path

import numpy as np

__all__ = ["Interrupted", "deferred_sigint", "check_interrupt", "end_with_parent",
           "run_interruptible", "new_stop_flag", "stop_scope"]


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


_SCOPE = threading.local()  # the stop flag of this thread's stop_scope, if any
_PENDING = [False]  # SIGINT received under deferred_sigint, not yet raised (no lock: a handler sets it)
_NUMBA = tuple(f"{os.sep}{name}{os.sep}" for name in ("numba", "llvmlite"))


def _note_sigint(signum, frame):
    """SIGINT under :func:`deferred_sigint`: a flag while numba or llvmlite code is on the stack,
    else KeyboardInterrupt."""
    while frame is not None:
        if any(part in frame.f_code.co_filename for part in _NUMBA):
            _PENDING[0] = True
            return
        frame = frame.f_back
    raise KeyboardInterrupt


def check_interrupt() -> None:
    """Raise KeyboardInterrupt if SIGINT arrived under :func:`deferred_sigint` while numba was on
    the stack, or if this thread runs in a :func:`stop_scope` whose flag is set (another thread
    stopped the run: the resonance sweeps of ``contactvib explore``, whose kernels take no stop
    flag, stop at their next check). Call it where no kernel runs."""
    if _PENDING[0]:
        _PENDING[0] = False
        raise KeyboardInterrupt
    scoped = getattr(_SCOPE, "flag", None)
    if scoped is not None and scoped[0]:
        raise KeyboardInterrupt


@contextmanager
def deferred_sigint():
    """Within: SIGINT raises KeyboardInterrupt, except while numba or llvmlite code is on the
    stack, where it sets a flag that :func:`check_interrupt` raises (or, if nothing did, the exit
    of this block). Only in the main thread and while SIGINT has Python's default handler;
    otherwise (another handler installed, a thread) nothing changes."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    _PENDING[0] = False
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


@contextmanager
def stop_scope(flag: np.ndarray):
    """Within (in this thread): :func:`new_stop_flag` returns ``flag``, so that another thread
    stops every kernel run here by setting ``flag[0] = 1`` (``contactvib explore``'s time
    limit; the result computed under a set flag is incomplete and must be dropped), and
    :func:`check_interrupt` raises KeyboardInterrupt once it is set."""
    previous = getattr(_SCOPE, "flag", None)
    _SCOPE.flag = flag
    try:
        yield flag
    finally:
        _SCOPE.flag = previous


def new_stop_flag() -> np.ndarray:
    """A cleared stop flag for a kernel (int64[1]); within :func:`stop_scope`, its flag."""
    scoped = getattr(_SCOPE, "flag", None)
    return np.zeros(1, np.int64) if scoped is None else scoped


def run_interruptible(kernel, *args, stop: np.ndarray):
    """``kernel(*args)``, where ``stop`` is among ``args``; Ctrl-C sets ``stop[0] = 1`` and raises
    KeyboardInterrupt once the kernel has returned. Outside the main thread (where no signal
    arrives) the kernel runs directly."""
    if threading.current_thread() is not threading.main_thread():
        return kernel(*args)
    box: dict = {}

    def target():
        try:
            box["value"] = kernel(*args)
        except BaseException as e:  # handed to the caller
            box["error"] = e

    worker = threading.Thread(target=target, name="contactvib-kernel", daemon=True)
    worker.start()
    try:
        while worker.is_alive():
            worker.join(0.05)
    except KeyboardInterrupt:
        stop[0] = 1
        worker.join()
        raise
    if "error" in box:
        raise box["error"]
    return box["value"]
