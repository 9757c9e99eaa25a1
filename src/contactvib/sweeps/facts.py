"""What a resonance dataset shows about each 1/m resonance at one P_a level (Kostek 2013, S3.1–S3.9).

:func:`resonance_facts` reads the labelled branches of one level and says whether the 1/m
resonance is present, where its peak is, whether it has bent, its period-doubling cascade, the
non-periodic attractors next to it, its parts and the parts no sweep reaches, and its stage
(S3.8: grows → bent → period doubling → chaos → divided). Everything is computed from the data.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib.labels import resonance_order
from contactvib.sweeps.stored import MissingLevel, ResonanceData

__all__ = ["ResonanceFacts", "resonance_facts", "level_stages", "coexisting_resonances", "max_coexistence",
           "intervals", "SUPERHARMONIC_ORDERS"]

#: The superharmonic resonances the paper follows (S3.8): 1/2 … 1/6.
SUPERHARMONIC_ORDERS = (2, 3, 4, 5, 6)


@dataclass
class ResonanceFacts:
    """What one P_a level of a dataset shows about the 1/m resonance (m = 1: main). Units: Hz, µm."""

    m: int
    fn0_over_m_hz: float
    present: bool
    peak_fe_hz: float = math.nan
    peak_app_um: float = math.nan
    coexisting_fe_hz: list = field(default_factory=list)   # ≥ 2 period-1 1/m orbits: a bent peak
    period_doubled: dict = field(default_factory=dict)      # period k → (f_min, f_max)
    nonperiodic_fe_hz: list = field(default_factory=list)   # non-periodic attractors of this order
    parts_hz: list = field(default_factory=list)            # disjoint f-intervals of its orbits
    isolated_hz: list = field(default_factory=list)         # branches no sweep reaches
    reached_by_sweep: bool = True                           # some orbit of it is reached by a sweep

    @property
    def bent(self) -> bool:
        """The peak leans left: its highest period-1 orbit lies below 0.9 f_n0/m, or two period-1
        orbits of the resonance coexist (a fold)."""
        return (len(self.coexisting_fe_hz) > 0
                or (math.isfinite(self.peak_fe_hz) and self.peak_fe_hz < 0.9 * self.fn0_over_m_hz))

    def stage(self) -> str:
        """The paper's stage (S3.8): absent / grows / bent / period doubling / chaos / divided.

        Divided: more than one part, or (m > 1) no orbit of it is reached by a sweep (the part
        that remains is isolated: S3.7)."""
        if not self.present:
            return "absent"
        if len(self.parts_hz) > 1 or (self.m > 1 and not self.reached_by_sweep):
            return "divided"
        if self.nonperiodic_fe_hz:
            return "chaos"
        if self.period_doubled:
            return "period doubling"
        if self.bent:
            return "bent"
        return "grows"


def intervals(f: np.ndarray, gap: float) -> list:
    f = np.unique(f)
    if f.size == 0:
        return []
    cut = np.nonzero(np.diff(f) > gap)[0]
    return [(float(s[0]), float(s[-1])) for s in np.split(f, cut + 1)]


def _orders(labels, sel) -> np.ndarray:
    """Resonance order m of each selected label (:func:`.labels.resonance_order`), 0 for none and
    where not selected; each distinct label is parsed once."""
    out = np.zeros(len(labels), np.int64)
    idx = np.flatnonzero(sel)
    if idx.size:
        uniq, inv = np.unique(np.asarray(labels)[idx].astype(str), return_inverse=True)
        out[idx] = np.array([resonance_order(x) or 0 for x in uniq], np.int64)[inv.reshape(-1)]
    return out


def resonance_facts(ds, pa_over_q: float, m: int, f_band=None) -> ResonanceFacts:
    """Facts about the 1/m resonance (main for m = 1) at one P_a level of a resonance dataset.

    Orbits of order m are the points labelled ``main``/``1/m`` and ``non-periodic (1/m)``;
    bouncing sub-/ultrasubharmonic orbits are not counted. The resonance proper is its period-1
    orbits plus its period-doubling cascade: period-2k branches that start within two grid steps
    of a period-k orbit of the cascade with an A_pp within 25 % (a period doubling is continuous),
    and non-periodic attractors next to a doubled orbit (within 50 %). Period-3, -5, … orbits of
    the same order (other attractors, e.g. in periodic windows) are not part of it. Parts are
    separated by gaps of more than 3 grid steps; ``f_band`` (Hz, optional) restricts f_e.
    """
    df = float(json.loads(ds.attrs["settings"])["df_hz"])
    fn0 = float(ds.attrs["fn0_hz"])
    sel = np.zeros(ds.sizes["point"], bool)
    sel[ResonanceData(ds).points(pa_over_q)] = True  # MissingLevel (a ValueError) when not stored
    mine = sel & (_orders(ds["resonance"].values, sel) == m)
    if f_band is not None:
        fe_all = ds["fe_hz"].values
        mine &= (fe_all >= f_band[0]) & (fe_all <= f_band[1])
    facts = ResonanceFacts(m=m, fn0_over_m_hz=fn0 / m, present=bool(mine.any()))
    if not facts.present:
        return facts
    fe = ds["fe_hz"].values[mine]
    app = ds["app_um"].values[mine]
    k = ds["period"].values[mine]
    br = ds["branch_index"].values[mine]
    periodic = ds["kind"].values[mine] == "periodic"
    p1 = periodic & (k == 1)
    if p1.any():
        j = np.argmax(np.where(p1, app, -1.0))
        facts.peak_fe_hz, facts.peak_app_um = float(fe[j]), float(app[j])
        u, c = np.unique(fe[p1], return_counts=True)
        facts.coexisting_fe_hz = [float(x) for x in u[c >= 2]]

    def adjacent(cand, prev, rel):
        """Points of ``cand`` within 2 grid steps and ``rel`` (relative A_pp) of a ``prev`` point."""
        out = np.zeros_like(cand)
        pi = np.nonzero(prev)[0]
        if pi.size == 0:
            return out
        for j in np.nonzero(cand)[0]:
            near = np.abs(fe[pi] - fe[j]) <= 2.0 * df + 1e-9
            out[j] = np.any(near & (np.abs(app[pi] - app[j]) <= rel * np.maximum(app[pi], app[j])))
        return out

    # the period-doubling cascade: period-2k orbits born where a period-k orbit of the family
    # ends (within two grid steps, continuous amplitude), followed along their whole branches
    chain = p1.copy()
    kk = 1
    while kk < 64:
        cand = periodic & (k == 2 * kk)
        hit = adjacent(cand, chain & (k == kk), 0.25)
        if not hit.any():
            break
        new = cand & np.isin(br, np.unique(br[hit]))
        facts.period_doubled[2 * kk] = (float(fe[new].min()), float(fe[new].max()))
        chain |= new
        kk *= 2
    chaos = adjacent(~periodic, chain & (k > 1), 0.5)
    facts.nonperiodic_fe_hz = [float(x) for x in np.unique(fe[chaos])]
    facts.parts_hz = intervals(fe[chain | chaos], 3.0 * df)
    reach = ds["branch_reached_by_sweep"].values
    iso = np.unique(br[chain & (reach[br] == 0)])
    facts.reached_by_sweep = bool(np.any(reach[br[chain]] == 1))
    facts.isolated_hz = intervals(np.concatenate(
        [np.arange(ds["branch_fmin_hz"].values[x], ds["branch_fmax_hz"].values[x] + 0.5 * df, df)
         for x in iso]) if iso.size else np.array([]), 1.5 * df)
    return facts


def level_stages(ds, pa_over_q: float, orders=SUPERHARMONIC_ORDERS) -> dict:
    """The stage (S3.8) of each 1/m resonance at one level: ``{m: "grows" | "bent" | …}``, from
    :meth:`ResonanceFacts.stage` (the S3.8 table of the index page and the film's captions)."""
    return {m: resonance_facts(ds, pa_over_q, m).stage() for m in orders}


def coexisting_resonances(ds, pa_over_q: float, fe_hz: float) -> list:
    """Resonance orders m of the stable period-1 orbits of order m stored at (P_a, f_e), sorted."""
    res = ResonanceData(ds).attractors_at(pa_over_q, fe_hz)
    ms = {resonance_order(a["resonance"]) for a in res["attractors"] if a["period"] == 1}
    return sorted(m for m in ms if m is not None)


def max_coexistence(ds, pa_over_q: float):
    """(largest number of resonance orders with period-1 orbits at one frequency, those f [Hz])."""
    try:
        sel = ResonanceData(ds).points(pa_over_q)
    except MissingLevel:
        return 0, []
    sel = sel[(ds["period"].values[sel] == 1) & (ds["kind"].values[sel] == "periodic")]
    orders = _orders(ds["resonance"].values[sel], np.ones(sel.size, bool))
    fe = ds["fe_hz"].values[sel]
    by_f: dict = {}
    for f, m in zip(fe, orders):
        if m:
            by_f.setdefault(float(f), set()).add(int(m))
    if not by_f:
        return 0, []
    n = max(len(v) for v in by_f.values())
    return n, sorted(f for f, v in by_f.items() if len(v) == n)


# ----------------------------------------------------------------------------- figures
