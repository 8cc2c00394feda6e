"""Rotation of rolls and rollers under web tension, drive torque and bearing friction (6.3, 6.9,
6.11, 6.13).

A roll that loses or gains web at its surface obeys J dω/dt = sum of torques, not
d(Jω)/dt = sum of torques: web leaves (or arrives) at the surface speed and carries its own
angular momentum away (or in). See docs/errata.md, E-6.1.
"""

from __future__ import annotations

import math

#: Speed [rad/s] below which Coulomb bearing friction is smoothed (tanh), so that a roller at
#: rest has a well-defined, continuous friction torque.
COULOMB_SMOOTHING = 0.1


def friction_torque(omega: float, viscous: float, coulomb: float) -> float:
    """Bearing friction torque [N·m] opposing rotation at ``omega`` [rad/s].

    ``viscous`` [N·m·s/rad] (the thesis's b_f), ``coulomb`` [N·m] smoothed by tanh.
    """
    return viscous * omega + coulomb * math.tanh(omega / COULOMB_SMOOTHING)


def angular_acceleration(inertia: float, arm: float, tension_out: float, tension_in: float,
                         shaft_torque: float, omega: float, viscous: float,
                         coulomb: float) -> float:
    """dω/dt [rad/s²] of a roller or roll of ``inertia`` [kg·m²].

    The web leaves towards downstream with ``tension_out`` [N] and arrives from upstream with
    ``tension_in`` [N], both at lever ``arm`` [m]; ``shaft_torque`` [N·m] is the drive torque
    at the roller shaft (ratio x motor torque), positive in the web direction.
    """
    torque = arm * (tension_out - tension_in) + shaft_torque
    return (torque - friction_torque(omega, viscous, coulomb)) / inertia
