"""Taper tension (docs/winder.md, W1): the factor on a rewind's tension reference."""

from __future__ import annotations

import math

import numpy as np

from webline.spec.winder import TaperSpec

LINEAR, HYPERBOLIC, TABLE = 1, 2, 3


def taper_factor(kind: int, taper: float, core_diameter: float, max_diameter: float,
                 diameter: float) -> float:
    """Factor [-] on the tension reference at roll diameter ``diameter`` [m] for a linear or
    hyperbolic taper of ``taper`` [-] (a table is interpolated by the caller); never below
    zero."""
    if kind == LINEAR:
        f = 1.0 - taper * (diameter - core_diameter) / (max_diameter - core_diameter)
    elif kind == HYPERBOLIC:
        f = 1.0 - taper * (1.0 - core_diameter / diameter)
    else:
        f = 1.0
    return f if f > 0.0 else 0.0


KINDS = {"linear": LINEAR, "hyperbolic": HYPERBOLIC, "table": TABLE}


def spec_factor(spec: TaperSpec | None, core_radius: float, radius: float) -> float:
    """``taper_factor`` of a line file's ``taper`` table at roll radius ``radius`` [m]
    (1 without one)."""
    if spec is None:
        return 1.0
    if spec.type == "table":
        return float(np.interp(2.0 * radius, spec.diameter, spec.factor))
    d_max = spec.max_diameter if spec.max_diameter is not None else math.inf
    return taper_factor(KINDS[spec.type], spec.taper, 2.0 * core_radius, d_max, 2.0 * radius)
