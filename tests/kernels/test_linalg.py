"""The kernels' small dense solvers (:mod:`contactvib._kernels.linalg`) against numpy.linalg."""

import numpy as np

from contactvib._kernels.linalg import solve3


def test_solve3_agrees_with_numpy_and_refuses_singular_systems():
    rng = np.random.default_rng(7)
    for _ in range(200):
        a = rng.normal(size=(3, 3)) * 10.0 ** rng.uniform(-3, 3)
        b = rng.normal(size=3)
        a0, b0 = a.copy(), b.copy()
        x = np.empty(3)
        assert solve3(a, b, x)
        assert np.array_equal(a, a0) and np.array_equal(b, b0)  # inputs untouched
        ref = np.linalg.solve(a, b)
        assert np.allclose(x, ref, rtol=1e-8 * np.linalg.cond(a), atol=0.0)
    x = np.empty(3)
    singular = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]])
    assert not solve3(singular, np.ones(3), x)
    assert not solve3(np.full((3, 3), np.nan), np.ones(3), x)
