"""Shared test setup: ``tests/`` is on ``sys.path`` (for the helper modules :mod:`figure_files`
and :mod:`chunks_wait`; the scipy reference integrator is :mod:`contactvib.testing`), figures are
drawn without a display, and the fixtures more than one test folder uses (:func:`small_dataset`)."""

import matplotlib
import pytest

matplotlib.use("Agg")


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
