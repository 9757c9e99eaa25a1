"""The table law: a measured or computed static load–deflection curve F_s(y), interpolated by
PCHIP (Fritsch–Carlson monotone cubic Hermite): monotone and shape-preserving, so the interpolated
stiffness is never negative and has no overshoot between rows, and C¹, so the stiffness that the
Jacobian and the Floquet multipliers use is continuous. Beyond the last row the curve is continued
linearly with the last stiffness; results whose motion goes there are refused
(:meth:`TableLaw.check_deflection`). Its data is a file (``--law-file``), not ``--set`` values.
"""

from __future__ import annotations

import csv
import hashlib
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np

from contactvib.model.checks import ParameterError
from contactvib.model.laws.contract import SpringLaw
from contactvib.model.laws.registry import register_law

__all__ = ["TableLaw", "TABLE_ROWS_MIN"]

#: Fewest rows of a load–deflection table (the origin and at least three measured points).
TABLE_ROWS_MIN = 4


def _table_error(source: str, why: str) -> ParameterError:
    return ParameterError("law_file", source, why)


@register_law
@dataclass(frozen=True, eq=False)
class TableLaw(SpringLaw):
    """A static load–deflection curve F_s(y) from rows (deflection [m], load [N]).

    The first row is (0, 0); deflections and loads increase strictly; at least
    ``TABLE_ROWS_MIN`` rows. Interpolated by PCHIP (monotone, C¹); linear beyond the last
    row with the last stiffness (refused by :meth:`check_deflection` in results).
    """

    name: ClassVar[str] = "table"
    formula: ClassVar[str] = "a measured load-deflection curve F_s(y) (--law-file FILE.csv), PCHIP"
    taylor: ClassVar[bool] = True

    deflection_m: np.ndarray
    load_n: np.ndarray
    source: str = "table"

    def __post_init__(self):
        d = np.asarray(self.deflection_m, dtype=float).ravel()
        F = np.asarray(self.load_n, dtype=float).ravel()
        src = self.source
        if d.shape != F.shape:
            raise _table_error(src, "deflection and load columns must have the same length")
        if d.size < TABLE_ROWS_MIN:
            raise _table_error(src, f"has {d.size} rows: needs at least {TABLE_ROWS_MIN} (the origin and 3 more)")
        if not (np.all(np.isfinite(d)) and np.all(np.isfinite(F))):
            bad = int(np.flatnonzero(~(np.isfinite(d) & np.isfinite(F)))[0])
            raise _table_error(src, f"row {bad + 1} is not a finite number (NaN or inf)")
        if d[0] != 0.0 or F[0] != 0.0:
            raise _table_error(src, f"must start at (0, 0) (first contact); starts at ({d[0]:g}, {F[0]:g})")
        for what, col in (("deflection", d), ("load", F)):
            steps = np.diff(col)
            if np.any(steps <= 0.0):
                bad = int(np.flatnonzero(steps <= 0.0)[0])
                raise _table_error(src, f"{what} must increase strictly; rows {bad + 1} and {bad + 2} "
                                        f"do not ({col[bad]:g}, {col[bad + 1]:g})")
        object.__setattr__(self, "deflection_m", d)
        object.__setattr__(self, "load_n", F)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_csv(cls, path) -> TableLaw:
        """Read ``deflection_um,load_n`` (header row, then numbers) from a CSV file."""
        p = Path(path)
        src = str(path)
        try:
            text = p.read_text()
        except OSError as e:
            raise _table_error(src, f"cannot be read ({e.strerror or type(e).__name__})") from None
        rows = list(csv.reader(line for line in text.splitlines() if line.strip()))
        if not rows:
            raise _table_error(src, "is empty: expected the columns deflection_um,load_n")
        header = [h.strip() for h in rows[0]]
        for col in ("deflection_um", "load_n"):
            if col not in header:
                raise _table_error(src, f"has no column {col} (columns: {', '.join(header)}); "
                                        "expected deflection_um,load_n")
        i_d, i_f = header.index("deflection_um"), header.index("load_n")
        d, F = [], []
        for n, row in enumerate(rows[1:], start=2):
            try:
                d.append(float(row[i_d]))
                F.append(float(row[i_f]))
            except (ValueError, IndexError):
                raise _table_error(src, f"line {n} is not two numbers: {','.join(row)}") from None
        return cls(np.array(d) * 1e-6, np.array(F), source=src)

    @classmethod
    def from_function(cls, load, y_max: float, n: int = 400, source: str = "function") -> TableLaw:
        """Tabulate a user's spring law ``load(y) -> F`` [N] (y in m, vectorised) on ``n`` rows
        from 0 to ``y_max`` [m]: the way to bring a law of one's own into every solver."""
        d = np.linspace(0.0, float(y_max), int(n))
        return cls(d, np.asarray(load(d), dtype=float), source=source)

    # ------------------------------------------------------------------ the law
    @property
    def sha256(self) -> str:
        """Content hash of the table (deflections and loads as float64)."""
        h = hashlib.sha256(self.deflection_m.tobytes())
        h.update(self.load_n.tobytes())
        return h.hexdigest()

    def __eq__(self, other):
        return isinstance(other, TableLaw) and self.sha256 == other.sha256

    def __hash__(self):
        return hash(self.sha256)

    def to_dict(self) -> dict:
        """The table as JSON-able lists (deflection in m: exact round trip), source and content hash."""
        return {"deflection_m": self.deflection_m.tolist(), "load_n": self.load_n.tolist(),
                "source": self.source, "sha256": self.sha256}

    @classmethod
    def from_dict(cls, d: dict) -> TableLaw:
        d_m = d["deflection_m"] if "deflection_m" in d else np.asarray(d["deflection_um"], float) * 1e-6
        return cls(np.asarray(d_m, float), np.asarray(d["load_n"], float),
                   source=d.get("source", "table"))

    def _pchip(self):
        from scipy.interpolate import PchipInterpolator

        return PchipInterpolator(self.deflection_m, self.load_n, extrapolate=False)

    def values(self) -> dict:
        """The table (rows, source, content hash) by its keyword ``table``."""
        return {"table": self.to_dict()}

    def __repr__(self):
        return f"TableLaw({self.source!r}, {self.deflection_m.size} rows, sha256 {self.sha256[:12]})"

    @property
    def y_max(self) -> float:
        """Largest tabulated deflection [m]."""
        return float(self.deflection_m[-1])

    def static_deflection(self, W: float, S: float = 0.0) -> float:
        if not W < self.load_n[-1]:
            raise ParameterError("law_file", self.source,
                                 f"its largest load {self.load_n[-1]:g} N does not reach the static load "
                                 f"W = Q + F_pre = {W:g} N: the table must extend beyond the static point")
        from scipy.optimize import brentq

        p = self._pchip()
        return float(brentq(lambda y: float(p(y)) - W, 0.0, self.y_max, xtol=1e-15 * self.y_max, rtol=1e-15))

    def force(self, y, S: float = 0.0):
        y = np.asarray(y, dtype=float)
        y0, F0, d0 = self.y_max, self.load_n[-1], self._slopes()[-1]
        inside = self._pchip()(np.clip(y, 0.0, y0))
        return np.where(y <= 0.0, 0.0, np.where(y > y0, F0 + d0 * (y - y0), inside))

    def stiffness(self, y, S: float = 0.0):
        y = np.asarray(y, dtype=float)
        inside = self._pchip().derivative()(np.clip(y, 0.0, self.y_max))
        return np.where(y <= 0.0, 0.0, np.where(y > self.y_max, self._slopes()[-1], inside))

    def _slopes(self) -> np.ndarray:
        return self._pchip().derivative()(self.deflection_m)

    def kernel_spring(self, y0: float, W: float, S: float = 0.0):
        x = self.deflection_m / y0
        f = self.load_n / W
        d = self._slopes() * (y0 / W)
        return self.compiled_table(x, f, d)

    def check_motion(self, delta_max_m: float, y0: float = 0.0, what: str = "the motion") -> None:
        """Refuse a result whose deflection leaves the table (ParameterError naming the file)."""
        self.check_deflection(delta_max_m, what)

    def check_deflection(self, y_max_m: float, what: str = "the motion") -> None:
        """Refuse a result whose deflection leaves the table (ParameterError naming the file)."""
        if y_max_m > self.y_max:
            raise ParameterError("law_file", self.source,
                                 f"{what} reaches a deflection of {y_max_m * 1e6:.4g} um, beyond the table's "
                                 f"last row at {self.y_max * 1e6:.4g} um: extend the table (the curve "
                                 f"beyond it would be an extrapolation)")
