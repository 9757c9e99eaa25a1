"""Harmonic-balance results: one solution (:class:`HBSolution`), a branch (:class:`HBBranch`),
and the measurements of a coefficient vector (extrema of the series, energy of its top harmonics).

Coefficients ``X = [a0, a1, b1, ..., aH, bH]`` of x = y/y0 in the excitation phase θ.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from contactvib._kernels.shooting import is_stable

__all__ = ["HBSolution", "HBBranch"]


@dataclass(frozen=True)
class HBSolution:
    """One harmonic-balance periodic solution.

    Attributes
    ----------
    fe_hz, pa_over_q : float
        Excitation frequency [Hz] and amplitude [Q].
    harmonics : int
        Number of harmonics H.
    app_um, ymin_um, ymax_um : float
        Peak-to-peak amplitude and extrema of y [µm] (from the series sampled on 64 H points
        and refined by Newton on x_θ).
    loses_contact : bool
        y_min < 0.
    top_energy_fraction : float
        Share of the AC energy Σ_{k≥1}(a_k²+b_k²) held by the harmonics k > 3H/4 [1].
    residual : float
        Max-norm of the HB residual at the solution [1, units of Q].
    floquet_multipliers : ndarray of complex
        Eigenvalues of the one-period monodromy from the HB orbit point (empty if not computed).
    closure : float
        Relative closure ``|P(z) − z|∞ / max(1, |z|∞)`` of one shooting period from the HB point.
    coefficients : ndarray (2H+1,)
        [a0, a1, b1, ..., aH, bH] of x = y/y0.
    """

    fe_hz: float
    pa_over_q: float
    harmonics: int
    app_um: float
    ymin_um: float
    ymax_um: float
    loses_contact: bool
    top_energy_fraction: float
    residual: float
    floquet_multipliers: np.ndarray
    closure: float
    y0_um: float
    coefficients: np.ndarray = field(repr=False)

    @property
    def stable(self) -> bool | None:
        """All ``|multipliers|`` < 1 (None if not computed)."""
        if self.floquet_multipliers.size == 0:
            return None
        return bool(is_stable(np.max(np.abs(self.floquet_multipliers))))

    @property
    def harmonics_um(self) -> np.ndarray:
        """One-sided amplitudes of the k·f_e components of y [µm]; k = 0: mean shift ⟨y⟩ − y0."""
        X = self.coefficients
        a = np.hypot(X[1::2], X[2::2]) * self.y0_um
        return np.concatenate([[(X[0] - 1.0) * self.y0_um], a])


def series_value(X, th, deriv=0):
    H = (X.size - 1) // 2
    k = np.arange(1, H + 1)
    a, b = X[1::2], X[2::2]
    ang = np.outer(np.atleast_1d(th), k)
    if deriv == 0:
        return X[0] + np.cos(ang) @ a + np.sin(ang) @ b
    if deriv == 1:
        return np.cos(ang) @ (k * b) - np.sin(ang) @ (k * a)
    return -(np.cos(ang) @ (k * k * a) + np.sin(ang) @ (k * k * b))


def series_extrema(X):
    """(x_min, x_max) of the series: samples on 64 H points (zero-padded inverse FFT), then
    Newton on x_θ = 0 inside the sampling bracket."""
    H = (X.size - 1) // 2
    n = max(1024, 64 * H)
    C = np.zeros(n // 2 + 1, complex)
    C[0] = X[0]
    C[1:H + 1] = 0.5 * (X[1::2] - 1j * X[2::2])
    s = np.fft.irfft(C * n, n)
    out = []
    for i in (int(np.argmin(s)), int(np.argmax(s))):
        t = 2.0 * math.pi * i / n
        for _ in range(20):
            d2 = series_value(X, t, 2)[0]
            if d2 == 0.0:
                break
            step = series_value(X, t, 1)[0] / d2
            if abs(step) > 2.0 * math.pi / n:  # stay in the bracket (corner of a contact orbit)
                break
            t -= step
            if abs(step) < 1e-14:
                break
        out.append(float(series_value(X, t)[0]))
    lo, hi = min(out[0], float(s.min())), max(out[1], float(s.max()))
    return lo, hi


def top_fraction(X):
    H = (X.size - 1) // 2
    e = X[1::2] ** 2 + X[2::2] ** 2
    tot = e.sum()
    if tot == 0.0:
        return 0.0
    return float(e[int(math.floor(0.75 * H)):].sum() / tot)


@dataclass(frozen=True)
class HBBranch:
    """A branch of HB solutions continued in f_e, stored column by column.

    Attributes
    ----------
    fe_hz, app_um, ymin_um, ymax_um : ndarray
        Excitation frequency [Hz], peak-to-peak amplitude and extrema of y [µm] per point.
    floquet_abs_max : ndarray
        Largest ``|Floquet multiplier|`` per point [1] (NaN if not computed).
    stable : ndarray of bool
    loses_contact : ndarray of bool
    top_energy_fraction : ndarray
        Energy share of the top quarter of the harmonics [1].
    pa_over_q : float
    harmonics : int
    stop_reason : str
        Why the continuation ended.
    solutions : list of HBSolution
    """

    fe_hz: np.ndarray
    app_um: np.ndarray
    ymin_um: np.ndarray
    ymax_um: np.ndarray
    floquet_abs_max: np.ndarray
    stable: np.ndarray
    loses_contact: np.ndarray
    top_energy_fraction: np.ndarray
    pa_over_q: float
    harmonics: int
    stop_reason: str
    solutions: list = field(repr=False)

    def __len__(self):
        return self.fe_hz.size

    def to_dict(self) -> dict:
        """The JSON contract of ``contactvib hbm --json``."""
        return {
            "pa_over_q": float(self.pa_over_q),
            "harmonics": int(self.harmonics),
            "stop_reason": self.stop_reason,
            "units": {"fe_hz": "Hz", "app_um": "um", "ymin_um": "um", "ymax_um": "um"},
            "points": [
                {"fe_hz": float(f), "app_um": float(a), "ymin_um": float(lo), "ymax_um": float(hi),
                 "stable": bool(s), "floquet_abs_max": float(mu) if np.isfinite(mu) else None,
                 "loses_contact": bool(g), "top_energy_fraction": float(e)}
                for f, a, lo, hi, s, mu, g, e in zip(
                    self.fe_hz, self.app_um, self.ymin_um, self.ymax_um, self.stable,
                    self.floquet_abs_max, self.loses_contact, self.top_energy_fraction)
            ],
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), **kwargs)
