"""Settings of a resonance sweep: the frequency grid, the multi-start frequencies, the tolerances
and what a level holds (:class:`SweepSettings`), used by :mod:`contactvib.sweeps.sweep`; the grid
check and grid both sweeps share (:func:`check_grid`, :func:`grid_frequencies`: also
:class:`~contactvib.sweeps.system_sweep.SystemSweepSettings`)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from contactvib.call_forms import renamed_fields
from contactvib.model import (
    KMAX_SWEEP_MAX,
    MULTISTART_PER_OCTAVE_MAX,
    ContactModel,
    ParameterError,
    check_frequency_range,
    check_int,
    check_level_kind,
    check_range,
    excitation_at,
)
from contactvib.model.checks import MEMORY_MAX, check_memory, format_number

__all__ = ["SweepSettings", "frequency_grid", "multistart_indices", "fill_in_indices", "check_grid", "grid_frequencies",
           "RECORD_NAMES"]

#: Fields of :class:`SweepSettings` stored under another name in a dataset's ``settings`` record
#: (the record's layout, which :meth:`SweepSettings.to_dict` writes and ``from_dict`` reads).
RECORD_NAMES = {"n_starts": "multistart_starts", "tol": "close_tol"}


def check_grid(fmin_hz, fmax_hz, df_hz) -> tuple[float, float, float]:
    """The frequency grid of a sweep checked, (f_min, f_max, Δf) [Hz] as floats:
    0 < f_min < f_max, 0 < Δf ≤ f_max − f_min (two frequencies at least), at most 1e6 frequencies."""
    fmin, fmax = check_frequency_range(fmin_hz, fmax_hz)
    df = check_range("df", df_hz, 0.0, False, "Hz")
    span = fmax - fmin
    if df > span * (1.0 + 1e-9):
        raise ParameterError("df", df_hz, f"must be <= f_max - f_min = {format_number(span)} Hz "
                             "(the grid needs at least two frequencies)", ("f_min", "f_max"))
    if span / df > 1e6:
        raise ParameterError("df", df_hz, f"gives more than 1e6 frequencies over f_max - f_min = "
                             f"{format_number(span)} Hz; use a larger step or a narrower range",
                             ("f_min", "f_max"))
    return fmin, fmax, df


def grid_frequencies(fmin_hz: float, fmax_hz: float, df_hz: float) -> np.ndarray:
    """The frequencies [Hz] f_min + j Δf ≤ f_max (+ 1e-9 Δf)."""
    n = int(math.floor((fmax_hz - fmin_hz) / df_hz + 1e-9)) + 1
    return fmin_hz + df_hz * np.arange(n)


@renamed_fields(multistart_starts="n_starts", close_tol="tol")
@dataclass(frozen=True)
class SweepSettings:
    """Settings of a resonance sweep.

    Attributes
    ----------
    fmin_hz, fmax_hz, df_hz : float
        Frequency grid [Hz].
    kmax : int
        Largest period detected [excitation periods].
    max_periods : int
        Transient limit after a jump [excitation periods].
    multistart_per_octave : float
        Multi-start frequencies per octave of f_e, geometrically spaced from f_min and snapped to
        the grid (0: no multi-start).
    n_starts : int
        Random box starts per multi-start frequency (ballistic seeds are added;
        ``multistart_starts`` before 0.2.0, still accepted with a DeprecationWarning).
    fill_in_per_octave : float
        Fill-in multi-start frequencies per octave, spaced as the multi-start's; those that are
        multi-start frequencies already are skipped (0: none; none either without a
        multi-start). They find the short isolated branches (superharmonic isolas a few Hz to
        tens of Hz wide) that lie between two multi-start frequencies.
    fill_in_starts : int
        Random box starts per fill-in frequency (ballistic seeds are added; 0: no fill-in).
    seed : int
        Random seed of the box samples.
    rtol : float
        Integrator tolerance of the shooting and the orbit descriptions.
    tol : float
        Newton closure ``|P^k(z) − z|∞ / max(1, |z|∞)`` for accepting an orbit (``close_tol``
        before 0.2.0, still accepted with a DeprecationWarning).
    excitation : str
        What the level holds (:data:`contactvib.model.LEVEL_KINDS`): "force" (P_a/Q, the
        paper's), "base-um" (base displacement U [µm]: the inertial force grows with f_e²) or
        "base-g" (base acceleration A [g]).
    friction : FrictionModel, dict or None
        The tangential model (:class:`contactvib.FrictionModel`, or its parameters as a
        dict) whose friction ratio, stick and free fractions and tangential oscillation are
        computed for every periodic point of the level (``contactvib.friction.columns``);
        None (the default): no friction columns.
    level_seeds : bool
        After every level is swept, sweep again each level that lacks an orbit of period ≤ 4
        a neighbouring level holds (repeated while a pass adds one, at most once per level), seeded by
        Newton with that orbit walked in the level to this one
        (``contactvib.sweeps.level_seeds``; root "level seed"). Off by default: the levels
        are then independent of one another.
    """

    fmin_hz: float = 30.0
    fmax_hz: float = 2000.0
    df_hz: float = 1.0
    kmax: int = 16
    max_periods: int = 300
    multistart_per_octave: float = 8.0
    n_starts: int = 24
    fill_in_per_octave: float = 32.0
    fill_in_starts: int = 12
    seed: int = 0
    rtol: float = 1e-10
    tol: float = 1e-9
    detect_tol: float = 1e-4
    rtol_transient: float = 1e-8
    same_tol: float = 1e-6
    capture_tol: float = 1e-3
    excitation: str = "force"
    friction: object = None
    level_seeds: bool = False

    def __post_init__(self):
        # stored as checked (a number given as text is a float, a count an int)
        fmin, fmax, df = check_grid(self.fmin_hz, self.fmax_hz, self.df_hz)
        kmax = check_int("kmax", self.kmax, 1, KMAX_SWEEP_MAX)
        v = dict(fmin_hz=fmin, fmax_hz=fmax, df_hz=df, kmax=kmax,
                 max_periods=check_int("max_periods", self.max_periods, 4 * kmax),
                 multistart_per_octave=check_range("multistart_per_octave", self.multistart_per_octave,
                                                   0.0, True, upper=MULTISTART_PER_OCTAVE_MAX),
                 n_starts=check_int("n_starts", self.n_starts, 0),
                 fill_in_per_octave=check_range("fill_in_per_octave", self.fill_in_per_octave,
                                                0.0, True, upper=MULTISTART_PER_OCTAVE_MAX),
                 fill_in_starts=check_int("fill_in_starts", self.fill_in_starts, 0))
        # the arrays of one multi-start search, as the attractor search's (2 KiB per start, x2)
        check_memory("n_starts", self.n_starts, 4096.0 * v["n_starts"], MEMORY_MAX // 4096)
        check_memory("fill_in_starts", self.fill_in_starts, 4096.0 * v["fill_in_starts"], MEMORY_MAX // 4096)
        v["seed"] = check_int("seed", self.seed, 0)
        v["tol"] = check_range("tol", self.tol, 0.0, False)
        v["excitation"] = check_level_kind(self.excitation)
        v["friction"] = _friction_model(self.friction)
        if not isinstance(self.level_seeds, (bool, np.bool_)):
            raise ParameterError("level_seeds", self.level_seeds, "must be True or False")
        v["level_seeds"] = bool(self.level_seeds)
        for name, value in v.items():
            object.__setattr__(self, name, value)

    def to_dict(self) -> dict:
        """The settings record of a dataset (its ``settings`` attribute; :meth:`from_dict` reads
        it back): the fields in order, those of ``RECORD_NAMES`` under their record name,
        ``excitation`` only when it is not the force and ``friction``, the FrictionModel's
        parameters, only when given, so that a force sweep's record holds the paper's fields only."""
        d = {RECORD_NAMES.get(k, k): v for k, v in asdict(self).items()}
        if d["excitation"] == "force":
            del d["excitation"]
        if d["friction"] is None:  # a sweep without friction: no friction field
            del d["friction"]
        if not d["level_seeds"]:  # off: the record of a sweep without them
            del d["level_seeds"]
        return d

    @classmethod
    def from_dict(cls, record: dict) -> SweepSettings:
        """The settings of a record written by :meth:`to_dict` (field names also accepted)."""
        back = {v: k for k, v in RECORD_NAMES.items()}
        return cls(**{back.get(k, k): v for k, v in record.items()})

    def excitation_at(self, model: ContactModel, level: float, f_e: float):
        """The sweep's excitation at ``level`` and f_e [Hz] (:func:`contactvib.model.excitation_at`)."""
        return excitation_at(model, level, f_e, self.excitation)


def _friction_model(friction):
    """``friction`` as a FrictionModel (a dict is its parameters), or None."""
    if friction is None:
        return None
    from contactvib.friction.model import FrictionModel

    if isinstance(friction, dict):
        return FrictionModel(**friction)
    if not isinstance(friction, FrictionModel):
        raise ParameterError("friction", friction, "must be a FrictionModel, its parameters as a dict, or None")
    return friction


def frequency_grid(settings: SweepSettings) -> np.ndarray:
    """The frequencies [Hz] f_min + j Δf ≤ f_max (+ 1e-9 Δf)."""
    return grid_frequencies(settings.fmin_hz, settings.fmax_hz, settings.df_hz)


def multistart_indices(settings: SweepSettings) -> np.ndarray:
    """Grid indices of the multi-start frequencies: f_min · 2^(j / per_octave), snapped, unique."""
    if settings.n_starts <= 0:
        return np.zeros(0, np.int64)
    return _octave_indices(settings, settings.multistart_per_octave)


def fill_in_indices(settings: SweepSettings) -> np.ndarray:
    """Grid indices of the fill-in multi-start frequencies: f_min · 2^(j / fill_in_per_octave),
    snapped, unique, without the multi-start frequencies (:func:`multistart_indices`); none
    without a multi-start (sweeps only)."""
    starts = multistart_indices(settings)
    if settings.fill_in_starts <= 0 or starts.size == 0:  # sweeps only: nothing to fill in
        return np.zeros(0, np.int64)
    return np.setdiff1d(_octave_indices(settings, settings.fill_in_per_octave), starts)


def _octave_indices(settings: SweepSettings, per_octave: float) -> np.ndarray:
    """Grid indices of f_min · 2^(j / per_octave) up to f_max, snapped, unique (none if 0)."""
    f = frequency_grid(settings)
    if per_octave <= 0:
        return np.zeros(0, np.int64)
    n_oct = math.log2(f[-1] / f[0])
    fs = f[0] * 2.0 ** (np.arange(int(n_oct * per_octave) + 1) / per_octave)
    idx = np.clip(np.round((fs - f[0]) / settings.df_hz).astype(np.int64), 0, f.size - 1)
    return np.unique(idx)
