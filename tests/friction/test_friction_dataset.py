"""Friction columns of resonance/atlas datasets (issue 26): SweepSettings(friction=...) and
``--friction``, the variables with units, their values against ``friction_at``, the parameters
as attributes, resume refusing other friction settings, datasets without friction unchanged."""

from __future__ import annotations

import json

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.friction import FrictionModel, friction_at
from contactvib.friction.columns import FRICTION_VARIABLES
from contactvib.model import ContactModel, ParameterError
from contactvib.sweeps.resonance import ResumeMismatch, resonance_dataset
from contactvib.sweeps.sweep import SweepSettings

FM = FrictionModel(mu=0.3, vd=0.5)


def _settings(friction=FM, **kw):
    base = dict(fmin_hz=340.0, fmax_hz=360.0, df_hz=10.0, multistart_per_octave=0, friction=friction)
    return SweepSettings(**{**base, **kw})


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    out = tmp_path_factory.mktemp("fr_ds")
    ds = resonance_dataset(ContactModel(), levels=[0.65], settings=_settings(), out=out, workers=1, progress=False)
    return out, ds


def test_settings_record_friction_only_when_given():
    assert "friction" not in _settings(None).to_dict()
    d = _settings().to_dict()
    assert d["friction"] == FM.parameters()
    assert SweepSettings.from_dict(d) == _settings()  # a dict is the FrictionModel's parameters
    with pytest.raises(ParameterError, match="friction"):
        _settings("mu=0.3")
    with pytest.raises(ParameterError, match="mu"):
        _settings({"mu": -1.0})


def test_columns_units_and_attributes(swept):
    _out, ds = swept
    for name in FRICTION_VARIABLES:
        assert ds[name].dims == ("point",) and "units" in ds[name].attrs
    assert json.loads(ds.attrs["friction"]) == FM.parameters()
    assert json.loads(ds.attrs["settings"])["friction"] == FM.parameters()
    periodic = ds["period"].values > 0
    ratio = ds["friction_ratio"].values
    assert periodic.any() and np.all(np.isfinite(ratio[periodic])) and np.all(np.isnan(ratio[~periodic]))
    assert np.all((ratio[periodic] > 0.0) & (ratio[periodic] <= 1.0 + 1e-9))
    fractions = sum(ds[f"friction_{m}_fraction"].values for m in ("stick", "slip", "free"))
    assert np.allclose(fractions[periodic], 1.0, atol=1e-9)
    # flight (y < 0) carries no compression: the free fraction is at least the contact loss
    assert np.all(ds["friction_free_fraction"].values[periodic]
                  >= ds["contact_loss_fraction"].values[periodic] - 1e-9)


def test_values_are_friction_at_of_the_stored_point(swept):
    _out, ds = swept
    model = ContactModel()
    j = int(np.nanargmin(ds["friction_ratio"].values))
    exc = model.excitation(0.65, float(ds["fe_hz"].values[j]))
    u = model.units
    z = np.array([ds["state_y_um"].values[j] / u.y_um, ds["state_ydot_mm_s"].values[j] / u.ydot_mm_s])

    class Orbit:
        state, period = z, int(ds["period"].values[j])
        contact_loss_fraction = float(ds["contact_loss_fraction"].values[j])

    res = friction_at(exc, Orbit, friction=FM)
    # the columns: Newton on the period map to WARM_TOL = 1e-6 (the one-point run: to the noise floor)
    assert ds["friction_ratio"].values[j] == pytest.approx(res.friction_ratio, rel=1e-5)
    assert ds["friction_stick_fraction"].values[j] == pytest.approx(res.stick_fraction, abs=1e-5)


def test_warm_newton_start_agrees_with_the_transient():
    """friction_at with a WarmStart (Newton on the period map, cold then warm along f_e) equals
    the settled transient; the warm start predicts the next state along the branch."""
    from contactvib.friction.newton import WarmStart
    from contactvib.steady.attractors import find_attractors

    model, ws = ContactModel(), WarmStart()
    for fe in (356.0, 358.0, 360.0, 362.0):
        exc = model.excitation(0.65, fe)
        a = max((a for a in find_attractors(exc, n_starts=64) if a.period == 1), key=lambda a: a.app_um)
        if fe == 362.0:
            predicted = ws.predict(1, fe)
        warm = friction_at(exc, a, friction=FM, warm=ws)
        assert warm.n_periods == 1 and warm.settled
    cold = friction_at(exc, a, friction=FM)
    assert warm.friction_ratio == pytest.approx(cold.friction_ratio, rel=1e-5)
    assert warm.stick_fraction == pytest.approx(cold.stick_fraction, abs=1e-5)
    assert np.max(np.abs(predicted - ws.z) / (FM.scales(model) + np.abs(ws.z))) < 1e-3


def test_resume_refuses_other_friction_settings(swept):
    out, _ds = swept
    model = ContactModel()
    with pytest.raises(ResumeMismatch, match=r"friction\.mu = 0\.3, not 0\.4"):
        resonance_dataset(model, levels=[0.65], settings=_settings(FrictionModel(mu=0.4, vd=0.5)), out=out, resume=True,
                          workers=1, progress=False)
    with pytest.raises(ResumeMismatch, match="made with friction = mu=0.3"):
        resonance_dataset(model, levels=[0.65], settings=_settings(None), out=out, resume=True, workers=1,
                          progress=False)


def test_without_friction_no_columns():
    ds = resonance_dataset(ContactModel(), levels=[0.65], settings=_settings(None, fmax_hz=350.0), workers=1,
                           progress=False)
    assert not set(FRICTION_VARIABLES) & set(ds.variables)
    assert "friction" not in ds.attrs and "friction" not in json.loads(ds.attrs["settings"])


@pytest.mark.parametrize("spec, words", [
    ("mu=-1", "--friction mu (mu) = -1: must be in (0, 100]"),
    ("foo=1", "--friction: 'foo=1' is not NAME=VALUE"),
    ("vd=-1", "--friction vd (v_d) = -1: must be in [0, 1e+6] mm/s"),
    ("mu=0.2,mu=0.3", "--friction: mu given twice"),
    ("drive=force", "--friction drive=force: needs the tangential force ft=N"),
])
def test_bad_friction_option_one_line(tmp_path, capsys, spec, words):
    assert main(["resonance", "--fmin", "340", "--fmax", "360", "--friction", spec, "--out",
                 str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and words in err
