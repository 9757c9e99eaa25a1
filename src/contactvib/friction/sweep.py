"""Friction under normal vibration over a grid: against the excitation frequency at one level
(every attractor the search finds at each f_e), or against the drive velocity at one operating
point. One loop over :func:`contactvib.friction.friction_at`; the rows are a
:class:`FrictionSweep`."""

from __future__ import annotations

import csv
from dataclasses import dataclass, field, replace

import numpy as np

from contactvib.errors import ComputationError
from contactvib.friction.model import FrictionModel
from contactvib.friction.tangential import friction_at
from contactvib.model import ContactModel, Excitation, ParameterError, check_range
from contactvib.steady import attractors as _search

__all__ = ["FrictionSweep", "friction_vs_frequency", "friction_vs_velocity", "check_velocities"]

#: Columns of a sweep, in order, with their units.
COLUMNS = {"fe_hz": "Hz", "vd_mm_s": "mm/s", "attractor": "1", "period": "excitation periods", "app_um": "um",
           "contact_loss_fraction": "1", "friction_ratio": "1", "stick_fraction": "1", "slip_fraction": "1",
           "free_fraction": "1", "tangential_app_um": "um", "settled": "1"}


@dataclass
class FrictionSweep:
    """Rows of friction results: one per (grid point, periodic normal attractor).

    Attributes
    ----------
    rows : dict of str -> ndarray
        The :data:`COLUMNS` (``attractor``: its rank by A_pp at that point, largest first).
    pa_over_q : float
        Excitation level [Q].
    friction : dict
        The FrictionModel's parameters (``vd`` the drive velocity of a frequency sweep).
    skipped : int
        Non-periodic normal attractors and failed tangential runs left out.
    """

    rows: dict = field(default_factory=lambda: {k: np.empty(0) for k in COLUMNS})
    pa_over_q: float = 0.0
    friction: dict = field(default_factory=dict)
    skipped: int = 0

    def __len__(self) -> int:
        return len(self.rows["fe_hz"])

    def to_dict(self) -> dict:
        """JSON-ready: the level, the parameters and the rows as a list of objects."""
        keys = list(COLUMNS)
        points = [{k: _plain(self.rows[k][i]) for k in keys} for i in range(len(self))]
        return {"pa_over_q": self.pa_over_q, "friction": self.friction, "skipped": self.skipped,
                "units": COLUMNS, "points": points}

    def to_csv(self, path) -> None:
        """Write the rows as CSV with a header of the column names."""
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(list(COLUMNS))
            for i in range(len(self)):
                w.writerow([_plain(self.rows[k][i]) for k in COLUMNS])


def _plain(v):
    if isinstance(v, (np.bool_, bool)):
        return bool(v)
    if isinstance(v, (np.integer,)):
        return int(v)
    return float(v)


def _rows(acc: list) -> dict:
    return {k: np.array([r[k] for r in acc]) if acc else np.empty(0) for k in COLUMNS}


def _row(exc: Excitation, vd: float, rank: int, a, res) -> dict:
    return {"fe_hz": exc.f_e, "vd_mm_s": vd, "attractor": rank, "period": a.period, "app_um": a.app_um,
            "contact_loss_fraction": a.contact_loss_fraction, "friction_ratio": res.friction_ratio,
            "stick_fraction": res.stick_fraction, "slip_fraction": res.slip_fraction,
            "free_fraction": res.free_fraction, "tangential_app_um": res.tangential_app_um,
            "settled": res.settled}


def friction_vs_frequency(model: ContactModel, excitations, friction: FrictionModel | None = None,
                          search: dict | None = None, on_point=None) -> FrictionSweep:
    """The friction of every periodic attractor at each excitation of ``excitations`` (one level,
    a grid of f_e), the attractors found by ``find_attractors(exc, **search)``;
    ``on_point(exc, rows)`` is called after each frequency (progress)."""
    fm = FrictionModel() if friction is None else friction
    acc, skipped = [], 0
    for exc in excitations:
        found = _search.find_attractors(exc, **(search or {}))
        new = []
        for rank, a in enumerate(found):
            try:
                new.append(_row(exc, fm.vd, rank, a, friction_at(exc, a, friction=fm)))
            except ComputationError:
                skipped += 1
        acc += new
        if on_point is not None:
            on_point(exc, new)
    level = excitations[0].pa_over_q if len(excitations) else 0.0
    return FrictionSweep(_rows(acc), level, fm.parameters(), skipped)


def check_velocities(vmin, vmax, n) -> np.ndarray:
    """``n`` drive velocities [mm/s] spaced logarithmically from ``vmin`` to ``vmax`` (> 0)."""
    from contactvib.model import check_int

    lo = check_range("v_min", vmin, 0.0, False, "mm/s", upper=1e6)
    hi = check_range("v_max", vmax, lo, False, "mm/s", upper=1e6, lower_name="v_min")
    n = check_int("n_vd", n, 2, 1000)
    return np.geomspace(lo, hi, n)


def friction_vs_velocity(model: ContactModel, excitation: Excitation, attractors, velocities,
                         friction: FrictionModel | None = None) -> FrictionSweep:
    """The friction of each periodic attractor of ``attractors`` at each drive velocity [mm/s]."""
    fm = FrictionModel() if friction is None else friction
    if not len(velocities):
        raise ParameterError("v_d", velocities, "needs at least one drive velocity")
    acc, skipped = [], 0
    for rank, a in enumerate(attractors):
        for vd in velocities:
            try:
                res = friction_at(excitation, a, friction=replace(fm, vd=float(vd)))
            except ComputationError:
                skipped += 1
                break
            acc.append(_row(excitation, float(vd), rank, a, res))
    return FrictionSweep(_rows(acc), excitation.pa_over_q, fm.parameters(), skipped)
