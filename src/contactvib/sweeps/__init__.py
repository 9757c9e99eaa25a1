"""Frequency sweeps of many P_a levels, their dataset, and the reproduction of the paper."""
