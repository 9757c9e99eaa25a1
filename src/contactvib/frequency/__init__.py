"""Frequency-domain solutions: the perturbation series and harmonic balance."""
