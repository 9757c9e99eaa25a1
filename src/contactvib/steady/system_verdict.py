"""The verdict on a start of a System's attractor search that found no period ≤ kmax, and the
grouping of the search's periodic orbits.

A start that settles on no period ≤ kmax within ``max_periods`` periods gets the verdict of the
1-DOF search (:mod:`contactvib.steady.transients`, :func:`~.transients.search_verdict`'s rule):
:data:`~.transients.WINDOW` strobe points are taken, then :data:`~.transients.VERDICT_PERIODS`
periods by Benettin's method (:func:`~contactvib.steady.lyapunov.system_benettin`, 2n exponents
with standard errors, the damping average and the contact fraction), and with F = 3:

* no contact closed over that run (a free flight): *unsettled*;
* λ1 > F · stderr and a recurrent cloud (the window at the run's end lies in the one before it,
  :func:`~.transients.unsettled_cloud`): *chaotic*;
* a return of the run's last strobe point within ``LONG_PERIOD_TOL`` after kmax < k ≤
  ``LONG_PERIOD_MAX`` periods that Newton shooting refines to a stable orbit of minimal period
  above kmax: *periodic* with that period;
* ``|λ1|`` ≤ F · stderr and the strobe points on closed curves
  (:func:`~contactvib.steady.lyapunov.closed_curve`): *quasi-periodic*;
* anything else: *unsettled*, its reason counted (``unsettled_reasons``).

The clouds, the recurrence and the closed-curve tests use a 2-D projection of the scaled
strobe points: the first contact's deflection ξ = δ/y0 and its rate ξ' = δ̇/(y0 ω) (the first
coordinate x_1 and x_1' in a system without contacts). A start whose window lies on the cloud of a
non-periodic attractor already found (:func:`~.transients.same_cloud`) counts on it without a
verdict; non-periodic attractors with the same cloud are merged, and each gets its basin fraction.
Equal orbits: the same period and a common stroboscopic point within 100 ``SAME_TOL`` relative to
max(1, |x|∞) of the scaled state (:func:`same_orbit_index`); :func:`settled_orbit` reduces an
orbit found first on a multiple of its period to its least period.
"""

from __future__ import annotations

import numpy as np

from contactvib._kernels import system_map as km
from contactvib._kernels.status import STATUS_OK
from contactvib.errors import ComputationError
from contactvib.steady.lyapunov import attractor_type, closed_curve, system_benettin
from contactvib.steady.system_orbits import periodic_orbit
from contactvib.steady.transients import (
    CONTACT_FRACTION_MIN,
    LONG_PERIOD_MAX,
    LONG_PERIOD_TOL,
    LONG_PERIOD_TRIES,
    VERDICT_BATCHES,
    VERDICT_PERIODS,
    WINDOW,
    same_cloud,
    unsettled_cloud,
)

__all__ = ["judge_start", "match_cloud", "add_orbit", "settled_orbit", "same_orbit_index", "strobe_projection",
           "SAME_TOL"]

#: Two orbits are the same when a stroboscopic point of one is within this of one of the other's
#: (relative to max(1, |x|∞) in the scaled state).
SAME_TOL = 1e-6


def _near(x, points, tol) -> bool:
    return bool(np.any(np.max(np.abs(points - x), axis=1) <= tol * max(1.0, float(np.max(np.abs(x))))))


def _strobes(sa, form, x, k, rtol) -> np.ndarray:
    """The k scaled stroboscopic points of the orbit through x."""
    pts, out, phi = [x], np.empty(x.size), np.empty((0, 0))
    for _ in range(k - 1):
        if km.strobe_map(sa, np.ascontiguousarray(pts[-1]), 1, rtol, rtol, out, phi) != STATUS_OK:
            raise ComputationError("the stroboscopic points of an orbit", stage="integration")
        pts.append(out.copy())
    return np.array(pts)


def strobe_projection(sa, X: np.ndarray) -> np.ndarray:
    """The 2-D projection (rows) of scaled strobe points ``X`` (rows of 2n) that the verdict's
    cloud, recurrence and closed-curve tests use: the first contact's ξ = U_0 · x − γ_0 and ξ' =
    U_0 · x' [y0, y0 ω]; the first coordinate (x_1, x_1') without contacts."""
    X = np.atleast_2d(X)
    n = X.shape[1] // 2
    if sa.U.shape[0] == 0:
        return np.column_stack([X[:, 0], X[:, n]])
    u = sa.U[0]
    return np.column_stack([X[:, :n] @ u - sa.gam[0], X[:, n:] @ u])


def _window(sa, x, rtol) -> np.ndarray:
    """WINDOW scaled strobe points after x (x excluded), one period apart."""
    pts, y, phi = np.empty((WINDOW, x.size)), np.ascontiguousarray(x, float), np.empty((0, 0))
    for j in range(WINDOW):
        if km.strobe_map(sa, y, 1, rtol, rtol, pts[j], phi) != STATUS_OK:
            raise ComputationError("the strobe window of a start", stage="integration")
        y = pts[j]
    return pts


def match_cloud(sa, x, rtol, clouds: list) -> tuple:
    """The WINDOW strobe points after the scaled point x and their projection
    (:func:`strobe_projection`), and the index in ``clouds`` (records with a projected "cloud") of
    the non-periodic attractor whose cloud they lie on (:func:`~.transients.same_cloud`), or None:
    ``(index, points, projection)``."""
    before = _window(sa, x, rtol)
    proj = strobe_projection(sa, before)
    for i, c in enumerate(clouds):
        if same_cloud(c["cloud"], proj):
            return i, before, proj
    return None, before, proj


def judge_start(system, pa, fe, sa, form, x, kmax, rtol, found: list, clouds: list) -> str | None:
    """The verdict on a start without a period ≤ kmax at the scaled point x (module docstring):
    counts it on an attractor in ``found`` (periodic) or ``clouds`` (non-periodic; a new one is
    appended) and returns None, or returns the reason it is unsettled."""
    try:
        i, before, proj = match_cloud(sa, x, rtol, clouds)
    except ComputationError:
        return "integration failed"
    if i is not None:
        clouds[i]["hits"] += 1
        return None
    after = np.empty((2 * LONG_PERIOD_MAX + 1, x.size))
    try:
        spec = system_benettin(sa, before[-1], fe, VERDICT_PERIODS, VERDICT_BATCHES, 0, rtol, with_trace=True,
                               strobe=after)
    except ComputationError:
        return "integration failed"
    if not spec.contact_fraction > CONTACT_FRACTION_MIN:
        return "free flight: no contact"
    typ = attractor_type(spec)
    cloud = strobe_projection(sa, after[-2 * WINDOW:])
    if typ == "chaotic":
        why = unsettled_cloud(np.vstack([proj, cloud[-WINDOW:]]))
        if why:
            return why
        return _add_cloud(clouds, "chaotic", cloud, spec, after, form)
    if _long_period(system, pa, fe, sa, form, after, kmax, found):
        return None
    if typ == "quasi-periodic" and closed_curve(strobe_projection(sa, after)) > 0:
        return _add_cloud(clouds, "quasi-periodic", cloud, spec, after, form)
    return "still converging" if typ == "converging" else "no period, not a torus"


def _add_cloud(clouds: list, kind: str, cloud, spec, after, form) -> None:
    """Count a non-periodic attractor on an equal cloud (:func:`~.transients.same_cloud`) or add it."""
    for c in clouds:
        if same_cloud(c["cloud"], cloud):
            c["hits"] += 1
            return None
    clouds.append({"kind": kind, "cloud": cloud, "spec": spec, "hits": 1,
                   "points": after[-2 * WINDOW:].copy()})
    return None


def _long_period(system, pa, fe, sa, form, after, kmax, found: list) -> bool:
    """A stable orbit of minimal period kmax < k ≤ LONG_PERIOD_MAX through the last of the scaled
    strobe points ``after`` (time order): the shortest returns within LONG_PERIOD_TOL refined by
    Newton shooting; counted in ``found`` (:func:`add_orbit`) when there is one."""
    last = after[-1]
    scale = max(1.0, float(np.max(np.abs(last))))
    kk = min(LONG_PERIOD_MAX, after.shape[0] - 1)
    d = np.max(np.abs(after[-2:-kk - 2:-1] - last), axis=1) / scale
    d[:kmax] = np.inf
    for k in np.flatnonzero(d < LONG_PERIOD_TOL)[:LONG_PERIOD_TRIES] + 1:
        try:
            orbit = periodic_orbit(system, pa, fe, form.scales.to_si(last), int(k))
        except ComputationError:
            continue
        if not orbit.stable:
            continue
        xo = form.scales.to_scaled(orbit.z)
        if _least_period(_strobes(sa, form, xo, int(k), 1e-12)) <= kmax:
            continue
        add_orbit(system, pa, fe, sa, form, xo, int(k), found)
        return True
    return False


def settled_orbit(system, pa: float, fe: float, sa, form, x, k: int):
    """The orbit of minimal period through the settled scaled point x (period k, or a divisor of
    it), refined by Newton shooting: ``(SystemOrbit, its scaled stroboscopic points)``."""
    orbit = periodic_orbit(system, pa, fe, form.scales.to_si(x), k)
    xo = form.scales.to_scaled(orbit.z)
    points = _strobes(sa, form, xo, k, 1e-12)
    d = _least_period(points)
    if d < k:  # settled first on a multiple of its period (a transient that turns by 2π/k)
        orbit = periodic_orbit(system, pa, fe, orbit.z, d)
        points = _strobes(sa, form, form.scales.to_scaled(orbit.z), d, 1e-12)
    return orbit, points


def same_orbit_index(orbit, points: np.ndarray, found: list) -> int | None:
    """The index in ``found`` (records with "orbit" and scaled "points") of the orbit equal to
    ``orbit`` (same period, a common stroboscopic point within 100 ``SAME_TOL``), or None."""
    for i, f in enumerate(found):
        if f["orbit"].k == orbit.k and _near(points[0], f["points"], SAME_TOL * 100):
            return i
    return None


def add_orbit(system, pa, fe, sa, form, x, k, found: list) -> None:
    """Refine the settled point x (period k); count it on an equal orbit or add it to ``found``."""
    orbit, points = settled_orbit(system, pa, fe, sa, form, x, k)
    i = same_orbit_index(orbit, points, found)
    if i is None:
        found.append({"orbit": orbit, "points": points, "hits": 1})
    else:
        found[i]["hits"] += 1


def _least_period(points: np.ndarray) -> int:
    """The least d dividing k = len(points) with points[d] = points[0] (to 100 SAME_TOL)."""
    k = len(points)
    for d in range(1, k):
        if k % d == 0 and _near(points[0], points[d:d + 1], 100 * SAME_TOL):
            return d
    return k
