"""Every status code of the kernels, one table, and its messages.

Kernels return these integers and never format a message; the library's Python code turns a
code into words with :func:`status_message` (error messages, stop reasons, dataset strings).
Codes of the integration/Newton families are distinct, so one code says what failed:

* flow (:mod:`.flow`, :mod:`.taylor`, and everything that integrates): 0–5;
* Newton shooting of period-k orbits (:mod:`.shooting`): 10–13;
* the pseudo-arclength corrector of the continuation (:mod:`.continuation`): 20–22;
* −1: the continuation's tangent turned too fast (set by the Python driver, not a kernel).

Three further families number their outcomes from 0 and are looked up by family name:
``"settle"`` (outcome of one settling run, :mod:`.settle`), ``"stop"`` (why a frequency trace
ended, :mod:`.trace`) and ``"origin"`` (how a traced point was reached, :mod:`.trace`).

To add a code: define the constant here (in its family's range), import it in the kernel, and
add its message to :data:`MESSAGES`; texts written into datasets must not change.
"""

from __future__ import annotations

__all__ = ["MESSAGES", "status_message"]

# ---------------------------------------------------------------- flow (integration)
STATUS_OK = 0
STATUS_MAX_STEPS = 1
STATUS_STEP_TOO_SMALL = 2
STATUS_RECORD_FULL = 3
STATUS_TOO_MANY_EVENTS = 4
STATUS_NONFINITE = 5
#: A run stopped by its stop flag (Ctrl-C, :mod:`contactvib.interrupts`).
STATUS_INTERRUPTED = 6
# ---------------------------------------------------------------- Newton shooting
STATUS_NEWTON_DIVERGED = 10
STATUS_NEWTON_SINGULAR = 11
STATUS_NEWTON_MAXITER = 12
#: Newton's step fell below the caller's quick-step size: closure to be checked by the caller.
STATUS_NEWTON_QUICK = 13
# ---------------------------------------------------------------- continuation corrector
STATUS_SINGULAR = 20
STATUS_DIVERGED = 21
STATUS_MAXITER = 22
#: Set by the continuation driver (Python) when the tangent turned by more than its limit.
STATUS_TANGENT_TURNED = -1
# ---------------------------------------------------------------- settle outcomes
SETTLE_PERIODIC = 0
SETTLE_NONPERIODIC = 1
SETTLE_FAILED = 2
SETTLE_CAPTURED = 3
SETTLE_INTERRUPTED = 4
# ---------------------------------------------------------------- trace stop reasons
STOP_GRID_END = 0
STOP_KNOWN = 1
STOP_FAILED = 2
STOP_TABLE_FULL = 3
# ---------------------------------------------------------------- trace origins of a point
ORIGIN_NEWTON = 0
ORIGIN_JUMP = 1
ORIGIN_START = 2

#: (family, code) -> message. Family "status" holds the flow, Newton and corrector codes.
MESSAGES = {
    ("status", STATUS_OK): "ok",
    ("status", STATUS_MAX_STEPS): "integrator step limit",
    ("status", STATUS_STEP_TOO_SMALL): "integrator step too small",
    ("status", STATUS_RECORD_FULL): "step record full",
    ("status", STATUS_TOO_MANY_EVENTS): "too many contact events in one step",
    ("status", STATUS_NONFINITE): "non-finite state",
    ("status", STATUS_INTERRUPTED): "interrupted",
    ("status", STATUS_NEWTON_DIVERGED): "Newton shooting diverged",
    ("status", STATUS_NEWTON_SINGULAR): "Newton shooting: singular M - I",
    ("status", STATUS_NEWTON_MAXITER): "Newton shooting did not converge",
    ("status", STATUS_NEWTON_QUICK): "Newton shooting: small step, closure unchecked",
    ("status", STATUS_SINGULAR): "singular Jacobian",
    ("status", STATUS_DIVERGED): "Newton diverged",
    ("status", STATUS_MAXITER): "Newton did not converge",
    ("status", STATUS_TANGENT_TURNED): "tangent turned too fast",
    ("settle", SETTLE_PERIODIC): "periodic",
    ("settle", SETTLE_NONPERIODIC): "non-periodic",
    ("settle", SETTLE_FAILED): "failed",
    ("settle", SETTLE_CAPTURED): "captured",
    ("settle", SETTLE_INTERRUPTED): "interrupted",
    ("stop", STOP_GRID_END): "end of frequency grid",
    ("stop", STOP_KNOWN): "joined an attractor already traced this way",
    ("stop", STOP_FAILED): "integration or Newton failure",
    ("stop", STOP_TABLE_FULL): "attractor table full",
    ("origin", ORIGIN_NEWTON): "newton",
    ("origin", ORIGIN_JUMP): "jump",
    ("origin", ORIGIN_START): "start",
}


def status_message(code, family: str = "status") -> str:
    """The message of a kernel status ``code`` of ``family`` ("status", "settle", "stop",
    "origin"); an unknown code gives ``"unknown <family> code <code>"``."""
    try:
        key = (family, int(code))
    except (TypeError, ValueError):
        return f"unknown {family} code {code!r}"
    return MESSAGES.get(key, f"unknown {family} code {code}")
