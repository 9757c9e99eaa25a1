"""Periodic orbits followed in a parameter: shooting continuation in f_e or P_a, Floquet
stability, special points and branch switching, whole bifurcation diagrams, and two-parameter
curves of folds and period doublings. The public names are exported by :mod:`contactvib`."""
