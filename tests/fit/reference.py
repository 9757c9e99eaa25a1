"""The synthetic measurements of tests/data (scipy solve_ivp with located contact events,
``tests/data/make_fit_reference.py``) with seeded noise, and their true parameters."""

import re
from pathlib import Path

import numpy as np

from contactvib import ContactModel
from contactvib.fitting import decay_data, frf_data, read_decay, read_frf

DATA = Path(__file__).resolve().parents[1] / "data"


def truth(name: str) -> tuple[ContactModel, dict]:
    """The model of a reference set and its fitted parameters (S_c_n, m2, S_h_n, l)."""
    head = (DATA / f"fit_{name}_decay.csv").read_text().splitlines()[0]
    kv = dict(re.findall(r"(\w+)=([-+0-9.e]+)", head))
    m = ContactModel(**{k: float(v) for k, v in kv.items()})
    return m, {"S_c_n": m.S * m.c_n, "m2": m.m2, "S_h_n": m.S * m.h_n, "l": m.l}


def noisy_decay(name: str, noise: float, seed: int):
    """The decay of set ``name`` plus Gaussian noise of ``noise`` times its largest |y|."""
    d = read_decay(DATA / f"fit_{name}_decay.csv")
    rng = np.random.default_rng(seed)
    return decay_data(d.t_ms, d.values + rng.normal(0.0, noise * np.abs(d.values).max(), d.n))


def noisy_frf(name: str, noise: float, seed: int):
    """The stepped-sine sweeps of set ``name`` with A_pp times exp(N(0, noise))."""
    d = read_frf(DATA / f"fit_{name}_frf.csv")
    rng = np.random.default_rng(seed)
    return frf_data(d.fe_hz, d.force_n, d.app_um * np.exp(rng.normal(0.0, noise, d.n)), d.direction)


def within(result, true: dict, k: float = 2.0) -> dict:
    """name -> (|error| / stderr) for every fitted contact parameter (log errors for the products)."""
    out = {}
    for n, v in true.items():
        if n not in result.parameters:
            continue
        est, se = result.value(n), result.stderr(n)
        err = abs(np.log(est / v)) / (se / est) if n in ("S_c_n", "S_h_n") else abs(est - v) / se
        out[n] = err
    return out
