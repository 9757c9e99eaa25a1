"""The one calling rule of the public verbs (``contactvib.call_forms``): the operating point first
(an Excitation, or the model of a range verb), options keyword-only; the old call forms still run
for one release, the same computation, with a DeprecationWarning that names the new form."""

from __future__ import annotations

import inspect
import warnings
from dataclasses import replace

import numpy as np
import pytest

import contactvib
from contactvib import ContactModel, HBSettings, hb_solve, perturbation_curve, perturbation_series
from contactvib.model import ParameterError

MODEL = ContactModel()
EXC = MODEL.excitation(0.3, 600.0)

#: what each verb takes positionally (the operating point, then what it acts on)
POSITIONAL = {
    "find_attractors": ["excitation"], "simulate": ["excitation"], "basins": ["excitation"],
    "attractor_history": ["excitation", "attractor"], "refine_orbit": ["excitation", "z", "k"],
    "describe_orbit": ["excitation", "z", "period"], "continue_orbit": ["excitation", "state", "period"],
    "hb_solve": ["excitation"], "perturbation_series": ["excitation"], "friction_at": ["excitation", "attractor"],
    "coefficients_from_orbit": ["excitation", "z"], "lyapunov_spectrum": ["excitation", "state"],
    "switch_period_doubling": ["model", "special"], "continue_attractors": ["model"],
    "bifurcation_diagram": ["model"], "evolution": ["model"], "perturbation_curve": ["model"],
    "hb_continuation": ["model"], "trace_level": ["model"], "resonance_dataset": ["model"],
    "reproduce_paper": ["model"],
    "open_resonance": ["path"], "attractors_at": ["ds"], "check_completeness": ["data"],
    "animate": ["dataset", "out"], "open_levels": ["path"],
    "regime_maps": ["ds"], "fit": [], "poincare_sections": ["excitation", "attractors"],
    "orbit_diagram": ["model"],
    "orbit_period": ["excitation"], "follow_cascade": ["model"], "cascades_at": ["model"],
}


def test_every_verb_takes_its_operating_point_first_and_options_by_keyword():
    verbs = [n for n in contactvib.__all__ if inspect.isfunction(getattr(contactvib, n))]
    assert sorted(verbs) == sorted(POSITIONAL), "a new verb: state its positional arguments here"
    for name in verbs:
        params = inspect.signature(getattr(contactvib, name)).parameters.values()
        pos = [p.name for p in params if p.kind == p.POSITIONAL_OR_KEYWORD]
        assert pos == POSITIONAL[name], name
        assert not any(p.kind in (p.VAR_POSITIONAL, p.POSITIONAL_ONLY) for p in params), name


def _same(a, b):
    for k, v in vars(a).items():
        w = getattr(b, k)
        if isinstance(v, np.ndarray):
            np.testing.assert_array_equal(v, w)
        elif not isinstance(v, (list, tuple)):
            assert v == w or (v != v and w != w), k


def test_old_point_form_warns_and_gives_the_same_result():
    new = perturbation_series(EXC, terms=12, summation="plain")
    with pytest.warns(DeprecationWarning, match=r"perturbation_series\(excitation, \*, terms=\.\.\."):
        old = perturbation_series(MODEL, EXC, 12, "plain")
    _same(new, old)
    with pytest.warns(DeprecationWarning):
        old = perturbation_series(model=MODEL, excitation=EXC, terms=12, summation="plain")
    _same(new, old)
    new = hb_solve(EXC, harmonics=8, stability=False)
    with pytest.warns(DeprecationWarning, match=r"call hb_solve\(excitation, \*"):
        old = hb_solve(MODEL, EXC, 8, stability=False)
    np.testing.assert_array_equal(new.coefficients, old.coefficients)


def test_old_range_form_warns_and_gives_the_same_result():
    f = np.array([300.0, 600.0])
    new = perturbation_curve(MODEL, pa_over_q=0.3, fe_hz=f, terms=8)
    with pytest.warns(DeprecationWarning, match=r"perturbation_curve\(model, \*, pa_over_q="):
        old = perturbation_curve(MODEL, 0.3, f, 8)
    for a, b in zip(new, old):
        np.testing.assert_array_equal(a, b)


def test_the_new_form_does_not_warn_and_positional_options_are_refused():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        perturbation_series(EXC, terms=4)
    with pytest.raises(TypeError):  # beyond the old form's arguments too
        perturbation_series(MODEL, EXC, 4, "plain", "extra")
    with pytest.raises(TypeError, match="keyword-only"):  # the new form with an option by position
        perturbation_series(EXC, 4)
    with pytest.raises(TypeError):  # an argument given twice
        perturbation_series(MODEL, EXC, 4, terms=5)


def test_old_form_with_another_model_is_refused():
    with pytest.raises(ParameterError) as e, pytest.warns(DeprecationWarning):
        perturbation_series(MODEL.replace(M=0.3), EXC, 4)
    assert e.value.symbol == "excitation" and "another model" in e.value.allowed


def test_renamed_settings_fields_stay_readable_and_accepted():
    with pytest.warns(DeprecationWarning, match=r"HBSettings.df_max is deprecated.*df_max_hz"):
        s = HBSettings(df_max=3.0)
    assert s == HBSettings(df_max_hz=3.0)
    with pytest.warns(DeprecationWarning):
        assert s.df_max == 3.0
    with pytest.warns(DeprecationWarning):
        assert replace(s, df_max=4.0).df_max_hz == 4.0
    with pytest.raises(AttributeError):
        s.no_such_field  # noqa: B018
