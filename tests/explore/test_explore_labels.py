"""The resonance column of the explore table: the page names each attractor as the sweep's
dataset names it (an independent route: the sweep takes the harmonics from its kernels and
smooths labels along branches; the page takes them from one orbit period of the time history),
and as the paper does at Figs. 4, 5 and 7 (S4.1, S4.2, S4.4)."""

from __future__ import annotations

import pytest
import xarray as xr

from contactvib.cli.explore import _check, _find
from contactvib.explore.state import Point, resonance_of, table_rows
from contactvib.steady.simulate import attractor_history
from contactvib.sweeps.stored import attractors_at


def _labels(pa: str, fe: str):
    point = Point()
    point.fields.update(pa=pa, fe=fe)
    model, exc = _check(point)
    result = _find(model, exc)
    return result, [resonance_of(a, attractor_history(exc, a), model.f_n0) for a in result]


def test_labels_equal_the_datasets(small_dataset):
    result, labels = _labels("0.65", "360")
    stored = attractors_at(xr.load_dataset(small_dataset), pa_over_q=0.65, fe_hz=360.0)["attractors"]
    matched = 0
    for s in stored:
        for a, label in zip(result, labels):
            if a.period == s["period"] and a.app_um == pytest.approx(s["app_um"], rel=1e-6):
                assert label == s["resonance"], (label, s)
                matched += 1
    assert matched == len(stored) > 0


@pytest.mark.parametrize("pa, fe, expected", [
    ("0.65", "360", ["subharmonic 1/2 bouncing", "main", "1/2", "1/3", "1/4"]),  # Fig. 4, S4.1
    ("0.65", "287", ["subharmonic 1/2 bouncing", "main", "1/2", "1/3", "1/5"]),  # Fig. 5: the 1/5, 2 minima
    ("0.85", "234", ["subharmonic 1/2 bouncing", "main", "1/5", "1/6"]),  # Fig. 7, S4.4
])
def test_labels_name_the_papers_resonances(pa, fe, expected):
    result, labels = _labels(pa, fe)
    assert labels == expected
    assert [r["resonance"] for r in table_rows(result, labels)] == expected
