"""The steady tangential motion is stable by the package's one rule (|μ|max ≤ 1 + STABILITY_TOL,
:func:`contactvib._kernels.shooting.is_stable`), and its peak-to-peak is the interpolant's, not
that of a few points per step."""

import numpy as np
import pytest

from contactvib import ContactModel, find_attractors
from contactvib._kernels.shooting import STABILITY_TOL, is_stable
from contactvib.friction import friction_at
from contactvib.friction.newton import stable_fixed_point


def _with_spectrum(rng, mu):
    """A real 3 × 3 matrix with eigenvalues ``mu`` (one real, one complex pair, or three real)."""
    q = rng.normal(size=(3, 3))
    if np.iscomplexobj(mu) and np.any(np.imag(mu) != 0.0):
        r, c = float(np.real(mu[0])), mu[1]
        block = np.array([[r, 0.0, 0.0], [0.0, c.real, c.imag], [0.0, -c.imag, c.real]])
    else:
        block = np.diag(np.real(mu))
    return q @ block @ np.linalg.inv(q)


def test_stability_is_the_package_rule_on_random_and_boundary_matrices():
    rng = np.random.default_rng(11)
    for _ in range(500):  # random matrices, spectral radius spread around 1
        j = rng.normal(size=(3, 3)) * rng.uniform(0.1, 0.8)
        rho = np.abs(np.linalg.eigvals(j)).max()
        assert stable_fixed_point(j) == is_stable(rho)
    top = 1.0 + STABILITY_TOL
    for _ in range(200):  # the largest |μ| just inside and just outside 1 + tol, real or complex
        for rel, expected in ((1.0 - 1e-4 * STABILITY_TOL, True), (1.0 + 1e-4 * STABILITY_TOL, False)):
            radius = top * rel
            if rng.random() < 0.5:
                phase = rng.uniform(0.1, 3.0)
                mu = np.array([rng.uniform(-0.9, 0.9), radius * np.exp(1j * phase), radius * np.exp(-1j * phase)])
            else:
                mu = np.array([radius * rng.choice([-1.0, 1.0]), rng.uniform(-0.9, 0.9), rng.uniform(-0.9, 0.9)])
            j = _with_spectrum(rng, mu)
            assert stable_fixed_point(j) == expected == is_stable(np.abs(np.linalg.eigvals(j)).max())
    # a multiplier on the unit circle (a neutral direction) is stable by the rule
    assert stable_fixed_point(np.diag([1.0, 0.5, -0.2]))
    assert not stable_fixed_point(np.full((3, 3), np.nan))


@pytest.fixture(scope="module")
def stick_slip():
    m = ContactModel()
    exc = m.excitation(0.65, 360.0)
    found = list(find_attractors(m, exc, n_starts=64))
    return m, exc, found


def test_the_tangential_range_is_the_interpolants(stick_slip):
    m, exc, found = stick_slip
    for a in found[:2] + found[3:4]:
        r = friction_at(m, exc, a)
        h = r.history(20000)  # (2π/20000)²/8 ≈ 1e-8 of the range from sampling
        app = np.ptp(h.tangential_um)
        assert r.tangential_app_um == pytest.approx(app, rel=1e-7)
