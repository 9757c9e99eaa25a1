"""No row of a resonance dataset contradicts itself (issue 13, acceptance): per point,
``app_um`` = ``ymax_um`` − ``ymin_um`` and ``loses_contact`` ⇔ ``ymin_um`` < 0 ⇔
``contact_loss_fraction`` > 0 (:func:`contactvib.sweeps.dataset.check_consistency`). The default
suite checks the small CLI dataset; the slow full paper run (tests/sweeps/test_sweep.py) checks
the whole ``paper`` dataset."""

import numpy as np
import pytest
import xarray as xr

from contactvib.sweeps.dataset import check_consistency


def test_small_dataset_has_no_contradicting_row(small_dataset):
    with xr.open_dataset(small_dataset) as ds:
        assert ds.sizes["point"] >= 21  # one attractor or more at each of the 21 frequencies
        assert check_consistency(ds) == []


def _changed(ds, name, p, value):
    ds = ds.copy(deep=True)
    data = ds[name].values.copy()
    data[p] = value
    ds[name] = ds[name].copy(data=data)
    return ds


@pytest.mark.parametrize("name, value, words", [
    ("app_um", lambda ds, p: float(ds["app_um"][p]) * (1 + 1e-6), "app_um = "),
    ("app_um", lambda ds, p: np.nan, "app_um = nan"),
    ("ymax_um", lambda ds, p: float(ds["ymax_um"][p]) + 1e-3, "ymax_um - ymin_um"),
    ("loses_contact", lambda ds, p: 1 - int(ds["loses_contact"][p]), "loses_contact = "),
    ("contact_loss_fraction", lambda ds, p: 0.0 if float(ds["contact_loss_fraction"][p]) > 0 else 0.25,
     "contact_loss_fraction = "),
])
def test_each_contradiction_is_found(small_dataset, name, value, words):
    with xr.open_dataset(small_dataset) as ds:
        ds = ds.load()
    for p in (0, ds.sizes["point"] - 1):
        bad = check_consistency(_changed(ds, name, p, value(ds, p)))
        assert len(bad) == 1 and bad[0].startswith(f"point {p} (P_a = 0.65 Q, f_e = ") and words in bad[0], bad


def test_rounding_is_not_a_contradiction(small_dataset):
    """app_um within 1e-9 relative (or 1e-12 µm) of ymax_um − ymin_um is consistent."""
    with xr.open_dataset(small_dataset) as ds:
        ds = ds.load()
    span = ds["ymax_um"].values - ds["ymin_um"].values
    ds["app_um"] = ds["app_um"].copy(data=span * (1 + 5e-10))
    assert check_consistency(ds) == []
