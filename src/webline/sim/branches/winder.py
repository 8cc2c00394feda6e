"""Winder functions of a branched line's rewinds in the plan (docs/branching.md, "Taper"):
a rewind's taper scales its zone's tension reference with its roll's diameter, as the chain's
``sim.core.winder`` does (docs/winder.md W1)."""

from __future__ import annotations

import math

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.physics.taper import KINDS, TABLE
from webline.sim.branches.loop import layout as B
from webline.spec.schema import RewindSpec


def taper_columns(line: BranchedLine, df: np.ndarray,
                  profiles: list[tuple[np.ndarray, np.ndarray]]) -> None:
    """Fill the taper columns of the drive table ``df``; a table taper's (diameter [m],
    factor) points are appended to ``profiles`` (a profile over the diameter)."""
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        if not isinstance(roller, RewindSpec) or roller.taper is None:
            continue
        spec = roller.taper
        df[d, B.D_TAPER_KIND] = KINDS[spec.type]
        df[d, B.D_TAPER] = spec.taper
        df[d, B.D_TAPER_DMAX] = math.inf if spec.max_diameter is None else spec.max_diameter
        if KINDS[spec.type] == TABLE:
            df[d, B.D_TAPER_PROF] = len(profiles)
            profiles.append((np.array(spec.diameter, dtype=float),
                             np.array(spec.factor, dtype=float)))


def diameter_columns(line: BranchedLine, df: np.ndarray, di: np.ndarray) -> np.ndarray:
    """Fill the diameter-calculator columns of ``df`` (docs/winder.md W2) and return each
    drive's starting calculated radius [m] (0 without a calculator): ``initial`` = "measured"
    is the true radius of the lane the drive measures speed on."""
    start = np.zeros(len(line.drives))
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        spec = getattr(roller, "diameter", None)
        j = di[d, B.DI_ROLL]
        if spec is None or j < 0:
            continue
        roll = line.rolls[j]
        df[d, B.D_DCALC] = (B.DCALC_THICKNESS if spec.method == "thickness"
                            else B.DCALC_SPEED_RATIO)
        df[d, B.D_DFILTER] = spec.filter
        df[d, B.D_DRATE] = math.inf if spec.rate_limit is None else spec.rate_limit
        df[d, B.D_DHOLD] = spec.hold_below
        df[d, B.D_DSOURCE] = (-1 if spec.line_speed == "reference" else line.master
                              if spec.line_speed == "master"
                              else line.node_index[spec.line_speed])
        df[d, B.D_DTHICK] = line.materials[roll.web].thickness
        df[d, B.D_DDIR] = roll.direction
        start[d] = roll.radius if spec.initial == "measured" else 0.5 * spec.initial
        df[d, B.D_PRESETN] = len(spec.preset)
        for p, preset in enumerate(spec.preset):
            df[d, B.D_PRESETT + p] = preset.at
            df[d, B.D_PRESETD + p] = 0.0 if preset.diameter == "measured" else preset.diameter
    return start
