"""Attractor types earned from the Lyapunov spectrum in the attractor search
(``contactvib.steady.transients.search_verdict``): chaotic only where λ1 > 3 standard errors,
quasi-periodic only on a closed-curve section, a start in free flight or still converging never
an attractor, a long-period orbit found with its true period; and the JSON keys of the spectrum.
"""

import math
import warnings

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib.steady.attractors import UnsettledWarning
from contactvib.steady.transients import VERDICT_PERIODS, search_verdict

MODEL = ContactModel()
LYAPUNOV_KEYS = {"attractor_type", "lyapunov_per_s", "lyapunov_stderr_per_s", "kaplan_yorke_dimension"}


def _search(exc, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsettledWarning)
        return find_attractors(exc, **kw)


def test_slowly_converging_long_period_orbit_is_periodic_not_chaotic():
    """0.9 Q, 1300 Hz: a start that finds no period ≤ kmax = 8 converges (λ1 < 0) onto a stable
    orbit of period 72; it is listed with that period and no attractor is chaotic."""
    res = _search(MODEL.excitation(0.9, 1300.0))
    assert all(a.attractor_type == "periodic" for a in res)
    long = [a for a in res if a.period > 8]
    assert long and all(a.floquet_abs_max < 1.0 for a in long)
    assert 72 in {a.period for a in long}
    for a in res:
        d = a.to_dict()
        assert LYAPUNOV_KEYS <= d.keys() and d["kind"] == "periodic"
        expected = np.sort(np.log(np.abs(a.floquet_multipliers)) * 1300.0 / a.period)[::-1]
        np.testing.assert_allclose(d["lyapunov_per_s"], expected, rtol=1e-12)
        assert d["lyapunov_stderr_per_s"] == [0.0, 0.0] and d["kaplan_yorke_dimension"] is None


def test_chaotic_attractor_earns_its_label_and_keys():
    """0.75 Q, 816.5 Hz: the chaotic attractor (small basin) with λ1 > 3 stderr, its spectrum and
    Kaplan–Yorke dimension in the JSON; the old keys kept (λ1 per period = λ1 [1/s] / f_e)."""
    res = _search(MODEL.excitation(0.75, 816.5))
    chaos = [a for a in res if a.period is None]
    assert len(chaos) == 1
    d = chaos[0].to_dict()
    assert d["attractor_type"] == d["kind"] == "chaotic"
    lam, se = d["lyapunov_per_s"], d["lyapunov_stderr_per_s"]
    assert lam[0] > 3.0 * se[0] and lam[0] > lam[1]
    assert 2.0 < d["kaplan_yorke_dimension"] < 3.0
    assert d["lyapunov_per_period"] == pytest.approx(lam[0] / 816.5, rel=1e-12)


def test_free_flight_start_is_unsettled():
    """A start thrown so far out of the contact that it flies longer than the verdict's run never
    touches the contact: unsettled, not an attractor."""
    exc = MODEL.excitation(0.75, 816.5)
    T = exc.tau_period
    v = -(VERDICT_PERIODS + 2200) * T / MODEL.m2  # x'' ≈ 1/m2 on average in flight: back after ~2 v m2
    tail = np.full((128, 2), np.nan)
    tail[-1] = (-1.0, v)
    verdict = search_verdict(exc, tail, 1e-8)
    assert verdict.kind == "unsettled" and "free flight" in verdict.reason


@pytest.mark.slow
def test_exponential_law_point_has_only_periodic_attractors():
    """The exponential law (c_e = 205.28, λ = 0.1 µm) at P_a = 1.033 N, 1563 Hz: bouncing
    transients that drift with the slow loss of energy per impact are unsettled; every listed
    attractor is periodic and touches the contact (y_max > 0); with the old 64-period λ rule
    nine were listed as chaotic (two of them in free flight, y_max < 0) and three as
    quasi-periodic; the unsettled starts are counted by reason, some of them free flights."""
    model = ContactModel(law="exponential", c_e=205.27978893320068, lam=1e-07)
    exc = model.excitation(1.032993 / model.Q, 1563.0)
    res = _search(exc)
    assert len(res) >= 3
    assert all(a.attractor_type == "periodic" and a.ymax_um > 0.0 for a in res)
    assert res.n_unsettled > 0 and res.to_dict()["n_unsettled"] == res.n_unsettled
    reasons = res.to_dict()["unsettled_reasons"]
    assert sum(reasons.values()) == res.n_unsettled and reasons.get("free flight: no contact", 0) > 0
    assert not any(math.isnan(x) for a in res for x in a.lyapunov_per_s)
