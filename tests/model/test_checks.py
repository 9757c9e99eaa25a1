"""The library's input checks (contactvib.model.checks): each check, its words, and the ranges."""
import math

import numpy as np
import pytest

from contactvib.model import (
    SHOOTING_RTOL_RANGE,
    ContactModel,
    Excitation,
    ParameterError,
    Units,
    check_choice,
    check_finite,
    check_frequency_range,
    check_int,
    check_pa_level,
    check_range,
)


@pytest.mark.parametrize("value", ["abc", None, math.nan, math.inf, -math.inf, "nan", True, [1.0]])
def test_check_finite_refuses_non_numbers(value):
    with pytest.raises(ParameterError) as e:
        check_finite("x", value)
    assert e.value.symbol == "x" and e.value.allowed == "must be a finite number"


def test_check_finite_returns_a_float():
    assert check_finite("x", "2.5") == 2.5 and isinstance(check_finite("x", 3), float)
    assert check_finite("x", np.float32(1.5)) == 1.5


@pytest.mark.parametrize("kwargs, value, allowed", [
    (dict(lower=0.0, inclusive=False, unit="Hz"), 0, "must be > 0 Hz"),
    (dict(lower=1.0, inclusive=True), 0.5, "must be >= 1"),
    (dict(lower=0.0, inclusive=True, unit="1"), -1, "must be >= 0"),
    (dict(upper=1e-6), 1e-3, "must be <= 1e-6"),
    (dict(upper=1.0, upper_inclusive=False), 1.0, "must be < 1"),
    (dict(lower=1e-15, inclusive=True, upper=1e-6), 1e-3, "must be in [1e-15, 1e-6]"),
    (dict(lower=0.0, inclusive=False, upper=1000), 0, "must be in (0, 1000]"),
    (dict(lower=300.0, inclusive=False, unit="Hz", lower_name="f_min"), 200,
     "must be > f_min = 300 Hz"),
    (dict(lower=30.0, upper=2000.0, unit="Hz", lower_name="f_min", upper_name="f_max"), 2500,
     "must lie in [f_min, f_max] = [30, 2000] Hz"),
])
def test_check_range_words(kwargs, value, allowed):
    with pytest.raises(ParameterError) as e:
        check_range("q", value, **kwargs)
    assert e.value.allowed == allowed and e.value.symbol == "q" and e.value.value == value
    assert str(e.value) == f"q = {value:g}: {allowed}".replace("e-06", "e-6")


def test_check_range_accepts_the_bounds_it_includes():
    assert check_range("q", 1e-15, 1e-15, True, upper=1e-6) == 1e-15
    assert check_range("q", 1e-6, 1e-15, True, upper=1e-6) == 1e-6
    assert check_range("q", "5", 0.0, False) == 5.0
    with pytest.raises(ParameterError, match="finite"):
        check_range("q", math.nan, 0.0, True)


def test_bounds_can_be_renamed():
    """The names of the bounds are listed, so the CLI can write its option names instead."""
    with pytest.raises(ParameterError) as e:
        check_range("f_e", 2500, 30, True, "Hz", upper=2000, lower_name="f_min", upper_name="f_max")
    assert e.value.bounds == ("f_min", "f_max")
    assert (e.value.allowed_with({"f_min": "--fmin", "f_max": "--fmax"})
            == "must lie in [--fmin, --fmax] = [30, 2000] Hz")


@pytest.mark.parametrize("value", [16.7, "16.7", "abc", math.nan, math.inf, None, True, 1e400])
def test_check_int_refuses_non_integers(value):
    """Non-integers are refused, never truncated (n_starts = 16.7 used to become 16)."""
    with pytest.raises(ParameterError, match="must be an integer"):
        check_int("n_starts", value, 1)


@pytest.mark.parametrize("value, expected", [(16, 16), (16.0, 16), ("16", 16), ("1e3", 1000),
                                              (np.int64(7), 7), (2**60, 2**60)])
def test_check_int_accepts_integers(value, expected):
    n = check_int("n", value, 1)
    assert n == expected and type(n) is int


@pytest.mark.parametrize("lower, upper, value, allowed", [
    (1, None, 0, "must be an integer >= 1"),
    (1, 64, 65, "must be an integer in 1..64"),
    (None, 8, 9, "must be an integer <= 8"),
    (None, None, 0.5, "must be an integer"),
])
def test_check_int_words(lower, upper, value, allowed):
    with pytest.raises(ParameterError) as e:
        check_int("k", value, lower, upper)
    assert e.value.allowed == allowed


def test_check_choice():
    assert check_choice("summation", "pade", ("pade", "plain")) == "pade"
    with pytest.raises(ParameterError, match="must be one of 'pade', 'plain'"):
        check_choice("summation", "fast", ("pade", "plain"))


def test_frequency_range_and_pa_level():
    assert check_frequency_range("30", 2000) == (30.0, 2000.0)
    with pytest.raises(ParameterError) as e:
        check_frequency_range(300, 200)
    assert e.value.symbol == "f_max" and e.value.allowed == "must be > f_min = 300 Hz"
    with pytest.raises(ParameterError) as e:
        check_frequency_range(0, 200)
    assert e.value.symbol == "f_min"
    assert check_pa_level("0.65") == 0.65
    with pytest.raises(ParameterError, match=r"P_a/Q = 0: must be > 0 \(multiple of Q = M g\)"):
        check_pa_level(0)


def test_shooting_rtol_range_is_the_continuations():
    from contactvib import ContinuationSettings

    lo, hi = SHOOTING_RTOL_RANGE
    ContinuationSettings(rtol=lo, tol=1e-11)
    ContinuationSettings(rtol=hi, tol=1e-4)
    for r in (lo / 10, hi * 10):
        with pytest.raises(ParameterError):
            ContinuationSettings(rtol=r)


def test_model_and_excitation_use_the_checks():
    with pytest.raises(ParameterError) as e:
        ContactModel(M=-1)
    assert (e.value.symbol, e.value.allowed) == ("M", "must be > 0 kg")
    with pytest.raises(ParameterError, match=r"P_a/Q = -1: must be >= 0 \(multiple of Q = M g\)"):
        Excitation(ContactModel(), -1, 360)
    with pytest.raises(ParameterError, match="model"):
        Excitation("not a model", 0.5, 360)


# ------------------------------------------------------------------ units

def test_units_follow_y0_and_omega_n0():
    """y [µm] = x y0 1e6, ẏ [mm/s] = x' y0 ω_n0 1e3, t [ms] = τ 1e3/ω_n0 (x = y/y0, τ = ω_n0 t)."""
    for m in (ContactModel(), ContactModel(m2=1.5, M=0.5)):
        u = m.units
        assert isinstance(u, Units)
        assert u.y_um == m.y0 * 1e6
        assert u.ydot_mm_s == m.y0 * m.omega_n0 * 1e3
        assert u.t_ms == 1e3 / m.omega_n0
        # one excitation period 1/f_e [ms] is 2π/r in τ
        exc = m.excitation(0.5, 360.0)
        assert exc.tau_period * u.t_ms == pytest.approx(1e3 / 360.0, rel=1e-13)
        assert u.state(u.y_um, 2 * u.ydot_mm_s) == (1.0, 2.0)
    assert ContactModel().units.y_um == pytest.approx(0.2254, abs=5e-5)  # the paper's y0 [µm]
