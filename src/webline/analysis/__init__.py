"""Analyses of a line on top of the model and the simulation: modes, drive trains, stability,
the decentralized certificate and the certified design (docs/architecture.md)."""

from webline.analysis.stability import (
    distance_to_instability,
    frequency_sweep_distance,
    instability_distance,
)

__all__ = ["distance_to_instability", "frequency_sweep_distance", "instability_distance"]
