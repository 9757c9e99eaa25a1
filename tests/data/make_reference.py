"""Independent reference data for the contactvib tests: numpy + scipy only.

Regenerate with ``python tests/data/make_reference.py`` (writes ``reference.json`` next to this
file). Nothing from ``contactvib`` but its kernel-free :mod:`contactvib.testing` is imported: the
model parameters are recomputed here from the paper's SI values (Kostek 2013, Section 2) and the
flow is integrated with ``scipy.integrate.solve_ivp`` (DOP853), mode by mode, with terminal events
at x = 0 (:func:`contactvib.testing.integrate_modes`).

Nondimensional equation (x = y/y0, τ = ω_n0 t, p = P_a/Q, r = f_e/f_n0, c = 2 m2 ζ)::

    x'' = [1 − x^m2 − c x^l x' + p cos(r τ)] / m2     contact (x > 0)
    x'' = [1 + p cos(r τ)] / m2                       flight  (x ≤ 0)

The contact right-hand side is continued below x = 0 as sign(x)|x|^a (only the overshoot of a
trial step before the event is located ever sees it).

Contents of the JSON:

``end_states``
    State after 5 excitation periods (phase 0 to phase 0) from given initial states.
``orbits``
    For given orbit points (found once with ``contactvib.find_attractors`` and pasted here as
    constants): 300 periods to settle, then one more k-period with dense output; extrema from
    the roots of x' on the dense output; A_pp, x_min, x_max in units of y0 and the strobe point.
"""

from __future__ import annotations

import json
import math
import os
import sys

import numpy as np
import scipy
from scipy.optimize import brentq

from contactvib.testing import initial_mode, integrate_modes, power_law_rhs

RTOL = 1e-12
ATOL = 1e-12
SETTLE_PERIODS = 300
END_STATE_PERIODS = 5
METHOD = "DOP853"

# Paper parameters (SI), Section 2.
M, G, S, C_N, M2, H_N, L = 0.2106, 9.81, 0.0009, 4.52e16, 2.0, 3.5e11, 1.0


def derived():
    Q = M * G
    y0 = (Q / (S * C_N)) ** (1.0 / M2)
    k = M2 * Q / y0
    omega = math.sqrt(k / M)
    zeta = S * H_N * y0**L / (2.0 * math.sqrt(k * M))
    return {"Q": Q, "y0": y0, "omega_n0": omega, "f_n0": omega / (2 * math.pi), "zeta": zeta,
            "c": 2.0 * M2 * zeta}


DER = derived()


def par_of(pa_over_q, f_e):
    return (M2, L, DER["c"], float(pa_over_q), float(f_e) / DER["f_n0"])


def one_period(y, contact, par, dense=False):
    """Integrate from τ = 0 to T = 2π/r, switching at x = 0. Returns state, mode, pieces."""
    T = 2.0 * math.pi / par[4]
    f_contact, f_flight = power_law_rhs(par)
    run = integrate_modes(f_contact, f_flight, y, 0.0, T, contact=contact, rtol=RTOL, atol=ATOL,
                          method=METHOD, dense_output=dense, max_step=T / 20)
    pieces = [(ts, sol) for ts, (_, _, sol) in zip(run.steps, run.segments)] if dense else []
    return [float(v) for v in run.y], run.contact, pieces


def run_periods(z, n, par):
    y = [float(z[0]), float(z[1])]
    contact = initial_mode(*y)
    for _ in range(n):
        y, contact, _ = one_period(y, contact, par)
    return y, contact


def extrema(pieces, offset, n_sub=16):
    """Extrema (t, x, is_min) from sign changes of x' on the dense output of every step."""
    out = []
    for ts, solf in pieces:
        for a, b in zip(ts[:-1], ts[1:]):
            grid = np.linspace(a, b, n_sub + 1)
            vs = [float(solf(g)[1]) for g in grid]
            for g0, g1, v0, v1 in zip(grid[:-1], grid[1:], vs[:-1], vs[1:]):
                if (v0 < 0.0) != (v1 < 0.0):
                    tr = brentq(lambda s, solf=solf: float(solf(s)[1]), g0, g1, xtol=1e-15, rtol=1e-15)
                    out.append((offset + tr, float(solf(tr)[0]), v0 < 0.0))
    return out


def orbit_reference(z, k, par):
    y, contact = run_periods(z, SETTLE_PERIODS, par)
    z_settled = list(y)
    T = 2.0 * math.pi / par[4]
    ext = []
    for j in range(k):
        y, contact, pieces = one_period(y, contact, par, dense=True)
        ext += extrema(pieces, j * T)
    xs = [e[1] for e in ext]
    n_min = sum(1 for e in ext if e[2])
    return {
        "strobe": z_settled,
        "strobe_after_k": list(y),
        "x_min": min(xs),
        "x_max": max(xs),
        "A_pp": max(xs) - min(xs),
        "minima_per_period": n_min,
        "n_extrema": len(ext),
    }


# (pa_over_q, f_e, initial state) for the 5-period end states (all lose contact on the way).
END_CASES = [
    (0.65, 360.0, (-45.6107, 0.5061)),
    (0.65, 360.0, (3.3857, -1.2839)),
    (0.65, 360.0, (-0.2552, 0.5431)),
    (0.65, 360.0, (0.0, -5.0)),
    (0.90, 50.0, (0.0, -40.0)),
]

# Orbit points at phase 0 from contactvib.find_attractors (default arguments), pasted as constants.
ORBIT_CASES = [
    # S4.1, Fig. 4 (0.65 Q, 360 Hz): main, 1/2, 1/3, 1/4
    (0.65, 360.0, 1, (-45.61067873823435, 0.506140967696524), "main"),
    (0.65, 360.0, 1, (3.3856590029111713, -1.283931954600569), "1/2"),
    (0.65, 360.0, 1, (-0.2552488677720183, 0.543121861921892), "1/3"),
    (0.65, 360.0, 1, (1.3016475558905405, -0.12492028931841524), "1/4"),
    # S4.3, Fig. 6 (0.70 Q, 470 Hz): 1/2 after the first period doubling
    (0.70, 470.0, 2, (3.0978978133283395, -0.2559271338768241), "1/2 period-2"),
    # S4.4, Fig. 7 (0.85 Q, 234 Hz): main, 1/5, 1/6
    (0.85, 234.0, 1, (-123.35459272558218, 0.7010678080817917), "main"),
    (0.85, 234.0, 1, (0.31950154321230284, 0.2010007678093629), "1/5"),
    (0.85, 234.0, 1, (1.3879031157736355, -0.12828358286498937), "1/6"),
    # S4.5, Fig. 8 (0.90 Q, 170 Hz): 1/6 with loss of contact
    (0.90, 170.0, 1, (2.4216534258399367, 0.5892312848964381), "1/6"),
    # S4.6, Fig. 9 (0.90 Q, 50 Hz): quasistatic orbit
    (0.90, 50.0, 1, (1.378671091237381, -3.66698462648873e-05), "quasistatic"),
]


def main(path=None):
    path = path or os.path.join(os.path.dirname(os.path.abspath(__file__)), "reference.json")
    end_states = []
    for pq, fe, z in END_CASES:
        par = par_of(pq, fe)
        y, contact = run_periods(z, END_STATE_PERIODS, par)
        end_states.append({"pa_over_q": pq, "f_e": fe, "z0": list(z), "n_periods": END_STATE_PERIODS,
                           "z_end": y, "contact_end": bool(contact)})
        print(f"end state {pq} {fe} {z}: {y}", file=sys.stderr)
    orbits = []
    for pq, fe, k, z, label in ORBIT_CASES:
        par = par_of(pq, fe)
        ref = orbit_reference(z, k, par)
        ref.update({"pa_over_q": pq, "f_e": fe, "period": k, "label": label, "z_start": list(z)})
        orbits.append(ref)
        print(f"orbit {pq} {fe} {label}: A_pp={ref['A_pp']!r} minima={ref['minima_per_period']}",
              file=sys.stderr)
    data = {
        "generator": "tests/data/make_reference.py",
        "scipy_version": scipy.__version__,
        "numpy_version": np.__version__,
        "method": METHOD,
        "rtol": RTOL,
        "atol": ATOL,
        "settle_periods": SETTLE_PERIODS,
        "units": "nondimensional: x = y/y0, x' = ydot/(y0 omega_n0), tau = omega_n0 t",
        "model": {"M": M, "g": G, "S": S, "c_n": C_N, "m2": M2, "h_n": H_N, "l": L, **DER},
        "end_states": end_states,
        "orbits": orbits,
    }
    with open(path, "w", encoding="utf-8") as fh:
        json.dump(data, fh, indent=1, sort_keys=True)
        fh.write("\n")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
