"""Drive motors: a first-order torque loop with a torque limit (thesis 4.1k)."""

from __future__ import annotations


def torque_rate(torque: float, command: float, lag: float) -> float:
    """dτ/dt [N·m/s]: ``torque`` [N·m] follows ``command`` [N·m] with time constant ``lag`` [s]."""
    return (command - torque) / lag


def saturate(command: float, limit: float) -> float:
    """The ``command`` [N·m] clipped to ±``limit`` [N·m]."""
    if command > limit:
        return limit
    if command < -limit:
        return -limit
    return command
