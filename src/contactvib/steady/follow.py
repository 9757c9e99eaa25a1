"""Following attractors along a grid of f_e or P_a (the walk of an orbit diagram).

Each followed attractor is a ``Track`` at one grid point (nondimensional: strobe points (x, x'),
contact losses at τ with x' there, λ1 [1/period]); :func:`walk_grid` walks a grid up from a
search at its first point and down again, and returns the attractors at each point.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from contactvib._kernels.shooting import strobe_map
from contactvib._kernels.status import STATUS_OK
from contactvib.errors import ComputationError
from contactvib.model import ContactModel, Excitation
from contactvib.steady.sections import SECTION_RTOL, largest_exponent, stable_orbit_in, trajectory_points

__all__ = ["Track", "walk_grid", "same_attractor", "excitation_at_point", "PERIOD_DETECT_TOL"]

#: Relative repetition of the recorded strobe points below which a period is tried by Newton.
PERIOD_DETECT_TOL = 1e-2


@dataclass
class Track:
    """One followed attractor at one grid point (nondimensional): its id, period (None:
    non-periodic), strobe points (n, 2), contact-loss instants [τ] and x' there, last state, λ1."""

    id: int
    period: int | None
    strobe: np.ndarray
    loss_tau: np.ndarray
    loss_v: np.ndarray
    z: np.ndarray
    lambda1: float


def _settle(excitation: Excitation, z, n_periods: int, rtol: float) -> np.ndarray | None:
    out = np.empty(2)
    st = strobe_map(np.asarray(z, float).copy(), np.int64(n_periods), excitation.kernel_parameters(), rtol, rtol,
                    out, np.empty((0, 0)))
    return out if st == STATUS_OK and np.all(np.isfinite(out)) else None


def _follow(excitation: Excitation, z, settle: int, settings, rtol: float) -> Track | None:
    """Settle ``settle`` periods from ``z``, record ``n_periods``: the attractor reached (id −1),
    or None where the integration fails."""
    try:
        if settle:
            z = _settle(excitation, z, settle, rtol)
            if z is None:
                return None
        pts = trajectory_points(excitation, z, settings.n_periods, rtol=rtol)
    except ComputationError:
        return None
    orbit = stable_orbit_in(excitation, pts, max(settings.kmax, settings.n_periods // 2), PERIOD_DETECT_TOL, rtol)
    if orbit is not None:
        k, z_orb, mu, one = orbit
        return Track(-1, k, one.strobe, one.loss_tau, one.loss_v, z_orb,
                      largest_exponent(excitation, z_orb, k, multipliers=mu, rtol=rtol))
    if not np.all(np.isfinite(pts.strobe)):
        return None
    return Track(-1, None, pts.strobe, pts.loss_tau, pts.loss_v, pts.z_end,
                  largest_exponent(excitation, pts.z_end, rtol=rtol))


def _same(a: Track, b: Track) -> bool:
    from contactvib.steady.attractors import same_cloud
    from contactvib.steady.orbits import same_orbit

    if a.period is not None and b.period is not None:
        return a.period == b.period and same_orbit(a.strobe, b.strobe)
    if a.period is None and b.period is None:
        return same_cloud(a.strobe, b.strobe)
    return False


def _search(excitation: Excitation, settings) -> list:
    from contactvib.steady.attractors import UnsettledWarning, find_attractors

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnsettledWarning)
        found = find_attractors(excitation, n_starts=settings.n_starts, kmax=settings.kmax)
    return [a.state for a in found]


def excitation_at_point(model: ContactModel, settings, fixed: float, value: float) -> Excitation:
    return Excitation(model, value, fixed) if settings.vary == "pa" else Excitation(model, fixed, value)


def walk_grid(model: ContactModel, settings, fixed: float, grid: np.ndarray,
              rtol: float = SECTION_RTOL, progress=None, first_id: int = 0) -> list:
    """The attractors at each point of ``grid`` (a list of ``Track`` lists, nondimensional): the
    grid walked up from a search at its first point, then down from the attractors at its end."""
    per_point: list[list[Track]] = [[] for _ in grid]
    ids = [first_id]
    tracks = _walk(model, settings, fixed, grid, range(grid.size), [], ids, per_point, rtol, progress, 2 * grid.size)
    _walk(model, settings, fixed, grid, range(grid.size - 1, -1, -1), tracks, ids, per_point, rtol, progress,
          2 * grid.size, offset=grid.size)
    return per_point


def same_attractor(a, b) -> bool:
    """Whether two followed attractors at one grid point are the same (same orbit, or overlapping clouds)."""
    return _same(a, b)


def _walk(model, settings, fixed, grid, order, tracks, ids, per_point, rtol, progress, total, offset=0):
    """Follow ``tracks`` over the grid points in ``order`` (a search at every ``search_every``-th
    of them, the first included unless tracks are handed in), adding each point's attractors to
    ``per_point`` where no attractor there is the same; returns the tracks at the last point."""
    for j, i in enumerate(order):
        exc = excitation_at_point(model, settings, fixed, float(grid[i]))
        cands = [(t.id, t.z, settings.n_periods if j or not tracks else 0) for t in tracks]
        if j % settings.search_every == 0 and not (j == 0 and tracks):
            cands += [(-1, z, 0) for z in _search(exc, settings)]
        kept: list[Track] = []
        for ident, z, settle in cands:
            t = _follow(exc, z, settle, settings, rtol)
            if t is None or any(_same(t, o) for o in kept):
                continue
            if ident < 0:
                ident, ids[0] = ids[0], ids[0] + 1
            t.id = ident
            kept.append(t)
        tracks = kept
        per_point[i].extend(t for t in kept if not any(_same(t, o) for o in per_point[i]))
        if progress is not None:
            progress(offset + j + 1, total)
    return tracks


