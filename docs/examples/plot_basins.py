"""
Basins of attraction at 0.65 Q, 360 Hz
======================================

Which of the coexisting attractors each initial state (y, ẏ) at phase 0 of the force reaches, on
a 40 × 30 grid of the search's start box (400 × 400 in the tutorial): the 1/4 holds the centre
around the equilibrium, wrapped by spiral bands of the 1/3, 1/2 and main resonance.
"""

from contactvib import ContactModel, basins
from contactvib.plotting import basins_figure

model = ContactModel()
bmap = basins(model.excitation(0.65, 360.0), grid=(40, 30), n_starts=32)
print(bmap.fractions())
fig = basins_figure(bmap)
