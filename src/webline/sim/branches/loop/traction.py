"""Slip over traction rollers and friction as drives measure it, in a branched line's compiled
loop (docs/branching.md, "Slip and measured friction"): the chain's model (docs/slip.md,
``sim.elements.web_state.update_slip``, ``sim.elements.friction_loop``) on the node table's
columns of ``loop.layout``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import roller, slip, span
from webline.sim.branches.loop import layout as B
from webline.sim.elements.friction_loop import STICK_SPEED, row_table_torque, stick
from webline.sim.elements.signals import jit

_tension: Any = jit(span.tension)
_slip_state: Any = jit(slip.slip_state)
_slip_velocity: Any = jit(slip.slip_velocity)
_friction: Any = jit(roller.friction_torque)


@jit
def _velocity(i: int, t_in: float, t_out: float, omega: float, nodes: np.ndarray) -> float:
    """Slip speed s = v_r - v [m/s] of the web over traction node ``i`` at its held state."""
    surface = nodes[i, B.N_RADIUS] * omega
    return _slip_velocity(t_in, t_out, nodes[i, B.N_WRAP], nodes[i, B.N_MU], nodes[i, B.N_MUK],
                          nodes[i, B.N_SLIPB], nodes[i, B.N_RHOA] * surface * surface,
                          int(nodes[i, B.N_SLIPPING]), nodes[i, B.N_NIPK])


@jit
def slip_speeds(x: np.ndarray, tension: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
                slip: np.ndarray) -> None:
    """Slip speed [m/s] of the web over every node into ``slip`` (0 where it sticks or the
    node has no traction contact), from the spans' ``tension`` [N]: the web leaves the
    span into a slipping roller and enters the span out of it at r ω - s (Ch. 5, E-5.3)."""
    off_w = offsets[B.O_OMEGA]
    for i in range(nodes.shape[0]):
        slip[i] = 0.0
        if nodes[i, B.N_TRACTION] != 0.0 and nodes[i, B.N_SLIPPING] != 0.0:
            slip[i] = _velocity(i, tension[int(nodes[i, B.N_SPIN])],
                                tension[int(nodes[i, B.N_SPOUT])], x[off_w + i], nodes)


@jit
def update_slip(t: float, dt: float, measured: np.ndarray, offsets: np.ndarray,
                nodes: np.ndarray) -> None:
    """Stick/slip state of every traction node for the tick at ``t`` [s] (held over its
    RK4 stages, so the fixed step never chatters: ``physics.slip.slip_state``) from the
    sampled spans' stretches or felt tensions ``measured`` [N]; adds the tick (period ``dt``
    [s]) to the slip findings' columns."""
    off_w = offsets[B.O_OMEGA]
    for i in range(nodes.shape[0]):
        if nodes[i, B.N_TRACTION] == 0.0:
            continue
        t_in = _tension(measured[int(nodes[i, B.N_SPIN])])
        t_out = _tension(measured[int(nodes[i, B.N_SPOUT])])
        surface = nodes[i, B.N_RADIUS] * measured[off_w + i]
        was = int(nodes[i, B.N_SLIPPING])
        now = _slip_state(t_in, t_out, nodes[i, B.N_WRAP], nodes[i, B.N_MU], nodes[i, B.N_MUK],
                          nodes[i, B.N_RHOA] * surface * surface, was, nodes[i, B.N_NIPS],
                          nodes[i, B.N_NIPK])
        nodes[i, B.N_SLIPPING] = now
        if now == 0:
            continue
        if was == 0:
            nodes[i, B.N_SLIPCOUNT] += 1.0
            if nodes[i, B.N_SLIPFIRST] != nodes[i, B.N_SLIPFIRST] or t < nodes[i, B.N_SLIPFIRST]:
                nodes[i, B.N_SLIPFIRST] = t  # (nan until the first)
        nodes[i, B.N_SLIPTIME] += dt
        s = abs(_velocity(i, t_in, t_out, measured[off_w + i], nodes))
        if s > nodes[i, B.N_SLIPPEAK]:
            nodes[i, B.N_SLIPPEAK] = s


@jit
def table_torque(i: int, omega: float, nodes: np.ndarray) -> float:
    """Friction torque [N·m] of node ``i``'s friction table at ``omega`` [rad/s] (F1; 0
    without one)."""
    return row_table_torque(nodes[i], omega, B.N_FRICN, B.N_FRICW, B.N_FRICT)


@jit
def measured_friction(i: int, omega: float, total: float, coulomb: float,
                      nodes: np.ndarray) -> tuple[bool, float]:
    """(held, torque [N·m]) of node ``i`` with the torque ``total`` on it (web, drive,
    viscous and Coulomb friction): its friction table's torque taken off (F1); at rest
    (|ω| < STICK_SPEED) with a break-away torque B, held while the torque without the dry
    friction stays within B, else that torque less B against it (Karnopp's model, F2)."""
    table = table_torque(i, omega, nodes)
    total -= table
    limit = nodes[i, B.N_BREAKAWAY]
    if limit > 0.0 and abs(omega) < STICK_SPEED:
        return stick(total + table + (_friction(omega, 0.0, coulomb) if coulomb != 0.0 else 0.0),
                     limit)
    return False, total
