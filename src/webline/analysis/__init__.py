"""Analyses of a line on top of the model and the simulation: modes, drive trains, stability,
the decentralized certificate and the certified design, the zone loops against what was asked
and the modes across the roll (docs/architecture.md, docs/winder.md).

The public functions are re-exported on first use (PEP 562): importing a submodule such as
``webline.analysis.modes`` (the run report does) then does not load scipy.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from webline.analysis.across_roll import modes_across_roll
    from webline.analysis.stability import (
        distance_to_instability,
        frequency_sweep_distance,
        instability_distance,
    )
    from webline.analysis.zone_loops import speed_leaks, zone_loops

#: public name -> the submodule that defines it
_HOMES = {"distance_to_instability": "stability", "frequency_sweep_distance": "stability",
          "instability_distance": "stability", "modes_across_roll": "across_roll",
          "zone_loops": "zone_loops", "speed_leaks": "zone_loops"}
__all__ = ["distance_to_instability", "frequency_sweep_distance", "instability_distance",
           "modes_across_roll", "speed_leaks", "zone_loops"]


def __getattr__(name: str) -> object:
    if name in _HOMES:
        return getattr(importlib.import_module(f"webline.analysis.{_HOMES[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
