"""The explore page's state without a browser: URL parameters, the CLI's checks and messages,
the time limit that stops the kernels."""

from __future__ import annotations

import time

import numpy as np
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


@pytest.mark.timing
def test_time_limit_stops_the_kernels():
    model, exc = _check(Point({**DEFAULTS, "pa": "2", "fe": "150"}))
    t0 = time.perf_counter()
    with pytest.raises(Stopped, match=r"^stopped after 0.05 s$"):
        run_limited(lambda: _find(model, exc), 0.05)
    assert time.perf_counter() - t0 < 20


def test_perturbation_series_is_drawn_where_valid_and_matches_the_numerics():
    """At 287 Hz (contact kept, small amplitude) the series is drawn on the in-contact period-1
    attractor, and its orbit equals that attractor's time history (shooting and integration, an
    independent method) to 1e-5 of A_pp; at 360 Hz (not converged) and 742 Hz (the series loses
    contact) it is not drawn, and the page says why in the series' own words."""
    from contactvib.explore.app import _compute

    k, payload = _compute(Point({**DEFAULTS, "fe": "287"}), (_check, _find), 30.0)
    overlay = payload["series"]
    i = overlay.attractor
    a, hist = payload["result"][i], payload["hists"][i]
    assert a.period == 1 and not a.loses_contact
    assert "drawn on attractor #" in overlay.note
    n = round(float(hist.t_ms[-1] - hist.t_ms[0]) * hist.fe_hz / 1000.0)
    series = overlay.series.history(n_periods=n, samples_per_period=(hist.y_um.size - 1) // n)
    assert series.t_ms == pytest.approx(hist.t_ms, abs=1e-9)
    assert np.max(np.abs(series.y_um - hist.y_um)) < 1e-5 * a.app_um
    for fe, why in (("360", "has not converged"), ("742", "predicts loss of contact")):
        k, payload = _compute(Point({**DEFAULTS, "fe": fe}), (_check, _find), 30.0)
        assert payload["series"].attractor is None
        assert "not drawn" in payload["series"].note and why in payload["series"].note
