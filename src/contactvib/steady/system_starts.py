"""Where a System's attractor search starts: a random box about the static state, and ballistic
seeds that such a box cannot reach.

The box (:func:`start_box`, :func:`box_starts`)
    In the scaled state of the compiled form (``contactvib.model.system_kernel``: each coordinate
    in its length L_j, each rate in L_j ω) about the static state (q_s, 0): half-widths of 2, or
    1.5 times the linear response to the force where that is larger; the rates' times
    max(1, ω_e/ω).

Ballistic seeds (:func:`seed_states`)
    Under a static load f0 (gravity, a preload) the structure flies free between contacts with
    the acceleration a = M⁻¹ f0. A take-off from the contacts' touching position q_c (every
    deflection w_i·q − e_i zero, the least-norm solution) with the velocity −s a j T/2 lands after
    s·j excitation periods T (exactly for K = C = 0, as the rocking unit in flight); the seeds are
    the states t = φ T after such take-offs, for flights of j = 1..``max_flight_periods``
    periods, s = 0.5, 0.75, 1 and φ = 0, 1/4, 1/2, 3/4 (those still in flight). They reach the
    large orbits that lose contact for whole periods (hundreds of y0, "bouncing" orbits) — the
    1-DOF search's ``ballistic_seeds`` written for a system. A system without a static load or
    without contacts has none.
"""

from __future__ import annotations

import math

import numpy as np

from contactvib.model.system import System

__all__ = ["start_box", "box_starts", "seed_states", "SEED_SPEEDS", "SEED_PHASES", "SEED_FLIGHT_PERIODS"]

#: Take-off speeds as fractions of the speed of a flight of j whole periods.
SEED_SPEEDS = (0.5, 0.75, 1.0)
#: Excitation phases [periods] after take-off at which the seeds start.
SEED_PHASES = (0.0, 0.25, 0.5, 0.75)
#: Longest free flight of a seed [excitation periods].
SEED_FLIGHT_PERIODS = 2


def start_box(system: System, form, pa: float, fe: float) -> tuple[np.ndarray, np.ndarray]:
    """The search's box of starts in the scaled state (rows of 2n): its centre, the static state
    (q_s, 0), and its half-widths: per coordinate 2, or 1.5 times the linear response to the force
    where that is larger; per rate the same times max(1, ω_e / ω)."""
    sc, nq = form.scales, system.n
    xs = sc.to_scaled(np.concatenate([system.static_state(), np.zeros(nq)]))
    w = 2.0 * math.pi * fe
    Kt = system.tangent_stiffness(system.static_state())
    Ct = np.array(system.C) + sum(c.damping_rate(c.deflection(system.static_state())) * np.outer(c.w, c.w)
                                  for c in system.contacts)
    try:
        amp = np.abs(np.linalg.solve(Kt - w * w * system.M + 1j * w * Ct, system.b * pa)) / sc.length
    except np.linalg.LinAlgError:
        amp = np.zeros(nq)
    half = np.maximum(2.0, 1.5 * np.where(np.isfinite(amp), amp, 0.0))
    return xs, np.concatenate([half, half * max(1.0, w / sc.omega)])


def box_starts(system: System, form, pa: float, fe: float, n: int, seed: int) -> np.ndarray:
    """``n`` scaled starts (rows of 2n) drawn uniformly in :func:`start_box` (generator seed ``seed``)."""
    xs, half = start_box(system, form, pa, fe)
    rng = np.random.default_rng(seed)
    return xs + rng.uniform(-1.0, 1.0, (n, 2 * system.n)) * half


def seed_states(system: System, form, fe: float, max_flight_periods: int = SEED_FLIGHT_PERIODS) -> np.ndarray:
    """The ballistic seeds (module docstring) as scaled states (rows of 2n); none (0 rows) without
    a static load or without contacts."""
    n = system.n
    f0 = np.asarray(system.f0, float)
    if not system.contacts or not np.any(f0):
        return np.empty((0, 2 * n))
    a = np.linalg.solve(np.asarray(system.M, float), f0)
    W = np.array([c.w for c in system.contacts], float)
    e = np.array([c.engagement for c in system.contacts], float)
    q_c = np.linalg.lstsq(W, e, rcond=None)[0]
    T = 1.0 / fe
    rows = []
    for j in range(1, max_flight_periods + 1):
        for s in SEED_SPEEDS:
            v = -s * a * j * T / 2.0
            for phi in SEED_PHASES:
                t = phi * T
                if t >= s * j * T:  # landed already
                    continue
                rows.append(form.scales.to_scaled(np.concatenate([q_c + v * t + 0.5 * a * t * t, v + a * t])))
    return np.array(rows, float).reshape(-1, 2 * n)
