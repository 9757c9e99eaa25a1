"""Helper of the interrupt tests (tests/robustness, tests/sweeps): wait for a run's first chunk."""

import time
from pathlib import Path


def first_chunk(p, out: Path, timeout: float = 180.0) -> None:
    """Wait until the run ``p`` (a Popen) has a finished chunk in ``out/.chunks``: it is then
    mid-way. Fails if it finished first or none came within ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not list((Path(out) / ".chunks").glob("level_pa*.nc")):
        assert p.poll() is None, f"finished before a chunk was seen: {p.communicate()}"
        assert time.monotonic() < deadline, "no chunk written"
        time.sleep(0.02)
