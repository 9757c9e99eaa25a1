"""Ctrl-C during a compiled kernel.

A numba kernel holds the interpreter until it returns, so a SIGINT would wait for it (seconds to
hours on legal input). :func:`run_interruptible` runs a kernel compiled with ``nogil=True`` in a
helper thread while this thread waits; on Ctrl-C it sets the kernel's ``stop`` flag (int64[1],
read by the kernel after every excitation period), waits for the kernel to return and re-raises
the KeyboardInterrupt, typically within milliseconds.
"""

from __future__ import annotations

import threading

import numpy as np

__all__ = ["run_interruptible", "new_stop_flag"]


def new_stop_flag() -> np.ndarray:
    """A cleared stop flag for a kernel (int64[1])."""
    return np.zeros(1, np.int64)


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
