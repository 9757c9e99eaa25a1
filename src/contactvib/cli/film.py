"""CLI command ``animate``: the film of a resonance dataset, one frame per P_a level."""

from __future__ import annotations

from pathlib import Path

import click

from contactvib.cli.common import InputError, checked_output_folder, ctrl_c, open_dataset_argument, option_error
from contactvib.model import ParameterError, level_text

_FILM_OPTIONS = {"fps": "--fps", "width": "--size", "height": "--size"}


def _size(text: str) -> tuple[str, str]:
    """``"1600x800"`` → ("1600", "800") (the numbers are checked by the library)."""
    parts = text.strip().lower().split("x")
    if len(parts) != 2 or not all(p.strip() for p in parts):
        raise InputError(f"--size = {text}: expected WxH, the frame's width and height in pixels, e.g. 1600x800")
    return parts[0].strip(), parts[1].strip()


def _output_file(out: str, gif: bool) -> Path:
    """``--out``: its folder created and writable (probe file), its suffix .mp4 (or .gif with
    --gif); an InputError otherwise — before anything is read or drawn."""
    path = Path(out)
    if path.is_dir():
        raise InputError(f"--out = {out}: is a folder; give the film's file name (e.g. evolution.mp4)")
    checked_output_folder(path.parent, file=out)  # created and writable, or one line naming --out
    want = ".gif" if gif else ".mp4"
    if path.suffix.lower() != want:
        hint = "with --gif the film is a GIF" if gif else "or in .gif with --gif"
        raise InputError(f"--out = {out}: must end in {want} ({hint})")
    return path


@click.command()
@click.argument("dataset", type=click.Path())
@click.option("--out", default="evolution.mp4", show_default=True, type=click.Path(),
              help="The film: an .mp4 file (H.264), or a .gif file with --gif.")
@click.option("--fps", default="2", show_default=True,
              help="Frame rate [frames/s], 0 < fps <= 60 (one frame per level).")
@click.option("--gif", is_flag=True, help="Write a GIF instead of an MP4.")
@click.option("--size", default="1600x800", show_default=True, metavar="WxH",
              help="Frame size in pixels, even numbers in 64..4096.")
def animate(dataset, out, fps, gif, size):
    """The film of a resonance dataset (paper.nc, resonance.nc or an atlas; a file or its folder):
    one frame per P_a level with Figs. 2 and 3 side by side at fixed axes, a P_a counter and the
    stage of each 1/m resonance (S3.8)."""
    from contactvib.sweeps.film import check_film

    try:
        fps_, width, height = check_film(fps, *_size(size))
    except ParameterError as e:
        raise option_error(_FILM_OPTIONS.get(e.symbol, e.symbol), e) from None
    path = _output_file(out, gif)
    source = open_dataset_argument(dataset, load=True)
    from contactvib.sweeps import film

    with ctrl_c():
        res = film.animate(source, path, fps=fps_, size=(width, height), gif=gif)
    kind = source.kind
    sym, unit = level_text(1.0, kind).split(" = 1 ")
    click.echo(f"{len(res.levels)} frames ({res.size[0]}x{res.size[1]} px, {res.fps:g} frames/s, "
               f"{sym} = {res.levels[0]:g}..{res.levels[-1]:g} {unit}) -> {res.path}")
    for pa in res.levels:
        click.echo(f"  {level_text(pa, kind)}: " + ", ".join(f"1/{m} {s}" for m, s in res.stages[pa].items()))
