"""Period-doubling cascades: a periodic orbit followed in f_e through doubling after doubling.

From an orbit of period p (in excitation periods) at a level P_a, the orbit is followed in f_e
by Newton shooting on the period-p map (each step started from the previous orbit) until the
period-doubling test function det(M + I) of its monodromy M changes sign
(:func:`.bifurcations.pd_test`); the crossing f_1 is located by the Illinois iteration
(:func:`.bifurcations.locate_zero`) to ``fe_tol``. Just beyond it the period-2p orbit is found by
Newton from the period-p orbit displaced along the eigenvector of the multiplier −1, and is
followed the same way to its own doubling f_2, and so on, with no cap on the period. The step
towards the next doubling is the last gap over ``STEP_DIVISIONS`` (the gaps shrink by Feigenbaum's
δ ≈ 4.669 per doubling). The ratios of successive gaps

    δ_k = (f_k − f_{k−1}) / (f_{k+1} − f_k)

tend to Feigenbaum's universal constant δ = 4.6692016… for a cascade of a one-hump map
(M. J. Feigenbaum, J. Stat. Phys. 19, 25 (1978)).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from contactvib.continuation.bifurcations import locate_zero, pd_test
from contactvib.errors import ComputationError
from contactvib.model import ContactModel, ParameterError

__all__ = ["Cascade", "follow_cascade", "cascades_at", "orbit_period", "FEIGENBAUM_DELTA"]

#: Feigenbaum's constant δ [1].
FEIGENBAUM_DELTA = 4.669201609102990
#: Steps per last gap while marching towards the next doubling.
STEP_DIVISIONS = 12


@dataclass
class Cascade:
    """A followed period-doubling cascade at one level.

    Attributes
    ----------
    pa_over_q : float
        The level P_a [Q].
    periods : list of int
        The orbit's period [excitation periods] before each located doubling: p, 2p, 4p, ...
    pd_fe_hz : list of float
        The located doublings f_1, f_2, ... [Hz] (``periods[i]`` → ``2 periods[i]`` at ``pd_fe_hz[i]``).
    delta : list of float
        δ_k = (f_k − f_{k−1}) / (f_{k+1} − f_k) [1], one per three successive doublings.
    stop : str
        Why the following ended (the tolerance reached, the range left, Newton failed, ...).
    states : list of ndarray
        Nondimensional orbit point (x, x') at phase 0 of each period's orbit at its doubling.
    """

    pa_over_q: float
    periods: list = field(default_factory=list)
    pd_fe_hz: list = field(default_factory=list)
    delta: list = field(default_factory=list)
    stop: str = ""
    states: list = field(default_factory=list, repr=False)

    def to_dict(self) -> dict:
        """The JSON form: ``pa_over_q``, ``periods``, ``pd_fe_hz``, ``delta`` (and ``stop``)."""
        return {"pa_over_q": float(self.pa_over_q), "periods": [int(p) for p in self.periods],
                "pd_fe_hz": [float(f) for f in self.pd_fe_hz], "delta": [float(d) for d in self.delta],
                "stop": self.stop}


def _deltas(f: list) -> list:
    return [(f[k] - f[k - 1]) / (f[k + 1] - f[k]) for k in range(1, len(f) - 1)]


def orbit_period(excitation, *, state, max_period: int = 4096, transient_periods: int = 2000,
                 tol: float = 1e-8, rtol: float = 1e-11):
    """The minimal period [excitation periods] of the orbit reached under ``excitation`` from
    ``state`` (nondimensional (x, x') at phase 0) after ``transient_periods``, up to
    ``max_period``; returns ``(period or None, state after the transient)``. A return within
    ``tol`` (relative to max(1, |z|)) is a period."""
    from contactvib._kernels.shooting import strobe_map

    par = excitation.kernel_parameters()
    z = np.array(state, float)
    out = np.empty(2)
    none = np.empty((0, 0))
    for _ in range(int(transient_periods)):
        if strobe_map(z, 1, par, rtol, rtol, out, none) != 0:
            raise ComputationError("the orbit could not be integrated", stage="integration")
        z = out.copy()
    z0 = z.copy()
    scale = max(1.0, float(np.max(np.abs(z0))))
    for k in range(1, int(max_period) + 1):
        strobe_map(z, 1, par, rtol, rtol, out, none)
        z = out.copy()
        if float(np.max(np.abs(z - z0))) <= tol * scale:
            return k, z0
    return None, z0


class _Follower:
    """Newton on the period-p map of one level along f_e (the orbits and monodromies it found)."""

    def __init__(self, model, pa_over_q, rtol, tol):
        self.model, self.pa, self.rtol, self.tol = model, pa_over_q, rtol, tol

    def orbit(self, fe: float, z0, p: int):
        """(z, M) of the period-p orbit near ``z0`` at ``fe``, or None."""
        from contactvib._kernels.shooting import newton_orbit
        from contactvib._kernels.status import STATUS_OK

        par = self.model.excitation(self.pa, fe).kernel_parameters()
        z = np.empty(2)
        M = np.empty((2, 2))
        st, _res = newton_orbit(np.asarray(z0, float).copy(), int(p), par, self.rtol, self.rtol, self.tol,
                                40, z, M)
        return (z, M) if st == STATUS_OK else None

    def minimal(self, fe: float, z, p: int) -> bool:
        """Whether the period-p orbit through ``z`` does not close after p/2 periods."""
        from contactvib._kernels.shooting import strobe_map

        if p % 2:
            return True
        par = self.model.excitation(self.pa, fe).kernel_parameters()
        out = np.empty(2)
        strobe_map(np.asarray(z, float).copy(), p // 2, par, self.rtol, self.rtol, out, np.empty((0, 0)))
        return float(np.max(np.abs(out - z))) > 1e3 * self.tol * max(1.0, float(np.max(np.abs(z))))


def follow_cascade(model: ContactModel, *, pa_over_q: float, fe_hz: float, state, period: int,
                   direction: int = +1, fe_limit_hz: float | None = None, first_step_hz: float = 0.05,
                   max_doublings: int = 10, fe_tol: float = 1e-9, rtol: float = 1e-12,
                   tol: float = 1e-10) -> Cascade:
    """Follow the period-``period`` orbit through ``state`` (nondimensional (x, x') at phase 0, at
    ``fe_hz`` [Hz] and ``pa_over_q`` [Q]) in f_e towards ``direction`` (+1: up), doubling after
    doubling (see the module doc), until ``max_doublings``, ``fe_limit_hz`` (default 10 Hz away),
    a gap below ``fe_tol`` relative to f_e (the tolerance can no longer resolve the next one) or
    a failure. Returns a :class:`Cascade` (its ``stop`` says why it ended).
    """
    if direction not in (-1, 1):
        raise ParameterError("direction", direction, "must be +1 or -1")
    if int(period) < 1:
        raise ParameterError("period", period, "must be an integer >= 1")
    fe_limit = fe_hz + 10.0 * direction if fe_limit_hz is None else float(fe_limit_hz)
    fol = _Follower(model, pa_over_q, rtol, tol)
    cas = Cascade(pa_over_q=float(pa_over_q))
    p = int(period)
    got = fol.orbit(fe_hz, state, p)
    if got is None:
        raise ComputationError(f"no period-{p} orbit near the given state at {fe_hz:g} Hz", stage="newton")
    z, M = got
    f, g = float(fe_hz), pd_test(M)
    step = float(first_step_hz)
    while len(cas.pd_fe_hz) < max_doublings:
        # march to the sign change of det(M + I)
        while True:
            f_next = f + direction * step
            if (f_next - fe_limit) * direction > 0:
                cas.stop = f"reached the f_e limit {fe_limit:g} Hz"
                return _finish(cas)
            got = fol.orbit(f_next, z, p)
            if got is not None and not fol.minimal(f_next, got[0], p):
                got = None  # slid onto the orbit of half the period (unstable beyond its doubling)
            if got is None:
                step *= 0.5
                if step < fe_tol * abs(f):
                    cas.stop = f"Newton failed on the period-{p} orbit near {f:.9g} Hz"
                    return _finish(cas)
                continue
            z_next, M_next = got
            g_next = pd_test(M_next)
            if g_next * g <= 0.0:
                break
            f, z, g = f_next, z_next, g_next
        a, b, za = f, f_next, z

        def evaluate(s, za=za, p=p):
            r = fol.orbit(s, za, p)
            return None if r is None or not fol.minimal(s, r[0], p) else (pd_test(r[1]), r)

        found = locate_zero(evaluate, a, b, g, g_next, xtol=fe_tol * abs(f))
        if found is None:
            cas.stop = f"the period-{p} doubling could not be located"
            return _finish(cas)
        f_pd, _gv, (z_pd, M_pd) = found
        cas.periods.append(p)
        cas.pd_fe_hz.append(float(f_pd))
        cas.states.append(z_pd.copy())
        gap = abs(cas.pd_fe_hz[-1] - cas.pd_fe_hz[-2]) if len(cas.pd_fe_hz) > 1 else None
        if gap is not None and gap < 1e3 * fe_tol * abs(f_pd):
            cas.stop = "the next doubling lies below the located tolerance"
            return _finish(cas)
        # switch to the doubled orbit just beyond the doubling
        w, V = np.linalg.eig(M_pd)
        v = np.real(V[:, int(np.argmin(np.abs(w + 1.0)))])
        beyond = (gap / FEIGENBAUM_DELTA if gap is not None else step) / STEP_DIVISIONS
        doubled = None
        for frac in (1.0, 0.3, 3.0, 0.1):
            fs = f_pd + direction * beyond * frac
            base = fol.orbit(fs, z_pd, p)
            zb = z_pd if base is None else base[0]
            for eps in (1e-3, 1e-2, 1e-4, 3e-2):
                for sign in (1.0, -1.0):
                    r = fol.orbit(fs, zb + sign * eps * max(1.0, float(np.max(np.abs(zb)))) * v, 2 * p)
                    if r is not None and fol.minimal(fs, r[0], 2 * p):
                        doubled = (fs, r)
                        break
                if doubled:
                    break
            if doubled:
                break
        if doubled is None:
            cas.stop = f"no period-{2 * p} orbit found beyond {f_pd:.9g} Hz"
            return _finish(cas)
        f, (z, M) = doubled[0], doubled[1]
        p *= 2
        g = pd_test(M)
        step = beyond
    cas.stop = f"{max_doublings} doublings located"
    return _finish(cas)


def _finish(cas: Cascade) -> Cascade:
    cas.delta = _deltas(cas.pd_fe_hz)
    return cas


def cascades_at(model: ContactModel, *, pa_over_q: float, fe_hz: float, direction: int = +1,
                fe_limit_hz: float | None = None, max_doublings: int = 10, max_period: int = 4096) -> list:
    """The cascades that start from the attractors at (``pa_over_q`` [Q], ``fe_hz`` [Hz]): each
    attractor's minimal period is detected by iterating the stroboscopic map (no cap below
    ``max_period``: a "non-periodic" verdict of the search may be a long period), and its orbit is
    followed towards ``direction`` by :func:`follow_cascade`. Returns the :class:`Cascade` of
    every attractor with at least one located doubling, largest amplitude first."""
    from contactvib.steady.attractors import find_attractors

    out = []
    for att in find_attractors(model.excitation(pa_over_q, fe_hz)):
        try:
            period, z = orbit_period(model.excitation(pa_over_q, fe_hz), state=att.state, max_period=max_period)
        except ComputationError:
            continue
        if period is None:
            continue
        try:
            cas = follow_cascade(model, pa_over_q=pa_over_q, fe_hz=fe_hz, state=z, period=period,
                                 direction=direction, fe_limit_hz=fe_limit_hz, max_doublings=max_doublings)
        except ComputationError:
            continue
        if cas.pd_fe_hz:
            out.append(cas)
    return out
