"""Issue 14, Acceptance: basin fractions converge as the grid is refined (100², 200², 400² at the
paper's Fig. 4 point, 0.65 Q, 360 Hz) and agree with the attractor search's basin fractions within
their standard errors. The 400² fractions are the attractors tutorial's table
(docs/tutorials/attractors.md), which the slow test
``test_basins.py::test_readme_basins_output_is_the_commands_output`` ties to the command's output,
so the 400² map is not computed twice."""

import math
import re

import pytest

from contactvib import ContactModel
from contactvib.steady.basins import basins
from doc_pages import block_after

#: Agreement within two combined standard errors (sqrt(p(1 - p)/N) each; grid points are
#: correlated, so these are lower bounds).
SIGMAS = 2.0


def _readme_400():
    table = block_after("## Basins (`contactvib basins`)")
    assert "400x400 starts" in table
    rows = re.findall(r"^\s+(-?\d+)\s+(\d+)\s+\d+\s+[\d.]+\s+([\d.]+)%\s+([\d.]+)%$", table, re.M)
    return {int(lab): (int(k), float(f) / 100, float(se) / 100) for lab, k, f, se in rows}


@pytest.fixture(scope="module")
def maps():
    model = ContactModel()
    exc = model.excitation(0.65, 360.0)
    out = {}
    for n in (100, 200):
        b = basins(exc, grid=(n, n))
        out[n] = {r["label"]: (r["period"], r["fraction"], r["stderr"]) for r in b.fractions()}
        search = b.search
    out[400] = _readme_400()
    return out, search


def test_fractions_sum_to_one_and_all_settle(maps):
    grids, _search = maps
    for n, rows in grids.items():
        assert sum(f for _k, f, _se in rows.values()) == pytest.approx(1.0, abs=2e-4 if n == 400 else 1e-12)
        assert rows.get(-1, (None, 0.0, 0.0))[1] == 0.0, n
    assert len(grids[400]) == 5


def test_fractions_converge_as_the_grid_is_refined(maps):
    grids, _search = maps
    labels = sorted(grids[400])
    for a, b in ((100, 200), (200, 400), (100, 400)):
        for lab in labels:
            ka, fa, sa = grids[a][lab]
            kb, fb, sb = grids[b][lab]
            assert ka == kb, (lab, a, b)
            assert abs(fa - fb) <= SIGMAS * math.hypot(sa, sb), (lab, a, b, fa, fb)
    err = {n: max(abs(grids[n][lab][1] - grids[400][lab][1]) for lab in labels) for n in (100, 200)}
    assert err[200] < err[100]


def test_grid_fractions_agree_with_the_search(maps):
    grids, search = maps
    for a_label, a in enumerate(search):
        se_box = math.sqrt(a.basin_fraction * (1 - a.basin_fraction) / search.n_box)
        for n, rows in grids.items():
            k, f, se = rows[a_label]
            assert k == a.period
            assert abs(f - a.basin_fraction) <= SIGMAS * math.hypot(se, se_box), (n, a_label, f, a.basin_fraction)
