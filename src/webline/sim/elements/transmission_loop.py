"""Compliant transmissions in the compiled loop (belt, shaft, backlash; thesis Ch. 2-3)."""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import backlash
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit

_transmitted: Any = jit(backlash.transmitted_torque)


@jit
def compliant_torque(d: int, x: np.ndarray, ds: np.ndarray, offsets: np.ndarray,
                     drives: np.ndarray, dx: np.ndarray) -> float:
    """Torque [N·m] a compliant transmission passes to its roller shaft; writes the
    derivatives of its motor speed and twist into ``dx``.

    Belt (2.10), shaft and backlash (3.22-3.23), belt and backlash (3.31-3.32), in rotary
    form seen from the load shaft: J_m dω_m/dt = τ - T_s/n - b_m ω_m, d(twist)/dt = ω_m/n - ω,
    and the roller gets T_s.
    """
    i = ds[d, L.DS_NODE]
    n = drives[d, L.D_RATIO]
    state = ds[d, L.DS_TSTATE]
    omega_m = x[state]
    rate = omega_m / n - x[offsets[L.O_OMEGA] + i]
    torque = _transmitted(x[state + 1], rate, drives[d, L.D_KTRANS], drives[d, L.D_CTRANS],
                          drives[d, L.D_GAPNEG], drives[d, L.D_GAPPOS])
    dx[state] = (x[offsets[L.O_TORQUE] + d] - torque / n - drives[d, L.D_BMOTOR] * omega_m) / (
        drives[d, L.D_JMOTOR])
    dx[state + 1] = rate
    return torque
