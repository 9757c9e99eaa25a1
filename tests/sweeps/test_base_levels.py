"""Resonance sweeps at a constant base-motion level (``SweepSettings(excitation="base-um")``,
``contactvib resonance --excitation base-um``): the level is the base displacement U [µm] and the
inertial force M U (2π f_e)² grows along the grid.

References: the equivalent force of every point against its closed form (rel 1e-12); every
periodic point of the dataset integrated again by scipy's DOP853 (rtol 1e-12, located contact
events, the base motion's inertial force written in the helper) — closure after k periods (rel
1e-7 of the state scale, the sweep's own tolerance is 1e-10 on the shooting) and A_pp (rel 1e-6).
"""

import contextlib
import io
import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from contactvib import ContactModel, Excitation
from contactvib.cli import main
from contactvib.model import ParameterError, level_text
from contactvib.sweeps.resonance import ResumeMismatch, resonance_dataset
from contactvib.sweeps.sweep import SweepSettings
from contactvib.testing import integrate_contact, model_ode

PAPER = ContactModel()
U_UM = 0.05
GRID = dict(fmin_hz=600.0, fmax_hz=2000.0, df_hz=20.0, multistart_per_octave=2.0, n_starts=8)


@pytest.fixture(scope="module")
def base_sweep():
    return resonance_dataset(PAPER, levels=[U_UM], settings=SweepSettings(**GRID, excitation="base-um"), workers=1,
                             progress=False)


def test_dataset_says_its_level_is_u(base_sweep):
    ds = base_sweep
    assert ds.attrs["excitation"] == "base-um"
    assert (ds.attrs["level_symbol"], ds.attrs["level_unit"]) == ("U", "um")
    assert ds["pa_over_q"].attrs["units"] == "um"
    assert ds["branch_pa_over_q"].attrs["units"] == "um"
    assert np.all(ds["pa_over_q"].values == U_UM)
    assert json.loads(ds.attrs["settings"])["excitation"] == "base-um"
    f = ds["fe_hz"].values
    expected = PAPER.M * U_UM * 1e-6 * (2.0 * math.pi * f) ** 2 / PAPER.Q
    np.testing.assert_allclose(ds["force_pa_over_q"].values, expected, rtol=1e-12)


def test_force_sweep_record_is_unchanged():
    """A force sweep's settings record has no ``excitation`` key (paper.nc as it always was)."""
    assert "excitation" not in SweepSettings().to_dict()
    assert SweepSettings(excitation="base-g").to_dict()["excitation"] == "base-g"
    with pytest.raises(ParameterError, match="excitation"):
        SweepSettings(excitation="random")


def test_points_close_under_the_scipy_reference(base_sweep):
    ds = base_sweep
    periodic = np.flatnonzero(ds["period"].values > 0)
    loses = periodic[ds["loses_contact"].values[periodic] == 1]
    stays = periodic[ds["loses_contact"].values[periodic] == 0]
    assert loses.size and stays.size
    picks = np.concatenate([loses[:: max(1, loses.size // 6)], stays[:: max(1, stays.size // 6)]])
    sy, sv = PAPER.y0, PAPER.y0 * PAPER.omega_n0
    for j in picks:
        f, k = float(ds["fe_hz"][j]), int(ds["period"][j])
        exc = Excitation.base(PAPER, f, u_um=U_UM)
        y = float(ds["state_y_um"][j]) * 1e-6
        v = float(ds["state_ydot_mm_s"][j]) * 1e-3
        tr = integrate_contact(model_ode(PAPER, exc), y, v, 0.0, k / f, rtol=1e-12, y_scale=sy, v_scale=sv)
        scale = max(1.0, abs(y) / sy, abs(v) / sv)
        assert max(abs(tr.y - y) / sy, abs(tr.ydot - v) / sv) <= 1e-7 * scale, (f, k)
        assert float(ds["app_um"][j]) == pytest.approx((tr.ymax - tr.ymin) * 1e6, rel=1e-6), (f, k)
        assert bool(ds["loses_contact"][j]) == (tr.ymin < 0.0)


def test_resume_refuses_a_force_chunk(tmp_path):
    small = dict(GRID, fmin_hz=1000.0, fmax_hz=1200.0, multistart_per_octave=0.0)
    resonance_dataset(PAPER, levels=[U_UM], settings=SweepSettings(**small), out=tmp_path, workers=1, progress=False)
    with pytest.raises(ResumeMismatch, match="excitation"):
        resonance_dataset(PAPER, levels=[U_UM], settings=SweepSettings(**small, excitation="base-um"), out=tmp_path,
                          resume=True, workers=1, progress=False)


def test_too_strong_base_level_is_refused_before_computing():
    with pytest.raises(ParameterError, match="U"):
        resonance_dataset(PAPER, levels=[200.0], settings=SweepSettings(**GRID, excitation="base-um"), workers=1,
                          progress=False)


def test_level_text():
    assert level_text(0.65) == "P_a = 0.65 Q"
    assert level_text(0.05, "base-um") == "U = 0.05 µm"
    assert level_text(0.3, "base-g") == "A = 0.3 g"


def _cli(*args):
    """``contactvib ARGS`` in this process: its exit code, standard output and standard error."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(list(args))
    return SimpleNamespace(returncode=rc, stdout=out.getvalue(), stderr=err.getvalue())


@pytest.mark.parametrize("args, needle", [
    (["resonance", "--excitation", "base-um", "--pa", "200", "--out", "{tmp}"], "--pa (U) = 200"),
    (["resonance", "--excitation", "base-um", "--pa", "-1", "--out", "{tmp}"], "--pa (U) = -1"),
    (["resonance", "--excitation", "sine", "--out", "{tmp}"], "--excitation"),
    (["paper", "--excitation", "base-g", "--out", "{tmp}"], "--excitation base-g"),
    (["atlas", "--excitation", "base-um", "--pa-min", "0.1", "--pa-max", "300", "--npa", "2", "--out", "{tmp}"],
     "--pa-max (U) = 300"),
])
def test_cli_refuses_bad_base_levels(tmp_path, args, needle):
    r = _cli(*[a.replace("{tmp}", str(tmp_path / "o")) for a in args])
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], r.stderr
    assert not (tmp_path / "o" / "resonance.nc").exists()


def test_cli_base_sweep_writes_its_figures(tmp_path):
    out = tmp_path / "rb"
    r = _cli("resonance", "--excitation", "base-um", "--pa", "0.05", "--fmin", "1000", "--fmax", "1300",
             "--df", "20", "--multistart-per-octave", "0", "--out", str(out), "--no-progress")
    assert r.returncode == 0, r.stderr
    assert (out / "resonance_U0.05um.png").is_file() and (out / "extrema_U0.05um.png").is_file()


# ---------------------------------------------------------------------------------------------
# Continuation in f_e at a constant base displacement U

@pytest.fixture(scope="module")
def base_branches():
    from contactvib.continuation.diagram import continue_attractors
    from contactvib.continuation.shooting import ContinuationSettings

    s = ContinuationSettings(fmin_hz=900.0, fmax_hz=1600.0, excitation="base-um", max_points=300)
    return continue_attractors(PAPER, pa_over_q=U_UM, fe_hz=1200.0, attractor=None, settings=s)


def test_branch_points_close_under_the_scipy_reference(base_branches):
    """Every 6th point of each branch (stable or not) is a period-k orbit of the base-excited
    oscillator: scipy closure after k periods (rel 1e-8 of the state scale; continuation rtol
    1e-12, Newton tol 1e-10)."""
    sy, sv = PAPER.y0, PAPER.y0 * PAPER.omega_n0
    assert len(base_branches) >= 3
    for b in base_branches:
        assert np.all(b.pa_over_q == U_UM)
        for j in range(0, len(b), 6):
            f, k = float(b.fe_hz[j]), int(b.period)
            x, xd = b.state[j]
            y, v = x * sy, xd * sv
            exc = Excitation.base(PAPER, f, u_um=U_UM)
            tr = integrate_contact(model_ode(PAPER, exc), y, v, 0.0, k / f, rtol=1e-12, y_scale=sy, v_scale=sv)
            scale = max(1.0, abs(x), abs(xd))
            assert max(abs(tr.y - y) / sy, abs(tr.ydot - v) / sv) <= 1e-8 * scale, (b.branch, f)
            assert float(b.app_um[j]) == pytest.approx((tr.ymax - tr.ymin) * 1e6, rel=1e-7)


def test_branches_pass_through_the_sweep(base_branches, base_sweep):
    """The sweep's stable period-1 points lie on the continued period-1 branches (A_pp interpolated
    linearly between the branch's points, which are up to 0.15 in scaled arclength apart: rel 1.5e-2;
    the points themselves are checked against scipy above)."""
    ds = base_sweep
    sel = np.flatnonzero((ds["period"].values == 1) & (ds["fe_hz"].values > 920) & (ds["fe_hz"].values < 1580))
    p1 = [b for b in base_branches if b.period == 1]
    matched = 0
    for j in sel:
        f, app = float(ds["fe_hz"][j]), float(ds["app_um"][j])
        best = np.inf
        for b in p1:
            fe, a = b.fe_hz, b.app_um
            for i in range(len(b) - 1):
                if (fe[i] - f) * (fe[i + 1] - f) <= 0 and fe[i] != fe[i + 1]:
                    t = (f - fe[i]) / (fe[i + 1] - fe[i])
                    best = min(best, abs(a[i] + t * (a[i + 1] - a[i]) - app) / app)
        matched += best < 1.5e-2
    assert matched == sel.size > 10


def test_cli_continuation_refuses_base_in_pa_and_a_force_dataset(tmp_path, base_sweep):
    r = _cli("continue", "--excitation", "base-um", "--pa", "0.05", "--parameter", "pa", "--out", str(tmp_path / "c"))
    assert r.returncode == 2 and "--parameter pa" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    force = resonance_dataset(PAPER, levels=[0.05],
                              settings=SweepSettings(**dict(GRID, fmin_hz=1000.0, fmax_hz=1100.0,
                                                                   multistart_per_octave=0.0)),
                              out=tmp_path / "f", workers=1, progress=False)
    assert force.attrs.get("excitation") is None
    r = _cli("continue", "--excitation", "base-um", "--pa", "0.05", "--dataset", str(tmp_path / "f" / "resonance.nc"),
             "--out", str(tmp_path / "c"))
    assert r.returncode == 2 and "its levels are P_a/Q" in r.stderr, r.stderr


def test_cli_base_atlas_through_query_map_and_animate(tmp_path):
    """An atlas of two U levels: query, map and animate say U [µm], not P_a [Q]."""
    import xarray as xr

    out = tmp_path / "atlas"
    r = _cli("atlas", "--excitation", "base-um", "--pa-min", "0.03", "--pa-max", "0.06", "--npa", "2",
             "--fmin", "1000", "--fmax", "1400", "--df", "20", "--multistart-per-octave", "0",
             "--out", str(out), "--no-progress")
    assert r.returncode == 0, r.stderr
    r = _cli("query", str(out), "--pa", "0.06", "--fe", "1200")
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("U = 0.06 µm, f_e = 1200 Hz")
    r = _cli("query", str(out), "--pa", "0.06", "--fe", "1200", "--json")
    d = json.loads(r.stdout)
    assert (d["excitation"], d["level_symbol"], d["level_unit"]) == ("base-um", "U", "um")
    assert d["force_pa_over_q"] == pytest.approx(PAPER.M * 0.06e-6 * (2 * math.pi * 1200.0) ** 2 / PAPER.Q, rel=1e-12)
    r = _cli("map", str(out), "--out", str(tmp_path / "map"))
    assert r.returncode == 0, r.stderr
    with xr.open_dataset(tmp_path / "map" / "map.nc") as maps:
        assert maps["pa_over_q"].attrs["units"] == "um" and maps.attrs["excitation"] == "base-um"
    r = _cli("map", str(out), "--orders", "2", "--out", str(tmp_path / "map2"))
    assert r.returncode == 2 and "base-motion" in r.stderr
    r = _cli("animate", str(out), "--out", str(tmp_path / "film.gif"), "--gif", "--size", "800x400")
    assert r.returncode == 0, r.stderr
    assert "U = 0.03..0.06 µm" in r.stdout and "P_a" not in r.stdout


# ---------------------------------------------------------------------------------------------
# The slider's absolute motion s = y + u under base motion

@pytest.mark.parametrize("kw", [{"u_um": 0.05}, {"a_g": 0.35}])
def test_slider_absolute_motion_against_scipy(kw):
    """slider_app_um = range of y(t) + u(t) over the orbit, u = U cos(2π f_e t) (U = A g_n/ω² for
    a base acceleration), from the scipy reference sampled at 20,000 points a period (rel 1e-5: the
    package samples 4000 points a period)."""
    from contactvib import attractor_history, find_attractors

    f = 1200.0
    exc = Excitation.base(PAPER, f, **kw)
    U = kw.get("u_um", kw.get("a_g", 0.0) * 9.80665 / (2 * math.pi * f) ** 2 * 1e6)
    assert exc.base_amplitude_um == pytest.approx(U, rel=1e-14)
    res = find_attractors(exc, n_starts=16)
    periodic = [a for a in res if a.period is not None]
    assert len(periodic) >= 2
    sy, sv = PAPER.y0, PAPER.y0 * PAPER.omega_n0
    for a in periodic:
        y, v = a.state[0] * sy, a.state[1] * sv
        tr = integrate_contact(model_ode(PAPER, exc), y, v, 0.0, a.period / f, rtol=1e-12, y_scale=sy, v_scale=sv)
        t = np.linspace(0.0, a.period / f, 20000 * a.period + 1)
        s = tr.sample(t)[0] * 1e6 + U * np.cos(2 * math.pi * f * t)
        assert a.slider_app_um == pytest.approx(s.max() - s.min(), rel=1e-5)
        assert a.to_dict()["slider_app_um"] == a.slider_app_um
        h = attractor_history(exc, a)
        np.testing.assert_allclose(h.slider_um, h.y_um + U * np.cos(2 * math.pi * f * h.t_ms * 1e-3),
                                   rtol=0, atol=1e-12)
    force = find_attractors(PAPER.excitation(0.3, f), n_starts=8)
    assert all(a.slider_app_um is None and "slider_app_um" not in a.to_dict() for a in force)


def test_sweep_points_carry_the_slider_motion(base_sweep):
    """Every periodic point of the base sweep has slider_app_um = the attractor search's value at
    the same orbit (rel 1e-9: the same orbit point sampled the same way), NaN elsewhere."""
    from contactvib.steady.orbits import slider_app_um

    ds = base_sweep
    s = ds["slider_app_um"].values
    periodic = ds["period"].values > 0
    assert np.all(np.isfinite(s[periodic])) and np.all(np.isnan(s[~periodic]))
    sy, sv = PAPER.y0, PAPER.y0 * PAPER.omega_n0
    for j in np.flatnonzero(periodic)[::40]:
        f = float(ds["fe_hz"][j])
        z = np.array([float(ds["state_y_um"][j]) * 1e-6 / sy, float(ds["state_ydot_mm_s"][j]) * 1e-3 / sv])
        exc = Excitation.base(PAPER, f, u_um=U_UM)
        assert s[j] == pytest.approx(slider_app_um(exc, z, int(ds["period"][j])), rel=1e-9)


def test_level_title_names_the_level_kind_and_a_law_of_ones_own():
    """Figure titles: the level's symbol and unit from the dataset, and a second line with the
    law for every model outside the paper's family (law, damping or preload changed)."""
    import xarray as xr

    from contactvib.plotting.figures import level_title

    def ds(model, **attrs):
        return xr.Dataset(attrs={"model": json.dumps(model.parameters()), "law": model.describe_law(), **attrs})

    assert level_title(ds(PAPER), 0.65) == "$P_a$ = 0.65 Q"
    assert level_title(ds(PAPER, excitation="base-um"), 0.05) == "$U$ = 0.05 µm (base motion)"
    for m in (ContactModel(law="exponential"), ContactModel(damping="hunt-crossley"), ContactModel(preload=1.0)):
        assert level_title(ds(m), 0.3) == f"$P_a$ = 0.3 Q\n{m.describe_law()}"
