"""The dataset's ``dof`` and ``contact`` variables (docs/formats.md, "Dataset layout"): written by
``level_dataset``, read back from the file, they rebuild through ``dofs_and_contacts`` the
``dofs``/``contacts`` of the attractor that ``find_attractors`` finds at the same point; the
stored mean contact force W of a periodic point is the identity that the attractor's integral
along the orbit meets."""

import json

import numpy as np
import pytest
import xarray as xr

from contactvib import ContactModel, attractors_at, find_attractors
from contactvib.steady.results import dofs_and_contacts
from contactvib.sweeps.dataset import check_consistency


@pytest.fixture(scope="module")
def level_file(tmp_path_factory):
    """One level (0.65 Q) over 340–380 Hz, 4 Hz step, with multi-starts: at 360 Hz the five
    attractors of the paper's point (period 1 in contact and bouncing, period 2), written to NetCDF."""
    from contactvib.sweeps.resonance import resonance_dataset
    from contactvib.sweeps.sweep import SweepSettings

    out = tmp_path_factory.mktemp("dofs")
    st = SweepSettings(fmin_hz=340.0, fmax_hz=380.0, df_hz=4.0, multistart_per_octave=2, n_starts=4)
    resonance_dataset(ContactModel(), levels=[0.65], settings=st, out=out, workers=1, progress=False)
    return out / "resonance.nc"


def test_variables_dimensions_and_units(small_dataset):
    with xr.open_dataset(small_dataset) as ds:
        assert ds.sizes["dof"] == 1 and ds.sizes["contact"] == 1
        assert list(ds["dof_name"].values) == ["y"] and list(ds["dof_unit"].values) == ["um"]
        assert list(ds["contact_name"].values) == ["contact"]
        for name in ("dof_min", "dof_max", "dof_app", "dof_h1"):
            assert ds[name].dims == ("point", "dof") and ds[name].attrs["units"] == "um"
        for name, unit in (("contact_loses_contact", "1"), ("contact_loss_frac", "1"),
                           ("contact_mean_force_n", "N")):
            assert ds[name].dims == ("point", "contact") and ds[name].attrs["units"] == unit
        # built from the point's own variables
        np.testing.assert_array_equal(ds["dof_min"].values[:, 0], ds["ymin_um"].values)
        np.testing.assert_array_equal(ds["dof_max"].values[:, 0], ds["ymax_um"].values)
        np.testing.assert_array_equal(ds["dof_app"].values[:, 0], ds["app_um"].values)
        k = ds["period"].values
        h1 = ds["harmonics_um"].values[np.arange(k.size), np.where(k > 0, k, 32) - 1]
        np.testing.assert_array_equal(ds["dof_h1"].values[:, 0], h1)
        np.testing.assert_array_equal(ds["contact_loss_frac"].values[:, 0], ds["contact_loss_fraction"].values)
        np.testing.assert_array_equal(ds["contact_loses_contact"].values[:, 0], ds["loses_contact"].values)
        w = ContactModel().W
        periodic = ds["kind"].values == "periodic"
        assert np.all(ds["contact_mean_force_n"].values[periodic, 0] == w)
        assert np.all(np.isnan(ds["contact_mean_force_n"].values[~periodic, 0]))
        assert check_consistency(ds) == []


def test_a_changed_dof_variable_is_a_contradiction(small_dataset):
    with xr.load_dataset(small_dataset) as ds:
        data = ds["dof_app"].values.copy()
        data[3, 0] *= 1 + 1e-6
        ds["dof_app"] = ds["dof_app"].copy(data=data)
        bad = check_consistency(ds)
    assert len(bad) == 1 and bad[0].startswith("point 3 ") and "dof_app differs" in bad[0], bad


def test_round_trip_rebuilds_the_attractors_dofs_and_contacts(level_file):
    """Write (the fixture's resonance.nc), read, rebuild: the query's dofs/contacts equal those of
    the attractor found at the same point to the orbits' refinement (1e-6 relative); the stored
    mean force W equals the attractor's integral along its orbit."""
    model = ContactModel()
    with xr.open_dataset(level_file) as ds:
        stored = attractors_at(ds, pa_over_q=0.65, fe_hz=360.0)["attractors"]
        # the query goes through dofs_and_contacts on the stored columns
        p = int(np.nonzero(np.asarray(ds["fe_hz"].values) == 360.0)[0][-1])
        cols = {n: ds[n].values[p] for n in ("dof_min", "dof_max", "dof_app", "dof_h1", "contact_loses_contact",
                                            "contact_loss_frac", "contact_mean_force_n")}
        cols.update({n: ds[n].values for n in ("dof_name", "dof_unit", "contact_name")})
    assert dofs_and_contacts(**cols) in [{"dofs": a["dofs"], "contacts": a["contacts"]} for a in stored]
    assert len(stored) == 5 and {s["contacts"][0]["loses_contact"] for s in stored} == {True, False}
    found = find_attractors(model.excitation(0.65, 360.0), n_starts=256)
    for s in stored:
        a = min(found, key=lambda a: abs(a.app_um - s["app_um"]))
        assert a.period == s["period"]
        mine = json.loads(json.dumps(a.to_dict()))
        assert [set(d) for d in s["dofs"]] == [set(d) for d in mine["dofs"]]
        assert [set(c) for c in s["contacts"]] == [set(c) for c in mine["contacts"]]
        for d_s, d_a in zip(s["dofs"], mine["dofs"]):
            assert (d_s["name"], d_s["unit"]) == (d_a["name"], d_a["unit"])
            for key in ("min", "max", "app", "h1"):
                assert d_s[key] == pytest.approx(d_a[key], rel=1e-6), key
        for c_s, c_a in zip(s["contacts"], mine["contacts"]):
            assert (c_s["name"], c_s["loses_contact"]) == (c_a["name"], c_a["loses_contact"])
            assert c_s["contact_loss_fraction"] == pytest.approx(c_a["contact_loss_fraction"], rel=1e-6, abs=1e-9)
            assert c_s["mean_force_n"] == model.W
            assert c_a["mean_force_n"] == pytest.approx(c_s["mean_force_n"], rel=1e-6)
        assert len(s["floquet_multipliers"]) == 2 * len(s["dofs"])


def test_non_periodic_rows_have_no_mean_force_and_h1_over_the_recorded_periods():
    """A non-periodic row's f_e amplitude is the harmonic j = 32 (its 32 recorded periods) and its
    mean contact force NaN; a period-k row's is j = k, its force W."""
    from contactvib._kernels.describe import NP_RECORD, new_rows
    from contactvib.sweeps.dataset import _dof_contact_variables

    model = ContactModel()
    rows = new_rows(2)
    rows.kind[:] = [0, 1]
    rows.k[:] = [3, 0]
    rows.harm[:] = np.arange(rows.harm.size, dtype=float).reshape(rows.harm.shape)
    v = _dof_contact_variables(model, rows, np.zeros(2), np.zeros(2, bool), NP_RECORD)
    h1 = v["dof_h1"].values[:, 0] / model.units.y_um
    assert h1.tolist() == pytest.approx([rows.harm[0, 2], rows.harm[1, NP_RECORD - 1]], rel=1e-15)
    assert v["contact_mean_force_n"].values[0, 0] == model.W and np.isnan(v["contact_mean_force_n"].values[1, 0])
