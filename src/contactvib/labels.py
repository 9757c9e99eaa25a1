"""Resonance labels of attractors: how they are given and how to read them back.

A period-k orbit gets the resonance ratio ν of the harmonic its contact amplifies
(:func:`dominant_ratio`), a label (:func:`resonance_label`), short flickers of the label along a
continued branch are smoothed away (:func:`smooth_labels`), and non-periodic attractors get a type
from their largest Lyapunov exponent (:func:`attractor_type`). A label is ``"main"``, ``"1/m"``, ``"main
period-k"``, ``"1/m period-k"``, ``"non-periodic (1/m)"``, ``"non-resonant"``,
``"subharmonic 1/q"`` or ``"ultrasubharmonic p/q"`` (with ``" bouncing"``). This module is the one
place that parses them.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

# One threshold on the largest Lyapunov exponent for the sweep's labels and the attractor search.
from contactvib.steady.transients import LYAPUNOV_ZERO

__all__ = ["dominant_ratio", "resonance_label", "smooth_labels",
           "attractor_type", "level_labels", "resonance_order", "label_family", "period_one_order",
           "LYAPUNOV_ZERO", "LABEL_FLICKER"]


def resonance_order(label) -> int | None:
    """Order m of the resonance a label belongs to: ``"main…"`` → 1, ``"1/m …"`` → m,
    ``"non-periodic (1/m)"`` → m; None for non-resonant and sub-/ultrasubharmonic labels."""
    m, _variant = label_family(label)
    return m


def label_family(label) -> tuple[int | None, str]:
    """(order m or None, variant) of a label: ``"1/3 period-2"`` → (3, "period-2"),
    ``"main"`` → (1, ""), ``"non-periodic (1/5)"`` → (5, "non-periodic"),
    ``"subharmonic 1/2"`` → (None, "subharmonic 1/2")."""
    label = str(label)
    if label.startswith("non-periodic ("):
        m, _ = label_family(label[len("non-periodic ("):-1])
        return m, "non-periodic"
    if label.startswith("main"):
        return 1, label[4:].strip()
    if label.startswith("1/"):
        head, _, rest = label.partition(" ")
        if head[2:].isdigit():
            return int(head[2:]), rest
    return None, label


def period_one_order(label) -> int | None:
    """m of a period-1 resonance label, exactly ``"main"`` (1) or ``"1/m"`` (m); else None."""
    m, variant = label_family(label)
    return m if variant == "" else None


def dominant_ratio(k: int, n_min: int, harmonics, loses_contact: bool, fe_hz: float,
                   fn0_hz: float) -> Fraction:
    """Resonance ratio ν (multiples of f_e) of a period-k orbit: the harmonic the contact amplifies.

    * Orbits in permanent contact: the harmonic ``j`` (frequency ``j f_e / k``) with the largest
      *acceleration* amplitude ``j² |Y_j|`` among those at or below ``1.1 f_n0`` — a softening
      contact only amplifies frequencies below its linear natural frequency (Eq. 2.6); ν = j/k.
    * Orbits that lose contact: their spectrum is broadband (impacts), and each minimum of y(t)
      is one resonant oscillation between impacts, so ν = n/k (minima per excitation period).
    """
    if loses_contact or harmonics is None:
        return Fraction(int(max(n_min, 1)), int(k))
    h = np.asarray(harmonics, float)
    j = np.arange(1, h.size + 1)
    ok = np.isfinite(h) & (j * fe_hz / k <= 1.1 * fn0_hz)
    if not ok.any():
        return Fraction(1, 1)
    score = np.where(ok, j * j * np.nan_to_num(h), -1.0)
    return Fraction(int(j[int(np.argmax(score))]), int(k))


def attractor_type(kind: int, lyapunov: float) -> str:
    """"periodic", or for attractors without a period ≤ kmax, by their largest Lyapunov exponent
    λ of the stroboscopic map: "chaotic" (λ > 0.02), "quasi-periodic" (|λ| ≤ 0.02) or
    "long-period" (λ < −0.02: a stable orbit of period above kmax, still converging)."""
    if kind == 0:
        return "periodic"
    if not math.isfinite(lyapunov):
        return "non-periodic"
    if lyapunov > LYAPUNOV_ZERO:
        return "chaotic"
    if lyapunov < -LYAPUNOV_ZERO:
        return "long-period"
    return "quasi-periodic"


def resonance_label(kind: int, k: int, nu: Fraction, n_min: int, loses_contact: bool, fe_hz: float,
                    fn0_hz: float) -> str:
    """Name of the resonance of an attractor with resonance ratio ``nu`` (:func:`dominant_ratio`).

    * non-periodic → ``"non-periodic (1/m)"`` with m the mean number of minima per excitation
      period over the recorded 32 periods (``nu``), rounded: the resonance whose cascade it ends;
    * ν = m integer, k = 1: m = 1 → ``"main"`` (``"non-resonant"`` when contact is kept and
      f_e < f_n0/2: the quasistatic motion below the resonances), m ≥ 2 → ``"1/m"``;
    * ν = m integer, k > 1 → ``"1/m period-k"`` (``"main period-k"``): after period doubling;
    * ν = p/q, q > 1 → ``"subharmonic 1/q"`` (p = 1) or ``"ultrasubharmonic p/q"``, with
      ``" bouncing"`` appended when the orbit has fewer minima than periods (n < k).

    The minima count alone would mislead: the early 1/5 resonance (287 Hz, 0.65 Q) has two minima
    per period, but its fifth harmonic dominates the acceleration.
    """
    if kind != 0:
        if nu is None:
            return "non-periodic"
        m = max(1, int(round(float(nu))))
        return f"non-periodic ({'main' if m == 1 else f'1/{m}'})"
    if nu.denominator == 1:
        m = nu.numerator
        if k == 1:
            if m == 1:
                return "non-resonant" if (not loses_contact and fe_hz < 0.5 * fn0_hz) else "main"
            return f"1/{m}"
        return f"main period-{k}" if m == 1 else f"1/{m} period-{k}"
    base = (f"subharmonic 1/{nu.denominator}" if nu.numerator == 1
            else f"ultrasubharmonic {nu.numerator}/{nu.denominator}")
    return base + (" bouncing" if n_min < k else "")


#: Longest flicker of the dominant-harmonic label that is smoothed away along a continued branch,
#: as a fraction of its frequency (see :func:`smooth_labels`).
LABEL_FLICKER = 0.03


def smooth_labels(labels, fe, minima, chains, df_hz: float, flicker: float = LABEL_FLICKER):
    """Labels with short flickers removed along continuous branches.

    In the flank of a peak two or three harmonics can be about equally amplified, and the
    dominant-harmonic label then flickers along one continuous orbit family (0.90 Q, 230–234 Hz:
    1/6 → 1/7 → 1/5 → 1/6 on an orbit with six minima throughout). A run of one label ``1/j`` on a
    chain of Newton-continued orbits (same kind and period) takes the label ``1/m`` of both its
    sides when it spans at most ``flicker`` of its frequency (or two grid steps), its orbits have
    m minima and not j.
    A short run whose minima agree with its own label is a resonance of its own and is kept (the
    early 1/6 at 234 Hz, 0.85 Q, inside the flank of the 1/5).

    Parameters
    ----------
    labels : object array (n,)
    fe : float array (n,) [Hz]
    minima : int array (n,)
        Minima per period of every row.
    chains : int array (n,)
        Chain id of every row (rows linked by Newton continuation, same kind and period).
    df_hz : float
        Grid step [Hz].
    """
    out = labels.copy()
    for c in np.unique(chains):
        idx = np.nonzero(chains == c)[0]
        if idx.size < 3 or np.unique(fe[idx]).size != idx.size:
            continue  # two orbits at one frequency: not a single path along f_e
        idx = idx[np.argsort(fe[idx], kind="stable")]
        lab = out[idx]
        n_row = minima[idx]
        i = 0
        while i < idx.size - 1:
            side = lab[i]
            m = period_one_order(side)
            # the next row with the same label after a run of other labels
            j = i + 1
            while j < idx.size and lab[j] != side:
                j += 1
            if m is None or j == i + 1 or j == idx.size:
                i = j if j > i + 1 else i + 1
                continue
            seg = np.arange(i + 1, j)
            orders = [period_one_order(x) for x in lab[seg]]
            f0, f1 = fe[idx[seg[0]]], fe[idx[seg[-1]]]
            if (None not in orders and f1 - f0 + df_hz <= max(flicker * 0.5 * (f0 + f1), 2 * df_hz)
                    and np.all(n_row[seg] == m)
                    and not any(n == o for n, o in zip(n_row[seg], orders))):
                lab[seg] = side
            i = j
        out[idx] = lab
    return out


def level_labels(rows, fe, fn0_hz: float, chains, df_hz: float, np_record: int):
    """Resonance ratios ν and smoothed labels of every row of a level's trace.

    ``rows``: the trace's rows (``kind``, ``k``, ``n_min``, ``xmin``, ``harm``); ``fe`` [Hz] per
    row; ``chains``: chain id per row (rows continued by Newton, same kind and period);
    ``np_record``: periods over which a non-periodic attractor's minima were counted.
    Returns ``(nus, labels)``: a list of Fractions and an object array of strings.
    """
    kind, k = rows.kind, rows.k
    n = kind.size
    nmin = np.where(kind == 0, rows.n_min, -1)
    loses = rows.xmin < 0.0
    nus = [dominant_ratio(int(k[j]), int(nmin[j]), rows.harm[j], bool(loses[j]), float(fe[j]),
                          fn0_hz) if kind[j] == 0
           else Fraction(int(rows.n_min[j]), np_record) for j in range(n)]
    labels = np.array([resonance_label(int(kind[j]), int(k[j]), nus[j], int(nmin[j]), bool(loses[j]),
                                       float(fe[j]), fn0_hz) for j in range(n)], dtype=object)
    return nus, smooth_labels(labels, fe, nmin, chains, df_hz)
