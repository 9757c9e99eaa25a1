"""Continuation of the periodic orbits of a system (``continuation.system_shooting``) against
independent references.

* n = 1 (``System.single_dof`` of the paper's model): the branch continued in f_e (0.65 Q,
  990..1100 Hz: a fold) and in P_a (360 Hz, 0.3..0.9 Q: a fold and a period doubling) has the
  1-DOF continuation's special points — the same types in the same order, the parameter to 1e-8
  (relative) [measured ≤ 6e-12], the multipliers to 1e-6 [measured ≤ 1e-10], A_pp to 1e-5
  (relative; the system samples the orbit, 512 points a period, extrema refined by a parabola)
  [measured ≤ 3e-8]; every point of the system branch is a fixed point of the 1-DOF kernel's
  map to 1e-8 of y0 [measured ≤ 1e-10], with its multipliers to 1e-6 [measured ≤ 4e-10] and its
  A_pp (the kernel's exact extrema) to 1e-5 [measured ≤ 7e-7].
* the 2-DOF file system (examples/two_dof_stop.toml, P_a = 0.1 N, 0.085..0.13 Hz): an
  independent ``solve_ivp`` integration (DOP853, rtol 1e-10, the contact switch located as a
  terminal event — and a contact shorter than a step found from the extrema of the deflection —,
  the right-hand side written here from the TOML's matrices and the clearance law S c_lin δ)
  confirms the branch — each checked point is a fixed point of the scipy period map to 1e-7 of
  |z|∞ [measured ≤ 4e-9 over all 165 points, the largest next to grazing] — and its special
  points: the multipliers of a central-difference monodromy of the scipy map (step 1e-8 of the
  state: at a grazing orbit the map's derivative varies like the square root of the penetration)
  at the branch points on either side of each located fold, period doubling and Neimark–Sacker
  point change the test function's sign (a real multiplier through +1, through −1, a complex pair
  through |μ| = 1) and agree with the variational ones to 1e-5 [measured ≤ 4.3e-6].
* two parameters, one point: the Neimark–Sacker point of the P_a continuation at 0.095 Hz is one
  of the f_e continuation at its P_a, at 0.095 Hz.
* bad input on the command line: one line, exit status 2; ``attractors --system`` with nothing
  settled: one error line, exit status 1.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import tomllib
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from contactvib import ContactModel, find_attractors
from contactvib._kernels.continuation import orbit_range
from contactvib._kernels.shooting import strobe_map
from contactvib.cli.main import main
from contactvib.continuation.shooting import ContinuationSettings, continue_orbit
from contactvib.continuation.system_shooting import (
    SystemContinuationSettings,
    continue_system_orbit,
    linear_seed,
    system_tests,
)
from contactvib.model.system import System
from contactvib.model.system_file import load_system
from contactvib.steady.system_orbits import periodic_orbit

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
TOML = ROOT / "examples" / "two_dof_stop.toml"
MODEL = ContactModel()
PA_N = 0.1  # N, the 2-DOF file system's level


# ---------------------------------------------------------------------------------------- n = 1
def _si(x):
    return np.array([MODEL.spring_law.engagement_m + x[0] * MODEL.y0, x[1] * MODEL.y0 * MODEL.omega_n0])


def _x(z):
    return np.array([(z[0] - MODEL.spring_law.engagement_m) / MODEL.y0, z[1] / (MODEL.y0 * MODEL.omega_n0)])


def _compare(b1, bs, q1, qs):
    """Special points of the 1-DOF branch b1 and the system branch bs (parameters q1, qs)."""
    assert [sp.type for sp in bs.special] == [sp.type for sp in b1.special]
    assert len(bs.special) >= 1
    for a, s in zip(b1.special, bs.special):
        assert q1(a) == pytest.approx(qs(s), rel=1e-8)
        assert np.max(np.abs(np.sort_complex(a.floquet_multipliers) - np.sort_complex(s.floquet_multipliers))) < 1e-6
        assert s.app_um == pytest.approx(a.app_um, rel=1e-5)


def _points_are_one_dof_orbits(bs, exc_of):
    """Every system branch point: a fixed point of the 1-DOF map, the same multipliers and A_pp."""
    for i in range(len(bs)):
        par = exc_of(i).kernel_parameters()
        x = _x(bs.state[i])
        out, M = np.empty(2), np.empty((2, 2))
        assert strobe_map(x.copy(), 1, par, 1e-12, 1e-12, out, M) == 0
        assert np.max(np.abs(out - x)) / max(1.0, np.max(np.abs(x))) < 1e-8
        mu = np.sort_complex(np.linalg.eigvals(M))
        assert np.max(np.abs(mu - np.sort_complex(bs.floquet_multipliers[i]))) < 1e-6
        xmin, xmax, _f, _n, st = orbit_range(x.copy(), 1, par, 1e-12)
        assert st == 0
        assert bs.app[i, 0] == pytest.approx((xmax - xmin) * MODEL.units.y_um, rel=1e-5)


def test_single_dof_in_fe_equals_the_one_dof_continuation():
    exc = MODEL.excitation(0.65, 990.0)
    seed = min((a for a in find_attractors(exc, n_starts=64) if a.period == 1), key=lambda a: a.app_um)
    b1 = continue_orbit(exc, seed.state, 1, direction="up",
                        settings=ContinuationSettings(fmin_hz=990, fmax_hz=1100, max_points=80))
    b1.special = [sp for sp in b1.special if sp.type != "grazing"]  # not a test of system branches
    s = System.single_dof(MODEL)
    bs = continue_system_orbit(s, exc.P_a, 990.0, _si(seed.state), 1, direction="up",
                               settings=SystemContinuationSettings(fmin_hz=990, fmax_hz=1100, rtol=1e-12, tol=1e-10))
    _compare(b1, bs, lambda sp: sp.fe_hz, lambda sp: sp.fe_hz)
    # the fold turns it back to 990 Hz (the unstable middle branch), like the 1-DOF branch
    assert [st.reason for st in bs.stops] == [st.reason for st in b1.stops]
    assert bs.fe_hz.max() == pytest.approx(b1.fe_hz.max(), rel=1e-9)
    _points_are_one_dof_orbits(bs, lambda i: MODEL.excitation(0.65, bs.fe_hz[i]))


def test_single_dof_in_pa_has_the_fold_and_period_doubling_of_the_one_dof_continuation():
    exc = MODEL.excitation(0.65, 360.0)
    a2 = [a for a in find_attractors(exc) if a.period == 1 and a.minima_per_period == 2][0]
    b1 = continue_orbit(exc, a2.state, 1, parameter="P_a", settings=ContinuationSettings(pa_min=0.3, pa_max=0.9))
    b1.special = [sp for sp in b1.special if sp.type != "grazing"]
    Q = MODEL.Q
    bs = continue_system_orbit(System.single_dof(MODEL), exc.P_a, 360.0, _si(a2.state), 1, parameter="P_a",
                               settings=SystemContinuationSettings(pa_min_newton=0.3 * Q, pa_max_newton=0.9 * Q,
                                                                   rtol=1e-12, tol=1e-10), Q=Q)
    assert [sp.type for sp in bs.special] == ["fold", "period-doubling"]
    _compare(b1, bs, lambda sp: sp.pa_over_q, lambda sp: sp.pa_over_q)
    assert bs.special[1].pa_newton == pytest.approx(bs.special[1].pa_over_q * Q, rel=1e-14)
    _points_are_one_dof_orbits(bs, lambda i: MODEL.excitation(bs.pa_over_q[i], 360.0))


# ---------------------------------------------------------------------------------------- 2-DOF
class ScipyTwoDof:
    """The file system's equation written from the TOML (never through the package)::

        M q̈ + C q̇ + K q = f0 + b P_a cos(2π f_e t) − w S c_lin max(0, w·q − gap)

    integrated mode by mode (contact open / closed) with the switch located as a terminal event.
    """

    def __init__(self, path):
        d = tomllib.loads(Path(path).read_text())
        s, c = d["system"], d["contact"][0]
        self.Minv = np.linalg.inv(np.array(s["mass"], float))
        self.K, self.C = np.array(s["stiffness"], float), np.array(s["damping"], float)
        self.b, self.f0 = np.array(s["force_shape"], float), np.array(s.get("static_load", [0.0, 0.0]), float)
        self.w = np.array(c["direction"], float)
        self.k = c.get("area", 1.0) * c["c_lin"]
        self.gap = c["gap_um"] * 1e-6

    def period_map(self, z0, fe, pa, rtol=1e-10):
        om, T, n = 2.0 * math.pi * fe, 1.0 / fe, self.b.size
        w, k, gap = self.w, self.k, self.gap

        def rhs(t, s, on):
            q, v = s[:n], s[n:]
            f = self.f0 + self.b * pa * math.cos(om * t) - self.C @ v - self.K @ q
            if on:
                f = f - w * k * (w @ q - gap)
            return np.concatenate([v, self.Minv @ f])

        s = np.array(z0, float)
        on = bool(w @ s[:n] > gap)
        atol = 1e-12 * max(1.0, float(np.max(np.abs(s))))

        def delta(t, s, on):
            return w @ s[:n] - gap

        def rate(t, s, on):
            return w @ s[n:]

        t, hmax = 0.0, np.inf
        while t < T:
            # a terminal event where δ changes sign, and the extrema of δ (δ' = 0): a contact
            # (a separation) shorter than a step shows as a maximum with δ > 0 (a minimum with
            # δ < 0) between two step ends of one sign; its switch is then found on the dense output
            delta.terminal, delta.direction = True, (-1.0 if on else 1.0)
            rate.terminal, rate.direction = False, (1.0 if on else -1.0)
            sol = solve_ivp(rhs, (t, T), s, method="DOP853", rtol=rtol, atol=atol, events=(delta, rate),
                            args=(on,), dense_output=True, max_step=hmax)
            assert sol.status >= 0
            missed = [tm for tm in sol.t_events[1] if (delta(tm, sol.sol(tm), on) > 0.0) != on]
            if missed:
                tm = missed[0]
                ts = sol.sol.ts
                ta = ts[max(0, int(np.searchsorted(ts, tm)) - 1)]
                t = brentq(lambda x, f=sol.sol, m=on: delta(x, f(x), m), ta, tm, xtol=1e-15, rtol=1e-15)
                # the short phase in steps of a quarter of its half-length (its end is then found)
                s, on, hmax = sol.sol(t), not on, 0.25 * (tm - t)
                continue
            t, s, hmax = float(sol.t[-1]), sol.y[:, -1].copy(), np.inf
            if sol.status == 1:
                on = not on
        return s

    def monodromy(self, z, fe, pa, rel=1e-8):
        n2 = z.size
        n = n2 // 2
        J = np.empty((n2, n2))
        scale = [float(np.max(np.abs(z[:n]))), float(np.max(np.abs(z[n:])))]
        for j in range(n2):
            h = rel * scale[j // n]
            zp, zm = z.copy(), z.copy()
            zp[j] += h
            zm[j] -= h
            J[:, j] = (self.period_map(zp, fe, pa) - self.period_map(zm, fe, pa)) / (2.0 * h)
        return J


@pytest.fixture(scope="module")
def two_dof_branch():
    system = load_system(TOML)
    fe0 = 0.085
    orbit = periodic_orbit(system, PA_N, fe0, linear_seed(system, PA_N, fe0), 1)
    return continue_system_orbit(system, PA_N, fe0, orbit.z, 1, direction="up",
                                 settings=SystemContinuationSettings(fmin_hz=0.08, fmax_hz=0.13))


def test_two_dof_branch_points_are_scipy_fixed_points(two_dof_branch):
    b = two_dof_branch
    ref = ScipyTwoDof(TOML)
    assert b.fe_hz.max() == pytest.approx(0.13, rel=1e-12)
    for i in np.linspace(0, len(b) - 1, 6).astype(int):
        z = b.state[i]
        assert np.max(np.abs(ref.period_map(z, b.fe_hz[i], PA_N) - z)) / np.max(np.abs(z)) < 1e-7


def _side(b, sp, before: bool):
    """Index of the branch point just before (after) the special point: the bracket's end."""
    lo, hi = sp.bracket
    i = [j for j in range(len(b) - 1) if b.fe_hz[j] == lo and b.fe_hz[j + 1] == hi]
    assert len(i) == 1
    return i[0] if before else i[0] + 1


def test_two_dof_special_points_cross_in_the_scipy_monodromy(two_dof_branch):
    b = two_dof_branch
    types = [sp.type for sp in b.special]
    for t in ("fold", "period-doubling", "neimark-sacker"):
        assert t in types
    ref = ScipyTwoDof(TOML)
    for sp in b.special:
        mu = sp.floquet_multipliers
        if sp.type == "neimark-sacker":
            c = mu[np.argmin(np.abs(np.abs(mu) - 1.0) + (np.abs(mu.imag) < 1e-9))]
            assert abs(abs(c) - 1.0) < 1e-6 and abs(c.imag) > 1e-3
            assert sp.angle_over_2pi == pytest.approx(abs(np.angle(c)) / (2 * math.pi), abs=1e-12)
        else:
            target = 1.0 if sp.type == "fold" else -1.0
            # 1e-4: at the grazing orbit (q1 touching the stop) a multiplier moves like the square
            # root of the arclength, so the arclength tolerance 1e-9 leaves ~3e-5 [measured 2.3e-5]
            assert np.min(np.abs(mu - target)) < 1e-4
        signs = []
        for before in (True, False):
            i = _side(b, sp, before)
            J = ref.monodromy(b.state[i], b.fe_hz[i], PA_N)
            mu_ref = np.sort_complex(np.linalg.eigvals(J))
            err = np.max(np.abs(mu_ref - np.sort_complex(b.floquet_multipliers[i])))
            print(f"{sp.type} at {sp.fe_hz:.9g} Hz, {'before' if before else 'after'}: f_e = {b.fe_hz[i]:.9g} Hz, "
                  f"|mu| = {np.round(np.abs(mu_ref), 5)}, test {system_tests(J)[sp.type]:.3g}, "
                  f"|mu_scipy - mu| = {err:.2g}")
            assert err < 1e-5
            signs.append(np.sign(system_tests(J)[sp.type]))
        assert signs[0] * signs[1] < 0, sp.type


def test_cli_continue_system_json(tmp_path, capsys):
    out = tmp_path / "c"
    rc = main(["continue", "--system", str(TOML), "--pa-newton", str(PA_N), "--from-fe", "0.085",
               "--fmin", "0.08", "--fmax", "0.13", "--coordinate", "q2", "--out", str(out), "--json"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["coordinates"] == ["q1", "q2"]
    types = [sp["type"] for sp in d["special_points"]]
    assert {"fold", "period-doubling", "neimark-sacker"} <= set(types)
    ns = [sp for sp in d["special_points"] if sp["type"] == "neimark-sacker"]
    assert all(0.0 < sp["angle_over_2pi"] < 0.5 and len(sp["floquet_multipliers"]) == 4 for sp in ns)
    for sp in d["special_points"]:
        assert [x["name"] for x in sp["dofs"]] == ["q1", "q2"] and sp["contacts"][0]["name"] == "stop"
        assert "pa_over_q" not in sp and sp["pa_newton"] == PA_N
    # the period-1 branch and the period-2 branch between its period doublings
    assert sorted(p.name.split("_")[1] for p in out.glob("branch_*.nc")) == ["b0", "b0.pd1"]
    assert len(list(out.glob("branches_*.png"))) == 1


@pytest.mark.parametrize("args, option", [
    (["--system", "no_such_file.toml", "--pa-newton", "0.1"], "--system"),
    (["--system", str(TOML), "--pa", "0.5"], "--pa"),
    (["--system", str(TOML)], "--pa-newton"),
    (["--system", str(TOML), "--pa-newton", "0.1", "--coordinate", "q9"], "--coordinate"),
    (["--system", str(TOML), "--pa-newton", "0.1", "--from-fe", "5", "--fmin", "0.05", "--fmax", "0.2"],
     "--from-fe"),
    (["--pa-newton", "0.1"], "--pa-newton"),
])
def test_cli_continue_system_bad_input(tmp_path, capsys, args, option):
    rc = main(["continue", *args, "--out", str(tmp_path / "x")])
    err = capsys.readouterr().err.strip()
    assert rc == 2
    assert len(err.splitlines()) == 1 and len(err) <= 400 and option in err


def test_cli_system_attractors_exit_1_when_nothing_settles(capsys):
    """As the slider's command: no start settled (1 period allowed) → one error line, status 1."""
    rc = main(["attractors", "--system", str(TOML), "--pa-newton", str(PA_N), "--fe", "0.12", "--starts", "2",
               "--max-periods", "1"])
    err = capsys.readouterr().err.strip()
    assert rc == 1
    assert len(err.splitlines()) == 1 and err.startswith("contactvib: error: no attractor")


def test_two_dof_neimark_sacker_in_pa_is_one_in_fe():
    """Continued in P_a at 0.095 Hz, the branch meets a Neimark–Sacker point at P*; the branch in
    f_e at P* has a Neimark–Sacker point at 0.095 Hz (to 1e-7 relative) [measured 5e-12] with the
    same angle θ/2π (to 1e-6) [measured 4e-9]."""
    system = load_system(TOML)
    z = periodic_orbit(system, 0.05, 0.095, linear_seed(system, 0.05, 0.095)).z
    bp = continue_system_orbit(system, 0.05, 0.095, z, 1, parameter="P_a", direction="up",
                               settings=SystemContinuationSettings(pa_min_newton=0.01, pa_max_newton=0.1))
    ns = [sp for sp in bp.special if sp.type == "neimark-sacker"]
    assert len(ns) == 1 and 0.05 < ns[0].pa_newton < 0.1 and np.all(bp.fe_hz == 0.095)
    p_star = ns[0].pa_newton
    z0 = periodic_orbit(system, p_star, 0.085, linear_seed(system, p_star, 0.085)).z
    bf = continue_system_orbit(system, p_star, 0.085, z0, 1, direction="up",
                               settings=SystemContinuationSettings(fmin_hz=0.085, fmax_hz=0.1))
    near = [sp for sp in bf.special if sp.type == "neimark-sacker" and abs(sp.fe_hz - 0.095) < 1e-3]
    assert len(near) == 1
    assert near[0].fe_hz == pytest.approx(0.095, rel=1e-7)
    assert near[0].angle_over_2pi == pytest.approx(ns[0].angle_over_2pi, abs=1e-6)


def test_a_period_k_branch_stops_where_it_merges_with_a_period_d_orbit():
    """The period-1 orbit taken as a period-2 orbit: P(x) = x, so the branch stops at once."""
    system = load_system(TOML)
    z = periodic_orbit(system, PA_N, 0.085, linear_seed(system, PA_N, 0.085)).z
    b = continue_system_orbit(system, PA_N, 0.085, z, 2, direction="up",
                              settings=SystemContinuationSettings(fmin_hz=0.08, fmax_hz=0.09))
    assert len(b) == 1 and b.period == 2
    assert b.stops[0].reason.startswith("merges with the period-1 branch")


def test_two_dof_period_two_branch_from_one_period_doubling_ends_at_the_other(two_dof_branch):
    """Switched at the lower period doubling, the period-2 branch ends on the period-1 branch at
    the upper one (1e-4 relative) [measured ≤ 3e-5: the last point before it passes]; its
    points are fixed points of the scipy map over 2 periods (1e-7 of |z|∞) and not over 1."""
    from contactvib.continuation.system_switch import switch_system_period_doubling

    b = two_dof_branch
    pd = sorted((sp for sp in b.special if sp.type == "period-doubling"), key=lambda sp: sp.fe_hz)
    assert len(pd) == 2
    b2 = switch_system_period_doubling(load_system(TOML), pd[0], settings=SystemContinuationSettings(
        fmin_hz=0.08, fmax_hz=0.13))
    assert b2.period == 2 and b2.stops[0].reason.startswith("merges with the period-1 branch")
    assert b2.stops[0].fe_hz == pytest.approx(pd[1].fe_hz, rel=1e-4)
    assert b2.fe_hz.min() == pytest.approx(pd[0].fe_hz, rel=1e-4)
    ref = ScipyTwoDof(TOML)
    for i in (len(b2) // 3, 2 * len(b2) // 3):
        z, fe = b2.state[i], b2.fe_hz[i]
        z1 = ref.period_map(z, fe, PA_N)
        z2 = ref.period_map(z1, fe, PA_N)
        scale = np.max(np.abs(z))
        assert np.max(np.abs(z2 - z)) / scale < 1e-7 and np.max(np.abs(z1 - z)) / scale > 1e-3


def test_cli_continue_rocking_in_q(tmp_path, capsys):
    """--system rocking takes --pa in multiples of Q: each special point carries P_a/Q and P_a [N]."""
    rc = main(["continue", "--system", "rocking", "--pa", "0.3", "--from-fe", "1000", "--fmin", "1000",
               "--fmax", "1300", "--no-switch", "--out", str(tmp_path / "r"), "--json"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["coordinates"] == ["y", "theta"] and d["special_points"]
    for sp in d["special_points"]:
        assert sp["pa_over_q"] == pytest.approx(0.3, rel=1e-12)
        assert sp["pa_newton"] == pytest.approx(0.3 * MODEL.Q, rel=1e-12)
        assert [c["name"] for c in sp["contacts"]] == ["front", "rear"]
