"""
Coexisting attractors at 0.65 Q, 360 Hz
=======================================

The paper's Fig. 4 operating point: the attractor search (64 random starts here, 512 by
default) and the time history and phase portrait of the main resonance.
"""

from contactvib import ContactModel, attractor_history, find_attractors
from contactvib.plotting import attractor_figure

model = ContactModel()
exc = model.excitation(0.65, 360.0)
found = find_attractors(exc, n_starts=64)
for a in found:
    print(a.period, a.minima_per_period, round(a.app_um, 3), a.loses_contact)

main = max(found, key=lambda a: a.app_um if a.period == 1 else 0.0)
fig = attractor_figure(attractor_history(exc, main), main)
