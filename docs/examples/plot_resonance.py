"""
A resonance graph at one level
==============================

The sweep of ``contactvib resonance`` at 0.65 Q over 250–450 Hz in 10 Hz steps (the paper's
Fig. 2d covers 30–2000 Hz at 1 Hz): every attractor at every frequency, linked into branches,
coloured by resonance order, next to the local extrema of y(t) (Fig. 3d). On a range this short
the laboratory sweeps start inside the resonances, so what they reach (and the gold "isolated"
underlay) differs from the full graph.
"""

import matplotlib.pyplot as plt

from contactvib import ContactModel, SweepSettings, resonance_dataset
from contactvib.plotting import extrema_diagram, resonance_graph

settings = SweepSettings(fmin_hz=250.0, fmax_hz=450.0, df_hz=10.0, multistart_per_octave=1)
ds = resonance_dataset(ContactModel(), levels=[0.65], settings=settings, workers=1, progress=False)
print(ds.sizes["point"], "attractor points,", ds.sizes["branch"], "branches")

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4))
resonance_graph(ds, 0.65, ax=ax1)
extrema_diagram(ds, 0.65, ax=ax2)
fig.tight_layout()
