"""An independent reference for the tests: scipy DOP853 on the contact-mode equation alone."""
import math

import numpy as np


def scipy_in_contact(par, z0, t_end, rtol=1e-12):
    """End state of x'' = [1 − x^m2 − c x^l x' + p cos rτ]/m2 from ``z0`` at τ = 0 to ``t_end``,
    written here independently of the kernels; asserts that contact is kept (x > 0.1)."""
    from scipy.integrate import solve_ivp

    m2, l, c, p, r = (float(v) for v in par)

    def f(t, y):
        return [y[1], (1.0 - y[0] ** m2 - c * y[0] ** l * y[1] + p * math.cos(r * t)) / m2]

    sol = solve_ivp(f, (0.0, t_end), np.asarray(z0, float), method="DOP853", rtol=rtol, atol=rtol)
    assert sol.success and np.min(sol.y[0]) > 0.1  # contact is kept throughout
    return sol.y[:, -1]
