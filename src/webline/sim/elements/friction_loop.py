"""Friction as drives measure it, in the compiled loop (docs/winder.md, F1-F2): a node's
friction table and the break-away torque of a roller at rest."""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import roller
from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit

_table_friction: Any = jit(roller.table_friction)
_table_magnitude: Any = jit(roller.table_magnitude)

#: Speed [rad/s] below which a roller with a break-away torque counts as at rest (F2): a
#: tenth of the Coulomb smoothing, where the running friction has fallen to a tenth
STICK_SPEED = 0.1 * roller.COULOMB_SMOOTHING


@jit
def row_table_torque(row: np.ndarray, omega: float, n_col: int, w_col: int,
                     t_col: int) -> float:
    """Friction torque [N·m] at ``omega`` [rad/s] of the friction table a node-table ``row``
    holds: its point count at column ``n_col``, speeds from ``w_col``, torques from ``t_col``
    (F1; 0 without one). Either loop's layout: the chain's and a branched line's."""
    n = int(row[n_col])
    if n == 0:
        return 0.0
    return _table_friction(omega, row[w_col:w_col + n], row[t_col:t_col + n])[0]


@jit
def table_torque(i: int, omega: float, nodes: np.ndarray) -> float:
    """Friction torque [N·m] of node ``i``'s friction table at ``omega`` [rad/s] (F1; 0
    without one)."""
    return row_table_torque(nodes[i], omega, L.N_FRICN, L.N_FRICW, L.N_FRICT)


@jit
def stick(applied: float, limit: float) -> tuple[bool, float]:
    """(stuck, torque [N·m]) of a roller at rest held by static friction up to ``limit``
    [N·m] under the ``applied`` torque (web, drive and viscous, no dry friction): stuck
    while |applied| <= limit, else applied less the limit against it (Karnopp's model, F2;
    a set brake's too, W8)."""
    if abs(applied) <= limit:
        return True, 0.0
    return False, applied - limit if applied > 0.0 else applied + limit


@jit
def breakaway(i: int, omega: float, applied: float, nodes: np.ndarray) -> tuple[bool, float]:
    """(stuck, torque [N·m]) of node ``i`` at rest (|ω| < STICK_SPEED) with break-away
    torque B under the ``applied`` torque (``stick``, F2)."""
    return stick(applied, nodes[i, L.N_BREAKAWAY])


@jit
def compensation_table(d: int, omega: float, drives: np.ndarray) -> float:
    """Friction torque [N·m] at the roll shaft a drive's compensation table gives at the
    measured ``omega`` [rad/s]: its magnitude at |ω| with the sign of ω (F1, W3)."""
    n = int(drives[d, L.D_COMPFN])
    if n == 0 or omega == 0.0:
        return 0.0
    mag = _table_magnitude(abs(omega), drives[d, L.D_COMPFW:L.D_COMPFW + n],
                           drives[d, L.D_COMPFT:L.D_COMPFT + n])
    return mag if omega > 0.0 else -mag


def friction_columns(nodes: np.ndarray, drives: np.ndarray, line: Any, dt: float) -> bool:
    """Fill the friction-table and break-away columns of the node table and the compensation
    tables of the drive table from ``line`` (control period ``dt`` [s]: a stuck roller's ω
    decays in it, slower than any RK4 sub-step); True if any is used (``O_FRICTION``)."""
    used = False
    for i, spec in enumerate(line.spec.rollers):
        if spec.friction_table is not None:
            speeds, torques = spec.friction_table.arrays()
            nodes[i, L.N_FRICN] = len(speeds)
            nodes[i, L.N_FRICW:L.N_FRICW + len(speeds)] = speeds
            nodes[i, L.N_FRICT:L.N_FRICT + len(speeds)] = torques
            used = True
        if spec.breakaway_torque > 0.0:
            nodes[i, L.N_BREAKAWAY] = spec.breakaway_torque
            used = True
        nodes[i, L.N_STICKTAU] = dt
        winder = getattr(spec, "winder", None)
        if winder is not None and winder.friction_table is not None:
            speeds, torques = winder.friction_table.arrays()
            row = drives[line.drives.index(i)]
            row[L.D_COMPFN] = len(speeds)
            row[L.D_COMPFW:L.D_COMPFW + len(speeds)] = speeds
            row[L.D_COMPFT:L.D_COMPFT + len(speeds)] = torques
            used = True
    return used
