"""The example measurements of ``contactvib fit`` (docs/tutorials/fitting.md).

Synthetic measurements of the paper's contact (Kostek 2013: M = 0.2106 kg, S = 0.0009 m²,
c_n = 4.52e16, m2 = 2, h_n = 3.5e11, l = 1) with seeded noise:

* ``fit_static.csv``: F = S c_n y^m2 at 25 loads 0..8 N, deflection + 2 % (of its largest value)
  Gaussian noise;
* ``fit_frf.csv``: the stepped-sine sweeps up and down at P_a = 0.3 Q and 0.65 Q of
  ``tests/data/fit_paper_frf.csv`` (scipy solve_ivp with located contact events), A_pp times
  exp(N(0, 0.02)), i.e. 2 % reading noise;
* ``fit_decay.csv``: the free decay of ``tests/data/fit_paper_decay.csv`` + 2 % (of its largest
  value) Gaussian noise.

Run ``python examples/make_fit_examples.py`` from the repository root.
"""

import csv
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE.parent / "tests" / "data"
S, C_N, M2 = 0.0009, 4.52e16, 2.0


def _rows(path):
    with open(path) as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def main():
    rng = np.random.default_rng(2013)
    F = np.linspace(0.0, 8.0, 25)
    y = (F / (S * C_N)) ** (1.0 / M2) * 1e6
    y = y + rng.normal(0.0, 0.02 * y.max(), y.size)
    with open(HERE / "fit_static.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["load_n", "deflection_um"])
        w.writerows([f"{a:.6g}", f"{b:.6g}"] for a, b in zip(F, y))
    frf = DATA / "fit_paper_frf.csv"
    if frf.exists():
        rows = _rows(frf)
        with open(HERE / "fit_frf.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["fe_hz", "force_amplitude_n", "app_um", "direction"])
            for r in rows:
                a = float(r["app_um"]) * np.exp(rng.normal(0.0, 0.02))
                w.writerow([r["fe_hz"], f"{float(r['force_amplitude_n']):.6g}", f"{a:.6g}", r["direction"]])
    decay = DATA / "fit_paper_decay.csv"
    if decay.exists():
        rows = _rows(decay)
        t = np.array([float(r["t_ms"]) for r in rows])
        v = np.array([float(r["y_um"]) for r in rows])
        v = v + rng.normal(0.0, 0.02 * np.abs(v).max(), v.size)
        with open(HERE / "fit_decay.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["t_ms", "y_um"])
            w.writerows([f"{a:.6g}", f"{b:.6g}"] for a, b in zip(t, v))


if __name__ == "__main__":
    main()
