"""Signals a run derives from its records through the plan's tables: slip velocities,
transmission twist and backlash contact (``Result``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.physics.slip import slip_velocity
from webline.sim.elements import layout as L

if TYPE_CHECKING:
    from webline.sim.core.plan import Plan


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


def transmission_twist(tstate: np.ndarray, states: np.ndarray) -> np.ndarray:
    """Twist θm/n - θL of each compliant transmission [rad] (records x drives; NaN for
    rigid drives) from the records ``states``; ``tstate``: each drive's first transmission
    state (motor speed, then twist), -1 for a rigid drive (any loop's drive table)."""
    out = np.full((states.shape[0], len(tstate)), np.nan)
    for d, state in enumerate(tstate):
        if state >= 0:
            out[:, d] = states[:, int(state) + 1]
    return out


def backlash_contact(tstate: np.ndarray, gap_neg: np.ndarray, gap_pos: np.ndarray,
                     twist: np.ndarray) -> np.ndarray:
    """Backlash contact of each drive from its ``twist`` [rad] and its gap's backward and
    forward travel [rad]: +1 forward flank, -1 backward flank, 0 in the gap (NaN for drives
    without backlash; ``tstate`` as in ``transmission_twist``)."""
    out = np.full_like(twist, np.nan)
    for d in range(len(tstate)):
        if tstate[d] >= 0 and gap_neg[d] + gap_pos[d] > 0:
            out[:, d] = np.where(twist[:, d] > gap_pos[d], 1.0,
                                 np.where(twist[:, d] < -gap_neg[d], -1.0, 0.0))
    return out


def span_lengths(plan: Plan, states: np.ndarray) -> np.ndarray:
    """Length of every span [m] over the records ``states``: as in the file, plus the
    excursion of a dancer at either end from its set position, times its strand gains
    (``elements.dancer_loop.span_motion``)."""
    nodes = plan.nodes
    lengths = np.tile(plan.spans[:, L.S_LENGTH], (states.shape[0], 1))
    for i in np.flatnonzero(nodes[:, L.N_DANCER] >= 0):
        index = plan.state_names.index(f"{plan.line.node_name(int(i))}.position")
        excursion = states[:, index] - nodes[i, L.N_DSET]
        lengths[:, [i - 1, i]] += excursion[:, None] * nodes[i, [L.N_DGIN, L.N_DGOUT]]
    return lengths
