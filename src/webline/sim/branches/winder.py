"""Winder functions of a branched line's rewinds in the plan (docs/branching.md, "Taper"):
a rewind's taper scales its zone's tension reference with its roll's diameter, as the chain's
``sim.core.winder`` does (docs/winder.md W1)."""

from __future__ import annotations

import math

import numpy as np

from webline.model.web_graph import BranchedLine
from webline.physics.taper import KINDS, TABLE
from webline.sim.branches import layout as B
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
