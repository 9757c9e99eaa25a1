"""One settings vocabulary: a concept has one field name (and unit) in every settings class, the
fields two classes share are checked in one place, and the names renamed in 0.2.0 still work for
one release with a DeprecationWarning that names the new field."""

from __future__ import annotations

import inspect
import warnings
from dataclasses import fields, replace

import pytest

from contactvib.continuation.engine import CorrectorSettings, StepControl
from contactvib.continuation.settings import BranchSettings
from contactvib.continuation.shooting import ContinuationSettings
from contactvib.continuation.system_shooting import SystemContinuationSettings
from contactvib.frequency.harmonic_balance import HBSettings
from contactvib.model import ParameterError
from contactvib.steady.orbit_diagram import OrbitDiagramSettings
from contactvib.sweeps.settings import RECORD_NAMES, SweepSettings
from contactvib.sweeps.system_sweep import SystemSweepSettings

#: (class, old name, new name, a value valid for both)
RENAMED = [
    (SweepSettings, "close_tol", "tol", 1e-8),
    (SweepSettings, "multistart_starts", "n_starts", 5),
    (SystemContinuationSettings, "app_max", "app_max_um", 300.0),
    (SystemContinuationSettings, "pa_min", "pa_min_newton", 0.5),
    (SystemContinuationSettings, "pa_max", "pa_max_newton", 7.0),
    (HBSettings, "df_max", "df_max_hz", 3.0),
]
SYSTEM_GRID = dict(fmin_hz=300.0, fmax_hz=400.0, df_hz=10.0)


def _make(cls, **kw):
    return cls(**SYSTEM_GRID, **kw) if cls is SystemSweepSettings else cls(**kw)


@pytest.mark.parametrize("cls, old, new, value", RENAMED, ids=lambda x: x if isinstance(x, str) else None)
def test_an_old_name_still_works_and_warns_with_the_new_one(cls, old, new, value):
    with pytest.warns(DeprecationWarning, match=rf"{cls.__name__}\.{old} is deprecated.*{cls.__name__}\.{new}"):
        s = cls(**{old: value})
    assert s == cls(**{new: value}) and getattr(s, new) == value
    with pytest.warns(DeprecationWarning, match=rf"use {cls.__name__}\.{new}"):
        assert getattr(s, old) == value
    with pytest.warns(DeprecationWarning):
        assert getattr(replace(s, **{old: value}), new) == value
    assert old not in {f.name for f in fields(cls)}


@pytest.mark.parametrize("cls, old, new, bad", [
    (SweepSettings, "multistart_starts", "n_starts", -1),
    (SweepSettings, "close_tol", "tol", 0.0),
    (SystemContinuationSettings, "app_max", "app_max_um", 0.0),
    (SystemContinuationSettings, "pa_min", "pa_min_newton", -1.0),
    (SystemContinuationSettings, "pa_max", "pa_max_newton", -1.0),
])
def test_a_refusal_names_the_new_field_whichever_name_was_given(cls, old, new, bad):
    for name in (new, old):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            with pytest.raises(ParameterError) as e:
                cls(**{name: bad})
        assert e.value.symbol == new and str(e.value).startswith(f"{new} = ")
        assert old + " " not in str(e.value)


#: a bad value of each field both continuation settings share: the same refusal from both (their
#: defaults of the bounds named in the message are equal)
SHARED_BAD = [("ds_min", 0.0), ("ds", 1e-8), ("ds_max", 0.01), ("max_points", 1), ("app_max_um", 0.0),
              ("rtol", 1.0), ("tol", 0.0), ("tol", "x"), ("max_iter", 0), ("max_turn", -0.1), ("locate_tol", 0.0),
              ("max_failures", 0)]


@pytest.mark.parametrize("name, bad", SHARED_BAD)
def test_both_continuation_settings_refuse_a_shared_field_alike(name, bad):
    messages = []
    for cls in (ContinuationSettings, SystemContinuationSettings):
        with pytest.raises(ParameterError) as e:
            cls(**{name: bad})
        assert e.value.symbol == name
        messages.append(str(e.value))
    assert messages[0] == messages[1]


def test_the_level_ranges_keep_their_units_in_their_names():
    with pytest.raises(ParameterError, match=r"^pa_max = 0\.1: must be > pa_min = 0\.5$"):
        ContinuationSettings(pa_min=0.5, pa_max=0.1)
    with pytest.raises(ParameterError, match=r"^pa_max_newton = 0\.1: must be > pa_min_newton = 0\.5 N$"):
        SystemContinuationSettings(pa_min_newton=0.5, pa_max_newton=0.1)
    assert SystemContinuationSettings(fmin_hz=0.0).fmin_hz == 0.0  # a system branch may run down to 0 Hz
    with pytest.raises(ParameterError, match="fmin_hz"):
        ContinuationSettings(fmin_hz=0.0)


def test_the_shared_checks_are_written_once():
    """The subclasses' __post_init__ check only their own fields (``locate``, ``excitation``); the
    shared ones, and the steps and Newton fields of HBSettings, go through one function."""
    for cls in (ContinuationSettings, SystemContinuationSettings):
        assert issubclass(cls, BranchSettings)
        src = inspect.getsource(cls.__post_init__)
        assert "check_range" not in src and "check_int" not in src, cls.__name__
    hb = inspect.getsource(HBSettings.__post_init__)
    assert all(f'"{n}"' not in hb for n in ("ds", "ds_min", "ds_max", "tol", "max_iter"))
    assert "check_steps" in hb and "check_newton" in hb
    assert "check_range" not in inspect.getsource(SystemSweepSettings.__post_init__).split("df_hz")[0]


@pytest.mark.parametrize("grid", [dict(fmin_hz=400.0, fmax_hz=300.0, df_hz=10.0),
                                  dict(fmin_hz=300.0, fmax_hz=400.0, df_hz=0.0),
                                  dict(fmin_hz=300.0, fmax_hz=400.0, df_hz=150.0),
                                  dict(fmin_hz=300.0, fmax_hz=400.0, df_hz=1e-5)])
def test_both_sweeps_check_their_grid_alike(grid):
    messages = []
    for cls in (SweepSettings, SystemSweepSettings):
        with pytest.raises(ParameterError) as e:
            cls(**grid)
        messages.append(str(e.value))
    assert messages[0] == messages[1]


def test_the_hb_steps_follow_the_continuation_rule():
    with pytest.raises(ParameterError, match=r"^ds = 1e-7: must be >= ds_min = 1e-6$"):
        HBSettings(ds=1e-7)
    with pytest.raises(ParameterError, match=r"^ds_max = 0\.01: must be >= ds = 0\.02$"):
        HBSettings(ds_max=0.01)


def test_the_engine_settings_come_from_the_shared_fields():
    for s in (ContinuationSettings(tol=1e-9, max_iter=5, ds=0.01, max_points=30, locate=False),
              SystemContinuationSettings(tol=1e-9, max_iter=5, ds=0.01, max_points=30)):
        assert s.corrector() == CorrectorSettings(tol=1e-9, max_iter=5, cons_tol=1e-9, max_step=1.0)
        sc = s.step_control()
        assert isinstance(sc, StepControl) and (sc.ds, sc.ds_min, sc.ds_max, sc.max_points) == \
            (0.01, s.ds_min, s.ds_max, 30)
        assert (sc.max_turn, sc.max_failures, sc.locate_tol) == (s.max_turn, s.max_failures, s.locate_tol)
        assert sc.locate is getattr(s, "locate", True) and sc.detect_loop and sc.bound_action == "fix"


def test_the_dataset_record_keeps_its_names_and_reads_back_without_warnings():
    """A resonance dataset's ``settings`` attribute: the fields in order, two under their record
    names (the stored layout; ``paper.nc`` unchanged), read back by from_dict."""
    s = SweepSettings(n_starts=5, tol=1e-8)
    d = s.to_dict()
    assert list(d) == [RECORD_NAMES.get(f.name, f.name) for f in fields(SweepSettings)][:len(d)]
    assert (d["multistart_starts"], d["close_tol"]) == (5, 1e-8) and "tol" not in d and "n_starts" not in d
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        assert SweepSettings.from_dict(d) == s
        assert SweepSettings.from_dict({"n_starts": 5, "tol": 1e-8}) == s


def test_one_concept_one_name_across_the_settings_classes():
    """The starts of a search and the Newton closure have one name in every class that has them."""
    names = {cls: {f.name for f in fields(cls)} for cls in (
        SweepSettings, SystemSweepSettings, ContinuationSettings, SystemContinuationSettings, HBSettings,
        OrbitDiagramSettings, CorrectorSettings, StepControl)}
    for cls, have in names.items():
        assert not have & {"close_tol", "multistart_starts", "app_max", "df_max", "starts"}, cls.__name__
    assert all("n_starts" in names[c] for c in (SweepSettings, SystemSweepSettings, OrbitDiagramSettings))
    assert all("tol" in names[c] for c in (SweepSettings, ContinuationSettings, SystemContinuationSettings,
                                           HBSettings, CorrectorSettings))
    assert all("app_max_um" in names[c] for c in (ContinuationSettings, SystemContinuationSettings))
    assert _make(SystemSweepSettings).n_starts == 6
