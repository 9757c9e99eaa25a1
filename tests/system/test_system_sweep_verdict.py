"""The non-periodic attractors of a System's resonance sweep (``contactvib.sweeps.system_sweep``
with ``nonperiodic``): the verdict of the attractor search (``steady.system_verdict``) on the grid
points and search starts that settle on no period ≤ kmax, stored in the system dataset as the
1-DOF dataset stores them.

References and tolerances (``examples/two_dof_stop.toml`` at P_a = 0.1 N, 0.095–0.096 Hz):

* every chaotic point has λ1 > 3 standard errors, and its four exponents sum to the damping
  average −⟨tr M⁻¹C(t)⟩ = −tr(M⁻¹C) = −0.09 1/s (the stop is undamped; the trace taken from the
  system file's matrices) to 1e-9; at 0.0955 Hz λ1 is the long Benettin run's +0.0114 ± 0.0003
  1/s (``tests/system/test_system_verdict.py``) within 4 of its standard errors + 3e-4;
* the orbit of period 10 > kmax at 0.095 Hz is a fixed point of P^10 (relative 1e-7), stable;
* the periodic points, branches, strobe points and traces of the sweep without the verdict are
  the first rows of the sweep with it, bit for bit;
* ``query`` and ``map`` report the chaotic points; the resonance graph draws them as red dots.

About 15 s for the two sweeps.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from contactvib.cli import main
from contactvib.model import ParameterError
from contactvib.model.system_file import load_system
from contactvib.steady.lyapunov import SIGMA_FACTOR
from contactvib.steady.system_orbits import period_map
from contactvib.sweeps.system_dataset import system_level_dataset
from contactvib.sweeps.system_resonance import system_description
from contactvib.sweeps.system_sweep import SystemSweepSettings, sweep_system_level

STOP = Path(__file__).resolve().parents[2] / "examples" / "two_dof_stop.toml"
PA = 0.1
#: λ1 [1/s] at 0.0955 Hz from the long Benettin run of the lyapunov tests, and its error.
LAMBDA1_0955, LAMBDA1_0955_ERR = 0.0114, 0.0003


def _dataset(system, nonperiodic: bool):
    st = SystemSweepSettings(0.095, 0.096, 0.0005, search_every=2, n_starts=2, nonperiodic=nonperiodic)
    level = sweep_system_level(system, PA, st)
    desc = system_description(system, STOP.name, STOP.read_text())
    return system_level_dataset(system, level, st, {**desc, "level": PA})


@pytest.fixture(scope="module")
def sweeps():
    """The sweep without the verdict and with it, as datasets."""
    system = load_system(STOP)
    return system, _dataset(system, False), _dataset(system, True)


def test_the_chaotic_points_have_a_positive_lambda1_and_the_damping_sum(sweeps):
    system, _off, ds = sweeps
    chaotic = np.flatnonzero(ds["attractor_type"].values == "chaotic")
    assert chaotic.size >= 2  # 0.0955 and 0.096 Hz at least
    assert ds.sizes["exponent"] == 4 and ds["lyapunov_per_s"].attrs["units"] == "1/s"
    lam, se = ds["lyapunov_per_s"].values, ds["lyapunov_stderr_per_s"].values
    damping = -np.trace(np.linalg.inv(np.array(system.M, float)) @ np.array(system.C, float))
    assert damping == pytest.approx(-0.09, abs=1e-12)
    for p in chaotic:
        assert ds["kind"].values[p] == "non-periodic" and ds["period"].values[p] == 0
        assert ds["true_period"].values[p] == 0 and ds["minima_per_period"].values[p] == -1
        assert lam[p, 0] > SIGMA_FACTOR * se[p, 0]
        assert np.all(np.diff(lam[p]) <= 0.0)
        assert float(np.sum(lam[p])) == pytest.approx(damping, abs=1e-9)
        assert 2.0 < float(ds["kaplan_yorke_dimension"].values[p]) < 3.0
        assert np.isnan(ds["floquet_abs_max"].values[p]) and np.isnan(ds["closure"].values[p])
        assert ds["strobe_count"].values[p] == 128  # the verdict's last 2 WINDOW strobe points
        assert ds["dof_app"].values[p, 0] > 1e6  # q1 beyond the stop at 1 m, in µm
    at = chaotic[np.abs(ds["fe_hz"].values[chaotic] - 0.0955) < 1e-9]
    assert at.size == 1
    p = int(at[0])
    assert abs(lam[p, 0] - LAMBDA1_0955) <= 4.0 * se[p, 0] + LAMBDA1_0955_ERR


def test_a_period_above_kmax_is_stored_periodic_with_its_true_period(sweeps):
    system, _off, ds = sweeps
    ten = np.flatnonzero(ds["period"].values == 10)
    assert ten.size == 1
    p = int(ten[0])
    assert ds["true_period"].values[p] == 10 and ds["attractor_type"].values[p] == "periodic"
    assert abs(float(ds["fe_hz"].values[p]) - 0.095) < 1e-9 and float(ds["floquet_abs_max"].values[p]) < 1.0
    z = np.concatenate([ds["state_q"].values[p] * 1e-6, ds["state_qdot"].values[p] * 1e-3])  # µm, mm/s -> SI
    pm = period_map(system, PA, 0.095, z, 10)
    scale = np.abs(z) + np.concatenate([system.scales.length, system.scales.length * system.scales.omega])
    assert np.max(np.abs(pm.z - z) / scale) < 1e-7
    # its exponents are ln|μ| f_e / k of its multipliers, descending, with zero errors
    mu = ds["floquet_re"].values[p] + 1j * ds["floquet_im"].values[p]
    ref = np.sort(np.log(np.abs(mu)) * 0.095 / 10)[::-1]
    assert np.array_equal(ds["lyapunov_per_s"].values[p], ref) and not ds["lyapunov_stderr_per_s"].values[p].any()


def test_the_periodic_points_are_those_without_the_verdict(sweeps):
    _system, off, ds = sweeps
    assert off.sizes["point"] >= 2 and ds.sizes["point"] > off.sizes["point"]
    assert set(off["attractor_type"].values) == {"periodic"}
    first = {dim: slice(0, off.sizes[dim]) for dim in ("point", "strobe", "branch")}
    for name in off.variables:
        a = off[name]
        b = ds[name].isel({d: first[d] for d in ds[name].dims if d in first})
        assert a.dims == b.dims and a.shape == b.shape, name
        if a.dtype.kind in "fc":
            assert np.array_equal(a.values, b.values, equal_nan=True), name
        else:
            assert np.array_equal(a.values, b.values), name
    # the verdict's rows come after, none of them periodic with a period <= kmax
    rest = ds["period"].values[off.sizes["point"]:]
    assert np.all((rest == 0) | (rest > 8))
    assert json.loads(ds.attrs["settings"])["nonperiodic"] is True


def test_query_map_and_the_graph_report_them(sweeps, tmp_path, capsys):
    from contactvib.plotting.system import system_resonance_figure
    from contactvib.sweeps.dataset import write_atomic
    from contactvib.sweeps.regimes import regime_maps
    from contactvib.sweeps.stored import open_resonance

    _system, _off, ds = sweeps
    write_atomic(ds, tmp_path / "resonance.nc")
    with open_resonance(tmp_path) as data:
        res = data.attractors_at(PA, 0.0955)
        maps = regime_maps(data.ds)
    chaos = [a for a in res["attractors"] if a["attractor_type"] == "chaotic"]
    assert len(chaos) == 1
    a = chaos[0]
    assert a["period"] is None and a["floquet_multipliers"] is None and len(a["lyapunov_per_s"]) == 4
    assert a["lyapunov_per_s"][0] > SIGMA_FACTOR * a["lyapunov_stderr_per_s"][0]
    assert 2.0 < a["kaplan_yorke_dimension"] < 3.0 and len(a["strobe_points"]) == 128
    assert [d["name"] for d in a["dofs"]] == ["q1", "q2"]
    chaotic_fe = np.unique(ds["fe_hz"].values[ds["attractor_type"].values == "chaotic"])
    row = maps["chaotic"].values[0]
    grid = maps["fe_hz"].values
    assert np.array_equal(grid[row == 1], chaotic_fe)
    assert maps["n_attractors"].values.sum() == ds.sizes["point"]
    p = int(np.flatnonzero(ds["attractor_type"].values == "chaotic")[0])
    cell = int(np.argmin(np.abs(grid - ds["fe_hz"].values[p])))
    assert maps["max_lambda1"].values[0, cell] >= ds["lyapunov_per_s"].values[p, 0] / ds["fe_hz"].values[p] > 0.0

    rc = main(["query", str(tmp_path), "--pa", str(PA), "--fe", "0.0955"])
    text = capsys.readouterr().out
    assert rc in (0, None) and "chaotic" in text and "lambda1 [1/s]" in text

    fig = system_resonance_figure(ds, [0, 1], "app", "two_dof_stop")
    dots = [ln for ln in fig.axes[0].lines if ln.get_marker() == "." and ln.get_color() == "tab:red"]
    assert len(dots) == 1 and np.array_equal(np.sort(dots[0].get_xdata()),
                                             np.sort(ds["fe_hz"].values[ds["attractor_type"].values == "chaotic"]))
    assert dots[0].get_label() == "chaotic"


def test_a_search_stores_the_chaotic_attractor_its_verdict_finds():
    """At 0.0965 Hz the sweeps' verdict leaves the motion unsettled; the search (2 starts) lands on
    the chaotic attractor: stored once, with its basin and the search's spectrum and measures; at
    0.097 Hz the search's cloud is the sweep's and is not stored twice."""
    from contactvib.steady.system_attractors import find_system_attractors

    system = load_system(STOP)
    level = sweep_system_level(system, PA, SystemSweepSettings(0.0965, 0.097, 0.0005, search_every=1, n_starts=2))
    rows = [(round(float(level.f_hz[r["i"]]), 6), r["type"], r["found_by"]) for r in level.rows]
    assert sorted(rows) == [(0.0965, "chaotic", "multi-start"), (0.097, "chaotic", "sweep")]
    row = next(r for r in level.rows if r["found_by"] == "multi-start")
    ref = find_system_attractors(system, PA, 0.0965, n_starts=2, seed=0, kmax=8, max_periods=2000, seeds=False)
    a = next(a for a in ref if a.attractor_type == "chaotic")
    assert row["basin"] == a.basin_fraction == 1.0 and row["origin"] == "start" and row["k"] == 0
    assert np.array_equal(row["lyap"], a.lyapunov_per_s) and np.array_equal(row["strobe"], a.strobe)
    assert np.array_equal(row["columns"]["dof_app"], a.columns["dof_app"])
    assert float(np.sum(row["lyap"])) == pytest.approx(-0.09, abs=1e-9)


def test_the_command_counts_them_and_draws_the_graph(tmp_path, capsys):
    """``resonance --system FILE --pa-newton 0.1`` over 0.0955–0.096 Hz: the summary line counts
    the non-periodic points; the dataset and the graph are written."""
    out = tmp_path / "out"
    rc = main(["resonance", "--system", str(STOP), "--pa-newton", "0.1", "--fmin", "0.0955", "--fmax", "0.096",
               "--df", "0.0005", "--starts", "1", "--no-progress", "--out", str(out)])
    text = capsys.readouterr().out
    assert rc in (0, None) and "non-periodic)" in text, text
    assert (out / "resonance_0.1N_q1_q2_app.png").is_file()
    import xarray as xr

    with xr.open_dataset(out / "resonance.nc") as ds:
        n = int((ds["period"].values == 0).sum())
        assert n >= 1 and f"({n} non-periodic)" in text and ds.sizes["exponent"] == 4


def test_the_setting_is_a_bool():
    with pytest.raises(ParameterError, match="nonperiodic"):
        SystemSweepSettings(1.0, 2.0, 0.5, nonperiodic="yes")
