"""Named studies: thesis reproductions and examples that return data and figures.

``STUDIES`` maps a study's name to ``run(out_dir, *, quick=False) -> StudyResult``; ``quick``
runs a shortened version (seconds) for the tests.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Protocol

from webline.studies import (
    belt_step,
    ecp_backlash,
    hswl_controllers,
    robustness,
    rockwell_rewind,
    slip_example,
    slip_threshold,
    solid_motion,
    speed_change_surge,
    tension_observer,
    unwind_belt_ramp,
    wound_roll_band,
)
from webline.studies.result import StudyResult


class Study(Protocol):
    def __call__(self, out_dir: Path, *, quick: bool = False) -> StudyResult: ...


STUDIES: dict[str, Callable[..., StudyResult]] = {
    "hswl-controllers": hswl_controllers.run,
    "belt-step": belt_step.run,
    "solid-motion": solid_motion.run,
    "ecp-backlash": ecp_backlash.run,
    "unwind-belt-ramp": unwind_belt_ramp.run,
    "rockwell-rewind": rockwell_rewind.run,
    "slip-example": slip_example.run,
    "slip-threshold": slip_threshold.run,
    "robustness": robustness.run,
    "tension-observer": tension_observer.run,
    "speed-change-surge": speed_change_surge.run,
    "wound-roll-band": wound_roll_band.run,
}


def run_study(name: str, out_dir: Path, *, quick: bool = False) -> StudyResult:
    """Run the study ``name`` writing its figures under ``out_dir``."""
    if name not in STUDIES:
        raise KeyError(f"no study named {name!r}; known: {', '.join(sorted(STUDIES))}")
    return STUDIES[name](Path(out_dir), quick=quick)


__all__ = ["STUDIES", "Study", "StudyResult", "run_study"]
