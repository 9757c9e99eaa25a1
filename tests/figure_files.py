"""Check of a PNG figure written by contactvib (the figures' content is tested through the
plotting functions' axes in ``tests/plotting``)."""

import numpy as np


def assert_figure_file(path, min_width: int = 500, min_height: int = 300, min_ink: float = 0.01):
    """A PNG written by contactvib: readable, at least ``min_width`` × ``min_height`` pixels, and
    not blank (at least ``min_ink`` of its pixels differ from white). The content of the figures
    is tested through the plotting functions' axes (``tests/plotting``)."""
    from matplotlib.image import imread

    img = imread(path)
    h, w = img.shape[:2]
    assert w >= min_width and h >= min_height, (path, img.shape)
    rgb = img[..., :3]
    ink = float(np.mean(np.any(rgb < 0.95, axis=-1)))
    assert ink >= min_ink, (path, ink)
