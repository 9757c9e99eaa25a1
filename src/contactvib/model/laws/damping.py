"""The damping families of the contact (the coefficient in contact, ``F_d = c_d(δ) δ̇``), acting
on the chosen spring law's deflection δ while δ > 0:

* ``"power"`` — ``S h_n δ^l δ̇`` (the paper's);
* ``"hunt-crossley"`` — ``α F_s(δ) δ̇`` (Hunt & Crossley 1975), ``alpha`` [s/m].
"""

from __future__ import annotations

__all__ = ["DAMPING_NAMES", "HUNT_CROSSLEY_DEFAULT", "DAMPING_PARAMETERS"]

#: Damping families by CLI name (``--damping``).
DAMPING_NAMES = ("power", "hunt-crossley")
#: The model parameters of each damping family (their ``--set`` names).
DAMPING_PARAMETERS = {"power": ("h_n", "l"), "hunt-crossley": ("alpha",)}
#: Default Hunt–Crossley coefficient [s/m]: the paper's linear damping ratio ζ ≈ 0.018 with the
#: paper's power spring (α = S h_n y0 / Q).
HUNT_CROSSLEY_DEFAULT = 34.4
