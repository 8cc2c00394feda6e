"""The cascaded PI's speed feedforward, shared by the built-in PI and a user's drive (which
is told the reference the built-in PI would follow)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics.span import draw_ratio
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit

_draw: Any = jit(draw_ratio)


@jit
def speed_feedforward(d: int, t: float, ds: np.ndarray, offsets: np.ndarray, web: np.ndarray,
                      refs: np.ndarray, speed_ripple: np.ndarray) -> float:
    """Speed reference [m/s] of drive ``d`` at time ``t`` [s]: line speed x draw (from the
    tension references upstream of the master and of the drive: the web's strain changes its
    speed) plus the drive's speed ripple (``speed_ripple`` rows: drive, amplitude [m/s],
    frequency [Hz], phase [rad])."""
    ea = web[L.W_EA]
    up = ds[d, L.DS_UPREF]
    t_up = web[L.W_T0] if up < 0 else refs[up]
    t_m = refs[offsets[L.O_MASTER_UP]]
    if offsets[L.O_EXACT]:  # v/(1 + ε) the same at every node (``physics.span.draw_ratio``)
        ref = refs[0] * _draw(ea, t_up, t_m, True)
    else:  # (6.22), written as before so that first-order runs keep their last bits
        ref = refs[0] * (ea - t_m) / (ea - t_up)
    for r in range(speed_ripple.shape[0]):
        if int(speed_ripple[r, 0]) == d:
            ref += speed_ripple[r, 1] * math.sin(2.0 * math.pi * speed_ripple[r, 2] * t
                                                 + speed_ripple[r, 3])
    return ref
