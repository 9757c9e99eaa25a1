"""Forward models of the fit: one class per kind of measurement, each turning parameter sets into
residuals (many sets at once, for the Jacobian's columns and the multi-start's candidates).

The model is the paper's (Kostek 2013, Eqs. 2.1–2.5)::

    M ÿ = M g − S c_n y^m2 [y > 0] − S h_n y^l ẏ [y > 0] + P_a cos(2π f_e t)

with the fitted parameters ``S_c_n`` = S·c_n [N/m^m2], ``m2``, ``S_h_n`` = S·h_n [N s/m^(1+l)],
``l`` (only these products enter the equation of motion) and M, g, S given.

* :class:`StaticSet`: F = S c_n y^m2. The loads of a static test are set (dead weights, a load
  cell) far more precisely than the deflection is read (a gauge with additive noise), so the
  residual is taken in deflection: y_i − (F_i / S c_n)^(1/m2), unweighted, with the noise level
  estimated from the residuals (ordinary least squares in the space where the noise is additive
  and of one size). A log–log regression would weight the small deflections, whose relative
  noise is largest, as much as the large ones, and is biased (log of a noisy number); the
  unloaded point (0, 0) carries no information there and is skipped, while here it simply
  holds the offset to zero.
* :class:`DecaySet`: the free oscillator (P_a = 0) from the initial state (``y_init_um``,
  ``v_init_mm_s``, fitted with the rest) against the measured time series, displacement about
  the static point (or acceleration); residual in µm (m/s²), additive noise.
* :class:`FrfSet`: a stepped-sine sweep followed step by step to the attractor reached from the
  previous step's state (:mod:`contactvib._kernels.fitting`); residual ln A_pp(model) − ln A_pp
  (a stepped-sine amplitude is read with a relative accuracy, e.g. 2 % of the reading).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contactvib.model import ContactModel, ParameterError

from .data import DecayData, FrfData, StaticData

#: Physical parameters of the contact, with units, as fitted.
CONTACT_NAMES = ("S_c_n", "m2", "S_h_n", "l")
UNITS = {"S_c_n": "N/m^m2", "m2": "1", "S_h_n": "N s/m^(1+l)", "l": "1", "y_init_um": "um",
         "v_init_mm_s": "mm/s"}
#: Parameters fitted in log10 (positive, many decades).
LOG_NAMES = ("S_c_n", "S_h_n")
#: A residual returned for a parameter set the model refuses (a wall for the solver).
PENALTY = 1e3


def make_model(p: dict, base: ContactModel) -> ContactModel:
    """The :class:`ContactModel` of the physical parameters ``p`` (M, g, S from ``base``)."""
    return ContactModel(M=base.M, g=base.g, S=base.S, c_n=p["S_c_n"] / base.S, m2=p["m2"],
                        h_n=p["S_h_n"] / base.S, l=p["l"])


def _models(plist: list[dict], base: ContactModel) -> list:
    out = []
    for p in plist:
        try:
            out.append(make_model(p, base))
        except (ParameterError, ValueError, OverflowError, ZeroDivisionError):
            out.append(None)
    return out


def guess_contact(f_n0: float, m2: float, zeta: float, l: float, base: ContactModel) -> dict:
    """S_c_n, S_h_n giving f_n0 [Hz] and ζ at these exponents (y0 ω_n0² = m2 g)."""
    w = 2.0 * math.pi * f_n0
    y0 = m2 * base.g / (w * w)
    return {"S_c_n": base.Q / y0**m2, "m2": m2, "S_h_n": 2.0 * zeta * base.M * w / y0**l, "l": l}


@dataclass
class StaticSet:
    """Residuals y_i − (F_i / S c_n)^(1/m2) [µm] of a :class:`StaticData`."""

    data: StaticData
    kind: str = "static"
    uses = ("S_c_n", "m2")
    nuisance = ()

    @property
    def n(self) -> int:
        return self.data.n

    def noise_guess(self) -> float:
        return 0.02 * float(np.max(np.abs(self.data.deflection_um)))

    def predict(self, p: dict, load_n) -> np.ndarray:
        """Deflection [µm] under ``load_n`` [N]."""
        return (np.asarray(load_n, float) / p["S_c_n"]) ** (1.0 / p["m2"]) * 1e6

    def residuals(self, plist: list[dict], base: ContactModel) -> np.ndarray:
        return np.array([self.predict(p, self.data.load_n) - self.data.deflection_um for p in plist])

    def log_log_guess(self) -> dict:
        """S_c_n, m2 of a log–log line through the loaded points (a start, not the fit)."""
        ok = (self.data.load_n > 0) & (self.data.deflection_um > 0)
        if np.count_nonzero(ok) < 2:
            return {"S_c_n": 1e13, "m2": 2.0}
        m2, b = np.polyfit(np.log(self.data.deflection_um[ok] * 1e-6), np.log(self.data.load_n[ok]), 1)
        m2 = float(np.clip(m2, 1.05, 6.0))
        ym = float(np.exp(np.mean(np.log(self.data.deflection_um[ok] * 1e-6))))
        Fm = float(np.exp(np.mean(np.log(self.data.load_n[ok]))))
        return {"S_c_n": Fm / ym**m2, "m2": m2}


@dataclass
class DecaySet:
    """Residuals [µm or m/s²] of the free oscillator from (``y_init_um``, ``v_init_mm_s``)."""

    data: DecayData
    kind: str = "decay"
    rtol: float = 1e-9
    #: fit only the samples up to t[0] + window_ms (the solver's first stages); None: all
    window_ms: float | None = None
    uses = CONTACT_NAMES
    nuisance = ("y_init_um", "v_init_mm_s")

    @property
    def n(self) -> int:
        return self.data.n

    def noise_guess(self) -> float:
        return 0.02 * float(np.max(np.abs(self.data.values)))

    def frequency_guess(self) -> float:
        """Oscillation frequency [Hz] from the zero crossings about the mean."""
        v = self.data.values - np.mean(self.data.values)
        s = np.flatnonzero(np.sign(v[1:]) * np.sign(v[:-1]) < 0)
        t = self.data.t_ms * 1e-3
        return (s.size - 1) / (2.0 * (t[s[-1]] - t[s[0]]))

    def initial_guess(self, p: dict, base: ContactModel) -> dict:
        """y_init, v_init from the first samples (displacement) or from the model's f_n0."""
        t, v = self.data.t_ms, self.data.values
        if self.data.kind == "y_um":  # a parabola through the first samples: y and dy/dt at t[0]
            j = min(6, v.size)
            c = np.polyfit(t[:j] - t[0], v[:j], 2)
            return {"y_init_um": float(c[2]), "v_init_mm_s": float(c[1])}
        m = _models([p], base)[0]
        w = m.omega_n0 if m is not None else 2 * math.pi * self.frequency_guess()
        return {"y_init_um": float(-v[0] / w**2 * 1e6), "v_init_mm_s": 0.0}

    def predict(self, plist: list[dict], base: ContactModel, t_ms) -> np.ndarray:
        """Model samples [µm or m/s²] at ``t_ms`` for each parameter set (NaN where refused)."""
        from contactvib._kernels.fitting import decays_many

        t_ms = np.asarray(t_ms, float)
        t_rel = t_ms - self.data.t_ms[0]
        out = np.full((len(plist), t_ms.size), np.nan)
        rows, pars, z0s, times, scales = [], [], [], [], []
        for j, (p, m) in enumerate(zip(plist, _models(plist, base))):
            if m is None:
                continue
            u = m.units
            tau = t_rel / u.t_ms
            x0, v0 = 1.0 + p["y_init_um"] / u.y_um, p["v_init_mm_s"] / u.ydot_mm_s
            if not (abs(x0) < 1e6 and abs(v0) < 1e6):
                continue
            rows.append(j)
            pars.append([m.m2, m.l, m.damping_coefficient, 0.0, 2 * math.pi / (tau[-1] * 1.000001)])
            z0s.append([x0, v0])
            times.append(tau)
            scales.append((u.y_um, m.m2, m.damping_coefficient, m.g * m.m2))
        if not rows:
            return out
        xs, vs = decays_many(np.array(pars), np.array(z0s), np.array(times), self.rtol)
        for j, x, v, (y_um, m2, c, acc) in zip(rows, xs, vs, scales):
            if self.data.kind == "y_um":
                out[j] = (x - 1.0) * y_um
            else:  # ÿ = x'' y0 ω_n0² = x'' m2 g
                f = np.where(x > 0, np.abs(x) ** m2 + c * np.abs(x) ** plist[j]["l"] * v, 0.0)
                out[j] = (1.0 - f) / m2 * acc
        return out

    def residuals(self, plist: list[dict], base: ContactModel) -> np.ndarray:
        d = self.data
        n = d.n if self.window_ms is None else max(8, int(np.searchsorted(d.t_ms, d.t_ms[0] + self.window_ms)))
        r = self.predict(plist, base, d.t_ms[:n]) - d.values[:n]
        scale = PENALTY * float(np.max(np.abs(self.data.values)))
        return np.where(np.isfinite(r), r, scale)


@dataclass
class FrfSet:
    """Residuals ln A_pp(model) − ln A_pp(data) of stepped-sine sweeps."""

    data: FrfData
    kind: str = "frf"
    kmax: int = 4
    last_states: object = None
    max_periods: int = 3000
    #: transient limit per step: this many linear decay times to 1e-4, at least ``min_periods``
    decay_times: float = 3.0
    min_periods: int = 100
    uses = CONTACT_NAMES
    nuisance = ()

    @property
    def n(self) -> int:
        return self.data.n

    def noise_guess(self) -> float:
        return 0.03

    def peak_frequency(self) -> float:
        """f_e [Hz] of the largest A_pp of the up sweeps at the lowest force (a jump's top)."""
        d = self.data
        F0 = float(np.min(d.force_n))
        sel = (d.force_n == F0) & (d.direction == "up")
        if not np.any(sel):
            sel = d.force_n == F0
        return float(d.fe_hz[sel][np.argmax(d.app_um[sel])])

    def predict(self, plist: list[dict], base: ContactModel, fe_hz=None, force_n=None,
                direction=None, warm=None) -> np.ndarray:
        """Model A_pp [µm] along the sweeps (the data's, or of ``fe_hz``, ``force_n``,
        ``direction`` given in sweep order) for each parameter set; NaN where refused.

        ``warm``: the orbit points (float64[n, 2], in the data's row order) of a sweep at nearby
        parameters to start every step from (see :func:`contactvib._kernels.fitting.stepped_sweep`);
        the orbit points of the first parameter set are kept in :attr:`last_states`."""
        from contactvib._kernels.fitting import sweeps_many

        d = self.data
        if fe_hz is not None:
            d = FrfData(np.asarray(fe_hz, float), np.asarray(force_n, float), np.ones(len(fe_hz)),
                        np.asarray(direction), d.source)
        sweeps = d.sweeps
        order = np.concatenate(sweeps)
        start = np.cumsum([0] + [s.size for s in sweeps])[:-1]
        seg_len = np.array([s.size for s in sweeps], np.int64)
        out = np.full((len(plist), d.n), np.nan)
        rows, pars, rs, ys, limits = [], [], [], [], []
        p_q = None
        for j, m in enumerate(_models(plist, base)):
            if m is None:
                continue
            p_q = d.force_n[order] / m.Q
            rows.append(j)
            pars.append([m.m2, m.l, m.damping_coefficient, 0.0, 1.0])
            rs.append(d.fe_hz[order] / m.f_n0)
            ys.append(m.y0 * 1e6)
            # periods for the linear decay to 1e-4 at the highest frequency, times decay_times
            n_dec = math.log(1e4) * float(np.max(rs[-1])) / (2.0 * math.pi * max(m.zeta, 1e-6))
            limits.append(int(min(self.max_periods, max(self.min_periods, self.decay_times * n_dec))))
        if not rows:
            return out
        z_start = np.zeros((d.n, 2)) if warm is None else np.asarray(warm, float)[order]
        app, _per, z_out = sweeps_many(np.array(pars), np.array(rs), p_q, z_start, warm is not None,
                                       start.astype(np.int64), seg_len, self.kmax, np.array(limits, np.int64),
                                       1e-4, 1e-7, 1e-9, 1e-8)
        for j, a, y in zip(rows, app, ys):
            out[j, order] = a * y
        self.last_states = np.empty((d.n, 2))
        self.last_states[order] = z_out[0]
        return out

    def residuals(self, plist: list[dict], base: ContactModel, warm=None) -> np.ndarray:
        a = self.predict(plist, base, warm=warm)
        with np.errstate(invalid="ignore", divide="ignore"):
            r = np.log(a) - np.log(self.data.app_um)
        return np.where(np.isfinite(r), r, math.log(PENALTY))


def make_set(data):
    """The forward model of a data object."""
    if isinstance(data, StaticData):
        return StaticSet(data)
    if isinstance(data, DecayData):
        return DecaySet(data)
    if isinstance(data, FrfData):
        return FrfSet(data)
    raise TypeError(f"not a data set: {type(data).__name__}")
