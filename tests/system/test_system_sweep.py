"""Resonance sweeps of a System (``contactvib.sweeps.system_sweep``, ``system_dataset``,
``system_resonance`` and ``resonance``/``atlas --system``) against independent references: the
1-DOF tracer on the n = 1 system and on the rocking unit's symmetric orbits, the period map and
the period average of the equation of motion at every stored point, and the local pool against
Dask."""

import json
from pathlib import Path

import numpy as np
import pytest

from contactvib import ContactModel
from contactvib.cli import main
from contactvib.model.rocking import rocking_system
from contactvib.model.system import System
from contactvib.steady.system_orbits import period_map
from contactvib.sweeps.system_dataset import system_level_dataset
from contactvib.sweeps.system_resonance import system_description, system_resonance_dataset
from contactvib.sweeps.system_sweep import SystemSweepSettings, sweep_system_level

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "two_dof_stop.toml"
#: A_pp of the same orbit from the system sweep and the 1-DOF tracer (both refined by Newton to
#: a closure of 1e-10, extrema on the dense output).
APP_RTOL = 1e-6


@pytest.fixture(scope="module")
def one_dof_level():
    """The 1-DOF tracer's dataset at 0.65 Q, 300–420 Hz, 5 Hz."""
    from contactvib.sweeps.dataset import level_dataset
    from contactvib.sweeps.sweep import SweepSettings, trace_level

    model = ContactModel()
    st = SweepSettings(fmin_hz=300.0, fmax_hz=420.0, df_hz=5.0)
    return level_dataset(model, trace_level(model, pa_over_q=0.65, settings=st), st.to_dict())


@pytest.fixture(scope="module")
def rocking_level():
    """The rocking unit (e = 0) at 0.65 Q, 300–420 Hz, 20 Hz, one search, as a dataset."""
    model = ContactModel()
    system = rocking_system(model)
    st = SystemSweepSettings(300.0, 420.0, 20.0, search_every=4, n_starts=4)
    level = sweep_system_level(system, 0.65 * model.Q, st)
    desc = system_description(system, "rocking", "rocking", model)
    return model, system, system_level_dataset(system, level, st, {**desc, "level": 0.65})


def _matches(fe, k, app, ref):
    """Whether (f_e, period, A_pp) is a periodic point of the 1-DOF dataset ``ref`` (A_pp to APP_RTOL)."""
    sel = (np.abs(ref["fe_hz"].values - fe) < 1e-9) & (ref["period"].values == k) & (ref["kind"].values == "periodic")
    return bool(np.any(np.abs(ref["app_um"].values[sel] - app) <= APP_RTOL * app))


def test_single_dof_system_sweep_finds_the_tracers_attractors(one_dof_level):
    """(a) The n = 1 system swept on the 1-DOF grid: every stored attractor is one of the 1-DOF
    tracer's at that grid point (period, A_pp to 1e-6), and its laboratory sweeps reach the
    tracer's sweep branch at every grid point."""
    model = ContactModel()
    level = sweep_system_level(System.single_dof(model), 0.65 * model.Q,
                               SystemSweepSettings(300.0, 420.0, 5.0, search_every=8, n_starts=6))
    assert len(level.rows) >= level.f_hz.size
    for r in level.rows:
        fe, k, app = level.f_hz[r["i"]], r["k"], float(r["columns"]["dof_app"][0])
        assert _matches(fe, k, app, one_dof_level), (fe, k, app)
    swept = {r["i"] for r in level.rows if r["found_by"] == "sweep"}
    assert swept == set(range(level.f_hz.size))


def test_rocking_unit_symmetric_orbits_are_the_paper_models(rocking_level, one_dof_level):
    """(b) With e = 0 the rocking unit's orbits without pitch (θ_pp < 1e-6 µrad) have the heave
    of the 1-DOF paper model's attractors (period, A_pp to 1e-6) at the same grid points."""
    _model, _system, ds = rocking_level
    theta = ds["dof_app"].values[:, 1]
    symmetric = np.flatnonzero(theta < 1e-6)
    assert symmetric.size >= 5
    for p in symmetric:
        assert _matches(float(ds["fe_hz"][p]), int(ds["period"][p]), float(ds["dof_app"][p, 0]), one_dof_level)


def test_every_stored_point_is_a_fixed_point_with_the_static_mean_force(rocking_level):
    """(c) Each stored orbit point (state_q, state_qdot) is a fixed point of P^k (relative
    1e-7 in its own scale), its stored multipliers are the period map's (|μ|max to 1e-6), and
    its mean contact forces sum to the static load Q (the period average of M ÿ = Q + P − ΣF_i,
    to 1e-8 relative)."""
    model, system, ds = rocking_level
    q = ds["state_q"].values * 1e-6   # µm, µrad -> m, rad
    v = ds["state_qdot"].values * 1e-3  # mm/s, mrad/s -> m/s, rad/s
    for p in range(ds.sizes["point"]):
        z = np.concatenate([q[p], v[p]])
        pm = period_map(system, float(ds["pa_newton"][p]), float(ds["fe_hz"][p]), z, int(ds["period"][p]))
        scale = np.abs(z) + np.concatenate([system.scales.length, system.scales.length * system.scales.omega])
        assert np.max(np.abs(pm.z - z) / scale) < 1e-7
        mu = np.abs(np.linalg.eigvals(pm.monodromy)).max()
        assert mu == pytest.approx(float(ds["floquet_abs_max"][p]), rel=1e-6)
        forces = ds["contact_mean_force_n"].values[p]
        assert forces.sum() == pytest.approx(model.Q, rel=1e-8)


def test_system_dataset_opens_with_the_readers(rocking_level, tmp_path):
    """The readers open the system dataset: query's attractors carry dofs and contacts, map
    counts the attractors per grid point."""
    from contactvib.sweeps.dataset import write_atomic
    from contactvib.sweeps.regimes import regime_maps
    from contactvib.sweeps.stored import open_resonance

    _model, _system, ds = rocking_level
    write_atomic(ds, tmp_path / "resonance.nc")
    with open_resonance(tmp_path) as data:
        assert data.levels == (0.65,)
        res = data.attractors_at(0.65, 340.0)
        assert res["fe_hz"] == 340.0 and res["attractors"]
        assert [d["name"] for d in res["attractors"][0]["dofs"]] == ["y", "theta"]
        maps = regime_maps(data.ds)
    n = maps["n_attractors"].values[0]
    assert n.sum() == ds.sizes["point"] and "max_order" not in maps


def test_atlas_local_pool_and_dask_give_identical_datasets(tmp_path):
    """(d) Two levels of the rocking unit on the local pool and on a Dask LocalCluster: the same
    dataset (about 15 s)."""
    model = ContactModel()
    system = rocking_system(model)
    st = SystemSweepSettings(850.0, 1000.0, 50.0, search_every=3, n_starts=3)
    desc = system_description(system, "rocking", "rocking", model)
    from contactvib.sweeps.backends import DaskBackend, LocalPool

    a = system_resonance_dataset(system, levels=[0.4, 0.8], settings=st, desc=desc, out=tmp_path / "local",
                                 backend=LocalPool(2), progress=False, compress=True)
    b = system_resonance_dataset(system, levels=[0.4, 0.8], settings=st, desc=desc, out=tmp_path / "dask",
                                 backend=DaskBackend(n_workers=2), progress=False, compress=True)
    assert a.identical(b)
    assert json.loads(a.attrs["levels"]) == [0.4, 0.8]


@pytest.mark.parametrize("argv, start", [
    (["resonance", "--system", "rocking", "--plot", "q2"], "contactvib: error: --plot q2: not a coordinate"),
    (["resonance", "--system", str(EXAMPLE), "--pa", "0.5"], "contactvib: error: --system"),
    (["resonance", "--system", "rocking", "--fmin", "500", "--fmax", "400"], "contactvib: error: --fmax"),
    (["resonance", "--system", "rocking", "--fmin", "500", "--fmax", "600", "--df", "200"],
     "contactvib: error: --df"),
    (["atlas", "--system", "rocking", "--pa-min", "0.8", "--pa-max", "0.3", "--npa", "2"],
     "contactvib: error: --pa-min"),
    (["resonance", "--plot", "y"], "contactvib: error: --plot: an option of --system only"),
])
def test_bad_system_sweep_input_is_one_line(argv, start, capsys, tmp_path):
    """(e) Bad input: one stderr line, exit 2, nothing computed."""
    rc = main(argv + ["--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith(start) and err.count("\n") == 1, err
    assert not (tmp_path / "out" / "resonance.nc").exists()


def test_resonance_system_command_writes_dataset_and_figure(tmp_path, capsys):
    """``contactvib resonance --system rocking`` on a short grid: resonance.nc and the figure."""
    out = tmp_path / "out"
    rc = main(["resonance", "--system", "rocking", "--pa", "0.65", "--fmin", "300", "--fmax", "360", "--df", "30",
               "--starts", "2", "--plot", "theta", "--measure", "h1", "--no-progress", "--out", str(out)])
    assert rc in (0, None)
    assert (out / "resonance.nc").is_file() and (out / "resonance_0.65Q_theta_h1.png").is_file()
    rc = main(["query", str(out), "--pa", "0.65", "--fe", "330"])
    text = capsys.readouterr().out
    assert rc in (0, None) and "theta A_pp [urad]" in text


def test_resume_reuses_a_finished_level_and_refuses_other_settings(tmp_path):
    """``resume``: a finished chunk of the same system and settings is read back, not recomputed;
    one made with other settings is refused (ParameterError ``resume``) before anything runs."""
    from contactvib.model import ParameterError
    from contactvib.sweeps.backends import LocalPool

    model = ContactModel()
    system = rocking_system(model)
    desc = system_description(system, "rocking", "rocking", model)
    st = SystemSweepSettings(300.0, 400.0, 50.0, search_every=0)
    first = system_resonance_dataset(system, levels=[0.5], settings=st, desc=desc, out=tmp_path, backend=LocalPool(1),
                                     progress=False)
    chunk = next((tmp_path / ".chunks").glob("level_*.nc"))
    stamp = chunk.stat().st_mtime_ns
    again = system_resonance_dataset(system, levels=[0.5], settings=st, desc=desc, out=tmp_path, resume=True,
                                     backend=LocalPool(1), progress=False)
    assert chunk.stat().st_mtime_ns == stamp and again.identical(first)
    with pytest.raises(ParameterError, match="resume"):
        system_resonance_dataset(system, levels=[0.5], settings=SystemSweepSettings(300.0, 400.0, 25.0), desc=desc,
                                 out=tmp_path, resume=True, backend=LocalPool(1), progress=False)


def test_levels_in_newton_without_a_q(tmp_path):
    """A system without a Q (as a TOML file's): the levels are P_a [N] in ``pa_newton``, no
    ``pa_over_q`` is written, and the readers find the level in N."""
    from contactvib.sweeps.regimes import regime_maps
    from contactvib.sweeps.stored import open_resonance

    model = ContactModel()
    system = System.single_dof(model)
    desc = system_description(system, "slider.toml", "[system]  # the slider", None)
    st = SystemSweepSettings(340.0, 380.0, 20.0, search_every=0)
    pa = round(0.65 * model.Q, 6)
    ds = system_resonance_dataset(system, levels=[pa], settings=st, desc=desc, out=tmp_path, progress=False)
    assert "pa_over_q" not in ds and ds.attrs["level_variable"] == "pa_newton"
    with open_resonance(tmp_path) as data:
        assert data.levels == (pa,) and data.level_unit == "N"
        res = data.attractors_at(pa, 360.0)
        assert res["level_unit"] == "N" and res["attractors"][0]["dofs"][0]["name"] == "y"
        assert regime_maps(data.ds)["n_attractors"].values.sum() == ds.sizes["point"]
