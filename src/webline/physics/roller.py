"""Rotation of rolls and rollers under web tension, drive torque and bearing friction (6.3, 6.9,
6.11, 6.13).

A roll that loses or gains web at its surface obeys J dω/dt = sum of torques, not
d(Jω)/dt = sum of torques: web leaves (or arrives) at the surface speed and carries its own
angular momentum away (or in). See docs/errata.md, E-6.1.
"""

from __future__ import annotations

import math

import numpy as np

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


def table_magnitude(speed: float, speeds: np.ndarray, torques: np.ndarray) -> float:
    """Friction torque [N·m] a drive measured at shaft speed ``speed`` = |ω| [rad/s]:
    linear between the measured points (``speeds`` [rad/s], increasing, ``torques`` [N·m]),
    constant beyond the first and the last (docs/winder.md, F1)."""
    n = speeds.shape[0]
    if speed <= speeds[0]:
        return float(torques[0])
    for k in range(n - 1):
        if speed < speeds[k + 1]:
            share = (speed - speeds[k]) / (speeds[k + 1] - speeds[k])
            return float(torques[k] + share * (torques[k + 1] - torques[k]))
    return float(torques[n - 1])


def table_friction(omega: float, speeds: np.ndarray, torques: np.ndarray) -> tuple[float, float]:
    """(torque [N·m], d torque/dω [N·m·s]) of a friction table at ``omega`` [rad/s]: the
    measured magnitude at |ω| with the sign of the rotation, smoothed at rest as Coulomb
    friction is: f(|ω|) tanh(ω/ω_s) (F1)."""
    speed = abs(omega)
    n = speeds.shape[0]  # (table_magnitude written out: numba compiles this alone)
    mag, slope = torques[n - 1], 0.0  # slope f'(|ω|): the segment's (0 beyond the ends)
    if speed <= speeds[0]:
        mag = torques[0]
    else:
        for k in range(n - 1):
            if speed < speeds[k + 1]:
                slope = (torques[k + 1] - torques[k]) / (speeds[k + 1] - speeds[k])
                mag = torques[k] + slope * (speed - speeds[k])
                break
    smooth = math.tanh(omega / COULOMB_SMOOTHING)
    return (float(mag * smooth),
            float(slope * abs(smooth) + mag * (1.0 - smooth * smooth) / COULOMB_SMOOTHING))
