"""Shared test setup: ``tests/`` is on ``sys.path`` (for the helper modules :mod:`figure_files`
and :mod:`chunks_wait`; the scipy reference integrator is :mod:`contactvib.testing`), figures are
drawn without a display, the fixtures more than one test folder uses (:func:`small_dataset`), and
a check that no test leaves a command's default output folder in the repository root."""

from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")

#: The repository root, and the default output folders of the commands (``--out`` not given):
#: a test writes into its tmp_path, never there.
ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUTPUTS = ("atlas", "basins", "bif", "branch", "evo", "evolution.mp4", "hbm", "map", "paper", "resonance",
                   "simulate")


@pytest.fixture(scope="session", autouse=True)
def no_output_in_the_repository():
    """Fails the session when a test left a command's default output folder in the repository
    root (one that was not there when the session started)."""
    before = {name for name in DEFAULT_OUTPUTS if (ROOT / name).exists()}
    yield
    left = sorted(name for name in DEFAULT_OUTPUTS if (ROOT / name).exists() and name not in before)
    assert not left, f"tests left {left} in {ROOT}: give the command --out under tmp_path (or chdir there)"


@pytest.fixture(scope="session")
def small_dataset(tmp_path_factory):
    """A resonance dataset of one level (0.65 Q) over 340–380 Hz, 2 Hz step."""
    from contactvib import ContactModel
    from contactvib.sweeps.resonance import resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    out = tmp_path_factory.mktemp("res")
    st = SweepSettings(fmin_hz=340.0, fmax_hz=380.0, df_hz=2.0, multistart_per_octave=0)
    resonance_dataset(ContactModel(), levels=[0.65], settings=st, out=out, workers=1, progress=False)
    return out / "resonance.nc"
