"""Perturbation series: linear limit, second order by hand, convergence to the shooting orbits
of the paper's Figs. 4g, 5a and 9a, invalidity at loss of contact, bad input."""
import json
import math

import numpy as np
import pytest

from contactvib import ContactModel, ParameterError
from contactvib.cli import main
from contactvib.frequency.perturbation import (
    linear_response,
    perturbation_series,
    series_state,
    steady_counterpart,
)
from contactvib.steady.orbits import describe_orbit, refine_orbit
from contactvib.steady.simulate import attractor_history

MODEL = ContactModel()


def _shooting(model, exc, terms=80):
    """Steady state by Newton shooting (tolerance 1e-12, closure 1e-10) started from the series."""
    z, M, res = refine_orbit(exc, perturbation_series(exc, terms=terms).state, 1)
    return describe_orbit(exc, z, 1, monodromy=M, closure=res)


@pytest.mark.parametrize("model,pa,fe", [(MODEL, 0.65, 287.0), (MODEL, 0.3, 1400.0),
                                         (ContactModel(m2=1.5, c_n=1e14, l=0.5), 0.4, 700.0)])
def test_order_one_is_the_linear_response(model, pa, fe):
    """Order 1 = M ÿ + c ẏ + k y = P_a cos ωt from the SI parameters (k = m2 S c_n y0^(m2−1),
    c = S h_n y0^l), amplitude and phase, to round-off; so is :func:`linear_response`."""
    y0 = (model.M * model.g / (model.S * model.c_n)) ** (1 / model.m2)
    k = model.m2 * model.S * model.c_n * y0 ** (model.m2 - 1)
    c = model.S * model.h_n * y0 ** model.l
    w = 2 * math.pi * fe
    Y = pa * model.M * model.g / (k - model.M * w * w + 1j * c * w) * 1e6  # µm
    res = perturbation_series(model.excitation(pa, fe), terms=1, summation="plain")
    assert res.harmonics_um[1] == pytest.approx(abs(Y), rel=1e-12)
    assert res.phases_rad[1] == pytest.approx(np.angle(Y), abs=1e-12)
    assert res.harmonics_um[0] == 0.0 and res.app_um == pytest.approx(2 * abs(Y), rel=1e-10)
    h = res.history(1, 200)
    t = h.t_ms * 1e-3
    assert np.allclose(h.y_um - y0 * 1e6, (Y * np.exp(1j * w * t)).real, atol=1e-12 * abs(Y))
    amplitude, phase = linear_response(model, model.excitation(pa, fe))  # the closed form in r, ζ
    assert amplitude == pytest.approx(abs(Y), rel=1e-12) and phase == pytest.approx(np.angle(Y), abs=1e-12)


@pytest.mark.parametrize("fe", [287.0, 700.0, 1300.0])
def test_second_order_matches_hand_formula(fe):
    """m2 = 2, l = 1: u2'' + 2ζu2' + u2 = −u1²/2 − 2ζ u1 u1', u1 = Re(A e^{iθ}),
    A = 1/(2(1 − r² + 2iζr)) ⇒ mean −|A|²/4, 2nd harmonic −A²(1/4 + iζr)/(1 − 4r² + 4iζr)."""
    exc = MODEL.excitation(0.5, fe)
    r, z = exc.r, MODEL.zeta
    A = 1.0 / (2.0 * (1 - r * r + 2j * z * r))
    B = -A * A * (0.25 + 1j * z * r) / (1 - 4 * r * r + 4j * z * r)
    C = perturbation_series(exc, terms=2, summation="plain").coefficients
    assert C[1, 1] == pytest.approx(A / 2, rel=1e-13)
    assert C[2, 0] == pytest.approx(-abs(A) ** 2 / 4, rel=1e-13)
    assert C[2, 2] == pytest.approx(B / 2, rel=1e-12)
    assert abs(C[2, 1]) == 0.0 and abs(C[1, 0]) == 0.0  # parity


def test_fig5a_287hz_series_converges_to_shooting():
    """1/5 resonance (0.65 Q, 287 Hz, Fig. 5a): two minima, contact kept; the plain series is
    within 1e-3 by N = 40 and 1e-5 by N = 80 (measured 2.1e-4, 1.0e-6), the Padé sum within
    1e-5 by N = 40 (measured 1.0e-6); time history within 1e-6 A_pp at N = 60 (Padé)."""
    exc = MODEL.excitation(0.65, 287.0)
    ref = _shooting(MODEL, exc)
    assert ref.minima_per_period == 2 and not ref.loses_contact
    err = {s: {n: abs(perturbation_series(exc, terms=n, summation=s).app_um - ref.app_um) / ref.app_um
               for n in (10, 20, 30, 40, 60, 80)} for s in ("plain", "pade")}
    assert err["plain"][40] <= 1e-3 and err["plain"][80] <= 1e-5
    assert max(err["plain"][n] for n in (10, 20)) > max(err["plain"][n] for n in (60, 80)) * 100
    assert err["pade"][40] <= 1e-5 and err["pade"][80] <= 1e-8
    assert err["pade"][40] < err["plain"][40]
    res = perturbation_series(exc, terms=60)
    assert res.valid and res.error_estimate_um >= abs(res.app_um - ref.app_um)
    hs = res.history(2, 500)
    hn = attractor_history(exc, ref, n_periods=2, samples_per_period=500)
    assert np.max(np.abs(hs.y_um - hn.y_um)) <= 1e-6 * ref.app_um
    assert np.max(np.abs(hs.ydot_mm_s - hn.ydot_mm_s)) <= 1e-6 * np.ptp(hn.ydot_mm_s)


def test_fig9a_50hz_padé_converges_plain_series_is_asymptotic():
    """Quasistatic 50 Hz, 0.90 Q (Fig. 9a): the plain series gets within 3e-4 (N ≈ 40), then
    diverges (harmonic 30 ≈ f_n0/f_e resonates) and is flagged; the Padé sum converges."""
    exc = MODEL.excitation(0.90, 50.0)
    ref = _shooting(MODEL, exc)
    assert ref.minima_per_period == 1 and not ref.loses_contact
    rel = lambda r: abs(r.app_um - ref.app_um) / ref.app_um  # noqa: E731
    plain = {n: perturbation_series(exc, terms=n, summation="plain") for n in (10, 40, 80)}
    assert rel(plain[40]) <= 3e-4 < rel(plain[10])
    assert rel(plain[80]) > 1e-1 and not plain[80].valid
    pade = {n: perturbation_series(exc, terms=n) for n in (16, 40, 80)}
    assert rel(pade[16]) > rel(pade[40]) > rel(pade[80])
    assert rel(pade[80]) <= 1e-7 and pade[80].valid  # measured 7.2e-9


def test_fig4g_360hz_quarter_resonance():
    """1/4 resonance at 0.65 Q, 360 Hz (Fig. 4g): four minima; the plain series oscillates
    (error > 1e-3 at N = 80), the Padé sum converges (≤ 1e-4 at N = 80, measured 4.3e-6)."""
    exc = MODEL.excitation(0.65, 360.0)
    res = perturbation_series(exc, terms=80)
    ref = steady_counterpart(MODEL, exc, res)
    assert ref.minima_per_period == 4 and not ref.loses_contact
    assert abs(res.app_um - ref.app_um) <= 1e-4 * ref.app_um and res.valid
    plain = perturbation_series(exc, terms=80, summation="plain")
    assert abs(plain.app_um - ref.app_um) > 1e-3 * ref.app_um and not plain.valid


def test_general_power_law_matches_shooting():
    model = ContactModel(m2=1.5, c_n=1e14)
    exc = model.excitation(0.3, 0.3 * model.f_n0)
    res = perturbation_series(exc, terms=60)
    ref = _shooting(model, exc)
    assert res.valid and res.app_um == pytest.approx(ref.app_um, rel=1e-9)


@pytest.mark.parametrize("pa,fe", [(0.65, 742.0), (0.2, 1485.0), (0.85, 234.0), (1.2, 50.0)])
def test_contact_losing_operating_points_are_invalid(pa, fe):
    """1/2 and main resonance with loss of contact, 234 Hz 0.85 Q (Fig. 7), P_a > Q quasistatic:
    the series is never valid there, with any number of terms up to 80, and says why."""
    exc = MODEL.excitation(pa, fe)
    for n in (8, 40, 80):
        res = perturbation_series(exc, terms=n)
        assert not res.valid and res.reason


def test_predicted_loss_of_contact_is_named():
    """P_a = 1.2 Q > Q at 50 Hz: the quasistatic deflection would have to become negative."""
    res = perturbation_series(MODEL.excitation(1.2, 50.0), terms=80)
    assert res.ymin_um <= 0 and not res.valid and "loss of contact" in res.reason


def test_json_contract_and_bad_input(capsys):
    assert main(["perturbation", "--pa", "0.65", "--fe", "287", "--terms", "30", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for key in ("app_um", "ymin_um", "ymax_um", "valid", "terms", "error_estimate", "fe_hz",
                "pa_over_q", "harmonics_um"):
        assert key in d
    assert "order" not in d
    assert d["terms"] == 30 and len(d["harmonics_um"]) == 31 and d["valid"] is True
    assert d["ymax_um"] - d["ymin_um"] == pytest.approx(d["app_um"], rel=1e-12)
    assert d["error_estimate"] <= 1e-3 * d["app_um"]
    for argv, msg in [(["--terms", "0"], "--terms (terms) = 0"), (["--terms", "2.5"], "--terms"),
                      (["--terms", "x"], "--terms"), (["--order", "0"], "--order (terms) = 0"),
                      (["--order", "8", "--terms", "8"], "--order"), (["--fe", "-5"], "--fe (f_e) = -5"),
                      (["--pa", "-1"], "--pa (P_a/Q) = -1")]:
        assert main(["perturbation", *argv]) == 2
        err = capsys.readouterr().err
        assert err.startswith("contactvib: error: ") and msg in err and err.count("\n") == 1
    for bad in (0, 401, 2.5, "x", math.nan):
        with pytest.raises(ParameterError, match="terms"):
            perturbation_series(MODEL.excitation(0.5, 300.0), terms=bad)
    with pytest.raises(ParameterError, match="summation"):
        perturbation_series(MODEL.excitation(0.5, 300.0), terms=8, summation="euler")


@pytest.mark.parametrize("pa", [0.05, 0.5, 0.9])
def test_series_state_is_the_series_state(pa):
    """``series_state`` (the sweep's Newton starts) gives exactly ``perturbation_series().state``,
    also where the series has diverged (near 1481 Hz: 1e12 y0 and beyond) and at 50 Hz."""
    for fe in (50.0, 360.0, 742.0, 1400.0, 1450.0, 1481.0, 1500.0, 1900.0):
        exc = MODEL.excitation(pa, fe)
        for terms, summation in ((24, "pade"), (7, "plain")):
            a = perturbation_series(exc, terms=terms, summation=summation).state
            b = series_state(MODEL, exc, terms=terms, summation=summation)
            np.testing.assert_array_equal(a, b, err_msg=f"{pa} Q, {fe} Hz, {summation}")
    with pytest.raises(ParameterError) as e:
        series_state(MODEL, MODEL.excitation(pa, 100.0), terms=0)
    assert e.value.symbol == "terms"


def test_deprecated_order_option_still_works_with_one_warning_line(capsys):
    """``--order N`` (the name of ``--terms`` before issue 25) gives the same JSON and one warning
    line on stderr; it is hidden from the help."""
    assert main(["perturbation", "--pa", "0.65", "--fe", "287", "--terms", "12", "--json"]) == 0
    new = capsys.readouterr()
    assert main(["perturbation", "--pa", "0.65", "--fe", "287", "--order", "12", "--json"]) == 0
    old = capsys.readouterr()
    assert old.out == new.out and json.loads(old.out)["terms"] == 12 and new.err == ""
    assert old.err == "contactvib: warning: --order is deprecated, use --terms\n"
    assert main(["perturbation", "--help"]) == 0
    shown = capsys.readouterr().out
    assert "--terms" in shown and "--order" not in shown


def test_partial_sums_by_number_of_terms():
    """``app_of_terms(n)`` and ``history(terms=n)`` are the sums of the first n terms: those of
    the n-term series itself."""
    exc = MODEL.excitation(0.65, 287.0)
    res = perturbation_series(exc, terms=24)
    assert res.terms == 24 and res.app_of_terms(24) == res.app_um
    short = perturbation_series(exc, terms=12)
    assert res.app_of_terms(12) == pytest.approx(short.app_um, rel=1e-12)
    np.testing.assert_allclose(res.history(1, 50, terms=12).y_um, short.history(1, 50).y_um, rtol=1e-12)
    with pytest.raises(ParameterError, match="terms"):
        res.app_of_terms(25)
