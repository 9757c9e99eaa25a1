"""Periodic orbits: shooting, continuation, Floquet stability, folds and period doublings.

Every check compares with something independent of the continuation: long time integration of
the stroboscopic map, a finite-difference monodromy, the linear resonance curve, a fine
frequency sweep carried state to state, the attractor search, or the same computation at a
tighter integrator tolerance.
"""
import json
import math

import numpy as np
import pytest

from contactvib import (
    Branch,
    ComputationError,
    ContactModel,
    ContinuationSettings,
    ParameterError,
    continue_attractors,
    continue_orbit,
    find_attractors,
)
from contactvib._kernels.shooting import strobe_map
from contactvib.cli import main
from contactvib.continuation.bifurcations import fold_test, locate_zero, ns_test, pd_test
from contactvib.continuation.diagram import on_branch
from figure_files import assert_figure_file

MODEL = ContactModel()
NONE = np.empty((0, 0))


def _iterate(exc, z, n, rtol=1e-13):
    par = exc.kernel_parameters()
    z = np.asarray(z, float).copy()
    out = np.empty(2)
    for _ in range(n):
        assert strobe_map(z, 1, par, rtol, rtol, out, NONE) == 0
        z = out.copy()
    return z


@pytest.fixture(scope="module")
def primary_1930():
    """The period-1 orbit at 1930 Hz, 0.65 Q (small amplitude, above the resonance)."""
    exc = MODEL.excitation(0.65, 1930.0)
    found = find_attractors(exc, n_starts=64)
    a = [a for a in found if a.period == 1][0]
    return exc, a


def test_shooting_matches_long_time_integration(primary_1930):
    """The converged first point equals the end of 600 periods of plain time integration."""
    exc, a = primary_1930
    b = continue_orbit(exc, a.state * 1.001, 1, direction="up",
                       settings=ContinuationSettings(fmin_hz=1900, fmax_hz=1940, max_points=3))
    z_shoot = b.state[0]
    assert b.fe_hz[0] == pytest.approx(1930.0, rel=1e-14)
    z_long = _iterate(exc, a.state + np.array([1e-3, -1e-3]), 600)  # |mu| = 0.92: 0.92^600 ~ 1e-22
    assert np.max(np.abs(z_shoot - z_long)) / max(1.0, np.max(np.abs(z_long))) < 1e-8
    assert np.max(np.abs(z_shoot - a.state)) < 1e-8


def test_multipliers_match_finite_difference_monodromy():
    """On the unstable middle branch (multiplier > 1) with contact loss: variational vs FD."""
    exc = MODEL.excitation(0.65, 1000.0)
    found = find_attractors(exc, n_starts=64)
    seed = min((a for a in found if a.period == 1), key=lambda a: a.app_um)
    b = continue_orbit(exc, seed.state, 1, direction="up",
                       settings=ContinuationSettings(fmin_hz=990, fmax_hz=1100, max_points=60))
    unstable = np.nonzero(~b.stable & (b.ymin_um < 0))[0]
    assert unstable.size > 0, "the branch should pass the fold onto its unstable part"
    i = unstable[unstable.size // 2]
    e = MODEL.excitation(0.65, b.fe_hz[i])
    par = e.kernel_parameters()
    z = b.state[i]
    J = np.empty((2, 2))
    h = 1e-6 * max(1.0, np.max(np.abs(z)))
    for j in range(2):
        zp, zm = z.copy(), z.copy()
        zp[j] += h
        zm[j] -= h
        op, om = np.empty(2), np.empty(2)
        strobe_map(zp, 1, par, 1e-13, 1e-13, op, NONE)
        strobe_map(zm, 1, par, 1e-13, 1e-13, om, NONE)
        J[:, j] = (op - om) / (2 * h)
    mu_fd = np.sort_complex(np.linalg.eigvals(J))
    mu = np.sort_complex(b.floquet_multipliers[i])
    assert np.max(np.abs(mu_fd - mu)) < 1e-6
    assert np.max(np.abs(mu)) > 1.0


def test_linear_limit_resonance_curve_and_multipliers():
    """Tiny P_a: A_pp = 2 (p/m2) y0 / sqrt((1 − r²)² + (2ζr)²) and μ = exp(λT)."""
    p = 1e-5
    exc = MODEL.excitation(p, 1800.0)
    b = continue_orbit(exc, [1.0, 0.0], 1, direction="down",
                       settings=ContinuationSettings(fmin_hz=1000, fmax_hz=2000, ds_max=0.05))
    assert "range reached" in b.stops[0].reason
    assert b.fe_hz.min() == pytest.approx(1000.0)
    r = b.fe_hz / MODEL.f_n0
    zeta = MODEL.zeta
    linear = 2 * (p / MODEL.m2) * MODEL.y0 * 1e6 / np.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)
    assert np.max(np.abs(b.app_um / linear - 1)) < 1e-4  # O(p) non-linear correction
    # the branch passes the resonance peak (r = 1) and is stable throughout
    assert r.min() < 0.9 < 1.1 < r.max() and b.stable.all()
    lam = np.roots([1.0, 2 * zeta, 1.0])
    for i in (0, len(b) // 2, len(b) - 1):
        T = 2 * math.pi / r[i]
        expected = np.sort_complex(np.exp(lam * T))
        assert np.max(np.abs(np.sort_complex(b.floquet_multipliers[i]) - expected)) < 1e-6


@pytest.fixture(scope="module")
def lower_branch_065():
    """The lower branch of the primary resonance at 0.65 Q through its jump-up fold."""
    exc = MODEL.excitation(0.65, 1000.0)
    found = find_attractors(exc, n_starts=64)
    seed = min((a for a in found if a.period == 1), key=lambda a: a.app_um)
    return exc, seed


def _fold(exc, seed, rtol):
    s = ContinuationSettings(fmin_hz=990, fmax_hz=1100, rtol=rtol, tol=max(100 * rtol, 1e-11), max_points=80)
    b = continue_orbit(exc, seed.state, 1, direction="up", settings=s)
    folds = [sp for sp in b.special if sp.type == "fold"]
    assert len(folds) == 1
    return b, folds[0]


def test_fold_within_one_step_of_the_up_sweep_jump(lower_branch_065):
    """An up-sweep carried state to state (0.5 Hz steps) jumps within one step of the fold."""
    exc, seed = lower_branch_065
    b, fold = _fold(exc, seed, 1e-12)
    assert abs(fold.floquet_multipliers - 1).min() < 1e-7  # one multiplier is +1 there
    df = 0.5
    z = seed.state.copy()
    f = 1030.0
    z = _iterate(MODEL.excitation(0.65, f), z, 200, rtol=1e-10)
    jump_at = None
    while f < 1060.0:
        f += df
        e = MODEL.excitation(0.65, f)
        z_new = z.copy()
        for _ in range(40):  # up to 8000 periods: slow convergence next to the fold
            z_next = _iterate(e, z_new, 200, rtol=1e-10)
            done = np.max(np.abs(z_next - z_new)) < 1e-9
            z_new = z_next
            if done:
                break
        if np.max(np.abs(z_new - z)) > 1.0:
            jump_at = f
            break
        z = z_new
    assert jump_at is not None
    assert jump_at - df <= fold.fe_hz <= jump_at
    # the state before the jump lies on the stable part of the branch below the fold
    assert fold.fe_hz == pytest.approx(1041.45, abs=0.05)


def test_fold_converges_with_integrator_tolerance(lower_branch_065):
    exc, seed = lower_branch_065
    f = {rtol: _fold(exc, seed, rtol)[1].fe_hz for rtol in (1e-9, 1e-10, 1e-11, 1e-12)}
    fn0 = MODEL.f_n0
    d = [abs(f[a] - f[1e-12]) / fn0 for a in (1e-9, 1e-10, 1e-11)]
    assert d[2] < 1e-10  # target of the issue: 1e-8 in f_e/f_n0
    assert d[1] < 1e-9


def test_period_doubling_of_the_half_resonance_at_070():
    """0.70 Q: the period-2 attractor at 470 Hz lies on a branch that merges with the period-1
    branch of the 1/2 resonance at period doublings; above the upper one the attractor search
    finds the period-1 orbit (two minima) of that branch."""
    known = []
    found470 = find_attractors(MODEL.excitation(0.70, 470.0), n_starts=128)
    assert any(a.period == 2 for a in found470)
    s = ContinuationSettings(fmin_hz=100, fmax_hz=1200)
    bs = continue_attractors(MODEL, pa_over_q=0.70, fe_hz=470.0, settings=s, known=known, attractors=found470)
    pds = [sp for sp in bs.special_points if sp.type == "period-doubling" and sp.period == 1]
    assert pds, "period doubling of the 1/2 resonance not found"
    upper = max(pds, key=lambda sp: sp.fe_hz)
    assert 470.0 < upper.fe_hz < 620.0
    assert np.min(np.abs(upper.floquet_multipliers + 1.0)) < 1e-7
    parent = [b for b in bs if b.branch == upper.branch][0]
    f1 = upper.fe_hz + 15.0
    e1 = MODEL.excitation(0.70, f1)
    above = find_attractors(e1, n_starts=128)
    p1 = [a for a in above if a.period == 1 and a.minima_per_period == 2]
    assert any(on_branch(MODEL, parent, e1, a.state, 1) for a in p1)
    # branch switching at the point lands on the branch of the period-2 attractor at 470 Hz
    from contactvib import switch_period_doubling

    b2 = switch_period_doubling(MODEL, upper, settings=s)
    assert b2.period == 2 and b2.parent == upper.branch
    a2 = [a for a in found470 if a.period == 2 and a.minima_per_period == 4][0]
    assert on_branch(MODEL, b2, MODEL.excitation(0.70, 470.0), a2.state, 2)
    assert any("merges" in st.reason for st in b2.stops)
    # just below the point the period-1 orbit of that branch is unstable (multiplier < −1)
    i = np.nonzero((parent.fe_hz > upper.fe_hz - 15) & (parent.fe_hz < upper.fe_hz))[0]
    assert i.size and not parent.stable[i].any()


def test_test_functions_and_locator():
    M = np.diag([0.5, 1.0])
    assert fold_test(M) == 0.0
    assert pd_test(np.diag([-1.0, 0.3])) == 0.0
    assert math.isnan(ns_test(M))
    R = 0.9 * np.array([[math.cos(1), -math.sin(1)], [math.sin(1), math.cos(1)]])
    assert ns_test(R) == pytest.approx(0.81 - 1)
    s, v, _ = locate_zero(lambda x: (x**3 - 2, None), 0.0, 2.0, -2.0, 6.0, 1e-13)
    assert s == pytest.approx(2 ** (1 / 3), abs=1e-12)


def test_branch_netcdf_roundtrip(tmp_path, primary_1930):
    import xarray as xr

    exc, a = primary_1930
    b = continue_orbit(exc, a.state, 1, direction="down", settings=ContinuationSettings(fmin_hz=1500, fmax_hz=2000))
    assert isinstance(b, Branch) and len(b) > 3
    p = tmp_path / "b.nc"
    b.to_netcdf(p)
    ds = xr.open_dataset(p)
    assert ds["fe_hz"].attrs["units"] == "Hz" and ds["app_um"].attrs["units"] == "um"
    np.testing.assert_allclose(ds["app_um"].values, b.app_um)
    sp = json.loads(ds.attrs["special_points"])
    assert {d["type"] for d in sp} <= {"fold", "period-doubling", "neimark-sacker", "grazing"}
    ds.close()
    # grazing: y_min crosses zero there
    g = [s for s in b.special if s.type == "grazing"]
    assert len(g) == 1 and b.ymin_um.min() < 0 < b.ymin_um.max()


def test_locate_off_changes_no_branch_point(lower_branch_065):
    """``locate=False`` (the sweep's post-pass) leaves the special points out and nothing else:
    the same points, multipliers and stability, bit for bit."""
    exc, seed = lower_branch_065
    kw = dict(fmin_hz=990, fmax_hz=1100, rtol=1e-10, tol=1e-9, max_points=80)
    on = continue_orbit(exc, seed.state, 1, direction="up", settings=ContinuationSettings(**kw))
    off = continue_orbit(exc, seed.state, 1, direction="up", settings=ContinuationSettings(**kw, locate=False))
    assert {sp.type for sp in on.special} >= {"fold"} and off.special == []
    for name in ("fe_hz", "state", "floquet_multipliers", "stable", "app_um"):
        np.testing.assert_array_equal(getattr(on, name), getattr(off, name), err_msg=name)
    assert [st.reason for st in on.stops] == [st.reason for st in off.stops]


@pytest.mark.parametrize("kwargs, symbol", [
    ({"locate": "no"}, "locate"),
    ({"fmin_hz": -1.0}, "fmin_hz"), ({"fmin_hz": 100.0, "fmax_hz": 50.0}, "fmax_hz"), ({"ds_min": 0.0}, "ds_min"),
    ({"max_points": 0}, "max_points"), ({"rtol": 1e-3}, "rtol"), ({"app_max_um": -5.0}, "app_max_um"),
])
def test_bad_settings(kwargs, symbol):
    with pytest.raises(ParameterError) as e:
        ContinuationSettings(**kwargs)
    assert e.value.symbol == symbol


def test_bad_continuation_input(primary_1930):
    exc, a = primary_1930
    with pytest.raises(ParameterError, match="period"):
        continue_orbit(exc, a.state, 0)
    with pytest.raises(ParameterError, match="state"):
        continue_orbit(exc, [np.nan, 0.0], 1)
    with pytest.raises(ParameterError, match="parameter"):
        continue_orbit(exc, a.state, 1, parameter="c_n")
    with pytest.raises(ParameterError, match="continuation range"):
        continue_orbit(exc, a.state, 1, settings=ContinuationSettings(fmin_hz=30, fmax_hz=1000))
    with pytest.raises(ComputationError) as failed:
        continue_orbit(exc, [1e4, 1e4], 1, settings=ContinuationSettings(max_iter=2))
    assert failed.value.stage == "continuation"
    with pytest.raises(ParameterError, match="attractor"):
        continue_attractors(MODEL, pa_over_q=0.65, fe_hz=1930.0, attractor=3, attractors=[])


def test_cli_continue_json_contract(tmp_path, capsys):
    import xarray as xr

    out = tmp_path / "br"
    rc = main(["continue", "--pa", "0.65", "--from-fe", "1930", "--attractor", "4", "--fmin", "1500",
               "--fmax", "2000", "--out", str(out), "--json", "--no-switch"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert set(d) == {"special_points", "stops"}
    assert len(d["stops"]) == 2 and all({"fe_hz", "reason"} <= set(s) for s in d["stops"])
    for sp in d["special_points"]:
        assert {"type", "fe_hz", "pa_over_q", "app_um", "period", "branch"} <= set(sp)
    files = sorted(out.glob("branch_*.nc"))
    assert len(files) == 1
    assert_figure_file(out / "branches_pa0.65_fe1930.png")
    with xr.open_dataset(files[0]) as ds:
        assert ds["fe_hz"].min() == pytest.approx(1500.0) and ds["fe_hz"].max() == pytest.approx(2000.0)


@pytest.fixture(scope="module")
def attractors_360():
    return find_attractors(MODEL.excitation(0.65, 360.0))


def test_continuation_in_pa_meets_the_attractors_and_the_fe_period_doubling(attractors_360):
    """Continuation in P_a at 360 Hz: the 1/4 branch carries the attractors the search finds at
    0.30 and 0.80 Q (long time integration), and the 1/2 branch's period doubling at P_a* is a
    period doubling of the f_e continuation at P_a* exactly at 360 Hz (1e-6 Hz)."""
    exc = MODEL.excitation(0.65, 360.0)
    a4 = [a for a in attractors_360 if a.period == 1 and a.minima_per_period == 4][0]
    b4 = continue_orbit(exc, a4.state, 1, parameter="P_a", settings=ContinuationSettings(pa_min=0.05, pa_max=0.9))
    assert b4.pa_over_q.min() == pytest.approx(0.05) and b4.pa_over_q.max() == pytest.approx(0.9)
    assert np.all(b4.stable) and np.all(b4.fe_hz == 360.0)
    for pa, minima in ((0.30, 1), (0.80, 4)):
        e = MODEL.excitation(pa, 360.0)
        found = [a for a in find_attractors(e, n_starts=128) if a.period == 1]
        on = [a for a in found if on_branch(MODEL, b4, e, a.state, 1, parameter="P_a")]
        assert len(on) == 1 and on[0].minima_per_period == minima
    a2 = [a for a in attractors_360 if a.period == 1 and a.minima_per_period == 2][0]
    b2 = continue_orbit(exc, a2.state, 1, parameter="P_a", settings=ContinuationSettings(pa_min=0.3, pa_max=0.9))
    assert [sp.type for sp in b2.special] == ["fold", "period-doubling"]
    fold, pd = b2.special
    assert 0.40 < fold.pa_over_q < 0.50 < 0.65 < pd.pa_over_q < 0.70  # born, then doubles (S3.3)
    e = MODEL.excitation(pd.pa_over_q, 360.0)
    bf = continue_orbit(e, pd.state, 1, settings=ContinuationSettings(fmin_hz=350, fmax_hz=370, ds=0.005, ds_max=0.01))
    pds = [sp.fe_hz for sp in bf.special if sp.type == "period-doubling"]
    assert len(pds) == 1 and abs(pds[0] - 360.0) < 1e-6


def test_cli_continue_in_pa(tmp_path, capsys):
    out = tmp_path / "pa"
    rc = main(["continue", "--parameter", "pa", "--pa", "0.65", "--from-fe", "360", "--attractor",
               "1", "--pa-min", "0.1", "--pa-max", "0.8", "--no-switch", "--out", str(out), "--json"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    folds = [sp for sp in d["special_points"] if sp["type"] == "fold"]
    assert len(folds) == 1 and 0.10 < folds[0]["pa_over_q"] < 0.2 and folds[0]["fe_hz"] == 360.0
    assert all(s["pa_over_q"] == pytest.approx(0.8) for s in d["stops"])
    assert_figure_file(out / "branches_pa0.65_fe360_in_pa.png")


def test_fold_curve_passes_through_one_parameter_folds():
    """The two-parameter fold curve from the 0.65 Q jump-up fold meets the one-parameter fold
    at 0.70 Q (computed independently, from an attractor seed at 0.70 Q)."""
    from contactvib.continuation.evolution import continue_codim1

    def fold_at(pa):
        exc = MODEL.excitation(pa, 1000.0)
        found = find_attractors(exc, n_starts=64)
        seed = min((a for a in found if a.period == 1), key=lambda a: a.app_um)
        return _fold(exc, seed, 1e-12)[1]

    f65, f70 = fold_at(0.65), fold_at(0.70)
    c = continue_codim1(MODEL, "fold", f65.fe_hz, 0.65, f65.state, pa_range=(0.6, 0.75), ds_max=0.02)
    assert c.stops == ["P_a range reached", "P_a range reached"]
    o = np.argsort(c.pa_over_q)
    f_curve = np.interp(0.70, c.pa_over_q[o], c.fe_hz[o])
    assert abs(f_curve - f70.fe_hz) / f70.fe_hz < 1e-6  # linear interpolation between curve points
    assert f70.fe_hz < f65.fe_hz - 20  # the fold moves down in f_e as P_a grows (softening)


def test_isola_closes_after_one_loop():
    """The period-3 'ultrasubharmonic 2/3' orbit at 1500 Hz, 0.65 Q lies on a closed branch
    (900–1960 Hz): the continuation goes round it once, back to its seed, and stops there."""
    from contactvib.continuation.shooting import ISOLA_STOP

    exc = MODEL.excitation(0.65, 1500.0)
    found = find_attractors(exc, n_starts=64)
    seed = min((a for a in found if a.period == 3), key=lambda a: a.app_um)
    b = continue_orbit(exc, seed.state, 3, settings=ContinuationSettings(fmin_hz=30, fmax_hz=2000))
    assert [s.reason for s in b.stops] == [ISOLA_STOP]
    assert 850 < b.fe_hz.min() < 950 and 1900 < b.fe_hz.max() < 2000
    assert len(b) < 500
    folds = [sp.fe_hz for sp in b.special if sp.type == "fold"]
    assert len(folds) == 2  # an isola has two folds
    # back at the start: the last point is within one continuation step of the first
    step_f = np.abs(np.diff(b.fe_hz)).max()
    step_z = np.abs(np.diff(b.state, axis=0)).max()
    assert abs(b.fe_hz[-1] - b.fe_hz[0]) <= 1.5 * step_f
    assert np.max(np.abs(b.state[-1] - b.state[0])) <= 1.5 * step_z


def test_special_points_carry_dofs_and_contacts(tmp_path, capsys):
    """The JSON of a special point lists the orbit's dofs and contacts: at the grazing point of the
    1/3 resonance (0.65 Q) y_min = 0, and the mean contact force of a periodic orbit is Q exactly
    (the equation of motion averaged over a period)."""
    assert main(["continue", "--pa", "0.65", "--from-fe", "360", "--attractor", "2", "--fmin", "200", "--fmax", "800",
                 "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    graze = [s for s in out["special_points"] if s["type"] == "grazing"]
    assert graze
    for s in graze:
        (dof,), (contact,) = s["dofs"], s["contacts"]
        assert set(dof) == {"name", "unit", "min", "max", "app", "h1"} and dof["name"] == "y"
        assert abs(dof["min"]) < 1e-6 and dof["app"] == pytest.approx(s["app_um"], rel=1e-9)
        assert set(contact) == {"name", "loses_contact", "contact_loss_fraction", "mean_force_n"}
        assert contact["mean_force_n"] == pytest.approx(ContactModel().Q, rel=1e-6)
