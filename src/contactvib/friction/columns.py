"""Friction columns of a resonance dataset: the steady tangential motion under every
periodic point of a level, as variables of dimension ``point``.

A sweep with ``SweepSettings(friction=FrictionModel(...))`` (``contactvib resonance/atlas
--friction mu=…,vd=…``) adds, per point (NaN where the point is non-periodic or its tangential
run failed):

``friction_ratio`` [1]
    ⟨F_drive⟩ / (μ W): the apparent friction coefficient over μ, its ratio to the no-vibration
    value (:class:`~contactvib.friction.FrictionResult`);
``friction_stick_fraction``, ``friction_slip_fraction``, ``friction_free_fraction`` [1]
    fractions of the period the contact sticks, slips, and carries no tangential force (no
    compression: the flight fraction of the tangential motion);
``tangential_app_um`` [µm]
    peak-to-peak of u − v_d t, the tangential displacement oscillation (NaN under a force drive);
``friction_settled`` [1]
    1 where the tangential motion became periodic (else the means are long-time averages).

The FrictionModel's parameters are the dataset attribute ``friction`` (JSON) and part of its
``settings`` (a resumed chunk made with other friction settings is refused). Datasets swept
without friction have none of these.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np

from contactvib.errors import ComputationError
from contactvib.friction.model import FrictionModel
from contactvib.friction.newton import WarmStart
from contactvib.friction.tangential import friction_at

__all__ = ["FRICTION_VARIABLES", "friction_variables", "with_friction"]

#: The point variables of a sweep with friction: (FrictionResult attribute, attributes).
FRICTION_VARIABLES = {
    "friction_ratio": ("friction_ratio", {
        "units": "1", "long_name": "apparent friction coefficient over mu, <F_drive>/(mu (Q + F_pre))",
        "comment": "1 without normal vibration; NaN for non-periodic points"}),
    "friction_stick_fraction": ("stick_fraction", {"units": "1", "long_name": "fraction of the period in stick"}),
    "friction_slip_fraction": ("slip_fraction", {"units": "1", "long_name": "fraction of the period in slip"}),
    "friction_free_fraction": ("free_fraction", {
        "units": "1", "long_name": "fraction of the period without compression (no tangential force)"}),
    "tangential_app_um": ("tangential_app_um", {
        "units": "um", "long_name": "peak-to-peak of u - v_d t, the tangential displacement oscillation"}),
    "friction_settled": ("settled", {"units": "1", "comment": "1 where the tangential motion became periodic"}),
}


@dataclass(frozen=True)
class _Orbit:
    """What :func:`friction_at` reads of a periodic point: its phase-0 state, period and flight."""

    state: np.ndarray
    period: int
    contact_loss_fraction: float


def _predecessors(level) -> np.ndarray:
    """Per row, the row continued by Newton into it (a link without a jump; −1: none), computed
    before it: its steady tangential state starts this row's."""
    before = np.full(level.n_rows, -1, np.int64)
    links = level.links
    for a, b, jump in zip(links.a, links.b, links.jump):
        if jump == 0 and 0 <= a < b and before[b] < 0:
            before[b] = a
    return before


def friction_variables(model, level, settings) -> dict:
    """The :data:`FRICTION_VARIABLES` of every row of ``level`` (a
    :class:`contactvib.sweeps.sweep.LevelTrace`) swept with ``settings`` (a SweepSettings whose
    ``friction`` is set), as ``{name: ("point", values, attrs)}``."""
    from contactvib.interrupts import check_interrupt

    fm = settings.friction
    if not isinstance(fm, FrictionModel):
        raise TypeError("settings.friction must be a FrictionModel")
    rows, n = level.rows, level.n_rows
    values = {name: np.full(n, math.nan) for name in FRICTION_VARIABLES}
    before = _predecessors(level)
    warm: dict = {}  # row -> its WarmStart (the steady tangential state, for the next point of its branch)
    for j in range(n):
        if rows.kind[j] != 0:
            continue
        check_interrupt()  # between kernel calls: a deferred Ctrl-C is honoured here
        exc = settings.excitation_at(model, level.pa_over_q, float(level.f_hz[rows.i[j]]))
        orbit = _Orbit(np.asarray(rows.z[j], float), int(rows.k[j]), float(rows.flight[j]))
        try:
            ws = warm.pop(before[j], None) if before[j] >= 0 else None
            ws = WarmStart() if ws is None else ws
            res = friction_at(exc, orbit, friction=fm, with_limit=False, warm=ws)
            warm[j] = ws
        except ComputationError:
            continue
        for name, (attr, _a) in FRICTION_VARIABLES.items():
            values[name][j] = float(getattr(res, attr))
    out = {name: ("point", values[name], dict(attrs)) for name, (_r, attrs) in FRICTION_VARIABLES.items()}
    out["friction_settled"] = ("point", np.where(np.isnan(values["friction_settled"]), -1,
                                                 values["friction_settled"]).astype(np.int8),
                               {**FRICTION_VARIABLES["friction_settled"][1],
                                "comment": "1 where the tangential motion became periodic, 0 where not, "
                                           "-1 where not computed (non-periodic point or failed run)"})
    return out


def with_friction(ds, model, level, settings):
    """``ds`` (the level's dataset) with the friction variables of ``level`` and the attribute
    ``friction`` (the FrictionModel's parameters, JSON); ``ds`` itself when ``settings`` has no
    friction."""
    if settings.friction is None:
        return ds
    ds = ds.assign(friction_variables(model, level, settings))
    ds.attrs["friction"] = json.dumps(settings.friction.parameters())
    return ds
