"""The index page's sentences are computed from the dataset (:mod:`contactvib.sweeps.paper_index`):
a peak at an end of the sweep's grid is reported as lying at or beyond that edge, and S4.7
("m minima for a 1/m orbit") names every exception in the Figs. 4–9 tables. Checked on the small
one-level dataset (340–380 Hz), without the paper's run."""

from __future__ import annotations

import json

import xarray as xr

from contactvib.sweeps.paper import TimeFigure
from contactvib.sweeps.paper_index import minima_sentence, peak_place, write_index
from contactvib.sweeps.stored import ResonanceData

GRID = (30.0, 2000.0, 1.0)


def test_a_peak_on_an_edge_of_the_grid_lies_at_or_beyond_it():
    assert peak_place(30.0, GRID) == ("at or below 30 Hz", "the sweep's lower edge")
    assert peak_place(2000.0, GRID) == ("at or above 2000 Hz", "the sweep's upper edge")
    assert peak_place(31.0, GRID) == ("at 31 Hz", "")
    assert peak_place(1999.0, GRID) == ("at 1999 Hz", "")


def _row(label, period, minima):
    return ({"resonance": label, "period": period, "minima_per_period": minima}, "")


def test_s4_7_names_every_orbit_whose_minima_are_not_m():
    f5 = TimeFigure(5, 0.65, 287.0, "S4.2", "")
    f8 = TimeFigure(8, 0.90, 170.0, "S4.5", "")
    rows = [(f5, None, [_row("main", 1, 1), _row("1/5", 1, 2), _row("subharmonic 1/2 bouncing", 2, 1)]),
            (f8, None, [_row("1/6", 1, 6), _row("1/9", 1, 5), _row("1/2 period-2", 2, 4),
                        _row("non-periodic (1/3)", None, None)])]
    text = minima_sentence(rows)
    assert "3 of the 5 periodic 1/m orbits" in text
    assert "the 1/5 at 0.65 Q, 287 Hz (2 minima, S4.2)" in text
    assert "the 1/9 at 0.9 Q, 170 Hz (5 minima, S4.5)" in text
    assert "exceptions are" in text
    # a period-2 orbit with 3 minima over 2 periods of a 1/2: named with its periods
    assert "(3 minima over 2 periods, S4.5)" in minima_sentence([(f8, None, [_row("1/2 period-2", 2, 3)])])
    assert "all 2 periodic 1/m orbits" in minima_sentence([(f8, None, [_row("main", 1, 1), _row("1/6", 1, 6)])])
    assert "no 1/m orbit" in minima_sentence([])


def _index(ds, tmp_path, rows):
    tf = TimeFigure(4, 0.65, 360.0, "S4.1", "")
    return write_index(ds, tmp_path, [0.65], {0.65: (tmp_path / "g.png", tmp_path / "e.png")},
                       [(tf, tmp_path / "fig4.png", rows)], {"sweeps_and_figures_s": 1.0}, None).read_text()


def test_the_index_of_a_stored_dataset_is_computed_from_it(small_dataset, tmp_path):
    ds = xr.load_dataset(small_dataset)
    rows = [(a, "") for a in ResonanceData(ds).attractors_at(0.65, 360.0)["attractors"]]
    # the small dataset's one resonance, the 1/4, peaks inside 340–380 Hz at 360 Hz
    assert "1/4 [grows]: peak 0.215 µm at 360 Hz (f_n0/4 = 371 Hz)" in _index(ds, tmp_path, rows)
    # the same points on a grid said to start at 360 Hz: the peak lies at or below its edge
    st = json.loads(ds.attrs["settings"])
    edge = ds.assign_attrs(settings=json.dumps({**st, "fmin_hz": 360.0}))
    text = _index(edge, tmp_path, rows)
    assert "1/4 [grows]: peak 0.215 µm at or below 360 Hz (the sweep's lower edge; f_n0/4 = 371 Hz)" in text
    edge = ds.assign_attrs(settings=json.dumps({**st, "fmax_hz": 360.0}))
    assert "at or above 360 Hz (the sweep's upper edge;" in _index(edge, tmp_path, rows)
    s47 = text[text.index("### S4.7"):]
    assert [a["resonance"] for a, _ in rows] == ["1/4"] and rows[0][0]["minima_per_period"] == 4
    assert "the one periodic 1/m orbit (main: m = 1) has m minima per excitation period" in s47
    assert "early 1/5" not in text and "no two resonances coexist at one frequency" in text
