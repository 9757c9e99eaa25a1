"""The fitted model's curves next to the data, for the figures of ``contactvib fit``."""

from __future__ import annotations

import numpy as np


def _envelope(t: np.ndarray, y: np.ndarray):
    """Upper and lower envelopes of an oscillation: its local maxima and minima [t, y]."""
    i = np.arange(1, y.size - 1)
    top = i[(y[i] >= y[i - 1]) & (y[i] > y[i + 1])]
    bot = i[(y[i] <= y[i - 1]) & (y[i] < y[i + 1])]
    return (t[top], y[top]), (t[bot], y[bot])


def model_curves(result, n_points: int = 120) -> dict:
    """For each data set of ``result``: the data, the model at the data points, the residuals
    (data − model, in the data's units) and a dense model curve.

    Returns
    -------
    dict
        ``static``: load_n, deflection_um, model_um, residual_um, curve_load_n, curve_um;
        ``decay``: t_ms, values, kind, model, residual, curve_t_ms, curve, envelope (upper, lower);
        ``frf``: fe_hz, force_n, app_um, direction, model_um, residual_um, and per force level
        ``curves``: [(force_n, f_up, app_up, f_down, app_down)].
    """
    p, base = result.values, result.model
    out = {}
    for s in result.sets:
        d = s.data
        if s.kind == "static":
            y = np.linspace(0.0, float(s.predict(p, d.load_n.max())) * 1.03, n_points)
            model = s.predict(p, d.load_n)
            out["static"] = dict(load_n=d.load_n, deflection_um=d.deflection_um, model_um=model,
                                 residual_um=d.deflection_um - model, curve_load_n=p["S_c_n"] * (y * 1e-6) ** p["m2"],
                                 curve_um=y)
        elif s.kind == "decay":
            model = s.predict([p], base, d.t_ms)[0]
            t = np.linspace(d.t_ms[0], d.t_ms[-1], max(8 * d.n, 2000))
            curve = s.predict([p], base, t)[0]
            out["decay"] = dict(t_ms=d.t_ms, values=d.values, kind=d.kind, model=model, residual=d.values - model,
                                curve_t_ms=t, curve=curve, envelope=_envelope(t, curve))
        else:
            model = s.predict([p], base)[0]
            curves = []
            for F in np.unique(d.force_n):
                sel = d.force_n == F
                f = np.linspace(float(d.fe_hz[sel].min()), float(d.fe_hz[sel].max()), n_points)
                a = s.predict([p], base, np.concatenate([f, f[::-1]]), np.full(2 * n_points, F),
                              ["up"] * n_points + ["down"] * n_points)[0]
                curves.append((float(F), f, a[:n_points], f[::-1], a[n_points:]))
            out["frf"] = dict(fe_hz=d.fe_hz, force_n=d.force_n, app_um=d.app_um, direction=d.direction,
                              model_um=model, residual_um=d.app_um - model, curves=curves)
    return out
