"""The tangential motion's exact limits and identities (issue 26): no normal vibration gives the
friction ratio 1; a drive fast against the tangential vibration slips forward always, so the ratio
is the mean slip limit ⟨(R⁺/W)^β⟩ (1 for Coulomb friction while R ≥ 0, the Hess & Soom value for a
harmonic R by Jensen's inequality); the energy balance of the tangential motion per period."""

import math

import numpy as np
import pytest
from scipy.special import hyp2f1

from contactvib import ContactModel, ParameterError, find_attractors
from contactvib.friction import FrictionModel, friction_at, mean_limit


@pytest.fixture(scope="module")
def paper_360():
    """The paper's attractors at 0.65 Q, 360 Hz (main, 1/2, 1/3, 1/4 resonances and the bouncing
    orbit), by A_pp, largest first."""
    m = ContactModel()
    exc = m.excitation(0.65, 360.0)
    found = find_attractors(exc, n_starts=64)
    assert len(found) == 5
    return m, exc, list(found)


def test_no_normal_vibration_gives_ratio_one():
    m = ContactModel()
    exc = m.excitation(0.0, 360.0)
    (rest,) = find_attractors(exc, n_starts=8, seeds=False)
    for fm in (FrictionModel(), FrictionModel(kt_law="constant", vd=0.01), FrictionModel(beta=0.6, cd=0.0)):
        r = friction_at(exc, rest, friction=fm)
        assert r.settled and r.tangential_period == 1
        assert r.friction_ratio == pytest.approx(1.0, abs=1e-12)
        assert r.stick_fraction == 0.0 and r.free_fraction == 0.0 and r.slip_fraction == pytest.approx(1.0)
        assert r.limit_mean == pytest.approx(1.0, abs=1e-12)
        assert r.tangential_app_um == pytest.approx(0.0, abs=1e-9)


def test_small_normal_vibration_keeps_sliding_and_ratio_one():
    """A normal vibration whose slip limit changes slower than k_t v_d never stops the slip:
    ⟨F_t⟩ = μ ⟨R⟩ = μ W exactly."""
    m = ContactModel()
    exc = m.excitation(0.01, 360.0)
    (a,) = find_attractors(exc, n_starts=8, seeds=False)
    r = friction_at(exc, a, friction=FrictionModel(vd=1.0))
    assert r.stick_fraction == 0.0 and r.free_fraction == 0.0
    assert r.friction_ratio == pytest.approx(1.0, abs=1e-9)


def test_fast_drive_always_slips_forward(paper_360):
    """v_d large against the tangential vibration velocity: ratio → ⟨R⁺⟩/W. With a constant k_t
    the contact slips from touchdown on (exact); with k_t following the normal stiffness (zero
    at touchdown) a stick after each touchdown shrinks as 1/v_d."""
    m, exc, found = paper_360
    for a in found:
        r = friction_at(exc, a, friction=FrictionModel(kt_law="constant", vd=200.0))
        assert r.stick_fraction < 1e-12  # touchdown: stick (F_t = 0) for an instant, then slip
        assert r.friction_ratio == pytest.approx(r.limit_mean, rel=1e-8)
        if not a.loses_contact:
            assert r.friction_ratio == pytest.approx(1.0, abs=1e-8)
        else:  # R < 0 just before each separation (the damper pulls): ⟨R⁺⟩ slightly above W
            assert 1.0 < r.limit_mean < 1.001
    a = found[3]  # 1/3 resonance, loses contact
    runs = [friction_at(exc, a, friction=FrictionModel(vd=vd)) for vd in (20.0, 200.0)]
    assert runs[0].stick_fraction > runs[1].stick_fraction > 0.0
    for r in runs:
        assert r.friction_ratio == pytest.approx(mean_limit(m, exc, a), rel=1e-7)


def _linear_model():
    """A linear contact (m2 = 1, l = 0) with the paper's f_n0 and ζ: its small steady response is
    harmonic, and so is R."""
    M, S = 0.2106, 0.0009
    k = M * (2.0 * math.pi * 1485.0) ** 2
    return ContactModel(m2=1.0, l=0.0, c_n=k / S, h_n=2.0 * 0.0181 * math.sqrt(k * M) / S)


@pytest.mark.parametrize("beta", [0.5, 2.0 / 3.0, 0.9])
def test_hess_soom_harmonic_normal_force(beta):
    """Jensen: ⟨(R/W)^β⟩ ≤ 1, and for R = W (1 + a cos θ) the mean is 2F1(−β/2, (1−β)/2; 1; a²);
    a fast drive's friction ratio equals it."""
    m = _linear_model()
    exc = m.excitation(0.3, 700.0)
    a = next(a for a in find_attractors(exc, n_starts=8, seeds=False) if not a.loses_contact)
    hist = friction_at(exc, a, friction=FrictionModel(kt_law="constant", vd=500.0, beta=beta))
    h = hist.history(400)
    rr = h.normal_force_n / m.W
    amp = 0.5 * (rr.max() - rr.min())
    assert 0.3 < amp < 1.0 and not a.loses_contact
    exact = hyp2f1(-beta / 2.0, (1.0 - beta) / 2.0, 1.0, amp**2)
    assert hist.limit_mean == pytest.approx(exact, rel=1e-6)  # amp from samples: (π/400)² errors
    assert hist.friction_ratio == pytest.approx(hist.limit_mean, rel=1e-8)
    assert hist.friction_ratio < 1.0
    assert mean_limit(m, exc, a, 1.0) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("kt_law", ["constant", "normal"])
def test_energy_balance(paper_360, kt_law):
    """Drive work = damper + slip dissipation (+ the spring's work with a varying k_t, which is 0
    over a period for a constant one), per steady period, to 1e-8."""
    m, exc, found = paper_360
    for a in found:
        r = friction_at(exc, a, friction=FrictionModel(kt_law=kt_law))
        assert r.settled
        assert abs(r.energy_residual) < 1e-8
        if kt_law == "constant":
            assert abs(r.spring_work_uj) < 1e-8 * r.drive_work_uj
            assert r.drive_work_uj == pytest.approx(r.damper_dissipation_uj + r.slip_dissipation_uj, rel=1e-8)
        assert 0.0 < r.friction_ratio < 1.0
        assert r.stick_fraction + r.slip_fraction + r.free_fraction == pytest.approx(1.0, abs=1e-12)
        assert r.free_fraction >= r.contact_loss_fraction - 1e-12


def test_history_over_one_steady_period(paper_360):
    m, exc, found = paper_360
    a = found[3]
    r = friction_at(exc, a)
    h = r.history(1000)
    n = r.tangential_period * a.period * 1000
    assert h.t_ms.shape == (n,) and np.all(np.isfinite(h.friction_force_n))
    # the mean drive force of the samples is the result's (rectangle rule on a periodic function)
    assert np.mean(h.drive_force_n) == pytest.approx(r.mean_drive_force_n, rel=1e-5)
    lim = 0.3 * h.normal_force_n
    assert np.all(np.abs(h.friction_force_n) <= lim + 1e-12)
    assert set(np.unique(h.mode)) <= {"stick", "slip", "free"}
    assert np.all(h.slip_velocity_mm_s[h.mode == "stick"] == 0.0)
    assert np.all(h.friction_force_n[h.mode == "free"] == 0.0)


@pytest.mark.parametrize("kw, symbol", [({"mu": -0.1}, "mu"), ({"mu": 0.0}, "mu"), ({"kt_ratio": -1}, "kt_ratio"),
                                        ({"kd": 0.0}, "k_d"), ({"vd": -1e-3}, "v_d"), ({"cd": -1.0}, "c_d"),
                                        ({"beta": 1.5}, "beta"), ({"kt_law": "x"}, "kt_law"),
                                        ({"drive": "x"}, "drive"), ({"mu": float("nan")}, "mu"),
                                        ({"drive": "force"}, "F_T"), ({"drive": "force", "ft": -1.0}, "F_T"),
                                        ({"ft": 1.0}, "F_T")])
def test_bad_parameters_name_the_symbol(kw, symbol):
    with pytest.raises(ParameterError) as e:
        FrictionModel(**kw)
    assert e.value.symbol == symbol


def test_switches_are_located_events(paper_360):
    """Each switch is one located event (no chattering): the 1/3 resonance has 11 per period,
    touchdown → stick → slip (→ stick → slip) → free at each of its three contacts, the same count
    in the samples of its history; the orbit without loss of contact 2 (stick ↔ slip)."""
    m, exc, found = paper_360
    r = friction_at(exc, found[3])
    assert r.switches_per_period == 11.0
    h = r.history(200000)  # a stick of 1e-5 of the period before the third separation
    assert int((h.mode[1:] != h.mode[:-1]).sum()) + int(h.mode[0] != h.mode[-1]) == 11
    r4 = friction_at(exc, found[4])
    assert r4.switches_per_period == 2.0 and r4.free_fraction == 0.0


def test_non_periodic_attractor_is_refused(paper_360):
    import dataclasses

    from contactvib import ComputationError

    m, exc, found = paper_360
    with pytest.raises(ComputationError, match="non-periodic") as failed:
        friction_at(exc, dataclasses.replace(found[3], period=None))
    assert failed.value.stage == "friction"


def test_table_law_gives_the_power_laws_friction(paper_360):
    """The paper's law as a 301-row PCHIP table (examples/power_law_table.csv) through the general
    kernel path (k_t from the table's slope) against the power law: measured 1e-6 … 2e-5."""
    from pathlib import Path

    from contactvib import TableLaw

    m, exc, found = paper_360
    table = ContactModel(law=TableLaw.from_csv(Path(__file__).parents[2] / "examples" / "power_law_table.csv"))
    t_exc = table.excitation(0.65, 360.0)
    t_found = list(find_attractors(t_exc, n_starts=32))
    for a in found[2:]:
        b = min(t_found, key=lambda b: abs(b.app_um - a.app_um))
        assert friction_at(t_exc, b).friction_ratio == pytest.approx(friction_at(exc, a).friction_ratio,
                                                                            rel=1e-4)


def test_constant_force_without_vibration_sticks_or_slides():
    """No normal vibration: a force below μ W sticks (no creep); above it the slider slides at
    (F_T − μ W)/c_d, the damper to the ground taking the rest."""
    m = ContactModel()
    exc = m.excitation(0.0, 360.0)
    (rest,) = find_attractors(exc, n_starts=8, seeds=False)
    mu_w = 0.3 * m.W
    stuck = friction_at(exc, rest, friction=FrictionModel(drive="force", ft=0.5 * mu_w))
    assert stuck.mean_velocity_mm_s == 0.0 and stuck.stick_fraction == 1.0
    slide = friction_at(exc, rest, friction=FrictionModel(drive="force", ft=1.5 * mu_w))
    assert slide.mean_velocity_mm_s == pytest.approx(0.5 * mu_w / 30.0 * 1e3, rel=1e-9)
    assert slide.friction_ratio == pytest.approx(1.0, abs=1e-9)


def test_constant_force_creep_under_vibration(paper_360):
    """Normal vibration lets a force below μ W creep (vibration-induced creep); a large force
    slips forward throughout at (F_T − μ⟨R⁺⟩)/c_d; the energy balance F_T Δu = damper + slip."""
    m, exc, found = paper_360
    mu_w = 0.3 * m.W
    for a in found[2:]:
        creep = friction_at(exc, a, friction=FrictionModel(drive="force", ft=0.5 * mu_w))
        assert creep.settled and creep.mean_velocity_mm_s > 0.01
        assert creep.friction_ratio == pytest.approx(0.5 - 30.0 * creep.mean_velocity_mm_s * 1e-3 / mu_w, rel=1e-6)
        assert abs(creep.energy_residual) < 1e-8
        fast = friction_at(exc, a, friction=FrictionModel(drive="force", ft=1.2 * mu_w, kt_law="constant"))
        v = (1.2 * mu_w - mu_w * mean_limit(m, exc, a)) / 30.0 * 1e3
        assert fast.mean_velocity_mm_s == pytest.approx(v, rel=1e-8) and fast.stick_fraction < 1e-12


def test_spring_at_rest_holds_what_the_vibrating_contact_can():
    """v_d = 0: the drive spring, stretched to μ W, holds the slider; the vibration relaxes it to
    the held mean force (friction_ratio): in contact all the period, a held fraction in (0, 1)
    (the paper's small orbit at 0.2 Q, 360 Hz: 0.785); almost all of it at a tiny level; none
    where the contact flies 91 % of the period. The slider stops: no drive work."""
    from contactvib.steady.attractors import find_attractors

    model = ContactModel()
    fm = FrictionModel(vd=0.0)
    exc = model.excitation(0.2, 360.0)
    found = {a.contact_loss_fraction > 0.5: a for a in find_attractors(exc, n_starts=64)}
    held = friction_at(exc, found[False], friction=fm)
    assert held.settled and held.friction_ratio == pytest.approx(0.784686, abs=1e-5)
    assert abs(held.mean_velocity_mm_s) < 1e-9 and math.isnan(held.energy_residual)
    flying = friction_at(exc, found[True], friction=fm)
    assert flying.settled and abs(flying.friction_ratio) < 1e-6
    tiny = model.excitation(0.01, 360.0)
    small = friction_at(tiny, find_attractors(tiny, n_starts=8)[0], friction=fm)
    assert 0.97 < small.friction_ratio <= 1.0


def test_the_tangential_transient_stops_on_its_flag():
    """The settling kernel polls its stop flag every normal period (Ctrl-C through
    run_interruptible, explore's stop_scope): a set flag ends friction_at at once with a
    KeyboardInterrupt; SIGINT during a long run ends it within a fraction of a second."""
    import os
    import signal
    import threading
    import time

    from contactvib.interrupts import stop_scope

    model = ContactModel()
    exc = model.excitation(0.65, 360.0)
    a = find_attractors(exc, n_starts=8)[0]
    with stop_scope(np.ones(1, np.int64)), pytest.raises(KeyboardInterrupt):
        friction_at(exc, a, friction=FrictionModel())
    fm = FrictionModel(vd=0.0, cd=1e-3)  # a slow creep: thousands of periods
    threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
    t = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        friction_at(exc, a, friction=fm, max_periods=10**6)
    assert time.perf_counter() - t < 5.0
