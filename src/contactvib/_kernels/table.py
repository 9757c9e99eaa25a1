"""The table of attractors known at each grid frequency, shared by the traces of one level.

A :class:`KnownTable` holds, per grid index ``i`` and slot ``s < n[i]``: the attractor's kind
(:data:`KIND_PERIODIC` with its period ``k`` and its k stroboscopic points ``pts``, or
:data:`KIND_NONPERIODIC` with the bounding box ``box`` = (x_min, x_max, x'_min, x'_max) of its
recorded stroboscopic cloud), the global output row ``row`` that describes it, and ``cov[i, s,
d]``, whether a trace has already gone through it downwards (d = 0) or upwards (d = 1).

:func:`find_known` is the sameness rule of the tracer: same period and the point equal to one
of the known stroboscopic points to ``same_tol`` (relative to :func:`.shooting.state_scale`);
non-periodic: the point inside a known cloud's box widened by 5 % of its size.
:func:`settle_known_many` runs multi-start transients that stop early at a known orbit.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit, prange

from .settle import settle_core
from .shooting import state_scale
from .status import SETTLE_PERIODIC

KIND_PERIODIC = 0
KIND_NONPERIODIC = 1

#: Per grid index ``i`` (axis 0) and slot ``s`` (axis 1): ``n[i]`` slots used; ``k``, ``kind``,
#: ``pts[i, s, j] = (x, x')`` (j < k), ``box[i, s] = (x_min, x_max, x'_min, x'_max)``,
#: ``row`` (global output row), ``cov[i, s, d]`` (traced downwards d = 0 / upwards d = 1).
KnownTable = namedtuple("KnownTable", ["n", "k", "kind", "pts", "box", "row", "cov"])


def new_table(n_f: int, max_attractors: int, max_period: int) -> KnownTable:
    """An empty :class:`KnownTable` for ``n_f`` grid frequencies, ``max_attractors`` slots each,
    periods up to ``max_period``."""
    return KnownTable(
        n=np.zeros(n_f, np.int64), k=np.zeros((n_f, max_attractors), np.int64),
        kind=np.zeros((n_f, max_attractors), np.int64),
        pts=np.zeros((n_f, max_attractors, max_period, 2)),
        box=np.zeros((n_f, max_attractors, 4)), row=np.zeros((n_f, max_attractors), np.int64),
        cov=np.zeros((n_f, max_attractors, 2), np.bool_),
    )


@njit(cache=True)
def find_known(table, i, z, k, kind, same_tol):
    """Slot of the attractor known at grid index ``i`` that ``z`` lies on, or −1."""
    sc = state_scale(z[0], z[1])
    for s in range(table.n[i]):
        if table.kind[i, s] != kind:
            continue
        if kind == KIND_PERIODIC:
            if table.k[i, s] != k:
                continue
            for j in range(k):
                p = table.pts[i, s, j]
                d = max(abs(z[0] - p[0]), abs(z[1] - p[1]))
                if d <= same_tol * max(sc, state_scale(p[0], p[1])):
                    return s
        else:
            b = table.box[i, s]
            wx = 0.05 * (b[1] - b[0]) + 1e-9
            wv = 0.05 * (b[3] - b[2]) + 1e-9
            if b[0] - wx <= z[0] <= b[1] + wx and b[2] - wv <= z[1] <= b[3] + wv:
                return s
    return -1


@njit(cache=True, inline='always')
def add_known(table, i, kind, k, strobe, n_strobe, row, d_slot):
    """Append an attractor at grid index ``i``: its kind, period ``k`` and stroboscopic points
    ``strobe[:k]`` (periodic) or the box of ``strobe[:n_strobe]`` (non-periodic), its output
    row, traced in direction ``d_slot`` only. Returns the slot."""
    s = table.n[i]
    table.kind[i, s] = kind
    table.row[i, s] = row
    table.cov[i, s, d_slot] = True
    table.cov[i, s, 1 - d_slot] = False
    if kind == KIND_PERIODIC:
        table.k[i, s] = k
        for j in range(k):
            table.pts[i, s, j, 0] = strobe[j, 0]
            table.pts[i, s, j, 1] = strobe[j, 1]
    else:
        table.k[i, s] = 0
        b = table.box[i, s]
        b[0] = math.inf
        b[1] = -math.inf
        b[2] = math.inf
        b[3] = -math.inf
        for j in range(n_strobe):
            b[0] = min(b[0], strobe[j, 0])
            b[1] = max(b[1], strobe[j, 0])
            b[2] = min(b[2], strobe[j, 1])
            b[3] = max(b[3], strobe[j, 1])
    table.n[i] += 1
    return s


@njit(cache=True, inline='always')
def _capture_points(table, i):
    """The stroboscopic points of the periodic attractors known at ``i`` and their slots."""
    m = 0
    for s in range(table.n[i]):
        if table.kind[i, s] == KIND_PERIODIC:
            m += table.k[i, s]
    cap_pts = np.empty((m, 2))
    cap_id = np.empty(m, np.int64)
    m = 0
    for s in range(table.n[i]):
        if table.kind[i, s] == KIND_PERIODIC:
            for j in range(table.k[i, s]):
                cap_pts[m, 0] = table.pts[i, s, j, 0]
                cap_pts[m, 1] = table.pts[i, s, j, 1]
                cap_id[m] = s
                m += 1
    return cap_pts, cap_id


@njit(cache=True, inline='always')
def _settle_known_start(q, Z, phases, par, cfg, cap_pts, cap_id, capture_tol, status, kk, zs):
    """Start ``q`` of :func:`settle_known_many` (the loop body of both of its kernels)."""
    hist = np.empty((cfg.max_periods + 1, 2))
    oz = np.empty(2)
    oM = np.zeros((2, 2))
    st, k, n, _res = settle_core(Z[q], phases[q], par, cfg.kmax, np.int64(4), cfg.max_periods,
                                 cfg.detect_tol, cfg.rtol_transient, cfg.rtol, cfg.tol,
                                 cap_pts, cap_id, capture_tol, hist, oz, oM, np.zeros(1, np.int64))
    status[q] = st
    kk[q] = k
    if st == SETTLE_PERIODIC:
        zs[q, 0] = oz[0]
        zs[q, 1] = oz[1]
    else:
        zs[q, 0] = hist[n, 0]
        zs[q, 1] = hist[n, 1]


@njit(cache=True, inline='always')
def _settle_known_setup(Z, i, table):
    """The capture points known at ``i`` and the empty outputs (status, k, z) of ``Z``'s starts."""
    cap_pts, cap_id = _capture_points(table, i)
    N = Z.shape[0]
    return cap_pts, cap_id, np.empty(N, np.int64), np.zeros(N, np.int64), np.empty((N, 2))


@njit(cache=True, parallel=True)
def _settle_known_threads(Z, phases, i, par, cfg, capture_tol, table):
    cap_pts, cap_id, status, kk, zs = _settle_known_setup(Z, i, table)
    for q in prange(Z.shape[0]):
        _settle_known_start(q, Z, phases, par, cfg, cap_pts, cap_id, capture_tol, status, kk, zs)
    return status, kk, zs


@njit(cache=True)
def _settle_known_serial(Z, phases, i, par, cfg, capture_tol, table):
    cap_pts, cap_id, status, kk, zs = _settle_known_setup(Z, i, table)
    for q in range(Z.shape[0]):
        _settle_known_start(q, Z, phases, par, cfg, cap_pts, cap_id, capture_tol, status, kk, zs)
    return status, kk, zs


def settle_known_many(Z, phases, i, par, cfg, capture_tol, table):
    """:func:`.settle.settle_core` for many starts, each stopped early once it comes within
    ``capture_tol`` of a stable periodic attractor known at grid index ``i``
    (``SETTLE_CAPTURED``; the table slot is returned as ``k``).

    ``cfg`` is a :class:`.trace.TraceSettings` (kmax, max_periods, detect_tol, rtol_transient,
    rtol, tol are used). Returns status, k (period, or the captured slot), z (refined point
    or last strobe point).

    The starts are independent: with more than one numba thread they run on the threads (a
    ``parallel=True`` kernel), with one (a pool worker) in a plain loop, whose compile is ~4 s
    shorter on a first run. Both give the same result.
    """
    from numba import get_num_threads

    kernel = _settle_known_threads if get_num_threads() > 1 else _settle_known_serial
    return kernel(Z, phases, i, par, cfg, capture_tol, table)
