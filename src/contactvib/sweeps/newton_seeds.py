"""Newton seeds of the sweep's multi-start (step 4 of :mod:`contactvib.sweeps.sweep`).

At a multi-start frequency the box starts, moved towards or away from the static equilibrium, are
corrected by Newton shooting as orbits of a given period (the settle's refinement: minimal period,
stable); each stable orbit no trace has met is traced up and down (root "multi-start"). They are
not box hits, so they change no basin fraction. :data:`NEWTON_SEEDS` says which periods, from
which starts and at which stage.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from contactvib.model import ContactModel
    from contactvib.sweeps.level_state import LevelState

__all__ = ["NEWTON_MIN_RATIO", "NEWTON_SEEDS", "newton_seeds", "late_newton_seeds"]

#: Period-2 Newton seeds run only at f_e ≥ this × f_n0: one Newton iteration integrates two
#: excitation periods, 2 f_n0/f_e natural periods, so below this they cost more than the
#: multi-start's settling (above it about 0.4 s CPU per level, 3–10 % of ``trace_level``).
NEWTON_MIN_RATIO = 0.2
#: The Newton seeds: (period, start factors, number of box starts, loose first, stage). For each
#: entry the first box starts (all if None), moved towards (factor < 1) or away from (factor > 1)
#: the static equilibrium by the factors in turn, are corrected by Newton shooting as orbits of
#: that period; with "loose first" Newton runs at :data:`NEWTON_LOOSE_RTOL` first and only what
#: closes there is refined at the sweep's tolerance (a start that fails costs about 0.6 as much).
#: Stage 0 runs with the multi-start at each frequency, stage 1 after the multi-start at every
#: frequency (so it traces only what the multi-start found nowhere, and changes none of it).
#: Period 2 from all starts shrunk by 1/2, 1/4, 1/8: the ultrasubharmonic isolas (A_pp 0.6–2.4
#: µm, within 1/4–1/2 of the box ±(2 + 10 P_a/Q) y0; their doublings are traced on). Periods 3,
#: 4, 5 from 8 starts each, as drawn and doubled: bouncing orbits above f_n0 (period 5 at 0.85 Q,
#: 1589–2000 Hz) and large orbits whose strobe points lie outside the box (period 3 with 2 minima
#: at 0.80 Q, 366–450 Hz: x down to −45 y0); a period-k Newton start converges to them from
#: 3–20 % of such starts.
NEWTON_SEEDS = ((2, (0.5, 0.25, 0.125), None, False, 0),
                (3, (1.0, 2.0), 8, True, 1),
                (4, (1.0, 2.0), 8, True, 1),
                (5, (1.0, 2.0), 8, True, 1))
#: Integrator tolerance and closure of a loose first Newton (then refined at the sweep's).
NEWTON_LOOSE_RTOL = 1e-7
NEWTON_LOOSE_CLOSE = 1e-6


def newton_seeds(lv: LevelState, i: int, Zb: np.ndarray, par: np.ndarray, stage: int) -> None:
    """The Newton seeds of ``stage`` (:data:`NEWTON_SEEDS`) at grid index ``i`` from the box
    starts ``Zb``: trace every new stable orbit up and down."""
    from contactvib._kernels.settle import refine_stable_orbit
    from contactvib._kernels.shooting import newton_orbit
    from contactvib._kernels.status import STATUS_OK
    from contactvib.interrupts import check_interrupt

    if lv.r[i] < NEWTON_MIN_RATIO:
        return
    st = lv.st
    oz = np.empty(2)
    oM = np.empty((2, 2))
    for period, shrinks, n_starts, loose, when in NEWTON_SEEDS:
        if when != stage:
            continue
        for j in range(Zb.shape[0] if n_starts is None else min(n_starts, Zb.shape[0])):
            check_interrupt()
            shrink = shrinks[j % len(shrinks)]
            z0 = np.array([1.0 + shrink * (Zb[j, 0] - 1.0), shrink * Zb[j, 1]])
            if loose:
                s, _res = newton_orbit(z0, period, par, NEWTON_LOOSE_RTOL, NEWTON_LOOSE_RTOL,
                                       NEWTON_LOOSE_CLOSE, 12, oz, oM)
                if s != STATUS_OK:
                    continue
                z0 = oz.copy()
            ok, k, _res = refine_stable_orbit(z0, period, par, st.rtol, st.tol, oz, oM)
            if ok and lv.known_slot(i, oz, k, 0) < 0:
                lv.trace_both_ways(oz.copy(), k, 0, i, "multi-start")


def late_newton_seeds(lv: LevelState, model: ContactModel, pa_over_q: float, starts) -> None:
    """The stage-1 Newton seeds at every multi-start frequency, from the same box starts."""
    from contactvib.steady.attractors import start_box

    st = lv.st
    for i in starts:
        i = int(i)
        if lv.r[i] < NEWTON_MIN_RATIO:
            continue
        Zb, _ph = start_box(st.excitation_at(model, pa_over_q, lv.f[i]), st.n_starts, st.seed + i)
        par = lv.par.copy()
        par[4] = lv.r[i]
        newton_seeds(lv, i, Zb, par, 1)
