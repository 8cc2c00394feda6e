"""Centre-winder torque functions in the compiled loop (docs/winder.md, W3-W4): inertia and
friction compensation, and open-loop (indirect) tension control."""

from __future__ import annotations

import numpy as np

from webline.sim import layout as L
from webline.sim.signals import jit


@jit
def compensation(d: int, inertia: float, radius: float, omega: float, a_line: float,
                 drives: np.ndarray) -> float:
    """Motor torque [N·m] drive ``d`` adds for its roll's inertia and friction (W3):
    (J a_line / R + c_s sign(ω) + b ω) / n, J [kg·m²] and R [m] as the controller knows them,
    a_line [m/s²] the line-speed reference's acceleration, ω [rad/s] the measured speed."""
    torque = drives[d, L.D_COMPJ] * inertia * a_line / radius
    if omega > 0.0:
        torque += drives[d, L.D_COMPCS]
    elif omega < 0.0:
        torque -= drives[d, L.D_COMPCS]
    torque += drives[d, L.D_COMPB] * omega
    return torque / drives[d, L.D_RATIO]


@jit
def open_loop_command(d: int, direction: float, radius: float, tension_ref: float,
                      comp: float, drives: np.ndarray, out: np.ndarray) -> None:
    """Indirect tension control (W4): τ = ±T_ref R / n + compensation, + on a rewind (the web
    pulls it back), - on an unwind (the motor brakes it); clipped to the torque limit."""
    raw = direction * tension_ref * radius / drives[d, L.D_RATIO] + comp
    limit = drives[d, L.D_LIMIT]
    out[0, d] = min(max(raw, -limit), limit)
    out[1, d] = 0.0
    out[2, d] = 0.0
    out[3, d] = raw
