"""Branch results with units: points of a continued branch, special points, stops.

Conventions as :mod:`contactvib.steady.results`: y [µm] positive downwards (contact deflection; y < 0 is
a gap), f_e [Hz], P_a in multiples of Q = M g. Stored column by column (as BifurcationKit's
``ContResult``) and convertible to an :class:`xarray.Dataset` (NetCDF).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

__all__ = ["SpecialPoint", "Stop", "Branch", "BranchSet", "SPECIAL_TYPES"]

#: Special-point types of the JSON contract.
SPECIAL_TYPES = ("fold", "period-doubling", "neimark-sacker", "grazing")


@dataclass(frozen=True)
class SpecialPoint:
    """A located bifurcation or grazing point on a branch.

    Attributes
    ----------
    type : str
        One of ``SPECIAL_TYPES``.
    fe_hz : float
        Excitation frequency [Hz].
    pa_over_q : float
        Excitation amplitude [Q].
    app_um : float
        Peak-to-peak amplitude of the orbit there [µm].
    period : int
        Period of the branch it lies on [excitation periods] (before any doubling).
    branch : str
        Id of that branch.
    floquet_multipliers : ndarray of complex, shape (2,)
        Floquet multipliers there.
    state : ndarray, shape (2,)
        Nondimensional orbit point (x, x') at phase 0.
    test_value : float
        Residual of the test function at the located point (det(M − I), det(M + I), det M − 1
        or x_min).
    bracket : tuple of float
        f_e [Hz] of the two branch points that enclose it.
    """

    type: str
    fe_hz: float
    pa_over_q: float
    app_um: float
    period: int
    branch: str
    floquet_multipliers: np.ndarray = field(repr=False)
    state: np.ndarray = field(repr=False)
    test_value: float = 0.0
    bracket: tuple = (np.nan, np.nan)
    #: the orbit's ``dofs`` and ``contacts`` (JSON contract) where they were measured, else empty
    measures: dict = field(default_factory=dict, repr=False, compare=False)

    def to_dict(self) -> dict:
        """The JSON contract entry: type, fe_hz, pa_over_q, app_um, period, branch (and the
        orbit's ``dofs`` and ``contacts`` where measured)."""
        return {"type": self.type, "fe_hz": float(self.fe_hz), "pa_over_q": float(self.pa_over_q),
                "app_um": float(self.app_um), "period": int(self.period), "branch": self.branch,
                **self.measures}


@dataclass(frozen=True)
class Stop:
    """Where and why a continuation stopped (one per direction)."""

    fe_hz: float
    pa_over_q: float
    reason: str
    branch: str
    #: approximate period-k/2 orbit point where a period-k branch merges (else None)
    merge_state: np.ndarray | None = field(default=None, repr=False)

    def to_dict(self) -> dict:
        return {"fe_hz": float(self.fe_hz), "pa_over_q": float(self.pa_over_q),
                "reason": self.reason, "branch": self.branch}


@dataclass
class Branch:
    """A continued branch of period-k orbits, ordered along the arclength.

    Attributes
    ----------
    branch : str
        Id (``"pa0.65/b0"``, ``".../b0.pd1"`` for a branch switched onto at a period doubling).
    period : int
        Period of the orbits [excitation periods].
    parameter : str
        Continuation parameter, ``"f_e"`` or ``"P_a"``.
    fe_hz, pa_over_q : ndarray (n,)
        Excitation frequency [Hz] and amplitude [Q] of each point.
    app_um, ymin_um, ymax_um : ndarray (n,)
        Peak-to-peak amplitude and extrema of y over the orbit [µm].
    floquet_multipliers : ndarray of complex (n, 2)
        Floquet multipliers.
    stable : ndarray of bool (n,)
        All ``|multipliers|`` < 1.
    state : ndarray (n, 2)
        Nondimensional orbit point (x = y/y0, x' = ẏ/(y0 ω_n0)) at phase 0.
    contact_loss_fraction : ndarray (n,)
        Fraction of the period with y < 0.
    minima_per_period : ndarray of int (n,)
        Local minima of y over the period-k orbit.
    arclength : ndarray (n,)
        Scaled pseudo-arclength (relative units) from the first point.
    special : list of SpecialPoint
    stops : list of Stop
    parent : str or None
        The branch it was switched from (period doubling), if any.
    settings : dict
        Continuation settings used.
    """

    branch: str
    period: int
    parameter: str
    fe_hz: np.ndarray
    pa_over_q: np.ndarray
    app_um: np.ndarray
    ymin_um: np.ndarray
    ymax_um: np.ndarray
    floquet_multipliers: np.ndarray
    stable: np.ndarray
    state: np.ndarray
    contact_loss_fraction: np.ndarray
    minima_per_period: np.ndarray
    arclength: np.ndarray
    special: list = field(default_factory=list)
    stops: list = field(default_factory=list)
    parent: str | None = None
    fn0_hz: float = np.nan
    y0_um: float = np.nan
    settings: dict = field(default_factory=dict)

    def __len__(self):
        return int(self.fe_hz.shape[0])

    @property
    def floquet_abs_max(self) -> np.ndarray:
        """Largest ``|multiplier|`` at each point [1]."""
        return np.max(np.abs(self.floquet_multipliers), axis=1)

    def to_xarray(self):
        """The branch as an :class:`xarray.Dataset` (dimension ``point``), units in attrs.

        Variables: fe_hz, pa_over_q, app_um, ymin_um, ymax_um, floquet_re, floquet_im, stable,
        state_x, state_xdot, contact_loss_fraction, minima_per_period, arclength.
        """
        import xarray as xr

        mu = self.floquet_multipliers
        ds = xr.Dataset(
            {
                "fe_hz": ("point", self.fe_hz, {"units": "Hz", "long_name": "excitation frequency f_e"}),
                "pa_over_q": ("point", self.pa_over_q, _level_attrs(self.settings)),
                "app_um": ("point", self.app_um, {"units": "um", "long_name": "peak-to-peak amplitude A_pp"}),
                "ymin_um": ("point", self.ymin_um, {"units": "um", "long_name": "minimum of y (y < 0: gap)"}),
                "ymax_um": ("point", self.ymax_um, {"units": "um", "long_name": "maximum of y"}),
                "floquet_re": (("point", "multiplier"), mu.real,
                               {"units": "1", "long_name": "Floquet multipliers, real part"}),
                "floquet_im": (("point", "multiplier"), mu.imag,
                               {"units": "1", "long_name": "Floquet multipliers, imaginary part"}),
                "stable": ("point", self.stable.astype(np.int8),
                           {"units": "1", "long_name": "stable (1) / unstable (0)"}),
                "state_x": ("point", self.state[:, 0], {"units": "y0", "long_name": "orbit point y/y0 at phase 0"}),
                "state_xdot": ("point", self.state[:, 1], {"units": "y0 omega_n0",
                                                           "long_name": "orbit point dy/dt/(y0 omega_n0) at phase 0"}),
                "contact_loss_fraction": ("point", self.contact_loss_fraction, {"units": "1"}),
                "minima_per_period": ("point", self.minima_per_period.astype(np.int32),
                                      {"units": "1", "long_name": "minima of y per period-k orbit"}),
                "arclength": ("point", self.arclength, {"units": "1", "long_name": "scaled pseudo-arclength"}),
            },
            coords={"point": np.arange(len(self)), "multiplier": [0, 1]},
            attrs={"branch": self.branch, "period": int(self.period), "parameter": self.parameter,
                   "parent": self.parent or "", "fn0_hz": float(self.fn0_hz), "y0_um": float(self.y0_um),
                   "special_points": json.dumps([s.to_dict() for s in self.special]),
                   "stops": json.dumps([s.to_dict() for s in self.stops]),
                   "settings": json.dumps(self.settings)},
        )
        return ds

    def to_netcdf(self, path) -> None:
        """Write :meth:`to_xarray` to a NetCDF file."""
        self.to_xarray().to_netcdf(path)

    @classmethod
    def from_xarray(cls, ds) -> Branch:
        """The branch of a :meth:`to_xarray` dataset; the names written before the one naming
        scheme (fe, pa, app, ymin, ymax, mu_re/mu_im, x/xdot, minima) are read too. Special points
        come back without multipliers and state (the file keeps their JSON entries only, ``dofs`` and
        ``contacts`` included)."""
        def col(name):
            for n in (name, _OLD_NAMES.get(name)):
                if n is not None and n in ds.variables:
                    return np.asarray(ds[n].values)
            raise KeyError(f"branch file has no variable {name!r}")

        mu = col("floquet_re") + 1j * col("floquet_im")
        attrs = ds.attrs
        specials = [SpecialPoint(type=d["type"], fe_hz=d["fe_hz"], pa_over_q=d["pa_over_q"],
                                 app_um=d["app_um"], period=d["period"], branch=d["branch"],
                                 floquet_multipliers=np.full(2, np.nan, complex),
                                 state=np.full(2, np.nan),
                                 measures={k: d[k] for k in ("dofs", "contacts") if k in d})
                    for d in json.loads(attrs.get("special_points", "[]"))]
        stops = [Stop(d["fe_hz"], d["pa_over_q"], d["reason"], d["branch"])
                 for d in json.loads(attrs.get("stops", "[]"))]
        return cls(branch=str(attrs.get("branch", "")), period=int(attrs.get("period", 1)),
                   parameter=str(attrs.get("parameter", "f_e")), fe_hz=col("fe_hz"),
                   pa_over_q=col("pa_over_q"), app_um=col("app_um"), ymin_um=col("ymin_um"),
                   ymax_um=col("ymax_um"), floquet_multipliers=mu, stable=col("stable").astype(bool),
                   state=np.column_stack([col("state_x"), col("state_xdot")]),
                   contact_loss_fraction=col("contact_loss_fraction"),
                   minima_per_period=col("minima_per_period").astype(int), arclength=col("arclength"),
                   special=specials, stops=stops, parent=attrs.get("parent") or None,
                   fn0_hz=float(attrs.get("fn0_hz", np.nan)), y0_um=float(attrs.get("y0_um", np.nan)),
                   settings=json.loads(attrs.get("settings", "{}")))

    @classmethod
    def from_netcdf(cls, path) -> Branch:
        """Read a branch file written by :meth:`to_netcdf` (new or old variable names)."""
        import xarray as xr

        with xr.open_dataset(path) as ds:
            return cls.from_xarray(ds.load())


#: variable names of branch files written before the one naming scheme (read, never written)
def _level_attrs(settings: dict) -> dict:
    """Units of a branch's ``pa_over_q``: P_a/Q, or the level U [µm] / A [g] of a base-motion
    continuation in f_e (``settings["excitation"]``)."""
    kind = settings.get("excitation", "force")
    if kind == "force":
        return {"units": "Q", "long_name": "excitation amplitude P_a/Q"}
    from contactvib.model import LEVEL_KINDS

    _sym, unit, name = LEVEL_KINDS[kind]
    return {"units": unit, "long_name": f"{name} (the level of this base-motion branch)"}


_OLD_NAMES = {"fe_hz": "fe", "pa_over_q": "pa", "app_um": "app", "ymin_um": "ymin",
              "ymax_um": "ymax", "floquet_re": "mu_re", "floquet_im": "mu_im", "state_x": "x",
              "state_xdot": "xdot", "minima_per_period": "minima"}


@dataclass
class BranchSet:
    """Branches of one or more continuation runs, with their special points and stops."""

    branches: list = field(default_factory=list)

    def __len__(self):
        return len(self.branches)

    def __iter__(self):
        return iter(self.branches)

    def __getitem__(self, i):
        return self.branches[i]

    @property
    def special_points(self) -> list:
        return [s for b in self.branches for s in b.special]

    @property
    def stops(self) -> list:
        return [s for b in self.branches for s in b.stops]

    def special_table(self):
        """Special points as an :class:`xarray.Dataset` (dimension ``special``)."""
        import xarray as xr

        sp = self.special_points
        mu = np.array([s.floquet_multipliers for s in sp], complex).reshape(-1, 2)
        return xr.Dataset(
            {
                "type": ("special", np.array([s.type for s in sp], dtype=object)),
                "fe_hz": ("special", np.array([s.fe_hz for s in sp], float), {"units": "Hz"}),
                "pa_over_q": ("special", np.array([s.pa_over_q for s in sp], float), {"units": "Q"}),
                "app_um": ("special", np.array([s.app_um for s in sp], float), {"units": "um"}),
                "period": ("special", np.array([s.period for s in sp], np.int32)),
                "branch": ("special", np.array([s.branch for s in sp], dtype=object)),
                "floquet_re": (("special", "multiplier"), mu.real),
                "floquet_im": (("special", "multiplier"), mu.imag),
            },
            coords={"special": np.arange(len(sp)), "multiplier": [0, 1]},
        )

    def to_dict(self) -> dict:
        """The JSON contract: ``{"special_points": [...], "stops": [...]}``."""
        return {"special_points": [s.to_dict() for s in self.special_points],
                "stops": [s.to_dict() for s in self.stops]}

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), **kwargs)
