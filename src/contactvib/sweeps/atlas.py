"""The evolution atlas: many P_a levels, each exactly ``resonance``'s level, on any backend.

:func:`atlas_dataset` is :func:`contactvib.sweeps.resonance.resonance_dataset` with the levels of
a P_a range, a backend (:mod:`contactvib.sweeps.backends`: the local process pool, a Dask
``LocalCluster`` or a running Dask cluster) and compressed storage: the per-level chunks
``OUT/.chunks/level_pa<level>.nc`` (resume, one level readable alone) and the merged
``OUT/atlas.nc``, both NetCDF4 with zlib compression level 4, chunked along ``point``, in the
layout of ``paper.nc`` (:mod:`contactvib.sweeps.dataset`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from contactvib.model import LEVEL_KINDS, ParameterError, check_int, check_level_kind, check_pa_level, check_range

__all__ = ["atlas_levels", "atlas_dataset", "ATLAS_NAME", "NPA_MAX"]

#: The merged dataset's file name in the output folder.
ATLAS_NAME = "atlas"
#: Most levels of one atlas.
NPA_MAX = 10_000


def atlas_levels(pa_min, pa_max, npa, excitation: str = "force") -> list[float]:
    """``npa`` levels P_a/Q evenly spaced from ``pa_min`` to ``pa_max`` (both included, rounded
    to 1e-9 so that a level's chunk name does not depend on rounding noise); ParameterError
    ``npa``, ``pa_min`` or ``pa_max`` otherwise. For base motion (``excitation`` "base-um" or
    "base-g") the levels are U [µm] or A [g], each > 0 (their force is checked by the sweep)."""
    n = check_int("npa", npa, 1, NPA_MAX)
    if excitation == "force":
        lo = check_pa_level(pa_min, "pa_min")
        hi = check_pa_level(pa_max, "pa_max")
    else:
        unit = LEVEL_KINDS[check_level_kind(excitation)][1]
        lo = check_range("pa_min", pa_min, 0.0, False, unit)
        hi = check_range("pa_max", pa_max, 0.0, False, unit)
    if lo > hi:
        raise ParameterError("pa_min", pa_min, f"must be <= pa_max = {hi:g}", ("pa_max",))
    if n == 1 and lo != hi:
        raise ParameterError("npa", npa, f"one level needs pa_min = pa_max (not {lo:g} and {hi:g})",
                             ("pa_min", "pa_max"))
    levels = [round(float(v), 9) for v in np.linspace(lo, hi, n)]
    if len(set(levels)) < n:
        raise ParameterError("npa", npa, f"levels closer than 1e-9 Q between pa_min = {lo:g} and "
                                         f"pa_max = {hi:g}", ("pa_min", "pa_max"))
    return levels


def atlas_dataset(model, levels, settings, out, resume: bool = False, backend=None,
                  progress: bool = True):
    """Sweep every level of ``levels`` [Q] into the atlas ``OUT/atlas.nc`` (compressed, with its
    compressed chunks in ``OUT/.chunks``) on ``backend`` (default: the local process pool).

    The same sweeps, chunks, resume rules, lock and interrupts as
    :func:`contactvib.sweeps.resonance.resonance_dataset`; the values at a level equal
    ``resonance``'s at that level whatever the backend. Returns the merged Dataset."""
    from contactvib.sweeps.resonance import resonance_dataset

    return resonance_dataset(model, levels=levels, settings=settings, out=Path(out), name=ATLAS_NAME, resume=resume,
                             progress=progress, backend=backend, compress=True)
