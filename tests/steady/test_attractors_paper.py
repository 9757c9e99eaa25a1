"""The paper's Section 4 facts (statements S4.1–S4.6 of the spec's paper-statements list) from
``find_attractors`` with its default arguments, and the A_pp of the periodic attractors against
the independent scipy reference (``tests/data/reference.json``, ``tests/data/make_reference.py``).

Minima are counted per orbit period (k excitation periods); A_pp = y_max − y_min over the orbit.
"""
import json
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors

MODEL = ContactModel()
REFERENCE = json.loads((Path(__file__).parents[1] / "data" / "reference.json").read_text())


@cache
def attractors(pa_over_q, f_e):
    return find_attractors(MODEL.excitation(pa_over_q, f_e))


def periodic(pa_over_q, f_e, period=None, minima=None):
    out = [a for a in attractors(pa_over_q, f_e) if a.period is not None]
    if period is not None:
        out = [a for a in out if a.period == period]
    if minima is not None:
        out = [a for a in out if a.minima_per_period == minima]
    return out


def test_s4_1_four_period1_motions_at_360hz():
    """S4.1 (Fig. 4, 0.65 Q, 360 Hz): four coexisting period-1 motions with 1, 2, 3 and 4 minima;
    the main, 1/2 and 1/3 lose contact, the small 1/4 does not; the main has the largest
    amplitude and its minima lie below zero."""
    p1 = periodic(0.65, 360.0, period=1)
    by_min = {}
    for a in p1:
        by_min.setdefault(a.minima_per_period, []).append(a)
    for m in (1, 2, 3, 4):
        assert len(by_min.get(m, [])) == 1, (m, [(a.period, a.minima_per_period) for a in p1])
    main, sub2, sub3, sub4 = (by_min[m][0] for m in (1, 2, 3, 4))
    assert main.loses_contact and sub2.loses_contact and sub3.loses_contact
    assert not sub4.loses_contact and sub4.ymin_um > 0
    assert main.ymin_um < 0
    assert main.app_um > sub2.app_um > sub3.app_um > sub4.app_um
    for a in (main, sub2, sub3, sub4):
        assert np.max(np.abs(a.floquet_multipliers)) < 1


def test_s4_3_period2_four_minima_at_470hz():
    """S4.3 (Fig. 6, 0.70 Q, 470 Hz): the 1/2 after the first period doubling, a period-2 orbit
    with four minima over two excitation cycles and loss of contact."""
    p2 = periodic(0.70, 470.0, period=2, minima=4)
    assert len(p2) == 1
    assert p2[0].loses_contact and p2[0].ymin_um < 0


def test_s4_4_three_resonances_at_234hz():
    """S4.4 / S3.6 (Fig. 7, 0.85 Q, 234 Hz): main (one minimum), the 1/5 (five minima, loss of
    contact) and the 1/6 (six minima) coexist."""
    assert len(periodic(0.85, 234.0, period=1, minima=1)) >= 1
    p5 = periodic(0.85, 234.0, period=1, minima=5)
    assert len(p5) == 1 and p5[0].loses_contact
    p6 = periodic(0.85, 234.0, period=1, minima=6)
    assert len(p6) == 1
    assert p6[0].app_um < p5[0].app_um  # the 1/6 is at an early stage


def test_s4_5_one_sixth_with_contact_loss_at_170hz():
    """S4.5 (Fig. 8, 0.90 Q, 170 Hz): the 1/6 with loss of contact and six minima per cycle."""
    p6 = periodic(0.90, 170.0, period=1, minima=6)
    assert len(p6) == 1 and p6[0].loses_contact


def test_s4_6_quasistatic_orbit_at_50hz():
    """S4.6 (Fig. 9, 0.90 Q, 50 Hz): quasistatic vibration, one minimum per cycle, no loss of
    contact, A_pp ≈ 0.241 µm; it coexists with the open primary branch (flights, A_pp > 100 µm)."""
    one = periodic(0.90, 50.0, period=1, minima=1)
    quasi = [a for a in one if not a.loses_contact]
    assert len(quasi) == 1
    assert quasi[0].app_um == pytest.approx(0.241, rel=1e-2)
    assert quasi[0].ymin_um > 0
    assert any(a.app_um > 100.0 for a in attractors(0.90, 50.0))


def _ref_id(o):
    return f"{o['pa_over_q']}Q-{o['f_e']}Hz-k{o['period']}-{o['label']}"


@pytest.mark.parametrize("ref", REFERENCE["orbits"], ids=_ref_id)
def test_app_matches_scipy_reference(ref):
    """A_pp, y_min, y_max and the minima count of each periodic attractor equal the scipy
    reference (300 periods settled from the same orbit, extrema on the dense output) to 1e-6;
    attractors are matched by period and minima count (and the nearest strobe point)."""
    y0_um = MODEL.y0 * 1e6
    cands = periodic(ref["pa_over_q"], ref["f_e"], period=ref["period"],
                     minima=ref["minima_per_period"])
    assert cands, f"no period-{ref['period']} attractor with {ref['minima_per_period']} minima"
    z_ref = np.array(ref["strobe"])

    def dist(a):
        pts = a.strobe_y_um / y0_um
        return np.min(np.abs(pts - z_ref[0]))

    a = min(cands, key=dist)
    assert a.app_um / y0_um == pytest.approx(ref["A_pp"], rel=1e-6)
    assert a.ymin_um / y0_um == pytest.approx(ref["x_min"], rel=1e-6, abs=1e-6)
    assert a.ymax_um / y0_um == pytest.approx(ref["x_max"], rel=1e-6, abs=1e-6)
    assert (a.ymin_um < 0) == (ref["x_min"] < 0)
    # the orbit point passes through the scipy strobe point (some cyclic phase)
    pts = np.column_stack([a.strobe_y_um / y0_um, a.strobe_ydot_mm_s / (MODEL.y0 * MODEL.omega_n0 * 1e3)])
    gap = np.min(np.max(np.abs(pts - z_ref), axis=1))
    assert gap <= 1e-7 * max(1.0, np.max(np.abs(z_ref)))
