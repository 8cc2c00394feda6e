"""The decentralized controller families on a branched line (thesis Ch. 6; docs/branching.md,
"State feedback"): each drive's section model, its LQ design, and the tables the compiled
tick (``sim.branches.loop.decentral``) and the linear models read.

A drive's **section** is its node and its zone: x = (S - S_ref, V - V_ref), S the zone's
loadcell tension (on a shaft with several lanes: the sum of its lanes' loadcells, the one
quantity its one torque controls), V the surface speed it measures; the master's section is
x = V - V_ref. Its model is the chain's (``control.sections``, 6.23-6.38) lumped zone, taken
from the branched operating point: with the zone's spans of each loadcell's web lumped into
one span of their total length L_c, EA_c, tension T_c and entering tension T_in,c,

    dS/dt = Σ_c [-(v_c / L_c) T_c + σ (EA_c - T*_c)/L_c (a_c / r) V]   (T* = T_c or T_in,c)
    dV/dt = (r / J) (n u - b V / r + σ' Σ_c a_c T_c),     B = n r / J

σ = +1 where the node ends the zone (the web enters it: a rewind, a pulling roller), -1
where it starts it (an unwind), σ' = -σ; a_c the lane's arm on the node, r the drive's
measuring arm. Every other span on the node (on a junction: the other layers arriving at a
nip) is a coupling the design leaves out, as the chain's leaves out its neighbours' zones.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from webline.control.decentralized import SectionDesign, design_section
from webline.control.sections import SectionModel
from webline.sim.branches.drives.observer import observer_columns
from webline.sim.branches.equilibrium import BranchPoint, analysis_time, operating_point
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.control import taper_at
from webline.sim.branches.loop.plant import node_inertia
from webline.sim.branches.loop.transmission import reflected_motor
from webline.sim.branches.plan import BranchPlan
from webline.spec.schema import AdaptiveSpec, IdleSpec, MRACSpec, StateFeedbackSpec


def has_decentral(plan: BranchPlan) -> bool:
    return bool(np.any(plan.di[:, B.DI_FAMILY] != B.FAMILY_PI))


def _arm(plan: BranchPlan, x: np.ndarray, roll: int, node: int) -> float:
    return float(x[plan.offsets[B.O_RADIUS] + roll]) if roll >= 0 else float(
        plan.nodes[node, B.N_RADIUS])


def _carried_in(plan: BranchPlan, x: np.ndarray, k: int) -> float:
    """What the web carries into span ``k`` at ``x`` [N] (``loop.plant.carried_in``)."""
    src, frm = plan.si[k, B.S_SRC], plan.si[k, B.S_FROM]
    if src == B.SRC_PREVIOUS:
        return float(x[frm])
    if src == B.SRC_WOUND:
        return float(plan.wound[plan.si[k, B.S_WEB]])
    if src == B.SRC_LAYERS:
        return float(sum(x[plan.layers[frm + j]] for j in range(plan.si[k, B.S_COUNT])))
    return float(plan.sf[k, B.SF_SHARE] * x[frm])


def section_model(plan: BranchPlan, point: BranchPoint, d: int) -> SectionModel:
    """Drive ``d``'s section model at ``point`` (module docstring), SI."""
    line, x = plan.line, point.x
    i = int(plan.di[d, B.DI_NODE])
    off_w = plan.offsets[B.O_OMEGA]
    r = _arm(plan, x, int(plan.di[d, B.DI_ROLL]), i)
    inertia = float(node_inertia(i, x, plan.const.offsets, plan.nodes, plan.rolls)
                    + reflected_motor(d, plan.const.di, plan.df))  # (a belt's motor, lumped)
    n = plan.df[d, B.D_RATIO]  # (the drive's: a compliant drive's node has none)
    b = plan.nodes[i, B.N_VISCOUS]
    zone = line.zones.get(i)
    name = line.spec.rollers[i].name
    if zone is None:
        return SectionModel(i, None, np.array([[-b / inertia]]), np.array([[n * r / inertia]]),
                            {}, (f"{name}_speed",))
    a_tt = a_tv = a_vt = weight = 0.0
    for k in zone.loadcells:
        web = line.spans[k].web
        spans = [s for s in zone.spans if line.spans[s].web == web]
        length = sum(line.spans[s].length for s in spans)
        ea = float(plan.sf[k, B.SF_EA])
        tension = float(x[k])
        last = max(spans, key=lambda s: line.spans[s].k)
        first = min(spans, key=lambda s: line.spans[s].k)
        end = plan.si[last, B.S_B]
        v_last = _arm(plan, x, int(plan.si[last, B.S_ARMB]), int(end)) * x[off_w + end]
        if zone.sigma > 0:  # the node ends the zone: the web enters it here
            a_c = _arm(plan, x, int(plan.si[last, B.S_ARMB]), i)
            a_tv += (ea - tension) / length * a_c / r
        else:
            a_c = _arm(plan, x, int(plan.si[first, B.S_ARMA]), i)
            a_tv -= (ea - _carried_in(plan, x, first)) / length * a_c / r
        a_tt -= v_last / length * tension
        weight += tension
        a_vt -= zone.sigma * r * a_c / inertia
    a = np.array([[a_tt / weight, a_tv], [a_vt / len(zone.loadcells), -b / inertia]])
    cells = "+".join(line.spans[k].name for k in zone.loadcells)
    return SectionModel(i, i, a, np.array([[0.0], [n * r / inertia]]), {},
                        (f"{cells}_tension", f"{name}_speed"))


def design(plan: BranchPlan, point: BranchPoint, d: int) -> SectionDesign:
    """The LQ design of drive ``d``'s section (``control.decentralized.design_section``, as the
    chain's ``sim.core.drive_table``): scales from the controller or 1 % of the zone's
    reference (its sum), 1 % of the line speed (at least 0.01 m/s), 10 % of the torque
    limit; fastest pole below min(0.2 / torque lag, 2π f_s / 20); given gains replace LQ's."""
    roller = plan.line.spec.rollers[int(plan.di[d, B.DI_NODE])]
    assert not isinstance(roller, IdleSpec)
    c = roller.controller
    assert isinstance(c, StateFeedbackSpec | AdaptiveSpec | MRACSpec)
    model = section_model(plan, point, d)
    first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
    reference = float(np.sum(point.x[plan.cells[first:first + count, 0]]))
    t_scale = c.tension_scale or (0.01 * reference if count else 1.0)
    v_scale = c.speed_scale or max(0.01 * abs(point.line_speed), 0.01)
    u_scale = c.torque_scale or 0.1 * roller.drive.torque_limit
    cap = min(0.2 / roller.drive.torque_lag, 2 * np.pi / plan.dt / 20)
    out = design_section(model, t_scale, v_scale, u_scale, cap)
    if isinstance(c, MRACSpec):  # its law's columns (the chain's drive_table._mrac_columns)
        scales = np.array([t_scale, v_scale])
        row = plan.fb[d]
        row[B.FB_PBT], row[B.FB_PBV] = out.pb_scaled / scales
        row[B.FB_GKT], row[B.FB_GKV] = c.adaptation_gain * u_scale / scales**2
        row[B.FB_GBIAS] = c.adaptation_gain * u_scale
        row[B.FB_KBT], row[B.FB_KBV] = c.parameter_bound * u_scale / scales
        row[B.FB_CBOUND] = c.parameter_bound * u_scale
        row[B.FB_GAMMA], row[B.FB_LEAK] = c.adaptation_gain, c.leakage
    if c.tension_gain is not None or c.speed_gain is not None:
        gain = out.gain.copy()
        gain[0] = gain[0] if c.tension_gain is None else c.tension_gain
        gain[1] = gain[1] if c.speed_gain is None else c.speed_gain
        k = gain[-model.a.shape[0]:]
        out = dataclasses.replace(out, gain=gain, closed=model.a - model.b @ k[None, :])
    return out


def design_time(plan: BranchPlan) -> float:
    """The time [s] the sections are designed at: 0, or the end of the speed ramp where the
    line starts from rest (``equilibrium.analysis_time``)."""
    return analysis_time(plan.line)


def ensure_prepared(plan: BranchPlan) -> None:
    """``prepare`` a plan with decentralized drives whose tables are still empty."""
    if has_decentral(plan) and plan.refs[-2, 0] == 0.0:
        prepare(plan)


def prepare(plan: BranchPlan) -> list[SectionDesign | None]:
    """Fill ``plan.fb`` and ``plan.refs`` (``layout`` FB_*) for its decentralized drives and
    return their designs (None for a PI drive). The reference tables: the design point's span
    tensions and drive speeds, and their change per newton of each loadcell's reference from
    a second operating point per loadcell (the tree's draws, idle drops and the knife's
    share follow; exact to first order in the step, the strains' (ΔT/EA)² aside)."""
    if not has_decentral(plan):
        return [None] * plan.di.shape[0]
    t = design_time(plan)
    point = operating_point(plan, t)
    n_s, n_d = len(plan.line.spans), plan.di.shape[0]
    refs = plan.refs
    refs[:n_s, 0] = point.x[:n_s]
    refs[n_s:n_s + n_d, 0] = point.ratio * point.line_speed
    refs[-2, 0] = point.line_speed
    for c, (k, p, *_) in enumerate(plan.cells):
        gain = plan.sf[k, B.SF_TGAIN]  # its loadcell reads gain T + offset (spec.sensors)
        refs[-2, 1 + c] = gain * point.x[k] + plan.sf[k, B.SF_TOFFSET]
        prof_v = plan.prof_v.copy()
        prof_v[plan.prof_off[p]:plan.prof_off[p + 1]] += 1.0
        moved = operating_point(dataclasses.replace(plan, prof_v=prof_v), t)
        step = gain * (moved.x[k] - point.x[k])  # 1 N times the taper factor at the start
        refs[:n_s, 1 + c] = (moved.x[:n_s] - point.x[:n_s]) / step
        refs[n_s:n_s + n_d, 1 + c] = (moved.ratio - point.ratio) * point.line_speed / step
    designs: list[SectionDesign | None] = []
    for d in range(n_d):
        if plan.di[d, B.DI_FAMILY] == B.FAMILY_PI:
            designs.append(None)
            continue
        designs.append(design(plan, point, d))
        _columns(plan, point, d, designs[-1])  # type: ignore[arg-type]
        observer_columns(plan, point, d, section_model(plan, point, d))  # (where asked)
    return designs


def _columns(plan: BranchPlan, point: BranchPoint, d: int, out: SectionDesign) -> None:
    i = int(plan.di[d, B.DI_NODE])
    roller = plan.line.spec.rollers[i]
    assert not isinstance(roller, IdleSpec)
    c = roller.controller
    assert isinstance(c, StateFeedbackSpec | AdaptiveSpec | MRACSpec)
    row = plan.fb[d]
    row[B.FB_KT], row[B.FB_KV] = out.gain
    n = roller.drive.ratio
    row[B.FB_BMOTOR] = n * n * roller.drive.motor_friction
    row[B.FB_BMODEL] = roller.friction if c.friction_estimate is None else c.friction_estimate
    j = plan.di[d, B.DI_ROLL]
    if j >= 0:
        roll = plan.line.rolls[j]
        row[B.FB_THICK] = plan.line.materials[roll.web].thickness
        row[B.FB_DIR] = roll.direction
    if isinstance(c, AdaptiveSpec):
        u_scale = c.torque_scale or 0.1 * roller.drive.torque_limit
        r = _arm(plan, point.x, int(j), i)
        omega = abs(point.ratio[d] * point.line_speed) / r
        row[B.FB_GAMMA], row[B.FB_LEAK] = c.adaptation_gain, c.leakage
        # the bound: a friction torque at the design speed of parameter_bound x torque scale
        row[B.FB_BMAX] = c.parameter_bound * u_scale / max(omega, 1.0)


def start_memory(plan: BranchPlan, istate: np.ndarray) -> None:
    """The decentralized families' controller memory at the start: the friction estimate at
    its model value (the initial guess), each drive's taper factor at its starting radius."""
    istate[:, B.I_FRICTION] = plan.fb[:, B.FB_BMODEL]
    istate[:, B.I_KT], istate[:, B.I_KV] = plan.fb[:, B.FB_KT], plan.fb[:, B.FB_KV]
    for d in range(plan.di.shape[0]):
        i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
        radius = plan.line.rolls[j].radius if j >= 0 else plan.nodes[i, B.N_RADIUS]
        if plan.radius0[d] > 0.0:
            radius = plan.radius0[d]
        istate[d, B.I_FACTOR] = taper_at(d, radius, plan.nodes[i, B.N_CORE], plan.df,
                                         plan.prof_t, plan.prof_v, plan.prof_off)


def linear_rows(plan: BranchPlan, point: BranchPoint, d: int, n_x: int, n_q: int,
                kept: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """Drive ``d``'s decentralized law linear at ``point`` (``loop.decentral``, radii frozen),
    as ``linear.controller_matrices``' rows: u = kx x + ki q + kr r, dq/dt = gx x + gi q + gr
    r, x the kept plant states, q the integrators (here ``d``'s friction estimate at column
    ``d``), r = (line speed [m/s], each loadcell's reference [N]). The reference motion's
    torque u_eq moves with r through the tables' sensitivities; at the point itself the
    feedback sees x_T = ΣT - Σref and x_V = r ω - v_ref, ω the roller's, or across a
    compliant transmission measured on the motor ω_m / n (``kept``: the model's states, to
    find the motor's)."""
    row, i = plan.fb[d], int(plan.di[d, B.DI_NODE])
    n_s, _n_d, n_c = len(plan.line.spans), plan.di.shape[0], plan.cells.shape[0]
    kx, ki, kr = np.zeros(n_x), np.zeros(n_q), np.zeros(1 + n_c)
    gx, gi, gr = np.zeros(n_x), np.zeros(n_q), np.zeros(1 + n_c)
    r = _arm(plan, point.x, int(plan.di[d, B.DI_ROLL]), i)
    n = plan.df[d, B.D_RATIO]  # (the drive's: a compliant drive's node has none)
    inertia = float(node_inertia(i, point.x, plan.offsets, plan.nodes, plan.rolls)
                    + reflected_motor(d, plan.const.di, plan.df))
    off_w = plan.offsets[B.O_OMEGA]
    # the column of the measured speed and its arm: the roller's r ω, or the motor's r ω_m / n
    speed, arm = off_w + i, r
    motor = int(plan.di[d, B.DI_TSTATE])
    if motor >= 0 and plan.df[d, B.D_FEEDBACK] > 0.0 and kept is not None:
        speed, arm = int(np.flatnonzero(kept == motor)[0]), r / n
    arm *= plan.df[d, B.D_VSCALE]  # its encoder reads scale x the speed (spec.sensors)
    gain = inertia / (n * r) / plan.df[d, B.D_GAINNORM]
    friction = row[B.FB_BMODEL] + row[B.FB_BMOTOR]
    # x_V = r ω - v_ref; the velocity-squared term f: -dir J h / (2π r³ n) 2 v δv
    v = point.ratio[d] * point.line_speed
    dv = -gain * row[B.FB_KV]
    if row[B.FB_DIR] != 0.0:
        dv -= row[B.FB_DIR] * inertia * row[B.FB_THICK] / (np.pi * r**3 * n) * v
    family = plan.di[d, B.DI_FAMILY]
    adaptive = family == B.FAMILY_ADAPTIVE
    if adaptive:
        dv += row[B.FB_BMODEL] / (r * n)
    kx[speed] = dv * arm
    if plan.di[d, B.DI_WINDER] != B.WINDER_NONE:  # a winder's b_c ω / n on the measured ω
        kx[speed] += plan.df[d, B.D_COMPB] / (r * n) * arm  # (static friction, J a: constant)
    first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
    for c in range(first, first + count):
        k = int(plan.cells[c, 0])
        kx[k] -= gain * row[B.FB_KT]
        kr[1 + c] += gain * row[B.FB_KT]
    # u_eq and v_ref: the line speed scales the reference speeds; a loadcell's reference
    # moves every span's reference tension and every drive's reference speed
    arms = np.zeros(n_s)
    for k in range(n_s):
        if plan.si[k, B.S_A] == i:
            arms[k] = _arm(plan, point.x, int(plan.si[k, B.S_ARMA]), i)
        elif plan.si[k, B.S_B] == i:
            arms[k] = -_arm(plan, point.x, int(plan.si[k, B.S_ARMB]), i)
    v_per = plan.refs[n_s + d, 0] / plan.refs[-2, 0]  # reference speed per line speed
    kr[0] += (friction / (r * n) - dv) * v_per
    for c in range(n_c):
        dv_ref = plan.refs[n_s + d, 1 + c] * point.line_speed / plan.refs[-2, 0]
        kr[1 + c] += -arms @ plan.refs[:n_s, 1 + c] / n + (friction / (r * n) - dv) * dv_ref
    if family == B.FAMILY_MRAC:  # q: the bias ĉ; dĉ/dt = γ_c (P_bT x_T + P_bV x_V) - σγ ĉ
        ki[d] = -1.0
        s_t, s_v = row[B.FB_GBIAS] * row[B.FB_PBT], row[B.FB_GBIAS] * row[B.FB_PBV]
        for c in range(first, first + count):
            gx[int(plan.cells[c, 0])] += s_t
            gr[1 + c] -= s_t
        gx[speed] += s_v * arm
        gr[0] -= s_v * v_per
        for c in range(n_c):
            gr[1 + c] -= s_v * plan.refs[n_s + d, 1 + c] * point.line_speed / plan.refs[-2, 0]
        gi[d] = -row[B.FB_LEAK] * row[B.FB_GAMMA]
    if adaptive:  # q: b̂ - b; u_eq's b̂ ω_ref, and db̂/dt = -γ' ω_ref x_V - σ γ (b̂ - b)
        omega = v / r
        ki[d] = omega / n
        rate = row[B.FB_GAMMA] * gain * row[B.FB_KV] * n / max(omega**2, 1.0)
        gx[speed] = -rate * omega * arm
        gr[0] = rate * omega * v_per
        gi[d] = -row[B.FB_LEAK] * row[B.FB_GAMMA]
    return kx, ki, kr, gx, gi, gr
