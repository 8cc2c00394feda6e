"""Drive motors: the torque limit. (The first-order torque loop of thesis 4.1k,
dτ/dt = (command - τ)/lag, is written out in the kernel with a precomputed 1/lag.)"""

from __future__ import annotations


def saturate(command: float, limit: float) -> float:
    """The ``command`` [N·m] clipped to ±``limit`` [N·m]."""
    if command > limit:
        return limit
    if command < -limit:
        return -limit
    return command
