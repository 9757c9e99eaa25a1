"""Shared test setup: ``tests/`` is on ``sys.path`` (for :mod:`scipy_contact`), and figures are
drawn without a display."""

import matplotlib

matplotlib.use("Agg")
