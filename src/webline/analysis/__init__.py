"""Analyses of a line: operating point, linear models, modes, drive trains, stability."""

from webline.analysis.stability import (
    distance_to_instability,
    frequency_sweep_distance,
    instability_distance,
)

__all__ = ["distance_to_instability", "frequency_sweep_distance", "instability_distance"]
