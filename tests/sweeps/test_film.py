"""The film of a resonance dataset (issue 14, "Animation"; ``contactvib animate``): one frame per
level, the declared size and frame rate read back from the file, frames that differ where the data
differ and are equal where they are equal, the GIF path, fixed axes, the stages of the index page,
and bad input refused in one line (exit 2) before anything is drawn."""

from __future__ import annotations

import imageio.v3 as iio
import imageio_ffmpeg
import numpy as np
import pytest
import xarray as xr

from contactvib import ContactModel
from contactvib.cli import main
from contactvib.model import ParameterError
from contactvib.sweeps.dataset import merge_levels
from contactvib.sweeps.facts import level_stages, resonance_facts
from contactvib.sweeps.film import (
    DatasetError,
    animate,
    check_film,
    film_limits,
    open_levels,
)
from contactvib.sweeps.resonance import resonance_dataset
from contactvib.sweeps.stored import ResonanceData
from contactvib.sweeps.sweep import SweepSettings

LEVELS = (0.5, 0.65, 0.7)
SIZE = (330, 250)  # even, not a multiple of 16: never resized by the encoder
#: rows of a SIZE frame below the P_a counter and above the captions: the two panels only
PANELS = slice(int(0.16 * SIZE[1]), int(0.74 * SIZE[1]))


@pytest.fixture(scope="module")
def films(tmp_path_factory):
    """A 3-level dataset (340–380 Hz at 4 Hz) as resonance.nc in its folder, and a 4-level one
    whose level 0.66 Q is a copy of 0.65 Q (identical data, another P_a)."""
    out = tmp_path_factory.mktemp("film")
    st = SweepSettings(fmin_hz=340.0, fmax_hz=380.0, df_hz=4.0, multistart_per_octave=0)
    resonance_dataset(ContactModel(), levels=list(LEVELS), settings=st, out=out / "res", workers=1, progress=False)
    chunks = {p: xr.load_dataset(out / "res" / ".chunks" / f"level_pa{p:g}.nc") for p in LEVELS}
    twin = chunks[0.65].copy(deep=True)
    for v in ("pa_over_q", "branch_pa_over_q", "trace_pa_over_q"):
        twin[v] = xr.full_like(twin[v], 0.66)
    dup = merge_levels([*chunks.values(), twin])
    dup.to_netcdf(out / "dup.nc")
    return out


def _mp4_frames(path):
    """(metadata, frames) of an MP4 decoded by the imageio-ffmpeg binary."""
    reader = imageio_ffmpeg.read_frames(str(path))
    meta = next(reader)
    w, h = meta["size"]
    return meta, [np.frombuffer(b, np.uint8).reshape(h, w, 3) for b in reader]


def test_mp4_one_frame_per_level_declared_size_and_rate(films, tmp_path):
    res = animate(films / "res", tmp_path / "film.mp4", fps=3, size=SIZE)
    assert res.levels == LEVELS and res.format == "mp4" and res.path.is_file()
    meta, frames = _mp4_frames(res.path)
    assert meta["codec"] == "h264" and meta["pix_fmt"].startswith("yuv420p")
    assert meta["size"] == SIZE and meta["fps"] == pytest.approx(3.0)
    assert len(frames) == len(LEVELS)
    assert imageio_ffmpeg.count_frames_and_secs(str(res.path)) == (3, pytest.approx(1.0))
    # the frames differ where the data do: the panels of different levels differ
    for a, b in ((0, 1), (1, 2)):
        diff = np.abs(frames[a][PANELS].astype(int) - frames[b][PANELS].astype(int))
        assert diff.mean() > 0.1, (a, b, diff.mean())  # the codec's noise is ~0.001
    assert not list(tmp_path.glob(".*partial*")), "no temporary file left"


def test_frames_equal_for_identical_data(films, tmp_path):
    res = animate(films / "dup.nc", tmp_path / "dup.mp4", fps=2, size=SIZE)
    assert res.levels == (0.5, 0.65, 0.66, 0.7)
    meta, frames = _mp4_frames(res.path)
    assert len(frames) == 4
    diff = lambda a, b: np.abs(frames[a][PANELS].astype(int) - frames[b][PANELS].astype(int)).mean()  # noqa: E731
    # 0.65 and its copy at 0.66: the same panels (up to the codec's noise); 0.5 and 0.7 differ
    assert diff(1, 2) < 0.05 * diff(0, 1) and diff(1, 2) < 0.05 * diff(2, 3), (diff(1, 2), diff(0, 1))
    # the P_a counter differs on every frame
    top = slice(0, int(0.1 * SIZE[1]))
    assert np.abs(frames[1][top].astype(int) - frames[2][top].astype(int)).mean() > 0.1


def test_rendered_frames_are_exact_and_deterministic(films):
    from contactvib.plotting.film import FrameText, film_frame

    src = open_levels(films / "dup.nc")
    lim = film_limits(src.ds)
    text = FrameText(0, 1, (0.5, 0.7), {2: "grows"}, "", src.levels)
    a, b = (film_frame(src.ds, p, lim, text, (642, 362)) for p in (0.65, 0.66))
    assert a.shape == (362, 642, 3) and a.dtype == np.uint8
    assert np.array_equal(a, film_frame(src.ds, 0.65, lim, text, (642, 362)))  # deterministic
    panels = slice(int(0.16 * 362), int(0.74 * 362))
    assert np.array_equal(a[panels], b[panels])  # same data: the same panels (the counter differs)
    assert not np.array_equal(a[:30], b[:30])
    c = film_frame(src.ds, 0.5, lim, text, (642, 362))
    assert not np.array_equal(a[panels], c[panels])
    for size in ((64, 64), (1600, 800), (1000, 1000), (4096, 64)):
        assert film_frame(src.ds, 0.65, lim, text, size).shape == (size[1], size[0], 3)


def test_gif_frames_size_and_rate(films, tmp_path):
    res = animate(films / "res" / "resonance.nc", tmp_path / "film.gif", fps=4, size=SIZE)
    assert res.format == "gif"
    props = iio.improps(res.path, plugin="pillow")
    assert props.n_images == len(LEVELS) and props.shape[1:3] == (SIZE[1], SIZE[0])
    durations = [iio.immeta(res.path, plugin="pillow", index=i)["duration"] for i in range(len(LEVELS))]
    assert all(d == pytest.approx(250, abs=10) for d in durations)  # GIF: centiseconds
    frames = iio.imread(res.path, plugin="pillow")
    assert not np.array_equal(frames[0][PANELS], frames[1][PANELS])


def test_fixed_axes_cover_every_level(films):
    ds = open_levels(films / "res").ds
    lim = film_limits(ds)
    assert lim["fe_hz"][0] == 0.0 and lim["fe_hz"][1] >= float(ds["fe_hz"].max())
    app = ds["app_um"].values
    assert lim["app_um"][0] < app[app > 0].min() and lim["app_um"][1] > app.max()
    y = ds["extremum_y_um"].values
    assert lim["y_um"][0] < y.min() and lim["y_um"][1] > y.max()


def test_stages_are_the_index_pages(films, tmp_path):
    res = animate(films / "res", tmp_path / "s.mp4", size=SIZE)
    ds = open_levels(films / "res").ds
    for p in LEVELS:
        assert res.stages[p] == level_stages(ds, p)
        assert res.stages[p] == {m: resonance_facts(ds, p, m).stage() for m in (2, 3, 4, 5, 6)}


def test_open_levels(films, tmp_path):
    src = open_levels(films / "res")
    assert isinstance(src, ResonanceData) and src.path.name == "resonance.nc" and src.levels == LEVELS
    assert src.level(0.65)["pa_over_q"].size == int((src.ds["pa_over_q"] == 0.65).sum()) > 0
    two = tmp_path / "two"
    two.mkdir()
    for name in ("paper.nc", "atlas.nc"):
        (two / name).write_bytes((films / "dup.nc").read_bytes())
    assert open_levels(two).path == two / "atlas.nc"  # as every command finds a folder's dataset
    with pytest.raises(DatasetError, match="no such file"):
        open_levels(tmp_path / "missing.nc")
    other = tmp_path / "other.nc"
    xr.Dataset({"x": ("a", [1.0])}).to_netcdf(other)
    with pytest.raises(DatasetError, match="not a contactvib resonance dataset"):
        open_levels(other)
    text = tmp_path / "text.nc"
    text.write_text("not netcdf")
    with pytest.raises(DatasetError, match="not a readable NetCDF"):
        open_levels(text)


@pytest.mark.parametrize("fps, w, h, symbol", [(0, 640, 360, "fps"), (61, 640, 360, "fps"), ("nan", 640, 360, "fps"),
                                               (2, 641, 360, "width"), (2, 62, 360, "width"),
                                               (2, 640, 4098, "height"), (2, 640, 36.5, "height")])
def test_check_film_refuses(fps, w, h, symbol):
    with pytest.raises(ParameterError) as e:
        check_film(fps, w, h)
    assert e.value.symbol == symbol
    assert check_film("60", "64", "4096") == (60.0, 64, 4096)


def _one_line_error(argv, capsys):
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and err.startswith("contactvib: error: "), (rc, err)
    return err


@pytest.mark.parametrize("args, says", [
    (["--fps", "0"], "--fps (fps) = 0"),
    (["--fps", "abc"], "--fps (fps) = abc"),
    (["--size", "1601x800"], "--size (width) = 1601: must be an even integer"),
    (["--size", "800"], "--size = 800: expected WxH"),
    (["--size", "640x30"], "--size (height) = 30"),
    (["--gif"], "must end in .gif"),
])
def test_cli_bad_input_is_one_line(films, tmp_path, capsys, args, says):
    err = _one_line_error(["animate", str(films / "res"), "--out", str(tmp_path / "f.mp4"), *args], capsys)
    assert says in err
    assert not list(tmp_path.iterdir())


def test_cli_bad_dataset_and_out_are_one_line(films, tmp_path, capsys):
    ok = str(tmp_path / "f.mp4")
    assert "DATASET = " in _one_line_error(["animate", str(tmp_path / "none.nc"), "--out", ok], capsys)
    assert "a folder without atlas.nc" in _one_line_error(["animate", str(tmp_path), "--out", ok], capsys)
    res = str(films / "res")
    assert "must end in .mp4" in _one_line_error(["animate", res, "--out", str(tmp_path / "f.gif")], capsys)
    assert "is a folder" in _one_line_error(["animate", res, "--out", str(tmp_path)], capsys)
    blocker = tmp_path / "a_file"
    blocker.write_text("kept")
    err = _one_line_error(["animate", res, "--out", str(blocker / "f.mp4")], capsys)
    assert f"--out = {blocker / 'f.mp4'}: cannot create" in err
    err = _one_line_error(["animate", res, "--out", str(blocker)], capsys)
    assert "--out" in err and blocker.read_text() == "kept"


def test_cli_writes_the_film(films, tmp_path, capsys):
    out = tmp_path / "sub" / "evolution.mp4"
    assert main(["animate", str(films / "res"), "--out", str(out), "--fps", "5", "--size", "400x240"]) == 0
    text = capsys.readouterr().out
    assert f"3 frames (400x240 px, 5 frames/s, P_a = 0.5..0.7 Q) -> {out}" in text
    assert "P_a = 0.65 Q: 1/2 " in text
    meta, frames = _mp4_frames(out)
    assert meta["size"] == (400, 240) and meta["fps"] == pytest.approx(5.0) and len(frames) == 3
    gif = tmp_path / "evolution.gif"
    assert main(["animate", str(films / "res"), "--out", str(gif), "--gif", "--size", "400x240"]) == 0
    assert iio.improps(gif, plugin="pillow").n_images == 3


@pytest.mark.parametrize("name, at", [("film.mp4", 0), ("film.mp4", 2), ("film.gif", 1)])
def test_an_interrupt_leaves_no_file(films, tmp_path, monkeypatch, name, at):
    """Ctrl-C while frame ``at`` is drawn: KeyboardInterrupt, no film and no temporary file."""
    import contactvib.plotting.film as pf

    real, calls = pf.film_frame, []

    def frame(*args, **kwargs):
        calls.append(1)
        if len(calls) > at:
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(pf, "film_frame", frame)
    with pytest.raises(KeyboardInterrupt):
        animate(films / "res", tmp_path / name, size=SIZE)
    assert list(tmp_path.iterdir()) == []
