"""The result of :func:`contactvib.fit`: :class:`FitResult`, with units and a JSON form."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib.model import ContactModel


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


@dataclass
class FitResult:
    """Fitted contact parameters with standard errors, correlations and the fit's diagnostics.

    Attributes
    ----------
    parameters : dict
        Each fitted name (``S_c_n`` [N/m^m2], ``m2``, ``S_h_n`` [N s/m^(1+l)], ``l``, and for a
        decay ``y_init_um``, ``v_init_mm_s``) -> ``{"value", "stderr", "unit"}``.
    fixed : dict
        Parameters held fixed (given, or not determined by the data sets), name -> value.
    derived : dict
        ``f_n0_hz``, ``y0_um``, ``zeta`` -> ``{"value", "stderr", "unit"}`` (stderr by the delta method).
    names, correlation : list of str, float64[p, p]
        Correlation matrix of the fitted parameters, in the fit's coordinates (log10 of S_c_n and
        S_h_n, the others as they are).
    residual_rms : dict
        Per data set (``static`` [µm], ``decay`` [µm or m/s²], ``frf`` [ln A_pp, ≈ relative]) the RMS
        of the residuals at the optimum; ``noise`` the noise levels the joint objective divided by.
    n_forward, time_s : int, float
        Parameter sets evaluated by the forward models, and the fit's wall time [s].
    converged : bool
        Whether the least-squares solver met its tolerance from the best start.
    message : str
        The solver's message.
    identifiability : list of str
        Statements on what the data do and do not determine.
    model : ContactModel
        The fitted contact (``model.parameters()`` is what ``--save-model`` writes).
    """

    parameters: dict
    fixed: dict
    derived: dict
    names: list
    correlation: np.ndarray
    residual_rms: dict
    noise: dict
    n_forward: int
    time_s: float
    converged: bool
    message: str
    identifiability: list
    model: ContactModel
    n_starts: int = 0
    cost: float = math.nan
    sets: list = field(default_factory=list, repr=False)
    values: dict = field(default_factory=dict, repr=False)

    def value(self, name: str) -> float:
        """A fitted, fixed or derived value by name."""
        for table in (self.parameters, self.derived):
            if name in table:
                return table[name]["value"]
        return self.fixed[name]

    def stderr(self, name: str) -> float:
        for table in (self.parameters, self.derived):
            if name in table:
                return table[name]["stderr"]
        return 0.0

    def to_dict(self) -> dict:
        """JSON-able: parameters (the fitted ones, then f_n0_hz, y0_um, zeta marked ``"derived":
        true``), derived (those three again), correlation, residual RMS, diagnostics, model."""
        def entry(d):
            return {k: {"value": _num(v["value"]), "stderr": _num(v["stderr"]), "unit": v["unit"]}
                    for k, v in d.items()}
        derived = {k: {**v, "derived": True} for k, v in entry(self.derived).items()}
        return {
            "parameters": {**entry(self.parameters), **derived},
            "derived": entry(self.derived),
            "fixed": {k: _num(v) for k, v in self.fixed.items()},
            "correlation": {"names": list(self.names),
                            "matrix": [[_num(x) for x in row] for row in np.asarray(self.correlation)]},
            "residual_rms": {k: _num(v) for k, v in self.residual_rms.items()},
            "noise": {k: _num(v) for k, v in self.noise.items()},
            "n_forward": int(self.n_forward),
            "n_starts": int(self.n_starts),
            "time_s": _num(self.time_s),
            "converged": bool(self.converged),
            "message": self.message,
            "identifiability": list(self.identifiability),
            "model": self.model.parameters(),
        }

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), allow_nan=False)

    def table(self) -> str:
        """The text table the command prints."""
        lines = [f"{'parameter':<12} {'value':>13} {'stderr':>11} {'rel':>8}  unit"]
        for k, v in {**self.parameters, **self.derived}.items():
            rel = abs(v["stderr"] / v["value"]) if v["value"] else math.inf
            lines.append(f"{k:<12} {v['value']:>13.6g} {v['stderr']:>11.3g} {100 * rel:>7.2f}%  {v['unit']}")
        for k, v in self.fixed.items():
            lines.append(f"{k:<12} {v:>13.6g} {'fixed':>11}")
        lines.append("residual RMS: " + ", ".join(f"{k} {v:.4g}" for k, v in self.residual_rms.items()))
        lines.append(f"{self.n_forward} forward solves in {self.time_s:.1f} s from {self.n_starts} starts; "
                     + ("converged" if self.converged else "NOT converged") + f" ({self.message})")
        if len(self.names) > 1:
            lines.append("correlation (" + ", ".join(self.names) + "):")
            for n, row in zip(self.names, np.asarray(self.correlation)):
                lines.append(f"  {n:<12} " + " ".join(f"{x:>6.3f}" for x in row))
        lines += self.identifiability
        return "\n".join(lines)
