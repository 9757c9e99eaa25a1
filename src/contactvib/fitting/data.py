"""Measurements that :func:`contactvib.fit` fits: reading and validating the CSV files.

Every file is a CSV with one header row naming its columns (any order, extra columns ignored);
lines starting with ``#`` are comments. Errors are :class:`~contactvib.model.ParameterError`
whose symbol is the kind of data set (``static``, ``decay``, ``frf``), value the file, and text
the row and column at fault, so that the command line prints them as one line naming its option.

============ ====================================== ==============================================
kind         columns                                meaning
============ ====================================== ==============================================
static       ``load_n,deflection_um``               load F [N] ≥ 0, deflection from first contact
                                                    [µm]
decay        ``t_ms,y_um`` or ``t_ms,a_ms2``        free decay (tap test): displacement about the
                                                    static point [µm] or acceleration [m/s²]
frf          ``fe_hz,force_amplitude_n,app_um,``    stepped sine: A_pp of the steady state [µm] at
             ``direction``                          f_e [Hz] under P_a [N], sweep ``up``/``down``
============ ====================================== ==============================================
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from contactvib.model import ParameterError

#: Columns of each kind of data set (the decay's second column is one of two).
COLUMNS = {
    "static": ("load_n", "deflection_um"),
    "decay": ("t_ms", "y_um|a_ms2"),
    "frf": ("fe_hz", "force_amplitude_n", "app_um", "direction"),
}
#: Fewest cycles a decay record must span (counted as zero crossings about its mean / 2).
DECAY_MIN_CYCLES = 3


def _fail(kind: str, source, text: str) -> ParameterError:
    return ParameterError(kind, str(source), text)


def _read_rows(kind: str, path) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header and (line number, fields) of the data rows; comments and blank lines skipped."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            lines = [(i, line) for i, line in enumerate(fh, 1) if line.strip() and not line.lstrip().startswith("#")]
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise _fail(kind, path, f"cannot read the file ({getattr(e, 'strerror', None) or type(e).__name__})") from None
    if not lines:
        raise _fail(kind, path, f"empty: expected a header {','.join(COLUMNS[kind])} and data rows")
    rows = list(csv.reader([text for _, text in lines]))
    header = [h.strip() for h in rows[0]]
    return header, [(lines[j][0], [f.strip() for f in rows[j]]) for j in range(1, len(rows))]


def _columns(kind: str, path, header: list[str], wanted: tuple[str, ...]) -> list[int]:
    idx = []
    for name in wanted:
        options = name.split("|")
        found = [header.index(o) for o in options if o in header]
        if not found:
            raise _fail(kind, path, f"missing column {' or '.join(options)} (columns: {', '.join(header)}; "
                                    f"expected {','.join(COLUMNS[kind])})")
        idx.append(found[0])
    return idx


def _numbers(kind: str, path, rows, idx: list[int], names: list[str]) -> np.ndarray:
    out = np.empty((len(rows), len(idx)))
    for r, (line, fields) in enumerate(rows):
        for c, (j, name) in enumerate(zip(idx, names)):
            text = fields[j] if j < len(fields) else ""
            try:
                v = float(text)
            except ValueError:
                v = math.nan
            if not math.isfinite(v):
                raise _fail(kind, path, f"line {line}, column {name}: {text!r} is not a finite number")
            out[r, c] = v
    return out


@dataclass(frozen=True)
class StaticData:
    """A static load–deflection curve: ``load_n`` [N] and ``deflection_um`` [µm] from first contact."""

    load_n: np.ndarray
    deflection_um: np.ndarray
    source: str = "static"

    @property
    def n(self) -> int:
        return int(self.load_n.size)


@dataclass(frozen=True)
class DecayData:
    """A free decay: ``t_ms`` [ms] and ``values`` (``kind`` ``"y_um"``: displacement about the static
    point [µm]; ``"a_ms2"``: acceleration [m/s²])."""

    t_ms: np.ndarray
    values: np.ndarray
    kind: str = "y_um"
    source: str = "decay"

    @property
    def n(self) -> int:
        return int(self.t_ms.size)


@dataclass(frozen=True)
class FrfData:
    """Stepped-sine sweeps: per row ``fe_hz``, ``force_n`` (P_a [N]), ``app_um`` (A_pp [µm]) and
    ``direction`` (``"up"``/``"down"``); rows of one (force, direction) form one sweep, in the
    order the experiment stepped (``sweeps``: the row indices of each)."""

    fe_hz: np.ndarray
    force_n: np.ndarray
    app_um: np.ndarray
    direction: np.ndarray
    source: str = "frf"

    @property
    def n(self) -> int:
        return int(self.fe_hz.size)

    @property
    def sweeps(self) -> list[np.ndarray]:
        keys = []
        for F, d in zip(self.force_n, self.direction):
            if (F, d) not in keys:
                keys.append((F, d))
        return [np.flatnonzero((self.force_n == F) & (self.direction == d)) for F, d in keys]


def read_static(path) -> StaticData:
    """Read and check a ``load_n,deflection_um`` file (loads ≥ 0, at least 3 rows)."""
    header, rows = _read_rows("static", path)
    names = list(COLUMNS["static"])
    a = _numbers("static", path, rows, _columns("static", path, header, COLUMNS["static"]), names)
    return static_data(a[:, 0], a[:, 1], source=str(path))


def static_data(load_n, deflection_um, source: str = "static") -> StaticData:
    """:class:`StaticData` from arrays, checked: finite, loads ≥ 0, at least 3 points."""
    F = np.asarray(load_n, float).ravel()
    y = np.asarray(deflection_um, float).ravel()
    if F.size != y.size:
        raise _fail("static", source, f"{F.size} loads but {y.size} deflections")
    if F.size < 3:
        raise _fail("static", source, f"{F.size} points: at least 3 needed")
    if not (np.all(np.isfinite(F)) and np.all(np.isfinite(y))):
        raise _fail("static", source, "NaN or infinite values")
    if np.any(F < 0):
        j = int(np.flatnonzero(F < 0)[0])
        raise _fail("static", source, f"negative load {F[j]:g} N at point {j + 1}: loads must be >= 0")
    if np.count_nonzero(F > 0) < 2:
        raise _fail("static", source, "fewer than 2 points with a load > 0")
    return StaticData(F, y, source)


#: UFF dataset 58 ordinate types read as a decay (SI units): displacement [m], acceleration [m/s²].
UFF_ORDINATES = {8: ("y_um", 1e6), 12: ("a_ms2", 1.0)}


def read_uff58(path) -> DecayData:
    """A decay from a universal file (``.uff``/``.unv``): its first dataset 58 of function type 1
    (a time response), abscissa time [s], ordinate displacement about the static point [m]
    (specific data type 8) or acceleration [m/s²] (12), read with pyuff."""
    try:
        import pyuff

        sets = pyuff.UFF(str(path)).read_sets()
    except Exception as e:  # pyuff raises many kinds on a foreign file: all mean "not a UFF"
        raise _fail("decay", path, f"not a readable universal file ({type(e).__name__}: {e})") from None
    sets = sets if isinstance(sets, list) else [sets]
    series = [d for d in sets if d.get("type") == 58 and d.get("func_type") == 1]
    if not series:
        raise _fail("decay", path, "no dataset 58 with a time response (function type 1)")
    d = series[0]
    kind = UFF_ORDINATES.get(int(d.get("ordinate_spec_data_type", -1)))
    if kind is None:
        raise _fail("decay", path, f"dataset 58 ordinate type {d.get('ordinate_spec_data_type')}: "
                                   "must be 8 (displacement) or 12 (acceleration)")
    t = np.real(np.asarray(d["x"], float)) * 1e3
    v = np.real(np.asarray(d["data"])) * kind[1]
    return decay_data(t, v, kind=kind[0], source=str(path))


def read_decay(path) -> DecayData:
    """Read and check a ``t_ms,y_um`` (or ``t_ms,a_ms2``) file, or a universal file's dataset 58
    (``.uff``, ``.unv``: ``read_uff58``)."""
    if Path(path).suffix.lower() in (".uff", ".unv"):
        return read_uff58(path)
    header, rows = _read_rows("decay", path)
    idx = _columns("decay", path, header, COLUMNS["decay"])
    kind = header[idx[1]]
    a = _numbers("decay", path, rows, idx, ["t_ms", kind])
    return decay_data(a[:, 0], a[:, 1], kind=kind, source=str(path))


def decay_data(t_ms, values, kind: str = "y_um", source: str = "decay") -> DecayData:
    """:class:`DecayData` from arrays, checked: finite, strictly increasing times, at least
    ``DECAY_MIN_CYCLES`` cycles (zero crossings about the mean)."""
    t = np.asarray(t_ms, float).ravel()
    v = np.asarray(values, float).ravel()
    if kind not in ("y_um", "a_ms2"):
        raise _fail("decay", source, f"kind {kind!r}: must be y_um or a_ms2")
    if t.size != v.size or t.size < 8:
        raise _fail("decay", source, f"{min(t.size, v.size)} samples: at least 8 needed")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(v))):
        raise _fail("decay", source, "NaN or infinite values")
    if np.any(np.diff(t) <= 0):
        j = int(np.flatnonzero(np.diff(t) <= 0)[0])
        raise _fail("decay", source, f"times not strictly increasing at sample {j + 2} (t = {t[j + 1]:g} ms)")
    s = np.sign(v - np.mean(v))
    crossings = np.count_nonzero(s[1:] * s[:-1] < 0)
    if crossings < 2 * DECAY_MIN_CYCLES:
        raise _fail("decay", source, f"spans about {crossings / 2:g} cycles: a decay record needs at least "
                                     f"{DECAY_MIN_CYCLES} cycles")
    return DecayData(t, v, kind, source)


def read_frf(path) -> FrfData:
    """Read and check a ``fe_hz,force_amplitude_n,app_um,direction`` file."""
    header, rows = _read_rows("frf", path)
    idx = _columns("frf", path, header, COLUMNS["frf"])
    a = _numbers("frf", path, rows, idx[:3], list(COLUMNS["frf"][:3]))
    d = []
    for line, fields in rows:
        text = fields[idx[3]].lower() if idx[3] < len(fields) else ""
        if text not in ("up", "down"):
            raise _fail("frf", path, f"line {line}, column direction: {text!r} must be up or down")
        d.append(text)
    return frf_data(a[:, 0], a[:, 1], a[:, 2], d, source=str(path))


def frf_data(fe_hz, force_n, app_um, direction, source: str = "frf") -> FrfData:
    """:class:`FrfData` from arrays, checked: finite, f_e > 0, P_a > 0, A_pp > 0, directions up or
    down, and within each sweep frequencies strictly increasing (up) or decreasing (down)."""
    f, F, A = (np.asarray(x, float).ravel() for x in (fe_hz, force_n, app_um))
    d = np.asarray([str(x).lower() for x in direction])
    if not (f.size == F.size == A.size == d.size) or f.size < 3:
        raise _fail("frf", source, "needs at least 3 rows with every column")
    for name, x in (("fe_hz", f), ("force_amplitude_n", F), ("app_um", A)):
        if not np.all(np.isfinite(x)):
            raise _fail("frf", source, f"NaN or infinite values in {name}")
        if np.any(x <= 0):
            raise _fail("frf", source, f"{name} = {x[x <= 0][0]:g}: must be > 0")
    bad = sorted(str(x) for x in set(d.tolist()) - {"up", "down"})
    if bad:
        raise _fail("frf", source, f"direction {bad[0]!r}: must be up or down")
    data = FrfData(f, F, A, d, source)
    for rows in data.sweeps:
        step = np.diff(f[rows]) * (1.0 if d[rows[0]] == "up" else -1.0)
        if np.any(step <= 0):
            j = rows[int(np.flatnonzero(step <= 0)[0]) + 1]
            what = "duplicated" if f[j] in f[rows[:rows.tolist().index(j)]] else "out of order"
            order = "increasing" if d[j] == "up" else "decreasing"
            raise _fail("frf", source, f"sweep {d[j]} at {F[j]:g} N: frequency {f[j]:g} Hz {what} (row {j + 1}); "
                                       f"a sweep {d[j]} must have strictly {order} f_e")
    return data


def load(kind: str, path):
    """Read a data set of ``kind`` (``static``, ``decay``, ``frf``) from ``path``."""
    return {"static": read_static, "decay": read_decay, "frf": read_frf}[kind](Path(path))
