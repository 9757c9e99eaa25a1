"""The non-periodic verdict of the sweep: a non-periodic row is kept only if it is an attractor.

The tracer (:mod:`contactvib._kernels.trace`) and the multi-start accept a state whose
stroboscopic points found no period ``≤ kmax`` within the transient limit as a non-periodic
point. Some of those are transients that have not settled yet (a spiral into a focus, a slow
approach to an orbit of period above ``kmax``): their largest Lyapunov exponent is negative.
:func:`drop_unsettled` applies the attractor search's own rule,
:func:`contactvib.steady.transients.cloud_verdict` (recurrent strobe cloud of two windows of
:data:`~contactvib.steady.transients.WINDOW` points that keeps its spread, and
λ ≥ −:data:`~contactvib.steady.transients.LYAPUNOV_ZERO`), to every non-periodic row of a level:
the cloud is the ``2 · WINDOW`` strobe points from the row's state, λ the row's own exponent.
Rows that fail are removed, with their links; nothing else changes.
"""

from __future__ import annotations

import numpy as np

from contactvib.errors import ComputationError
from contactvib.model import ContactModel, excitation_at
from contactvib.steady.orbits import strobe_points
from contactvib.steady.transients import WINDOW, cloud_verdict

__all__ = ["settled_nonperiodic", "drop_unsettled", "judge_rows"]


def settled_nonperiodic(model: ContactModel, pa_over_q: float, f_hz: float, z, lyapunov: float,
                        rtol: float, settle_periods: int, excitation: str = "force") -> bool:
    """Whether the non-periodic point ``z`` (nondimensional, phase 0) at (P_a/Q, f_e) with largest
    Lyapunov exponent ``lyapunov`` [1/period] is on a non-periodic attractor:
    :func:`~contactvib.steady.transients.cloud_verdict` on the next ``2 · WINDOW`` strobe points
    (integrated at tolerance ``rtol``); a cloud that fails only the cloud test is settled
    ``settle_periods`` longer and judged once more (λ < −LYAPUNOV_ZERO is final). The level is
    of the kind ``excitation`` (:data:`contactvib.model.LEVEL_KINDS`)."""
    exc = excitation_at(model, pa_over_q, f_hz, excitation)
    try:
        tail = strobe_points(exc, z, 2 * WINDOW, rtol)
        ok, why = cloud_verdict(tail, float(lyapunov))
        if ok or why == "still converging" or settle_periods <= 0:
            return ok
        tail = strobe_points(exc, tail[-1], settle_periods + 2 * WINDOW, rtol)[-2 * WINDOW:]
    except ComputationError:
        return False
    return cloud_verdict(tail, float(lyapunov))[0]


def drop_unsettled(lt, model: ContactModel, rtol: float, settle_periods: int, excitation: str = "force"):
    """The :class:`~contactvib.sweeps.sweep.LevelTrace` ``lt`` without its non-periodic rows that
    :func:`settled_nonperiodic` rejects (rows, found_by, basin and links renumbered)."""
    from contactvib._kernels.table import KIND_NONPERIODIC

    rows = lt.rows
    keep = np.ones(lt.n_rows, bool)
    for j in np.flatnonzero(rows.kind == KIND_NONPERIODIC):
        keep[j] = settled_nonperiodic(model, lt.pa_over_q, float(lt.f_hz[rows.i[j]]), rows.z[j],
                                      rows.lyap[j], rtol, settle_periods, excitation)
    return _kept(lt, keep)


def _kept(lt, keep: np.ndarray, verdicts: dict | None = None):
    """``lt`` with the rows ``keep`` only (links renumbered), and ``verdicts`` (per row, of all rows)."""
    rows = lt.rows
    if verdicts is not None:
        verdicts = {k: v[keep] for k, v in verdicts.items()}
    if keep.all():
        return lt if verdicts is None else type(lt)(**{**vars(lt), "verdicts": verdicts})
    new_id = np.cumsum(keep) - 1
    links = lt.links
    ok = keep[links.a] & keep[links.b]
    new_links = type(links)(new_id[links.a[ok]], new_id[links.b[ok]], links.jump[ok].copy())
    return type(lt)(rows=type(rows)(*(v[keep] for v in rows)), found_by=lt.found_by[keep],
                    basin=lt.basin[keep], links=new_links, f_hz=lt.f_hz, stops=lt.stops,
                    pa_over_q=lt.pa_over_q, verdicts=verdicts)


def judge_rows(lt, model: ContactModel, rtol: float, kmax: int, excitation: str = "force"):
    """Every row of ``lt`` judged by the attractor search's rule: a periodic row keeps its type and
    gets the exponents ln|μ_i| / (k T) [1/s] of its Floquet multipliers; a non-periodic row gets
    :func:`contactvib.steady.transients.search_verdict` from its stroboscopic points (2000 periods
    of Benettin's method: "chaotic" when λ1 > 3 stderr, a stable orbit of period kmax < k ≤ 512 in
    that run "periodic" with its ``true_period``, "quasi-periodic" when ``|λ1|`` ≤ 3 stderr on a
    closed curve), and an "unsettled" row (a free flight, a transient still converging, a cloud
    that is neither) is removed. The Benettin runs of all non-periodic rows are one compiled call
    (:func:`~contactvib.steady.transients.search_verdicts`, on this process's numba threads); the
    verdicts are those of one ``search_verdict`` per row, bit for bit. Returns ``lt`` with its
    ``verdicts``."""
    from contactvib._kernels.table import KIND_NONPERIODIC
    from contactvib.steady.transients import search_verdicts

    rows, n = lt.rows, lt.n_rows
    types = np.array(["periodic"] * n, dtype=object)
    nonperiodic = rows.kind == KIND_NONPERIODIC
    true_period = np.where(nonperiodic, 0, rows.k).astype(np.int64)
    lam = np.full((n, 2), np.nan)
    se = np.zeros((n, 2))
    keep = np.ones(n, bool)
    fe = lt.f_hz[rows.i]
    periodic = np.flatnonzero(~nonperiodic)
    with np.errstate(divide="ignore"):
        mu = np.log(np.hypot(rows.mu_re[periodic], rows.mu_im[periodic]))
    # ln|μ_i| f_e / k, each row sorted descending (row by row: np.sort of one row, reversed)
    lam[periodic] = np.sort(mu * fe[periodic, None] / rows.k[periodic, None], axis=1)[:, ::-1]
    judged = np.flatnonzero(nonperiodic)
    verdicts = search_verdicts([excitation_at(model, lt.pa_over_q, float(fe[j]), excitation) for j in judged],
                               [rows.strobe[j, :rows.n_strobe[j]] for j in judged], rtol, kmax)
    for j, v in zip(judged, verdicts):
        types[j] = v.kind
        keep[j] = v.kind != "unsettled"
        if v.kind == "periodic":
            true_period[j] = v.period
            lam[j] = np.sort(np.log(np.abs(np.linalg.eigvals(v.monodromy))) * fe[j] / v.period)[::-1]
        elif v.spectrum is not None:
            lam[j], se[j] = v.spectrum.exponents_per_s, v.spectrum.stderr_per_s
    verdicts = {"attractor_type": types, "true_period": true_period, "lyapunov_per_s": lam,
                "lyapunov_stderr_per_s": se}
    return _kept(lt, keep, verdicts)


def settle_nonperiodic_start(model: ContactModel, pa_over_q: float, f_hz: float, z, rtol: float,
                             resettle, excitation: str = "force"):
    """The outcome of a multi-start start that ended non-periodic at ``z``: ``(z, 0, 1)`` when it
    is on a non-periodic attractor (:func:`settled_nonperiodic`, λ computed here); else the
    start is settled once more from there by ``resettle(z)`` (→ ``(z, k, kind)`` or None) and a
    periodic outcome is returned, a non-periodic one only if it passes the verdict; None when it
    has not settled (the start reached no attractor)."""
    from contactvib._kernels.describe import NP_LYAPUNOV, lyapunov_strobe

    exc = excitation_at(model, pa_over_q, f_hz, excitation)

    def lyap(p):
        return float(lyapunov_strobe(np.asarray(p, float).copy(), exc.kernel_parameters(), rtol, NP_LYAPUNOV))

    if settled_nonperiodic(model, pa_over_q, f_hz, z, lyap(z), rtol, 0, excitation):
        return np.asarray(z, float), 0, 1
    res = resettle(z)
    if res is None or res[2] == 0:
        return res
    return res if settled_nonperiodic(model, pa_over_q, f_hz, res[0], lyap(res[0]), rtol, 0, excitation) else None
