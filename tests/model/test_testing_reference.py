"""The scipy reference integrator itself (:mod:`contactvib.testing`): a grazing exit from the
contact, where each mode's event has its root at the mode's own start, is followed (it looped
forever at one instant), and a motion held on y = 0 is refused instead of looped."""

import math

import numpy as np
import pytest

from contactvib.testing import integrate_modes, power_law_rhs

EPS = 1e-4  # ẏ at the exit, against ÿ = 1: a dip of 2 EPS below y = 0


def contact(t, s):
    """ÿ = 1, and a component that varies fast after t = 0 (like the contact-only damping
    integral): the contact's first step is far shorter than the dip, the flight's longer."""
    return [s[1], 1.0, math.exp(-1e9 * t)]


def flight(t, s):
    return [s[1], 1.0, 0.0]


def test_a_grazing_exit_is_followed_through_the_dip():
    """Contact left at y = 0 with ẏ = −EPS: the contact's own exit event fires at its start,
    the flight's landing event fires at its start too (its first step overshoots the dip). The
    mode is started again a hair inside itself; the trajectory is y = −EPS t + t²/2 throughout."""
    t1 = 1e-2
    tr = integrate_modes(contact, flight, [0.0, -EPS, 0.0], 0.0, t1, contact=True, rtol=1e-10, atol=1e-14)
    assert tr.contact and tr.n_switches == 2  # out at once, back after the dip
    (m0, (_, a), _), (m1, (_, b), _), _ = tr.segments
    assert (m0, m1) == (True, False) and a < 1e-9 and b == pytest.approx(2 * EPS, rel=1e-6)
    assert tr.y[:2] == pytest.approx([-EPS * t1 + t1**2 / 2, -EPS + t1], rel=1e-8)


def test_without_the_hair_the_grazing_exit_is_refused_not_looped():
    with pytest.raises(RuntimeError, match="held on y = 0 at t = 0.0"):
        integrate_modes(contact, flight, [0.0, -EPS, 0.0], 0.0, 1e-2, contact=True, rtol=1e-10, atol=1e-14,
                        graze=0.0)


def test_a_motion_held_on_the_boundary_is_refused_not_looped():
    """Fields that push both modes back onto y = 0 (a sliding motion) cannot be followed by two
    modes switched at y = 0: an error after a few restarts."""
    def push(direction):
        return lambda t, s: [s[1], direction * 1.0 - 1e6 * s[1]]

    with pytest.raises(RuntimeError, match="held on y = 0"):
        integrate_modes(push(-1.0), push(1.0), [0.0, 0.0], 0.0, 1.0, contact=True, rtol=1e-9, atol=1e-12)


def test_the_nondimensional_rhs_is_the_papers_equation():
    contact_rhs, flight_rhs = power_law_rhs((2.0, 1.0, 0.1, 0.5, 0.8))
    assert contact_rhs(0.0, [2.0, 1.0])[1] == pytest.approx((1.0 - 4.0 - 0.1 * 2.0 + 0.5) / 2.0)
    assert contact_rhs(0.0, [-2.0, 0.0])[1] == pytest.approx((1.0 + 4.0 + 0.5) / 2.0)  # odd continuation
    assert np.allclose(flight_rhs(0.0, [-1.0, 3.0]), [3.0, 0.75])
