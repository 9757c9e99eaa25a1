"""One frame of the film of a resonance dataset (``contactvib animate``): the level's resonance
graph (Fig. 2) and local-extrema diagram (Fig. 3) side by side at axes fixed over all levels, a
P_a counter, and the stage (S3.8) of each 1/m resonance written under the panels.

The frame is an RGB array of exactly the declared pixel size: the figure's inches times its dpi
(:data:`FRAME_DPI`, scaled with the size) are the pixels, drawn on an Agg canvas (no pyplot state,
no file).
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass, field

import numpy as np

from contactvib.model import level_text
from contactvib.plotting.figures import new_figure
from contactvib.plotting.paper import draw_level
from contactvib.plotting.style import order_colour

__all__ = ["FrameText", "film_frame", "FRAME_DPI", "REFERENCE_SIZE"]

#: The frames' resolution [dots per inch] at REFERENCE_SIZE [pixels]: a frame of another size is
#: drawn at ``FRAME_DPI × min(width / 1600, height / 800)`` dpi, its figure size in inches being its
#: pixel size / dpi.
FRAME_DPI = 100
REFERENCE_SIZE = (1600, 800)
#: The lowest dpi (frames of a few hundred pixels): below it the type is smaller than a pixel.
MIN_DPI = 16.0


@dataclass(frozen=True)
class FrameText:
    """What a frame says besides its panels.

    ``index``/``count``: the frame's number (from 0) and the number of frames; ``pa_range``: the
    film's lowest and highest P_a [Q] (the counter's scale); ``stages``: ``{m: stage}`` of the 1/m
    resonances at this level; ``statement``: the paper's statement about this level (id and text,
    ``""`` for a level the paper does not draw); ``levels``: all P_a levels [Q] (ticks of the counter);
    ``level_kind``: what the levels hold (:data:`contactvib.model.LEVEL_KINDS`; "base-um": U [µm]).
    """

    index: int
    count: int
    pa_range: tuple
    stages: dict = field(default_factory=dict)
    statement: str = ""
    levels: tuple = ()
    level_kind: str = "force"


def film_frame(ds, pa_over_q: float, limits: dict, text: FrameText, size=(1600, 800)) -> np.ndarray:
    """One frame, an ``(height, width, 3)`` uint8 RGB array of exactly ``size = (width, height)``
    pixels: Fig. 2 (left) and Fig. 3 (right) of the level at the axes ``limits`` of
    :func:`contactvib.plotting.paper.draw_level`, the P_a counter on top, the stages below."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    width, height = (int(s) for s in size)
    # the layout of a REFERENCE_SIZE frame, rendered at the declared pixels: the dpi scales with the
    # size, so that a smaller frame is the same picture with smaller type (never a resize)
    dpi = max(FRAME_DPI * min(width / REFERENCE_SIZE[0], height / REFERENCE_SIZE[1]), MIN_DPI)
    fig, axes = new_figure(1, 2, figsize=(width / dpi, height / dpi))
    fig.set_dpi(dpi)
    canvas = FigureCanvasAgg(fig)
    draw_level(ds, pa_over_q, axes[0, 0], axes[0, 1], limits=limits)
    for ax in axes[0]:
        ax.set_title("")
    axes[0, 0].set_title("Resonance graph (cf. Fig. 2)", fontsize=10)
    axes[0, 1].set_title("Local extrema of y(t) (cf. Fig. 3)", fontsize=10)
    _counter(fig, pa_over_q, text)
    _captions(fig, text)
    fig.subplots_adjust(left=0.06, right=0.985, top=0.86, bottom=0.24, wspace=0.16)
    canvas.draw()
    rgb = np.asarray(canvas.buffer_rgba())[..., :3].copy()
    if rgb.shape != (height, width, 3):  # a backend that rounds the size: never a silent resize
        raise RuntimeError(f"frame drawn at {rgb.shape[1]}x{rgb.shape[0]} px instead of {width}x{height}")
    return rgb


def _counter(fig, pa_over_q: float, text: FrameText) -> None:
    """The P_a counter: the value, the frame number and a bar over the film's P_a range."""
    lo, hi = (float(x) for x in text.pa_range)
    sym, unit = level_text(1.0, text.level_kind).split(" = 1 ")
    fig.text(0.06, 0.955, f"${sym}$ = {pa_over_q:.3g} {unit}" if sym != "P_a" else f"$P_a$ = {pa_over_q:.3f} Q",
             fontsize=18, weight="bold", va="center")
    fig.text(0.24, 0.955, f"level {text.index + 1} of {text.count}", fontsize=11, va="center", color="0.3")
    bar = fig.add_axes((0.40, 0.94, 0.585, 0.03))
    frac = 1.0 if hi <= lo else (pa_over_q - lo) / (hi - lo)
    bar.barh([0], [frac], color="0.45", height=1.0)
    bar.set_xlim(0, 1)
    bar.set_ylim(-0.5, 0.5)
    bar.set_yticks([])
    levels = text.levels or (lo, hi)
    ticks = [0.5 if hi <= lo else (p - lo) / (hi - lo) for p in levels]
    bar.set_xticks(ticks, [f"{p:g}" if len(levels) <= 12 or p in (lo, hi) else "" for p in levels],
                   fontsize=8)
    bar.tick_params(axis="x", length=3, pad=1)
    bar.set_xlabel(f"${sym}$ [{unit}]" + (" (base motion)" if sym != "P_a" else ""), fontsize=8, labelpad=1)


def _captions(fig, text: FrameText) -> None:
    """The stage of each 1/m resonance (in its colour of the resonance graph) and the paper's
    statement about the level."""
    fig.text(0.06, 0.135, "Stage (S3.8, from the data):", fontsize=11, weight="bold", va="center")
    x = 0.245
    step = min(0.15, 0.74 / max(len(text.stages), 1))
    for m, stage in sorted(text.stages.items()):
        fig.text(x, 0.135, f"1/{m}: {stage}", fontsize=11, va="center", color=order_colour(m),
                 weight="bold" if stage not in ("absent", "grows") else "normal")
        x += step
    if text.statement:
        chars = fig.get_figwidth() * 72.0 * 0.9 / (9 * 0.6)  # 9 pt text, ~0.6 em per character
        wrapped = textwrap.fill(text.statement, width=max(int(chars), 20))
        fig.text(0.06, 0.095, wrapped, fontsize=9, va="top", color="0.15")
