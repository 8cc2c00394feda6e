"""Analyses of a line on top of the model and the simulation: modes, drive trains, stability,
the decentralized certificate and the certified design (docs/architecture.md).

The stability functions are re-exported on first use (PEP 562): importing a submodule such as
``webline.analysis.modes`` (the run report does) then does not load scipy.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from webline.analysis.stability import (
        distance_to_instability,
        frequency_sweep_distance,
        instability_distance,
    )

__all__ = ["distance_to_instability", "frequency_sweep_distance", "instability_distance"]


def __getattr__(name: str) -> object:
    if name in __all__:
        return getattr(importlib.import_module("webline.analysis.stability"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
