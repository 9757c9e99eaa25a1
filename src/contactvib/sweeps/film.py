"""The film of a resonance dataset (``contactvib animate``): one frame per
P_a level, Fig. 2 and Fig. 3 side by side at axes fixed over all levels, a P_a counter, and the
stage of each 1/m resonance (S3.8) computed from the data as the paper's index page does
(:func:`contactvib.sweeps.facts.level_stages`).

MP4 (H.264, yuv420p) is written through the ffmpeg binary of the ``imageio-ffmpeg`` wheel (no
system ffmpeg needed); GIF through imageio's pillow plugin. Files are written under a temporary
name and renamed when complete.

:func:`animate` reads a dataset file, or a folder holding one, as every reader does
(:func:`contactvib.sweeps.stored.open_resonance`, read into memory: :func:`open_levels`), and
draws each frame from the dataset's :class:`~contactvib.sweeps.stored.ResonanceData`.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contactvib.call_forms import old_form
from contactvib.model.checks import ParameterError, check_int, check_range
from contactvib.sweeps.stored import DatasetError, ResonanceData, matching_level, open_resonance

__all__ = ["FPS_RANGE", "SIZE_RANGE", "DatasetError", "open_levels",
           "check_film", "film_limits", "FilmResult", "animate"]

#: Frame rate [frames per second]: 0 < fps <= 60.
FPS_RANGE = (0.0, 60.0)
#: Frame width and height [pixels]: even integers (H.264 with yuv420p) in this range.
SIZE_RANGE = (64, 4096)


def open_levels(path) -> ResonanceData:
    """The resonance dataset of ``path`` (a ``.nc`` file written by ``paper``, ``resonance`` or
    ``atlas``, or a folder holding one) read into memory: :func:`open_resonance` with
    ``load=True``. Raises ``DatasetError`` (one line) when it cannot be read or holds no level."""
    return open_resonance(path, load=True)


def check_film(fps, width, height) -> tuple[float, int, int]:
    """``(fps, width, height)`` checked: 0 < fps <= 60 frames/s, width and height even integers
    in 64..4096 pixels. Raises :class:`ParameterError` (symbols ``fps``, ``width``, ``height``)."""
    fps = check_range("fps", fps, FPS_RANGE[0], inclusive=False, unit="frames/s", upper=FPS_RANGE[1])
    sizes = []
    for symbol, value in (("width", width), ("height", height)):
        allowed = f"must be an even integer in {SIZE_RANGE[0]}..{SIZE_RANGE[1]} pixels (H.264 with yuv420p)"
        try:
            v = check_int(symbol, value, *SIZE_RANGE)
        except ParameterError:
            raise ParameterError(symbol, value, allowed) from None
        if v % 2:
            raise ParameterError(symbol, value, allowed)
        sizes.append(v)
    return fps, sizes[0], sizes[1]


def film_limits(ds) -> dict:
    """Axes fixed over all levels of ``ds``: f_e from 0 to the highest frequency + 2 % [Hz],
    A_pp [µm] (log) from half the smallest positive to twice the largest amplitude, the local
    extrema of y [µm] (symlog) with a margin."""
    fe = ds["fe_hz"].values
    app = ds["app_um"].values
    app = app[np.isfinite(app) & (app > 0)]
    y = ds["extremum_y_um"].values
    y = y[np.isfinite(y)]
    a_lo, a_hi = (max(app.min() * 0.5, 1e-3), app.max() * 2.0) if app.size else (1e-3, 1.0)
    y_lo, y_hi = (float(y.min()), float(y.max())) if y.size else (-1.0, 1.0)
    return {"fe_hz": (0.0, float(fe.max()) * 1.02 if fe.size else 1.0),
            "app_um": (float(a_lo), float(a_hi)),
            "y_um": (y_lo * 1.5 if y_lo < 0 else y_lo * 0.5, y_hi * 1.5 if y_hi > 0 else y_hi * 0.5)}


def _statement(pa: float, statements: dict) -> str:
    from contactvib.sweeps.paper_index import S3_LEVELS

    if not statements:  # not the paper's kind of level
        return ""
    ids = [sid for sid, pas in S3_LEVELS.items() if matching_level(pas, pa) is not None]
    return " ".join(f"Kostek 2013, {sid}: {statements.get(sid, '')}" for sid in ids)


@dataclass(frozen=True)
class FilmResult:
    """What :func:`animate` wrote: the file, its frames (one per level, P_a [Q] each), the pixel
    size ``(width, height)``, the frame rate [1/s], the format ("mp4" or "gif") and the stages
    ``{P_a: {m: stage}}`` written on the frames."""

    path: Path
    levels: tuple
    size: tuple
    fps: float
    format: str
    stages: dict


def _frames(source: ResonanceData, size):
    """Yield ``(P_a, stages, frame)`` level by level."""
    from contactvib.interrupts import check_interrupt
    from contactvib.plotting.film import FrameText, film_frame
    from contactvib.sweeps.facts import level_stages
    from contactvib.sweeps.paper_index import paper_statements

    ds = source.ds
    limits = film_limits(ds)
    kind = source.kind
    statements = paper_statements() if kind == "force" else {}  # the paper's levels are forces
    lo, hi = source.levels[0], source.levels[-1]
    for i, pa in enumerate(source.levels):
        stages = level_stages(ds, pa)
        text = FrameText(i, len(source.levels), (lo, hi), stages, _statement(pa, statements), source.levels,
                         kind)
        frame = film_frame(ds, pa, limits, text, size)
        check_interrupt()
        yield pa, stages, frame


def _write_mp4(frames, path: Path, size, fps: float) -> dict:
    import imageio_ffmpeg

    stages, writer = {}, None
    try:
        for pa, st, frame in frames:
            if writer is None:  # ffmpeg starts with the first frame (an interrupt before: nothing to end)
                writer = imageio_ffmpeg.write_frames(
                    str(path), tuple(size), fps=fps, codec="libx264", pix_fmt_out="yuv420p", quality=None,
                    macro_block_size=2, output_params=["-crf", "18", "-movflags", "+faststart"],
                    ffmpeg_log_level="error")
                writer.send(None)
            writer.send(np.ascontiguousarray(frame))
            stages[pa] = st
    finally:
        if writer is not None:
            writer.close()
    return stages


def _write_gif(frames, path: Path, fps: float) -> dict:
    import imageio.v3 as iio

    stages, images = {}, []
    for pa, st, frame in frames:
        images.append(frame)
        stages[pa] = st
    # frames of different levels always differ (the counter), so pillow merges none of them
    iio.imwrite(path, np.stack(images), extension=".gif", plugin="pillow",
                duration=1000.0 / fps, loop=0)
    return stages


@old_form("dataset", "out", "fps", "size", "gif")
def animate(dataset, out, *, fps: float = 2.0, size=(1600, 800), gif: bool | None = None) -> FilmResult:
    """Write the film of ``dataset`` (a path for :func:`open_levels`, or a ``ResonanceData``)
    to ``out``: MP4 (H.264) or, with ``gif`` (default: from the suffix of ``out``), GIF; one frame
    of ``size = (width, height)`` pixels per level at ``fps`` frames per second. Returns a
    :class:`FilmResult`."""
    fps, width, height = check_film(fps, *size)
    source = dataset if isinstance(dataset, ResonanceData) else open_levels(dataset)
    out = Path(out)
    gif = out.suffix.lower() == ".gif" if gif is None else bool(gif)
    fmt = "gif" if gif else "mp4"
    tmp = out.with_name(f".{out.stem}.partial{os.getpid()}.{fmt}")
    frames = _frames(source, (width, height))
    try:
        stages = _write_gif(frames, tmp, fps) if gif else _write_mp4(frames, tmp, (width, height), fps)
        os.replace(tmp, out)
    finally:
        frames.close()
        if tmp.exists():
            tmp.unlink()
    return FilmResult(out, source.levels, (width, height), fps, fmt, stages)

