"""Basins of a system on a 2-D slice of its state space (``steady.system_basins``) and
``contactvib basins --system``.

On the 2-DOF file system at P_a = 0.1 N, f_e = 0.0935 Hz (between its two Neimark–Sacker points,
where locking gives a period-7 and a period-6 orbit) the grid reaches both orbits. The label of
a grid start is checked by scipy (``scipy_system``: solve_ivp DOP853 with located events, rtol
1e-10): integrated from the same start over 200 periods, its stroboscopic
point lies on the labelled orbit, within 1e-3 of the orbit's size and nearer to it than to the
other orbit."""

import json
from pathlib import Path

import numpy as np
import pytest
from scipy_system import integrate_system

from contactvib.cli import main
from contactvib.model import ContactModel, ParameterError
from contactvib.model.rocking import rocking_system
from contactvib.model.system_file import load_system
from contactvib.steady.system_basins import default_slice, state_component, system_basins

EXAMPLE = Path(__file__).parents[2] / "examples" / "two_dof_stop.toml"
PA, FE = 0.1, 0.0935
#: Periods scipy integrates from a grid start (its stroboscopic point is then within 1e-4 of the
#: orbit: measured 7e-6..6e-5; the search's transient limit is 400).
SCIPY_PERIODS = 200


@pytest.fixture(scope="module")
def two_orbits():
    s = load_system(EXAMPLE)
    return s, system_basins(s, PA, FE, grid=(8, 8), n_starts=32)


def _deepest(labels: np.ndarray, label: int) -> tuple[int, int]:
    """The grid cell of ``label`` with the most 4-neighbours of the same label (farthest from the
    basin boundaries that a start on them may cross either way)."""
    padded = np.pad(labels, 1, constant_values=-2)
    same = sum((np.roll(padded, s, axis=ax) == label) for s in (1, -1) for ax in (0, 1))[1:-1, 1:-1]
    score = np.where(labels == label, same, -1)
    return np.unravel_index(int(np.argmax(score)), labels.shape)


def test_both_orbits_are_reached_and_scipy_confirms_the_labels(two_orbits):
    s, m = two_orbits
    assert m.axes == ("q1", "q1_dot") and m.units == ("um", "mm/s")
    assert sorted(a.period for a in m.attractors) == [6, 7]
    assert all(a.stable for a in m.attractors)
    fr = m.fractions()
    assert sum(r["fraction"] for r in fr) == pytest.approx(1.0)
    assert all(np.count_nonzero(m.labels == k) > 0 for k in range(len(m.attractors)))
    checked = 0
    for label in range(len(m.attractors)):
        for i, j in [_deepest(m.labels, label)]:
            z0 = m.base_state.copy()
            z0[m.indices[0]] = m.a[j] / m.factors[0]
            z0[m.indices[1]] = m.b[i] / m.factors[1]
            z, _, _ = integrate_system(s, PA, FE, z0, SCIPY_PERIODS / FE, rtol=1e-10, liouville=False)
            d = []
            for a in m.attractors:
                size = np.max(np.abs(a.strobe), axis=0)
                d.append(np.min(np.max(np.abs(a.strobe - z) / size, axis=1)))
            assert int(np.argmin(d)) == label and d[label] < 1e-3, (label, d)
            checked += 1
    assert checked == 2


def test_default_slice_and_components():
    s = load_system(EXAMPLE)
    assert default_slice(s) == ("q1", "q1_dot")
    assert state_component(s, "q2") == (1, "um", 1e6)
    assert state_component(s, "q1_dot") == (2, "mm/s", 1e3)
    r = rocking_system(ContactModel())
    assert state_component(r, "theta") == (1, "urad", 1e6)
    assert state_component(r, "theta_dot") == (3, "mrad/s", 1e3)


@pytest.mark.parametrize("kw, symbol", [({"axes": ("q1", "q9")}, "slice"), ({"axes": ("q1", "q1")}, "slice"),
                                         ({"axes": ("q1",)}, "slice"), ({"grid": (1, 5)}, "n_a"),
                                         ({"box": ((1.0, 0.0), (0.0, 1.0))}, "a_max"),
                                         ({"base_state": [0.0, 0.0]}, "base_state"), ({"kmax": 0}, "kmax")])
def test_bad_input_is_refused_before_any_computation(kw, symbol):
    with pytest.raises(ParameterError) as e:
        system_basins(load_system(EXAMPLE), PA, FE, **kw)
    assert e.value.symbol == symbol


def test_cli_json_and_files(tmp_path, capsys):
    out = tmp_path / "b"
    rc = main(["basins", "--system", str(EXAMPLE), "--pa-newton", "0.1", "--fe", "0.0982",
                                  "--grid", "4x3", "--starts", "8", "--slice", "q2,q2_dot", "--a-range", "-1e6",
                                  "1e6", "--out", str(out), "--json"])
    text = capsys.readouterr().out
    assert rc == 0, text
    d = json.loads(text)
    assert d["slice"] == ["q2", "q2_dot"] and d["slice_units"] == ["um", "mm/s"] and d["grid"] == [4, 3]
    assert d["range_a"] == [-1e6, 1e6]
    assert sum(f["fraction"] for f in d["fractions"]) == pytest.approx(1.0)
    assert [a["period"] for a in d["attractors"]] == [4]
    assert (out / "system_basins.nc").exists() and list(out.glob("system_basins_*.png"))
    import xarray as xr

    with xr.open_dataset(out / "system_basins.nc") as ds:
        assert ds["label"].shape == (3, 4) and ds["a"].attrs["units"] == "um" and ds["b"].attrs["units"] == "mm/s"


@pytest.mark.parametrize("args, text", [
    (["--slice", "q1,q9"], "--slice (slice) = q9: must name a state component"),
    (["--slice", "q1,q1"], "must name two different state components"),
    (["--a-range", "1", "0"], "--a-range (a_max) = 0: must be >"),
    (["--grid", "1x4"], "--grid (n_a) = 1"),
    (["--y-range", "0", "1"], "--system and --y-range"),
    (["--pa", "0.5"], "defines no Q"),
    (["--through", "1,2", "0"], "--through 0: expected 2 rates"),
    (["--through", "1,x", "0,0"], "--through"),
])
def test_cli_bad_input_one_line(args, text, capsys, tmp_path):
    level = ["--pa-newton", "0.1"] if "--pa" not in args else []
    rc = main(["basins", "--system", str(EXAMPLE), *level, "--fe", "0.0982", *args, "--out", str(tmp_path / "b")])
    line = capsys.readouterr().err.strip()
    assert rc == 2, line
    assert text in line and "\n" not in line and len(line) <= 400


def test_cli_slice_belongs_to_systems(capsys):
    rc = main(["basins", "--pa", "0.65", "--fe", "700", "--slice", "y,theta"])
    assert rc == 2 and "--slice belongs to --system" in capsys.readouterr().err


def test_the_torus_basin_is_labelled_by_the_search_s_cloud():
    """The self-excited stop system forced off its limit cycle (examples/self_excited_stop.toml,
    0.05 N, 0.12 Hz) has one attractor, a 2-torus: every grid start lands on its cloud."""
    s = load_system(Path(__file__).parents[2] / "examples" / "self_excited_stop.toml")
    m = system_basins(s, 0.05, 0.12, grid=(3, 3), n_starts=4)
    assert [a.attractor_type for a in m.attractors] == ["quasi-periodic"]
    assert m.fractions()[0] == {"label": 0, "period": None, "minima_per_period": None,
                                "attractor_type": "quasi-periodic", "fraction": 1.0, "stderr": 0.0}
    ds = m.to_dataset()
    assert ds["attractor_type"].values.tolist() == ["quasi-periodic"] and int(ds["period"][0]) == 0


def test_a_slice_through_a_state_of_the_attractor(capsys, tmp_path):
    """At 0.0982 Hz the file system has one attractor (period 4); a slice in (q2, q2_dot) through
    one of its stroboscopic points holds that point's q1, q1_dot, and every start reaches it."""
    s = load_system(EXAMPLE)
    first = system_basins(s, PA, 0.0982, grid=(2, 2), n_starts=4)
    z = first.attractors[0].strobe[0]
    m = system_basins(s, PA, 0.0982, axes=("q2", "q2_dot"), grid=(3, 2), n_starts=4, base_state=z)
    assert m.base_given and not first.base_given and np.array_equal(m.base_state, z)
    assert (m.labels == 0).all() and m.attractors[0].period == 4
    through = [f"{float(z[0]) * 1e6!r},{float(z[1]) * 1e6!r}", f"{float(z[2]) * 1e3!r},{float(z[3]) * 1e3!r}"]
    rc = main(["basins", "--system", str(EXAMPLE), "--pa-newton", "0.1", "--fe", "0.0982", "--slice", "q2,q2_dot",
               "--grid", "3x2", "--starts", "4", "--through", *through, "--out", str(tmp_path / "t"), "--json"])
    d = json.loads(capsys.readouterr().out)
    assert rc == 0 and np.allclose(d["base_state_si"][:1], z[:1], rtol=1e-12)
