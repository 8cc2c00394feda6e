"""Signals a run derives from its records through the plan's tables: slip velocities,
transmission twist and backlash contact (``Result``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.physics.slip import slip_velocity
from webline.sim import layout as L

if TYPE_CHECKING:
    from webline.sim.plan import Plan


def slip_velocities(plan: Plan, tension: np.ndarray, surface_speed: np.ndarray,
                    slipping: np.ndarray) -> np.ndarray:
    """Surface speed minus web speed [m/s] at each node of ``plan``'s line (records x nodes;
    0 where the web adheres), from the span tensions [N], the rollers' surface speeds [m/s]
    and their stick/slip states, as the kernel computes it (Ch. 5, E-5.3)."""
    out = np.zeros_like(surface_speed)
    nodes = plan.nodes
    rho_a = plan.web[L.W_RHOA]
    for i in range(1, surface_speed.shape[1] - 1):
        if nodes[i, L.N_TRACTION] == 0.0:
            continue
        surface = surface_speed[:, i]
        out[:, i] = np.vectorize(slip_velocity)(
            tension[:, i - 1], tension[:, i], nodes[i, L.N_WRAP], nodes[i, L.N_MU],
            nodes[i, L.N_MUK], nodes[i, L.N_SLIPB], rho_a * surface**2,
            slipping[:, i].astype(int), nodes[i, L.N_NIPK])
    return out


def transmission_twist(plan: Plan, states: np.ndarray) -> np.ndarray:
    """Twist θm/n - θL of each compliant transmission [rad] (records x drives; NaN for
    rigid drives)."""
    out = np.full((states.shape[0], plan.drives.shape[0]), np.nan)
    for d in range(plan.drives.shape[0]):
        state = int(plan.drives[d, L.D_TSTATE])
        if state >= 0:
            out[:, d] = states[:, state + 1]
    return out


def backlash_contact(plan: Plan, twist: np.ndarray) -> np.ndarray:
    """Backlash contact of each drive from its ``twist`` [rad]: +1 forward flank, -1 backward
    flank, 0 in the gap (NaN for drives without backlash)."""
    out = np.full_like(twist, np.nan)
    for d in range(plan.drives.shape[0]):
        row = plan.drives[d]
        if row[L.D_TSTATE] >= 0 and row[L.D_GAPNEG] + row[L.D_GAPPOS] > 0:
            out[:, d] = np.where(twist[:, d] > row[L.D_GAPPOS], 1.0,
                                 np.where(twist[:, d] < -row[L.D_GAPNEG], -1.0, 0.0))
    return out
