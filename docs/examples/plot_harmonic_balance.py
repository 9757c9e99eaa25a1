"""
Harmonic balance and the perturbation series
============================================

Two frequency-domain cross-checks of the time integration at 0.65 Q: the harmonic-balance
branch (16 harmonics) from 300 to 340 Hz, stable solid, unstable dashed, and the perturbation
series' A_pp where it holds (contact kept, converged).
"""

import numpy as np

from contactvib import ContactModel, hb_continuation, perturbation_curve
from contactvib.plotting import plot_branch

model = ContactModel()
branch = hb_continuation(model, pa_over_q=0.65, fmin_hz=300.0, fmax_hz=340.0, harmonics=16)
ax = plot_branch(branch, label="harmonic balance (H = 16)")
fe, app, valid = perturbation_curve(model, pa_over_q=0.65, fe_hz=np.arange(300.0, 341.0, 5.0), terms=16)
ax.plot(fe[valid], app[valid], "rx", label="perturbation series (N = 16 terms)")
ax.legend()
ax.figure.tight_layout()
