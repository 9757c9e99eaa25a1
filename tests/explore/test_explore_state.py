"""The explore page's state without a browser: URL parameters, the CLI's checks and messages,
the time limit that stops the kernels."""

from __future__ import annotations

import time

import pytest

from contactvib.cli.explore import _check, _find
from contactvib.explore.state import DEFAULTS, BadInput, Point, Stopped, run_limited, search, table_rows


def test_query_round_trip_keeps_only_changes_and_ignores_unknown_names():
    p = Point.from_query({"fe": [b"287"], "pa": ["0.5"], "evil": ["rm -rf /"], "M": []})
    assert p.fields == {**DEFAULTS, "fe": "287", "pa": "0.5"}
    assert p.query() == {"fe": "287", "pa": "0.5"}
    assert Point.from_query(p.query()).fields == p.fields
    assert Point.from_query({"fe": ["9" * 1000]}).fields["fe"] == "9" * 64  # bounded


def test_bad_values_give_the_cli_message():
    with pytest.raises(BadInput, match=r"^contactvib: error: --fe \(f_e\) = -5: must be > 0 Hz$"):
        _check(Point({**DEFAULTS, "fe": "-5"}))
    with pytest.raises(BadInput, match=r"^contactvib: error: --set h_n"):
        _check(Point({**DEFAULTS, "h_n": "-1"}))
    with pytest.raises(BadInput, match=r"^contactvib: error: --pa"):
        _check(Point({**DEFAULTS, "pa": "abc"}))
    model, exc = _check(Point({**DEFAULTS, "M": "0.3"}))
    assert model.M == 0.3 and exc.f_e == 360.0 and exc.pa_over_q == 0.65


def test_the_page_search_is_the_cli_search():
    model, exc = _check(Point())
    result, seconds = search(_find, model, exc)
    rows = table_rows(result)
    assert [r["period"] for r in rows] == ["2", "1", "1", "1", "1"]
    assert rows[0]["A_pp [µm]"] == pytest.approx(37.389679634309296, abs=1e-6)
    assert seconds > 0


def test_time_limit_stops_the_kernels():
    model, exc = _check(Point({**DEFAULTS, "pa": "2", "fe": "150"}))
    t0 = time.perf_counter()
    with pytest.raises(Stopped, match=r"^stopped after 0.05 s$"):
        run_limited(lambda: _find(model, exc), 0.05)
    assert time.perf_counter() - t0 < 20
