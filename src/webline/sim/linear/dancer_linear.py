"""The dancer's rows of the linear model (docs/winder.md): its carriage states, the span
rows it lengthens and what a drive's tension loop reads from it."""

from __future__ import annotations

import numpy as np

from webline.physics.span import length_change_rate
from webline.sim.core.dancer import dancer_nodes
from webline.sim.core.plan import Plan
from webline.sim.elements import layout as L


def linear_states(plan: Plan) -> list[str]:
    """Names of the dancer states in the linear model (after the transmissions')."""
    return [f"{plan.line.node_name(i)}_{part}" for i in dancer_nodes(plan.line)
            for part in ("position", "velocity")]


def plant_rows(a: np.ndarray, e: np.ndarray, plan: Plan, stretch: np.ndarray,
               first: int) -> None:
    """Dancer entries of the plant matrices ``a`` (and the wound-in column ``e``) at span
    stretches ``stretch`` = EA ε [N] (the tensions of a linear web; an equilibrium: the
    spans' flows balance, so only the lengthening rate enters their rows); the dancer states
    start at row ``first``. Span k next to a dancer: d(stretch_k)/dt gains
    (EA - s_k) g_k v_y / (L_k + g_k y) (exact transport: EA + s_k), g_k its strand gain;
    the carriage:
    M dv_y/dt = -(g_in T_in + g_out T_out) - k y - c v_y (end stops inactive at the set
    position; T the felt tensions, ``viscoelastic.felt_rows``).
    """
    ea = plan.line.ea
    for j, i in enumerate(dancer_nodes(plan.line)):
        row = plan.nodes[i]
        pos, vel = first + 2 * j, first + 2 * j + 1
        y = plan.initial_state(plan.op)[0][int(row[L.N_DANCER])] - row[L.N_DSET]
        for k, gain in ((i - 1, row[L.N_DGIN]), (i, row[L.N_DGOUT])):
            length = plan.spans[k, L.S_LENGTH] + gain * y
            a[k, :] *= plan.spans[k, L.S_LENGTH] / length  # the span is L + g y long here
            e[k, :] *= plan.spans[k, L.S_LENGTH] / length
            a[k, vel] = length_change_rate(ea, stretch[k], gain, length, plan.line.exact)
        inv_m = row[L.N_DINVM]
        a[vel, i - 1] = -row[L.N_DGIN] * inv_m
        a[vel, i] = -row[L.N_DGOUT] * inv_m
        a[pos, vel] = 1.0
        a[vel, pos] = -row[L.N_DK] * inv_m
        a[vel, vel] = -row[L.N_DC] * inv_m


def measurement_row(plan: Plan, d: int, first: int) -> tuple[int, float] | None:
    """(linear state, d(measured tension)/d(position)) of the dancer drive ``d`` reads, or
    None: the position loop's error y - y_set enters as T_ref - T_meas (so -1 [N/m] per m, in
    the loop's units), the tension sensor's (load - k y)/2 as -k/2 [N/m]."""
    i = int(plan.drives[d, L.D_DANCER])
    if i < 0:
        return None
    state = first + 2 * dancer_nodes(plan.line).index(i)
    if plan.drives[d, L.D_DUSE] == L.DANCER_POSITION:
        return state, -1.0
    row = plan.nodes[i]
    return state, -float(row[L.N_DK]) / float(row[L.N_DGIN] + row[L.N_DGOUT])
