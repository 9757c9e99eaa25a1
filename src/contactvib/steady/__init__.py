"""Steady states at one operating point: orbit refinement and description, the attractor search,
time histories."""
