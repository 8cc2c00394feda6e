"""Plan side of the section observer (docs/branching.md, "Section observer"): its gains and
tables, its start, and its rows in the linear models (``sim.branches.linear``).

Gains, as the chain's ``sim.core.drive_table.observer_columns``: with the measured speeds in
(B1) the estimation error (e_T, e_ω) = (T - T̂, ω - ω̂) obeys

    de_T/dt = -(v_b/L) e_T - l_T e_ω,    de_ω/dt = c e_T - (β + l_ω) e_ω

(c = ±a/J the span's arm on the node over its inertia [rad/s² per N], β = b/J) when the
observer's model is the plant's: l_ω = 2λ - v_b/L - β and l_T = (λ² - (v_b/L)(β + l_ω)) / c
put both error poles at -λ (``observer_bandwidth``), read off the drive's section model
(``sim.branches.drives.decentral.section_model``) at the design point.
"""

from __future__ import annotations

import numpy as np

from webline.errors import LineFileError
from webline.sim.branches.equilibrium import BranchPoint
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import node_inertia
from webline.sim.branches.plan import BranchPlan
from webline.spec.schema import AdaptiveSpec, MRACSpec, StateFeedbackSpec


def has_observer(plan: BranchPlan) -> bool:
    return bool(np.any(plan.di[:, B.DI_OBS] > 0))


def observer_columns(plan: BranchPlan, point: BranchPoint, d: int, model: object) -> None:
    """Drive ``d``'s observer tables (``layout`` DI_OBS, FB_OBS_*) where its controller asks
    for one; ``LineFileError`` naming the key where its zone is not one span with its
    loadcell or its drive not rigid (the chain's conditions)."""
    line = plan.line
    i = int(plan.di[d, B.DI_NODE])
    c = getattr(line.spec.rollers[i], "controller", None)
    if not isinstance(c, StateFeedbackSpec | AdaptiveSpec | MRACSpec) or (
            c.tension_feedback != "observer"):
        return
    name = line.spec.rollers[i].name
    key = f"rollers[{i}].controller.tension_feedback"
    zone = line.zones.get(i)
    if zone is None or len(zone.spans) != 1 or len(zone.loadcells) != 1:
        raise LineFileError(line.source, key, f"roller {name!r}: 'observer' needs a zone of "
                            "one span with its loadcell (no idle rollers, no lanes' sum)")
    if plan.di[d, B.DI_TSTATE] >= 0:
        raise LineFileError(line.source, key, f"roller {name!r}: 'observer' needs a rigid "
                            "drive (no transmission)")
    k = zone.spans[0]
    a = np.asarray(model.a)  # type: ignore[attr-defined]  # (T, V): section_model's
    roll = int(plan.di[d, B.DI_ROLL])
    r = float(point.x[plan.offsets[B.O_RADIUS] + roll]) if roll >= 0 else float(
        plan.nodes[i, B.N_RADIUS])
    decay, coupling, damping = -a[0, 0], a[1, 0] / r, -a[1, 1]
    bandwidth = float(c.observer_bandwidth)
    l_w = 2.0 * bandwidth - decay - damping
    row = plan.fb[d]
    row[B.FB_OBS_LW] = l_w
    row[B.FB_OBS_LT] = (bandwidth**2 - decay * (damping + l_w)) / coupling
    row[B.FB_OBS_EA] = float(plan.sf[k, B.SF_EA]) if c.observer_ea is None else float(
        c.observer_ea)
    row[B.FB_OBS_LENGTH] = line.spans[k].length
    if plan.si[k, B.S_SRC] == B.SRC_WOUND:
        row[B.FB_OBS_TIN] = plan.wound[plan.si[k, B.S_WEB]]
    plan.di[d, B.DI_OBS] = k + 1


def start_observers(plan: BranchPlan, istate: np.ndarray, x: np.ndarray) -> None:
    """Every observer starts at the run's initial state ``x``: T̂ its span's, ω̂ its node's."""
    for d in range(plan.di.shape[0]):
        k = int(plan.di[d, B.DI_OBS]) - 1
        if k >= 0:
            istate[d, B.I_THAT] = x[k]
            istate[d, B.I_WHAT] = x[plan.offsets[B.O_OMEGA] + plan.di[d, B.DI_NODE]]


def observer_names(plan: BranchPlan) -> list[str]:
    """The linear model's observer states: per observer drive T̂ [N], ω̂ [rad/s]."""
    names = []
    for d in range(plan.di.shape[0]):
        if plan.di[d, B.DI_OBS] > 0:
            drive = plan.line.spec.rollers[int(plan.di[d, B.DI_NODE])].name
            names += [f"{drive}_tension_estimate", f"{drive}_omega_estimate"]
    return names


def observer_rows(plan: BranchPlan, point: BranchPoint, kept: np.ndarray,
                  matrices: tuple[np.ndarray, ...]) -> tuple[np.ndarray, ...]:
    """The controller matrices (kx, ki, kr, gx, gi, gr of ``linear.controller_matrices``)
    with every observer's two states appended to the controller states: its (B1) and (B4)
    linear at ``point`` in the plant's kept states (``kept``: their indices in the kernel's
    state) and its own, and the drive's law reading T̂ where it read its loadcell (each row's
    dependence on the loadcell span's state moves to T̂); the references it reads (T_in, the
    node's other spans) move with the loadcells' references through ``plan.refs``."""
    kx, ki, kr, gx, gi, gr = matrices
    observers = [d for d in range(plan.di.shape[0]) if plan.di[d, B.DI_OBS] > 0]
    if not observers:
        return matrices
    n_x, n_q, n_o = kx.shape[1], gi.shape[0], 2 * len(observers)
    x, off_w = point.x, plan.offsets[B.O_OMEGA]
    column = {int(s): m for m, s in enumerate(kept)}
    ki = np.hstack([ki, np.zeros((ki.shape[0], n_o))])
    gx = np.vstack([gx, np.zeros((n_o, n_x))])
    gi = np.block([[gi, np.zeros((n_q, n_o))], [np.zeros((n_o, n_q + n_o))]])
    gr = np.vstack([gr, np.zeros((n_o, gr.shape[1]))])
    with_memory = [d for d in range(plan.di.shape[0])  # (linear._integrators' first part)
                   if plan.di[d, B.DI_FAMILY] != B.FAMILY_STATE_FEEDBACK]
    for o, d in enumerate(observers):
        k, i = int(plan.di[d, B.DI_OBS]) - 1, int(plan.di[d, B.DI_NODE])
        t_hat, w_hat = n_q + 2 * o, n_q + 2 * o + 1
        state = column[k]
        own = [with_memory.index(d)] if d in with_memory else []  # an MRAC's bias reads x_T
        for rows, cols in ((kx[d], ki[d]), *((gx[q], gi[q]) for q in own)):
            moved = rows[state]  # the law read T (its loadcell) here: now T̂
            rows[state] = 0.0
            cols[t_hat] += moved
        row = plan.fb[d]
        a, b = int(plan.si[k, B.S_A]), int(plan.si[k, B.S_B])
        arm_a, arm_b = _arm(plan, x, k, a, B.S_ARMA), _arm(plan, x, k, b, B.S_ARMB)
        length, ea = row[B.FB_OBS_LENGTH], row[B.FB_OBS_EA]
        t_in = _reference_in(plan, x, k, row)
        # L dT̂/dt = EA (v_b - v_a) + T_in v_a - T̂ v_b + L l_T (ω - ω̂), v from the measured ω;
        # exactly (E-6.6) (EA + T̂) v_b - (EA + T̂)² v_a/(EA + T_in) for the first three terms
        v_a, v_b = arm_a * x[off_w + a], arm_b * x[off_w + b]
        if plan.offsets[B.O_EXACT]:
            grow, carried = ea + x[k], ea + t_in
            gx[t_hat, column[off_w + b]] += grow * arm_b / length
            gx[t_hat, column[off_w + a]] -= grow**2 / carried * arm_a / length
            gi[t_hat, t_hat] = (v_b - 2.0 * grow * v_a / carried) / length
            by_t_in = grow**2 / carried**2 * v_a / length  # ∂(dT̂/dt)/∂T_in [1/s]
        else:
            gx[t_hat, column[off_w + b]] += (ea - x[k]) * arm_b / length
            gx[t_hat, column[off_w + a]] -= (ea - t_in) * arm_a / length
            gi[t_hat, t_hat] = -v_b / length
            by_t_in = v_a / length
        gx[t_hat, column[off_w + i]] += row[B.FB_OBS_LT]
        gi[t_hat, w_hat] = -row[B.FB_OBS_LT]
        sensitivity = plan.refs[:len(plan.line.spans), 1:]  # per span, per loadcell reference
        gr[t_hat, 1:] += _sources_in(plan, k) @ sensitivity * by_t_in
        # J dω̂/dt = ±a T̂ + n τ - b ω̂ (+ the others at their references) + J l_ω (ω - ω̂)
        inertia = float(node_inertia(i, x, plan.const.offsets, plan.nodes, plan.rolls))
        sign = 1.0 if a == i else -1.0
        gi[w_hat, t_hat] = sign * (arm_a if a == i else arm_b) / inertia
        torque = column[plan.offsets[B.O_TORQUE] + d]
        gx[w_hat, torque] += plan.nodes[i, B.N_RATIO] / inertia
        slope = row[B.FB_BMODEL] + row[B.FB_BMOTOR] + _coulomb_slope(plan, i, x[off_w + i])
        gi[w_hat, w_hat] = -slope / inertia - row[B.FB_OBS_LW]
        gx[w_hat, column[off_w + i]] += row[B.FB_OBS_LW]
        for other in range(len(plan.line.spans)):  # the node's other spans: their references
            if other != k and i in (plan.si[other, B.S_A], plan.si[other, B.S_B]):
                end = B.S_ARMA if plan.si[other, B.S_A] == i else B.S_ARMB
                side = 1.0 if end == B.S_ARMA else -1.0
                gr[w_hat, 1:] += side * _arm(plan, x, other, i, end) * sensitivity[other] / (
                    inertia)
    return kx, ki, kr, gx, gi, gr


def _arm(plan: BranchPlan, x: np.ndarray, k: int, node: int, end: int) -> float:
    roll = int(plan.si[k, end])
    return float(x[plan.offsets[B.O_RADIUS] + roll]) if roll >= 0 else float(
        plan.nodes[node, B.N_RADIUS])


def _reference_in(plan: BranchPlan, x: np.ndarray, k: int, row: np.ndarray) -> float:
    """What the observer takes as carried into span ``k`` at the operating point [N]."""
    src, frm = int(plan.si[k, B.S_SRC]), int(plan.si[k, B.S_FROM])
    if src == B.SRC_WOUND:
        return float(row[B.FB_OBS_TIN])
    if src == B.SRC_LAYERS:
        return float(sum(x[plan.layers[frm + j]] for j in range(int(plan.si[k, B.S_COUNT]))))
    if src == B.SRC_PREVIOUS:
        return float(x[frm])
    return float(plan.sf[k, B.SF_SHARE] * x[frm])


def _sources_in(plan: BranchPlan, k: int) -> np.ndarray:
    """∂T_in/∂T_s [-] of what the observer takes carried into span ``k``, per span s (none
    for a wound-in tension: the observer holds its plan value)."""
    out = np.zeros(len(plan.line.spans))
    src, frm = int(plan.si[k, B.S_SRC]), int(plan.si[k, B.S_FROM])
    if src == B.SRC_LAYERS:
        for j in range(int(plan.si[k, B.S_COUNT])):
            out[plan.layers[frm + j]] += 1.0
    elif src == B.SRC_PREVIOUS:
        out[frm] = 1.0
    elif src != B.SRC_WOUND:
        out[frm] = plan.sf[k, B.SF_SHARE]
    return out


def _coulomb_slope(plan: BranchPlan, i: int, omega: float) -> float:
    """d/dω of the Coulomb term c tanh(ω/ω_s) at ``omega`` [N·m·s]."""
    from webline.physics import roller

    h = 1e-6 * max(abs(omega), 1.0)
    return (roller.friction_torque(omega + h, 0.0, plan.nodes[i, B.N_COULOMB])
            - roller.friction_torque(omega - h, 0.0, plan.nodes[i, B.N_COULOMB])) / (2 * h)
