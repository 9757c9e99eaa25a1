"""A progress bar for the commands whose library call reports ``progress(done, total)``."""

from __future__ import annotations

import contextlib
import sys

__all__ = ["start_progress_bar"]


@contextlib.contextmanager
def start_progress_bar(desc: str, unit: str = "start"):
    """Within: a ``progress(done, total)`` callback that draws a tqdm bar of ``desc`` on a
    terminal's stderr (nothing when stderr is not a terminal), gone when the block ends."""
    bar = []

    def progress(done, total):
        if not done and sys.stderr.isatty():
            from tqdm import tqdm

            bar.append(tqdm(total=total, unit=unit, file=sys.stderr, leave=False, desc=desc))
        elif bar:
            bar[0].update(done - bar[0].n)

    try:
        yield progress
    finally:
        while bar:
            bar.pop().close()
