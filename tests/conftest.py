"""Shared test setup: ``tests/`` is on ``sys.path`` (for the helper modules :mod:`scipy_contact`
and :mod:`figure_files`), and figures are drawn without a display."""

import matplotlib

matplotlib.use("Agg")
