"""The disturbances of a branched line as the compiled loop's table (``layout`` DS_*):
wound-in ripple per unwind, speed ripple per drive, drag torque per roller, measurement
noise (docs/branching.md, "Disturbances")."""

from __future__ import annotations

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.profiles import breakpoints
from webline.sim.branches.loop import layout as B
from webline.spec.disturbances import (
    EccentricRoller,
    MeasurementNoise,
    RollerDrag,
    SpeedRipple,
    WoundInRipple,
)
from webline.spec.schema import UnwindSpec


def eccentricities(line: BranchedLine) -> dict[int, float]:
    """Node -> eccentricity [m] of every out-of-round roller or roll (``eccentric_roller``):
    its lever arm and surface speed are r + e cos(angle), the angle a state (dθ/dt = ω)."""
    return {line.node_index[item.roller]: item.eccentricity for item in line.spec.disturbances
            if isinstance(item, EccentricRoller)}


def disturbance_table(line: BranchedLine,
                      profiles: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Rows (kind, index, a, b, c) of ``line``'s disturbances; a drag's torque profile is
    appended to ``profiles`` and its row names it."""
    rows = []
    unwinds = [i for i, r in enumerate(line.spec.rollers) if isinstance(r, UnwindSpec)]
    for item in line.spec.disturbances:
        if isinstance(item, WoundInRipple):
            node = unwinds[0] if item.roller is None else line.node_index[item.roller]
            web = next(w for w, v in enumerate(line.spec.webs)
                       if line.node_index[v.path[0]] == node)
            rows.append((B.DIST_WOUND_RIPPLE, web, item.amplitude, item.frequency, item.phase))
        elif isinstance(item, SpeedRipple):
            drive = line.drives.index(line.node_index[item.roller])
            rows.append((B.DIST_SPEED_RIPPLE, drive, item.amplitude, item.frequency,
                         item.phase))
        elif isinstance(item, RollerDrag):
            rows.append((B.DIST_DRAG, line.node_index[item.roller], len(profiles), 0.0, 0.0))
            profiles.append(breakpoints(item.torque))
        elif isinstance(item, MeasurementNoise):
            rows.append((B.DIST_NOISE, item.seed, item.tension, item.speed,
                         item.speed_resolution))
    return np.array(rows, dtype=float).reshape(-1, B.DS_COLS)
