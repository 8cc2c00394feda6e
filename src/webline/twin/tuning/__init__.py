"""Tuning controllers on a (fitted) line: the search space, constraints (margins, limits,
robustness), identification experiments, outputs."""
