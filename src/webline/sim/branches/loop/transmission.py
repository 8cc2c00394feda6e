"""Compliant transmissions of a branched line's drives in the compiled loop (belt, shaft,
backlash; thesis 2.10, 3.22-3.23, 3.31-3.32), as the chain's ``sim.elements.transmission_loop``:
the motor turns at its own speed ω_m and the transmission's twist (θ_m/n - θ_L, at the load
shaft) carries the torque to the roller. Columns: ``layout`` DI_TSTATE, D_KTRANS...D_FEEDBACK.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import backlash
from webline.sim.branches.loop import layout as B
from webline.sim.elements.signals import jit

_transmitted: Any = jit(backlash.transmitted_torque)


@jit
def drive_trains(x: np.ndarray, di: np.ndarray, df: np.ndarray, offsets: np.ndarray,
                 torque: np.ndarray, dx: np.ndarray) -> None:
    """Add each compliant drive's transmitted torque T_s [N·m] to its roller's ``torque``
    and write the derivatives of its motor speed and twist into ``dx``:
    J_m dω_m/dt = τ - T_s/n - b_m ω_m, d(twist)/dt = ω_m/n - ω_L, T_s = k (twist past the
    dead zone) + c d(twist)/dt while the teeth touch (``physics.backlash``). ``di`` is frozen
    into the compiled loop: a line of direct drives folds this away."""
    off_w, off_tq = offsets[B.O_OMEGA], offsets[B.O_TORQUE]
    for d in range(di.shape[0]):
        state = di[d, B.DI_TSTATE]
        if state < 0:
            continue
        i = di[d, B.DI_NODE]
        n = df[d, B.D_RATIO]
        omega_m = x[state]
        rate = omega_m / n - x[off_w + i]
        passed = _transmitted(x[state + 1], rate, df[d, B.D_KTRANS], df[d, B.D_CTRANS],
                              df[d, B.D_GAPNEG], df[d, B.D_GAPPOS])
        torque[i] += passed
        dx[state] = (x[off_tq + d] - passed / n - df[d, B.D_BMOTOR] * omega_m) / (
            df[d, B.D_JMOTOR])
        dx[state + 1] = rate


@jit
def measured_omega(d: int, i: int, x: np.ndarray, offsets: np.ndarray, di: np.ndarray,
                   df: np.ndarray) -> float:
    """Speed [rad/s of the roller] drive ``d``'s speed loop measures on node ``i``: the
    roller's, or across a compliant transmission with ``feedback = "motor"`` the motor's / n
    (thesis 2.16-2.19)."""
    state = di[d, B.DI_TSTATE]
    if state >= 0 and df[d, B.D_FEEDBACK] > 0.0:
        return x[state] / df[d, B.D_RATIO]
    return x[offsets[B.O_OMEGA] + i]


@jit
def reflected_motor(d: int, di: np.ndarray, df: np.ndarray) -> float:
    """n² J_m [kg·m²] of a compliant drive's motor (on the far side of its transmission, not
    in its node's inertia), 0 for a direct drive (its node holds it)."""
    if di[d, B.DI_TSTATE] < 0:
        return 0.0
    return df[d, B.D_RATIO] ** 2 * df[d, B.D_JMOTOR]


@jit
def motor_beyond(d: int, df: np.ndarray) -> float:
    """n² J_m [kg·m²] of drive ``d``'s motor where a compliant transmission keeps it out of
    its node's inertia (stiffness > 0), else 0 (from the float table alone, for the centre
    winder's inertia compensation, which sees no integer table)."""
    if df[d, B.D_KTRANS] <= 0.0:
        return 0.0
    return df[d, B.D_RATIO] ** 2 * df[d, B.D_JMOTOR]
