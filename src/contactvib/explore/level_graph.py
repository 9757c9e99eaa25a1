"""The explore page's resonance graph without a dataset: the current P_a level swept in the
background, as ``contactvib resonance`` sweeps it.

A :class:`LevelRun` is one level's sweep (:func:`contactvib.sweeps.resonance.resonance_dataset`,
one worker: in the calling thread) with the page's model. :func:`sweep_level` runs it in a worker
thread: its progress is the sweep's own (:func:`contactvib.sweeps.level_progress.report_points`,
sent to the run through :func:`~contactvib.sweeps.level_progress.points_to`: f_e points done, two
fifths after the up/down sweeps, then with each multi-start frequency); it stops when the page sets the run's
flag (a new P_a or model) or after its own time limit (:func:`.state.run_limited`: the sweep
stops at its next check between kernel calls, :func:`contactvib.interrupts.check_interrupt`); its
result is the level's points as the dataset mode reads them (:func:`.dataset_view.level_points`),
drawn by :func:`.dataset_view.graph_figure`. Pure Python, no browser."""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, field

import numpy as np

from contactvib.explore.state import Stopped, run_limited

__all__ = ["LevelRun", "sweep_level", "GRAPH_TIME_LIMIT_S"]

#: Default time limit of one background level [s] (the CLI's --graph-time-limit): the CLI's
#: default grid (30-2000 Hz, 1 Hz) takes seconds at 0.65 Q, and much longer at large P_a or
#: with unusual models; the page's 30 s limit is for the searches a change waits for.
GRAPH_TIME_LIMIT_S = 300.0


@dataclass
class LevelRun:
    """One background level: the checked model, P_a [Q] and SweepSettings, the command that
    computes the same level, the f_e points done so far (as reported) and the stop flag."""

    model: object
    pa_over_q: float
    settings: object
    command: str
    flag: np.ndarray = field(default_factory=lambda: np.zeros(1, np.int64))
    points: int = 0

    @property
    def total(self) -> int:
        """The f_e points of the level's grid."""
        from contactvib.sweeps.sweep import frequency_grid

        return int(frequency_grid(self.settings).size)

    def stop(self) -> None:
        """Stop the sweep at its next check (from any thread); its result is dropped."""
        self.flag[0] = 1

    def _report(self, item) -> None:
        self.points = max(self.points, int(item[1]))


def sweep_level(run: LevelRun, limit_s: float = GRAPH_TIME_LIMIT_S):
    """Worker thread: the level of ``run``, ``("ok", (LevelPoints, seconds))``, or
    ``("stopped", "stopped after 300 s")`` (its time limit, or ``"stopped"`` when the page
    stopped it), or ``("error", message)`` (one line; never an exception)."""
    from contactvib.explore.dataset_view import level_points
    from contactvib.model import ParameterError
    from contactvib.sweeps.level_progress import points_to
    from contactvib.sweeps.resonance import resonance_dataset
    from contactvib.sweeps.stored import ResonanceData

    if run.flag[0]:
        return "stopped", "stopped"
    t0 = time.perf_counter()
    try:
        with points_to(run._report):
            ds = run_limited(lambda: resonance_dataset(run.model, levels=[run.pa_over_q], settings=run.settings,
                                                       workers=1, progress=False), limit_s, run.flag)
    except Stopped as e:
        return "stopped", str(e)
    except ParameterError as e:  # the inputs are checked before; a refusal is still one line
        return "error", f"contactvib: error: {e}"
    except Exception as e:  # a failure is one line in the page, its traceback in the server's log
        logging.getLogger("contactvib.explore").exception("explore: the level sweep failed")
        return "error", f"contactvib: the sweep failed: {type(e).__name__}: {e}"
    return "ok", (level_points(ResonanceData(ds), run.pa_over_q), time.perf_counter() - t0)
