"""The friction ratio against an independent integrator (``scipy_friction``: scipy DOP853 on the
normal and tangential motion together, in SI, stick/slip switches located as events) at three
operating points, two of them losing contact, to 1e-4."""

import time

import pytest
from scipy_friction import FrictionODE, integrate_friction

from contactvib import ContactModel, find_attractors
from contactvib.friction import FrictionModel, friction_at

#: (preload [N], P_a/Q, f_e [Hz], which attractor by A_pp rank, FrictionModel keywords)
POINTS = [
    (0.0, 0.65, 360.0, 4, {"cd": 100.0}),  # the 1/4 resonance: no loss of contact
    (0.0, 0.65, 360.0, 3, {"cd": 100.0}),  # the 1/3 resonance: 49 % in flight
    (0.5, 0.5, 700.0, 2, {"cd": 100.0, "kt_law": "constant", "beta": 0.7, "mu": 0.2, "vd": 0.5}),  # 16 % flight
]


@pytest.mark.parametrize("preload, pa, fe, rank, kw", POINTS)
def test_friction_ratio_against_scipy(preload, pa, fe, rank, kw):
    m = ContactModel(preload=preload)
    exc = m.excitation(pa, fe)
    a = list(find_attractors(exc, n_starts=32))[rank]
    fm = FrictionModel(**kw)
    r = friction_at(exc, a, friction=fm)
    assert r.settled
    ode = FrictionODE(m, exc.P_a, fe, fm.mu, fm.kt_ratio, fm.kt_law, fm.kd, fm.cd, fm.vd * 1e-3, fm.beta)
    K = a.period / fe
    t1 = r.n_periods * K
    span = r.tangential_period * K
    y0, w = m.y0, m.omega_n0
    state = (a.state[0] * y0, a.state[1] * y0 * w, -fm.mu * m.W / fm.kd, 0.0)
    t = time.perf_counter()
    (i0, i1), n_seg = integrate_friction(ode, state, t1, t_marks=(t1 - span, t1))
    ratio = (i1 - i0) / span / (fm.mu * m.W)
    print(f"package {r.friction_ratio:.10f} scipy {ratio:.10f} ({n_seg} segments, "
          f"{r.n_periods} periods, {time.perf_counter() - t:.1f} s)")
    assert r.friction_ratio == pytest.approx(ratio, rel=1e-6)  # the issue asks 1e-4; measured 6e-9
    assert 0.0 < r.friction_ratio < 1.0
    assert n_seg < 20 * r.n_periods  # located switches, no chattering
