"""Complete bifurcation diagrams: continuation seeded from every attractor, de-duplicated.

At each seed frequency the multi-start search (:func:`contactvib.find_attractors`) gives the
stable orbits; each periodic one that lies on no branch computed so far is continued in f_e both
ways (:func:`.continuation.continue_orbit`). A seed lies on a known branch when Newton shooting at
the seed's f_e, started from the branch interpolated there, lands on the same orbit (sameness rule
of :func:`contactvib.steady.orbits.same_orbit`). Isolas (closed branches unreachable from the others)
are found this way as long as one of their stable orbits is an attractor at a seed frequency.
At every period-doubling point the period-2k branch is entered (:func:`.switch_period_doubling`)
unless a branch already ends there.
"""

from __future__ import annotations

import numpy as np

from contactvib.call_forms import old_form
from contactvib.continuation.branch import Branch, BranchSet
from contactvib.continuation.shooting import (
    ContinuationSettings,
    continue_orbit,
    switch_period_doubling,
)
from contactvib.errors import ComputationError
from contactvib.model import LEVEL_TAGS, ContactModel, ParameterError, check_range
from contactvib.steady.orbits import refine_orbit, same_orbit, strobe_points

__all__ = ["continue_attractors", "bifurcation_diagram", "on_branch", "DEFAULT_SEED_FE"]

#: Seed frequencies [Hz] of :func:`bifurcation_diagram`: below, between and above the 1/m peaks.
DEFAULT_SEED_FE = (60.0, 200.0, 297.0, 420.0, 600.0, 900.0, 1200.0, 1930.0)


def _param_column(branch: Branch, parameter: str) -> np.ndarray:
    return branch.fe_hz if parameter == "f_e" else branch.pa_over_q


def _param_value(exc, parameter: str) -> float:
    return exc.f_e if parameter == "f_e" else exc.pa_over_q


def on_branch(model: ContactModel, branch: Branch, exc, z, k: int, parameter: str = "f_e") -> bool:
    """True when the period-``k`` orbit through ``z`` at ``exc`` lies on ``branch`` (a branch
    continued in ``parameter``, "f_e" or "P_a")."""
    if branch.period != k or len(branch) < 2:
        return False
    other = "P_a" if parameter == "f_e" else "f_e"  # held fixed along the branch
    fixed = _param_column(branch, other) - _param_value(exc, other)
    if np.any(np.abs(fixed) > 1e-12 * max(1.0, _param_value(exc, other))):
        return False
    f = _param_column(branch, parameter) - _param_value(exc, parameter)
    pts_seed = strobe_points(exc, z, k)
    for i in np.nonzero(f[:-1] * f[1:] <= 0.0)[0]:
        a = 0.0 if f[i + 1] == f[i] else f[i] / (f[i] - f[i + 1])
        guess = branch.state[i] + a * (branch.state[i + 1] - branch.state[i])
        try:
            zb, _M, _res = refine_orbit(exc, guess, k, max_iter=30)
        except ComputationError:
            continue
        if same_orbit(strobe_points(exc, zb, k), pts_seed):
            return True
    return False


def _pd_done(sp, branches, parameter: str = "f_e") -> bool:
    """True when a known period-2k branch already starts or ends at this period doubling.

    At a period doubling the period-2k branch touches the period-k orbit (same parameter and
    A_pp), so a branch with a point within 1 % of (parameter, A_pp) of the doubling has been
    found (from either end of its cascade, or switched onto from a copy of the period-k branch).
    """
    q_sp = sp.fe_hz if parameter == "f_e" else sp.pa_over_q
    for b in branches:
        if b.period != 2 * sp.period:
            continue
        q = _param_column(b, parameter)
        near = np.abs(q - q_sp) / q_sp + np.abs(b.app_um - sp.app_um) / max(sp.app_um, 1e-12)
        if near.size and float(near.min()) < 0.01:
            return True
        for st in b.stops:
            q_st = st.fe_hz if parameter == "f_e" else st.pa_over_q
            if "merges" in st.reason and abs(q_st - q_sp) <= 1e-3 * q_sp:
                return True
        if abs(q[0] - q_sp) <= 1e-6 * q_sp and b.parent is not None:
            return True
    return False


def _switch_all(model, branches: list, settings, kmax_switch: int, log, parameter: str = "f_e"):
    queue = list(branches)
    while queue:
        b = queue.pop(0)
        for sp in b.special:
            if sp.type != "period-doubling" or 2 * sp.period > kmax_switch:
                continue
            if _pd_done(sp, branches, parameter):
                continue
            try:
                nb = switch_period_doubling(model, sp, parameter=parameter, settings=settings,
                                            branch_id=f"{sp.branch}.pd{len(branches)}")
            except ComputationError as e:
                log(f"branch switching at {_where(sp, parameter)} failed: {e}")
                continue
            branches.append(nb)
            queue.append(nb)
        for st in b.stops:  # a period-k branch merging onto an unknown period-k/2 branch
            if st.merge_state is None:
                continue
            exc = settings.excitation_at(model, st.pa_over_q, st.fe_hz)
            k = b.period // 2
            try:
                z, _M, _r = refine_orbit(exc, st.merge_state, k, max_iter=30)
            except ComputationError:
                continue
            if any(on_branch(model, o, exc, z, k, parameter) for o in branches):
                continue
            bid = f"{b.branch}.m{len(branches)}"
            try:
                nb = continue_orbit(exc, z, k, parameter=parameter, settings=settings,
                                    branch_id=bid)
            except (ComputationError, ParameterError) as e:
                log(f"continuation from the merge at {_where(st, parameter)} failed: {e}")
                continue
            log(f"{bid}: period {k} branch found where {b.branch} merges ({_where(st, parameter)})")
            branches.append(nb)
            queue.append(nb)


def _where(point, parameter: str) -> str:
    if parameter == "f_e":
        return f"f_e = {point.fe_hz:.6g} Hz"
    return f"P_a = {point.pa_over_q:.6g} Q"


@old_form("model", "pa_over_q", "fe_hz", "attractor", "settings", "switch", "kmax_switch", "known", "prefix",
          "attractors", "log", "parameter")
def continue_attractors(model: ContactModel, *, pa_over_q: float, fe_hz: float,
                        attractor: int | None = None, settings: ContinuationSettings | None = None,
                        switch: bool = True, kmax_switch: int = 8, known: list | None = None,
                        prefix: str | None = None, attractors=None, log=None,
                        parameter: str = "f_e") -> BranchSet:
    """Continue the attractors found at (``pa_over_q``, ``fe_hz``) in ``parameter``, both ways.

    Parameters
    ----------
    model : ContactModel
    pa_over_q, fe_hz : float
        The seeds' operating point: the level (P_a/Q, or U [µm] or A [g] as
        ``settings.excitation`` says) and f_e [Hz].
    attractor : int or None
        Index into the attractor list (sorted by A_pp, largest first, as ``attractors --json``);
        None: every periodic attractor.
    switch : bool
        Enter the period-2k branch at each period doubling (periods up to ``kmax_switch``).
    known : list of Branch
        Branches already computed (seeds on them are skipped); extended in place.
    attractors : AttractorSet, optional
        Reuse a search result instead of running :func:`find_attractors`.
    parameter : {"f_e", "P_a"}
        Continuation parameter: the frequency at fixed P_a (default) or the amplitude at
        fixed f_e (range ``settings.pa_min`` … ``settings.pa_max``).

    Returns
    -------
    BranchSet
        The new branches (not those in ``known``).
    """
    from contactvib.steady.attractors import find_attractors

    settings = settings or ContinuationSettings()
    if parameter not in ("f_e", "P_a"):
        raise ParameterError("parameter", parameter, "must be 'f_e' or 'P_a'")
    if parameter == "P_a" and settings.excitation != "force":
        raise ParameterError("parameter", parameter, f"continuation in P_a needs a force level, not "
                                                     f"{settings.excitation}; continue in f_e instead")
    exc = settings.excitation_at(model, pa_over_q, fe_hz)
    if parameter == "f_e" and not (settings.fmin_hz <= exc.f_e <= settings.fmax_hz):
        raise ParameterError("f_e", fe_hz, f"seed must lie in [fmin, fmax] = [{settings.fmin_hz:g}, "
                                           f"{settings.fmax_hz:g}] Hz")
    if parameter == "P_a" and not (settings.pa_min <= exc.pa_over_q <= settings.pa_max):
        raise ParameterError("P_a", pa_over_q, f"seed must lie in [pa_min, pa_max] = "
                                               f"[{settings.pa_min:g}, {settings.pa_max:g}] Q")
    found = attractors if attractors is not None else find_attractors(exc)
    if attractor is not None:
        n = int(check_range("attractor", attractor, 0, True))
        if n != attractor or n >= len(found):
            raise ParameterError("attractor", attractor,
                                 f"must be an index 0..{len(found) - 1} of the {len(found)} attractors "
                                 f"found at {exc.f_e:g} Hz")
        idx = [n]
    else:
        idx = list(range(len(found)))
    log = log or (lambda msg: None)
    known = known if known is not None else []
    if prefix is None:
        prefix = f"{LEVEL_TAGS[settings.excitation]}{float(pa_over_q):g}" if parameter == "f_e" else f"fe{exc.f_e:g}"
    new = []
    for i in idx:
        a = found[i]
        if a.period is None:
            log(f"attractor {i} at {exc.f_e:g} Hz is non-periodic: not continued")
            continue
        if any(on_branch(model, b, exc, a.state, a.period, parameter) for b in known + new):
            continue
        bid = f"{prefix}/b{len(known) + len(new)}"
        try:
            b = continue_orbit(exc, a.state, a.period, parameter=parameter,
                               settings=settings, branch_id=bid)
        except ComputationError as e:
            log(f"attractor {i}: {e}")
            continue
        new.append(b)
        log(f"{bid}: period {b.period}, {len(b)} points, {len(b.special)} special points")
    if switch:
        n0 = len(new)
        allb = known + new
        _switch_all(model, allb, settings, kmax_switch, log, parameter)
        new.extend(allb[len(known) + n0:])
    known.extend(new)
    return BranchSet(new)


@old_form("model", "pa_over_q", "seed_fe", "settings", "switch", "kmax_switch", "log")
def bifurcation_diagram(model: ContactModel, *, pa_over_q: float,
                        seed_fe=DEFAULT_SEED_FE, settings: ContinuationSettings | None = None,
                        switch: bool = True, kmax_switch: int = 8, log=None) -> BranchSet:
    """All branches at one amplitude seeded from the attractors at the frequencies ``seed_fe``."""
    settings = settings or ContinuationSettings()
    seed_fe = [check_range("seed f_e", f, 0.0, False, "Hz") for f in seed_fe]
    known: list = []
    for f in seed_fe:
        if not (settings.fmin_hz <= f <= settings.fmax_hz):
            continue
        continue_attractors(model, pa_over_q=pa_over_q, fe_hz=f, settings=settings, switch=switch,
                            kmax_switch=kmax_switch, known=known,
                            prefix=f"{LEVEL_TAGS[settings.excitation]}{pa_over_q:g}", log=log)
    return BranchSet(known)
