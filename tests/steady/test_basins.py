"""Basins of attraction on a grid of initial states (``contactvib basins``, steady/basins.py): the
fractions agree with the attractor search's random box, a start on an attractor gets its label,
row blocks are independent, bad input is one line, the JSON contract and the files."""

import json
import math
import time

import numpy as np
import pytest
import xarray as xr

from contactvib import ContactModel, ParameterError
from contactvib.cli import main
from contactvib.steady.basins import basin_block, basins, default_box, merge_blocks
from figure_files import assert_figure_file

GRID = (40, 40)


@pytest.fixture(scope="module")
def model():
    return ContactModel()


@pytest.fixture(scope="module")
def exc(model):
    return model.excitation(0.65, 360.0)


@pytest.fixture(scope="module")
def bmap(model, exc):
    """The paper's Fig. 4 point on a 40 × 40 grid over the search's box."""
    return basins(exc, grid=GRID)


def test_fractions_agree_with_the_search(bmap):
    search = bmap.search
    assert len(search) == 5  # the Fig. 4 point's five attractors
    assert bmap.n_known == len(bmap.attractors) == len(search)  # every label is one the search found
    assert set(np.unique(bmap.labels)) <= set(range(-1, len(search)))
    rows = bmap.fractions()
    assert [r["label"] for r in rows] == [*range(len(search)), -1]
    assert sum(r["fraction"] for r in rows) == pytest.approx(1.0, abs=1e-12)
    n = bmap.labels.size
    for r, a in zip(rows, search):
        assert (r["period"], r["minima_per_period"], r["app_um"]) == (a.period, a.minima_per_period, a.app_um)
        assert r["stderr"] == pytest.approx(math.sqrt(r["fraction"] * (1 - r["fraction"]) / n))
        p_box = a.basin_fraction
        se_box = math.sqrt(p_box * (1 - p_box) / search.n_box)
        tol = 3 * math.hypot(r["stderr"], se_box) + 0.02
        assert abs(r["fraction"] - p_box) <= tol, (r, p_box, tol)


def test_default_box_is_the_search_box(bmap, model, exc):
    (y0, y1), (v0, v1) = default_box(model, exc)
    a = 2 + 10 * 0.65
    assert (y0, y1) == pytest.approx(((1 - a) * model.units.y_um, (1 + a) * model.units.y_um))
    assert (v0, v1) == pytest.approx((-a * model.units.ydot_mm_s, a * model.units.ydot_mm_s))
    assert (bmap.y_um[0], bmap.y_um[-1], bmap.ydot_mm_s[0], bmap.ydot_mm_s[-1]) == pytest.approx((y0, y1, v0, v1))
    assert bmap.labels.shape == (GRID[1], GRID[0])


def test_a_start_on_an_attractor_gets_its_label(bmap, model, exc):
    for i, a in enumerate(bmap.search):
        if a.period is None:
            continue
        for ys, vs in zip(a.strobe_y_um, a.strobe_ydot_mm_s):
            box = ((ys - 0.5, ys + 0.5), (vs - 1.0, vs + 1.0))  # the middle of a 3 × 3 grid is on it
            block = basin_block(model, exc, bmap.search, (3, 3), box, (1, 2))
            assert block.labels[0, 1] == i, (i, ys, vs, block.labels)


def test_row_blocks_are_independent(bmap, model, exc):
    grid, box = GRID, default_box(model, exc)
    blocks = [basin_block(model, exc, bmap.search, grid, box, rows) for rows in ((17, 40), (0, 17))]
    joined = merge_blocks(model, exc, bmap.search, grid, box, blocks)
    np.testing.assert_array_equal(joined.labels, bmap.labels)
    assert [r["fraction"] for r in joined.fractions()] == [r["fraction"] for r in bmap.fractions()]
    again = basins(exc, grid=GRID, block_starts=7 * GRID[0])  # 6 blocks of 7 rows
    np.testing.assert_array_equal(again.labels, bmap.labels)
    with pytest.raises(ValueError, match="do not cover"):
        merge_blocks(model, exc, bmap.search, grid, box, blocks[:1])


@pytest.mark.timing
@pytest.mark.parametrize("kwargs, symbol", [
    ({"grid": (0, 5)}, "n_y"), ({"grid": (5, 1)}, "n_ydot"), ({"grid": (2.5, 5)}, "n_y"),
    ({"box": ((1.0, 1.0), (-1.0, 1.0))}, "y_max"), ({"box": ((0.0, 1.0), (2.0, -2.0))}, "ydot_max"),
    ({"box": ((math.nan, 1.0), (-1.0, 1.0))}, "y_min"), ({"grid": (100000, 100000)}, "grid"),
    ({"grid": (400, 400), "max_periods": 10**6}, "f_e"),
])
def test_library_refuses_bad_input(model, exc, kwargs, symbol):
    t = time.perf_counter()
    with pytest.raises(ParameterError) as e:
        basins(exc, **kwargs)
    assert e.value.symbol == symbol
    assert time.perf_counter() - t < 2.0  # refused before any computation


def _cli(args, capsys, cwd=None, monkeypatch=None):
    if cwd is not None:
        monkeypatch.chdir(cwd)
    capsys.readouterr()
    rc = main(["basins", *args])
    out = capsys.readouterr()
    return rc, out.out, out.err


@pytest.mark.timing
@pytest.mark.parametrize("args, message", [
    (["--grid", "0x5"], "contactvib: error: --grid (n_y) = 0: must be an integer >= 2"),
    (["--grid", "5x1"], "contactvib: error: --grid (n_ydot) = 1: must be an integer >= 2"),
    (["--grid", "ax3"], "contactvib: error: --grid (n_y) = a: must be an integer >= 2"),
    (["--grid", "40"], "contactvib: error: --grid = 40: expected NxM"),
    (["--grid", "4x4x4"], "contactvib: error: --grid = 4x4x4: expected NxM"),
    (["--grid", "x4"], "contactvib: error: --grid = x4: expected NxM"),
    (["--y-range", "1", "-1"], "contactvib: error: --y-range (y_max) = -1: must be > y_min = 1 µm"),
    (["--y-range", "1", "1"], "contactvib: error: --y-range (y_max) = 1: must be > y_min = 1 µm"),
    (["--ydot-range", "-2", "-5"], "contactvib: error: --ydot-range (ydot_max) = -5: must be > ydot_min"),
    (["--y-range", "nan", "1"], "contactvib: error: --y-range (y_min) = nan: must be a finite number"),
    (["--kmax", "0"], "contactvib: error: --kmax (kmax) = 0: must be an integer in 1..64"),
    (["--max-periods", "3"], "contactvib: error: --max-periods (max_periods) = 3: must be an integer >= 32"),
    (["--starts", "0"], "contactvib: error: --starts (n_starts) = 0: must be an integer >= 1"),
    (["--fe", "-5"], "contactvib: error: --fe (f_e) = -5: must be > 0 Hz"),
    (["--set", "h_n=0"], "contactvib: error: --set h_n (h_n) = 0: must be > 0 for basins of attraction"),
])
def test_cli_bad_input_one_line(args, message, capsys, tmp_path, monkeypatch):
    t = time.perf_counter()
    rc, out, err = _cli(args, capsys, tmp_path, monkeypatch)
    assert rc == 2 and out == ""
    assert list(tmp_path.iterdir()) == []  # refused before the default folder basins/ is made
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(message), err
    assert time.perf_counter() - t < 5.0


@pytest.mark.timing
def test_cli_unwritable_out_is_refused_before_computing(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    t = time.perf_counter()
    rc, out, err = _cli(["--grid", "400x400", "--out", str(blocker)], capsys)
    assert rc == 2 and out == "" and time.perf_counter() - t < 5.0
    assert len(err.strip().splitlines()) == 1
    assert err.startswith("contactvib: error: ") and "--out" in err and "is a file" in err
    rc, _out, err = _cli(["--grid", "40x40", "--out", str(blocker / "sub")], capsys)
    assert rc == 2 and err.startswith(f"contactvib: error: --out = {blocker / 'sub'}: cannot create or write")


def test_cli_json_contract(capsys, tmp_path, monkeypatch):
    rc, out, err = _cli(["--pa", "0.65", "--fe", "360", "--grid", "12x10", "--starts", "64", "--json"],
                        capsys, tmp_path, monkeypatch)
    assert rc == 0, err
    d = json.loads(out)
    assert {"pa_over_q", "fe_hz", "grid", "y_range_um", "ydot_range_mm_s", "n_points", "fractions",
            "attractors"} <= set(d)
    assert d["grid"] == [12, 10] and d["n_points"] == 120
    rows = d["fractions"]
    for r in rows:
        assert set(r) == {"label", "period", "minima_per_period", "app_um", "fraction", "stderr"}
    assert rows[-1]["label"] == -1 and rows[-1]["period"] is None
    assert [r["label"] for r in rows[:-1]] == list(range(len(d["attractors"])))
    assert sum(r["fraction"] for r in rows) == pytest.approx(1.0)
    assert list(tmp_path.iterdir()) == []  # --json without --out writes nothing


def test_cli_writes_the_dataset_and_the_figure(tmp_path, capsys, monkeypatch):
    rc, out, err = _cli(["--grid", "16x12", "--starts", "64", "--y-range", "-1", "2", "--out", "b/"],
                        capsys, tmp_path, monkeypatch)
    assert rc == 0, err
    png = tmp_path / "b" / "basins_pa0.65_fe360.png"
    assert_figure_file(png)
    assert png.stat().st_size > 20_000
    with xr.open_dataset(tmp_path / "b" / "basins.nc") as ds:
        assert ds["label"].dims == ("ydot_mm_s", "y_um") and ds["label"].shape == (12, 16)
        assert ds["y_um"].attrs["units"] == "um" and ds["ydot_mm_s"].attrs["units"] == "mm/s"
        assert float(ds["y_um"][0]) == -1.0 and float(ds["y_um"][-1]) == 2.0
        assert float(ds["fraction"].sum()) == pytest.approx(1.0)
        assert ds.attrs["pa_over_q"] == 0.65 and ds.attrs["fe_hz"] == 360.0
    assert out.splitlines()[1].split()[:3] == ["label", "period", "minima"]
    assert "wrote" in out and "basins.nc" in out
    assert not list((tmp_path / "b").glob(".*tmp*"))


@pytest.mark.slow
def test_readme_basins_output_is_the_commands_output(capsys, tmp_path, monkeypatch):
    """The attractors tutorial's 400 × 400 table (about 30–60 s)."""
    from doc_pages import block_after

    expected = block_after("## Basins (`contactvib basins`)")
    rc, out, err = _cli(["--pa", "0.65", "--fe", "360", "--grid", "400x400", "--out", "basins/"],
                        capsys, tmp_path, monkeypatch)
    assert rc == 0, err
    assert out == expected


def test_a_chaotic_attractor_is_matched_by_its_cloud(model):
    """0.90 Q, 242 Hz: the 1/5's chaotic attractor (README) is one label; the grid's chaotic
    starts join it by cloud overlap instead of making new labels."""
    b = basins(model.excitation(0.9, 242.0), grid=(16, 16), n_starts=128)
    chaotic = [i for i, a in enumerate(b.attractors) if a.kind == "chaotic"]
    assert len(chaotic) == 1 and chaotic[0] < b.n_known
    assert b.fraction(chaotic[0])[0] > 0.01
    assert all(a.period is not None for a in b.attractors[b.n_known:])


def test_plot_basins_axes(bmap):
    from contactvib.plotting.basins import basins_figure, plot_basins
    from contactvib.plotting.figures import new_figure

    _fig, axes = new_figure()
    ax = plot_basins(bmap, axes[0, 0])
    assert "[µm]" in ax.get_xlabel() and "[mm/s]" in ax.get_ylabel()
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert len(texts) == len(bmap.attractors) + int(np.any(bmap.labels < 0))
    assert texts[1].startswith("1: period 1, 1 minimum") and "%" in texts[1]
    assert ax.get_xlim() == pytest.approx((bmap.y_um[0] - 0.5 * (bmap.y_um[1] - bmap.y_um[0]),
                                           bmap.y_um[-1] + 0.5 * (bmap.y_um[1] - bmap.y_um[0])))
    fig = basins_figure(bmap)
    assert "0.65 Q" in fig.texts[0].get_text() and "360 Hz" in fig.texts[0].get_text()
