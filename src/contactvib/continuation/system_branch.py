"""Results of a system continuation (:mod:`.system_shooting`): the measured orbits, the special
points and the branch, with units (f_e [Hz], P_a [N], displacements in µm or µrad)."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib.continuation.branch import SpecialPoint, Stop

__all__ = ["SystemOrbitRecord", "SystemSpecialPoint", "SystemBranch", "stop_dict"]


@dataclass(frozen=True)
class SystemOrbitRecord:
    """Measurements of one orbit of a system branch (:meth:`SystemOrbitProblem.measure`).

    ``app``, ``qmin``, ``qmax``: each coordinate's peak-to-peak amplitude and extrema over the
    orbit in display units (µm, µrad); ``contact_loss``: each contact's fraction of the period
    open; ``floquet_multipliers``: Φ's eigenvalues, largest modulus first.
    """

    fe_hz: float
    pa_newton: float
    floquet_multipliers: np.ndarray
    app: np.ndarray
    qmin: np.ndarray
    qmax: np.ndarray
    contact_loss: np.ndarray


@dataclass(frozen=True)
class SystemSpecialPoint(SpecialPoint):
    """A located special point of a system branch: :class:`~.branch.SpecialPoint` with the level
    P_a [N] (``pa_over_q`` is P_a/Q, NaN where the system defines no Q), ``app_um`` the plotted
    coordinate's A_pp (µm or µrad), ``state`` the SI orbit point (2n) and, at a Neimark–Sacker
    point, the crossing pair's angle θ/2π [1]."""

    pa_newton: float = math.nan
    angle_over_2pi: float = math.nan

    def to_dict(self) -> dict:
        d = {"type": self.type, "fe_hz": float(self.fe_hz), "pa_newton": float(self.pa_newton)}
        if math.isfinite(self.pa_over_q):
            d["pa_over_q"] = float(self.pa_over_q)
        d.update({"period": int(self.period), "branch": self.branch,
                  "floquet_multipliers": [[float(m.real), float(m.imag)] for m in self.floquet_multipliers],
                  "floquet_abs": [float(abs(m)) for m in self.floquet_multipliers],
                  "test_value": float(self.test_value)})
        if self.type == "neimark-sacker":
            d["angle_over_2pi"] = float(self.angle_over_2pi)
        return {**d, **self.measures}


@dataclass
class SystemBranch:
    """A continued branch of period-k orbits of a system, ordered along the arclength.

    Attributes
    ----------
    branch, period, parameter : str, int, str
        Id, period [excitation periods], ``"f_e"`` or ``"P_a"``.
    fe_hz, pa_newton : ndarray (N,)
        f_e [Hz] and P_a [N] of each point.
    pa_over_q : ndarray (N,)
        P_a / Q (NaN where the system defines no Q).
    app, qmin, qmax : ndarray (N, n)
        Each coordinate's peak-to-peak amplitude and extrema in display units (``units``).
    contact_loss_fraction : ndarray (N, m)
        Each contact's fraction of the period open.
    floquet_multipliers : ndarray of complex (N, 2n)
        Largest modulus first.
    stable : ndarray of bool (N,)
    state : ndarray (N, 2n)
        Orbit point (q, q̇) [SI] at phase 0.
    arclength : ndarray (N,)
        Scaled pseudo-arclength from the first point.
    coordinates, units, contacts : tuple of str
        Names and display units of the columns of ``app``, names of the contacts.
    coordinate : int
        The coordinate whose A_pp is :attr:`app_um` (the one plotted).
    special, stops : list
    """

    branch: str
    period: int
    parameter: str
    fe_hz: np.ndarray
    pa_newton: np.ndarray
    pa_over_q: np.ndarray
    app: np.ndarray
    qmin: np.ndarray
    qmax: np.ndarray
    contact_loss_fraction: np.ndarray
    floquet_multipliers: np.ndarray
    stable: np.ndarray
    state: np.ndarray
    arclength: np.ndarray
    coordinates: tuple
    units: tuple
    contacts: tuple
    coordinate: int = 0
    special: list = field(default_factory=list)
    stops: list = field(default_factory=list)
    settings: dict = field(default_factory=dict)

    def __len__(self):
        return int(self.fe_hz.shape[0])

    @property
    def app_um(self) -> np.ndarray:
        """A_pp of the plotted coordinate (µm, or µrad for a rotation)."""
        return self.app[:, self.coordinate]

    @property
    def floquet_abs_max(self) -> np.ndarray:
        return np.max(np.abs(self.floquet_multipliers), axis=1)

    def to_xarray(self):
        """The branch as an :class:`xarray.Dataset` (dimensions ``point``, ``coordinate``,
        ``contact``, ``multiplier``, ``component``), units in attrs."""
        import xarray as xr

        mu = self.floquet_multipliers
        unit = "/".join(sorted(set(self.units)))
        return xr.Dataset(
            {
                "fe_hz": ("point", self.fe_hz, {"units": "Hz", "long_name": "excitation frequency f_e"}),
                "pa_newton": ("point", self.pa_newton, {"units": "N", "long_name": "excitation amplitude P_a"}),
                "pa_over_q": ("point", self.pa_over_q, {"units": "Q", "long_name": "P_a / Q (NaN: no Q)"}),
                "app": (("point", "coordinate"), self.app, {"units": unit, "long_name": "peak-to-peak amplitude"}),
                "qmin": (("point", "coordinate"), self.qmin, {"units": unit, "long_name": "minimum over the orbit"}),
                "qmax": (("point", "coordinate"), self.qmax, {"units": unit, "long_name": "maximum over the orbit"}),
                "contact_loss_fraction": (("point", "contact"), self.contact_loss_fraction,
                                          {"units": "1", "long_name": "fraction of the period open"}),
                "floquet_re": (("point", "multiplier"), mu.real, {"units": "1"}),
                "floquet_im": (("point", "multiplier"), mu.imag, {"units": "1"}),
                "stable": ("point", self.stable.astype(np.int8), {"units": "1"}),
                "state": (("point", "component"), self.state,
                          {"units": "SI", "long_name": "orbit point (q, qdot) at phase 0"}),
                "arclength": ("point", self.arclength, {"units": "1"}),
            },
            coords={"point": np.arange(len(self)), "coordinate": list(self.coordinates),
                    "coordinate_unit": ("coordinate", list(self.units)), "contact": list(self.contacts),
                    "multiplier": np.arange(mu.shape[1]), "component": np.arange(self.state.shape[1])},
            attrs={"branch": self.branch, "period": int(self.period), "parameter": self.parameter,
                   "special_points": json.dumps([s.to_dict() for s in self.special]),
                   "stops": json.dumps([stop_dict(s) for s in self.stops]),
                   "settings": json.dumps(self.settings)})

    def to_netcdf(self, path) -> None:
        self.to_xarray().to_netcdf(path)


def stop_dict(s: Stop) -> dict:
    """A stop of a system branch as JSON: f_e [Hz], P_a [N] (kept in ``Stop.pa_over_q``), reason."""
    return {"fe_hz": float(s.fe_hz), "pa_newton": float(s.pa_over_q), "reason": s.reason, "branch": s.branch}
