"""The operating point of a branched line: the state its simulation starts at.

Solved on the kernel's own right-hand side (``sim.branches.loop.plant.rhs``), so a run started
there stays put to the solver's tolerance: unknowns are the span stretches, node speeds and
motor torques; equations are every span's and node's balance (a roll node turning at the
rate that holds its surface speed while its radius changes), the master's encoder reading
the line speed (the master at the line speed / its encoder's scale, ``spec.sensors``) and
every tension drive's loadcell (or sum of loadcells) at its reference. Speeds follow from
mass flow along each web (v (1 - ε) is the same at both ends of a steady span), so the draw
between drives comes out of the solution, and each drive's speed feedforward is its speed at
the operating point over the line speed.

At rest (line speed 0) every span is trivially steady: the tensions are then those of the
line at its top speed without bearing friction (the limit of a slow start), the speeds 0 and
the torques what holds each node at rest.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from webline.errors import SimulationError
from webline.model.web_graph import BranchedLine
from webline.profiles import breakpoints
from webline.sim.branches.dancer_views import place_carriages, settle_passive
from webline.sim.branches.drives.drive_trains import steady_trains
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.control import taper_at
from webline.sim.branches.loop.plant import node_inertia, rhs
from webline.sim.branches.loop.web_law import felt_view, law_stretch
from webline.sim.branches.plan import BranchPlan
from webline.sim.branches.sensor_views import master_scale
from webline.sim.branches.winder import open_loop_torque

#: the solver's relative tolerance on the scaled unknowns [-]
XTOL = 1e-13


@dataclass(frozen=True)
class BranchPoint:
    """An operating point: ``x`` the full state, ``torque`` [N·m] per drive, ``ratio`` [-]
    each drive's surface speed over the line speed as the drives reference it (times the
    master encoder's scale, ``spec.sensors``: the line runs at the reference / scale),
    ``line_speed`` [m/s]."""

    x: np.ndarray
    torque: np.ndarray
    ratio: np.ndarray
    line_speed: float


def references(plan: BranchPlan, t: float, radii: np.ndarray | None = None) -> np.ndarray:
    """Each loadcell span's reference [N] at ``t``, times its drive's taper at the roll's
    starting radius (or ``radii`` [m] per roll) and the tension ramp's factor."""
    refs = np.full(len(plan.line.spans), np.nan)
    for d in range(plan.di.shape[0]):
        i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
        radius = plan.line.rolls[j].radius if radii is None or j < 0 else float(radii[j])
        factor = 1.0 if j < 0 else taper_at(d, radius, plan.nodes[i, B.N_CORE],
                                            plan.df, plan.prof_t, plan.prof_v, plan.prof_off)
        if plan.offsets[B.O_RAMP] >= 0:  # the tension ramp at start and stop (R1)
            factor *= plan.profile(int(plan.offsets[B.O_RAMP]), t)
        first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
        for k, p, *_ in plan.cells[first:first + count]:
            refs[k] = factor * plan.profile(int(p), t)
    return refs


def _guess(plan: BranchPlan, refs: np.ndarray) -> np.ndarray:
    """Stretch guesses [N]: a span's reference, else its web's first reference, else the
    mean reference scaled to its web's stiffness."""
    mean = float(np.nanmean(refs)) if np.any(np.isfinite(refs)) else 1.0
    guess = np.empty(len(refs))
    for w in range(plan.webs.shape[0]):
        spans = range(plan.webs[w, B.WB_FIRST], plan.webs[w, B.WB_LAST] + 1)
        known = [refs[k] for k in spans if np.isfinite(refs[k])]
        for k in spans:
            guess[k] = refs[k] if np.isfinite(refs[k]) else (known[0] if known else mean)
    for k in range(len(refs) if plan.lawi.shape[0] else 0):  # web laws: the stretch of it
        guess[k] = law_stretch(k, guess[k], plan.const.si, plan.const.lawi, plan.lawf,
                               plan.laws)
    return guess


def _solve(plan: BranchPlan, speed: float, nodes: np.ndarray, t: float,
           radii: np.ndarray | None = None) -> np.ndarray:
    """Stretches, node speeds and torques (one vector) of the steady line at ``speed``, the
    rolls at their starting radii or at ``radii`` [m]."""
    n_s, n_n, n_d = len(plan.line.spans), plan.nodes.shape[0], plan.di.shape[0]
    n_c = plan.cores.shape[0]
    off_w, off_r, off_tq = (plan.offsets[B.O_OMEGA], plan.offsets[B.O_RADIUS],
                            plan.offsets[B.O_TORQUE])
    off_c = plan.offsets[B.O_CORE]
    shafts = set(plan.cores[:, B.C_NODE].tolist())
    friction = nodes is plan.nodes  # (False: the frictionless line of a start from rest)
    if np.any(nodes[:, B.N_ECC] != 0.0):  # out-of-round rollers turn at their mean arm r
        nodes = nodes.copy()  # (as the chain's operating point; docs/errata.md, issue 33)
        nodes[:, B.N_ECC] = 0.0
    refs = references(plan, t, radii)
    t_scale = float(np.nanmean(np.abs(refs))) if np.any(np.isfinite(refs)) else 1.0
    x = np.zeros(plan.n_x)
    for j, roll in enumerate(plan.line.rolls):
        x[off_r + j] = roll.radius if radii is None else radii[j]
    held = plan.held(t)  # wound-in tensions and drags at t (ripples: their mean, 0)
    place_carriages(plan, x, refs, held)  # where each dancer's loop holds its carriage
    arms = plan.nodes[:, B.N_RADIUS].copy()
    for d in range(n_d):
        j = plan.di[d, B.DI_ROLL]
        if j >= 0:
            arms[plan.di[d, B.DI_NODE]] = x[off_r + j]
    tables = (plan.tables()[0], nodes, *plan.tables()[2:])
    dx = np.zeros(plan.n_x)
    work = plan.scratch()
    cmd = np.zeros(n_d)
    w_scale = speed / arms
    c_scale = w_scale[plan.cores[:, B.C_NODE]]
    tq_scale = t_scale * plan.nodes[plan.di[:, B.DI_NODE], B.N_RADIUS]
    master = plan.line.master
    scale = master_scale(plan)
    bonded = plan.lawi[plan.lawi[:, B.LI_STATE] >= 0]  # a laminate's layers' offsets
    layer_states = bonded[:, B.LI_STATE]
    layer_spans = bonded[:, B.LI_SPAN]
    layer_lengths = plan.sf[layer_spans, B.SF_LENGTH]

    def steady_layers() -> None:
        """Each layer's offset where its rate is 0, v_b o = v_a o_in (``loop.laminate``):
        o_in reads only the stretches and the offsets upstream, so passes in any order
        settle it within the laminates' depth (a dancer's moved length: a contraction)."""
        x[layer_states] = 0.0
        for _ in range(len(layer_states) + 50):
            rhs(x, cmd, held, *tables, dx, work)
            v_b = work[3 * n_s:4 * n_s][layer_spans]
            step = dx[layer_states] * layer_lengths / np.where(v_b != 0.0, v_b, 1.0)
            x[layer_states] += step
            if np.all(np.abs(step) <= 1e-15 * (1.0 + np.abs(x[layer_states]))):
                break

    def state(z: np.ndarray) -> np.ndarray:
        x[:n_s] = z[:n_s] * t_scale
        x[off_w:off_w + n_n] = z[n_s:n_s + n_n] * w_scale
        x[off_c:off_c + n_c] = z[n_s + n_n:n_s + n_n + n_c] * c_scale
        cmd[:] = z[n_s + n_n + n_c:] * tq_scale
        x[off_tq:off_tq + n_d] = cmd
        steady_trains(x, plan.offsets, plan.di, plan.df, plan.rolls)  # twists carry torques
        if len(layer_states):
            steady_layers()
        return x

    def residual(z: np.ndarray) -> np.ndarray:
        rhs(state(z), cmd, held, *tables, dx, work)
        out = np.empty(n_s + n_n + n_c + n_d)
        out[:n_s] = dx[:n_s] * plan.sf[:, B.SF_LENGTH] / (t_scale * max(speed, 1e-9))
        accel = dx[off_w:off_w + n_n].copy()
        for d in range(n_d):  # a roll drive holds its surface speed as its radius changes
            i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
            if j >= 0:
                accel[i] += x[off_w + i] * dx[off_r + j] / x[off_r + j]
        out[n_s:n_s + n_n] = accel / w_scale * 1e-3
        for c in range(n_c):  # a clutch core holds its lane's surface speed as the lane grows
            j = plan.cores[c, B.C_ROLL]
            out[n_s + n_n + c] = (dx[off_c + c] + x[off_c + c] * dx[off_r + j] / x[off_r + j]
                                  ) / c_scale[c] * 1e-3
        for d in range(n_d):
            i = plan.di[d, B.DI_NODE]
            row = n_s + n_n + n_c + d
            if i == master:  # its encoder's reading on the line speed (spec.sensors)
                out[row] = (scale * arms[i] * x[off_w + i] - speed) / max(speed, 1e-9)
                continue
            if i in shafts:  # a differential shaft overspeeds its fastest lane's core
                on = plan.cores[:, B.C_NODE] == i
                fastest = np.max(x[off_c:off_c + n_c][on] * (1.0 + plan.clutch[on, B.CF_OVERSPEED]))
                out[row] = (x[off_w + i] - fastest) / w_scale[i]
                continue
            if plan.di[d, B.DI_WINDER] == B.WINDER_OPEN:  # its torque, not its zone (W4)
                out[row] = (cmd[d] - open_loop_torque(plan, d, x, refs, t, friction)
                            ) / tq_scale[d]
                continue
            first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
            dancer = plan.cells[first, B.CELL_DANCER]
            if dancer >= 0:  # position control: the carriage's forces balance there (D2)
                carriage = int(plan.nodes[dancer, B.N_DSTATE])
                out[row] = dx[carriage + 1] / plan.nodes[dancer, B.N_DINVM] / t_scale
                continue
            cells = plan.cells[first:first + count, 0]
            felt = felt_view(work, n_s, n_n, plan.lawi.shape[0] > 0, plan.kv.shape[0] > 0)
            if plan.offsets[B.O_SENSORS]:  # its loadcells read gain T + offset (sensors)
                felt = plan.sf[:, B.SF_TGAIN] * felt + plan.sf[:, B.SF_TOFFSET]
            out[row] = (np.sum(felt[cells]) - np.sum(refs[cells])) / t_scale  # (web laws: F(s))
        return out

    z0 = np.concatenate([_guess(plan, refs) / t_scale, np.ones(n_n), np.ones(n_c),
                         np.zeros(n_d)])
    found = root(residual, z0, method="hybr", options={"xtol": XTOL})
    if not found.success or np.max(np.abs(residual(found.x))) > 1e-9:  # (a slow start: hybr's
        found = root(residual, found.x, method="lm", options={"xtol": XTOL})  # trust region)
    if not found.success or np.max(np.abs(residual(found.x))) > 1e-9:
        raise SimulationError(f"{plan.line.name}: no steady operating point found at "
                              f"{speed:.4g} m/s ({found.message})")
    rhs(state(found.x), cmd, held, *tables, dx, work)
    settle_passive(plan, x, dx)  # a passive carriage where its forces balance
    return x.copy()


def operating_point(plan: BranchPlan, t: float = 0.0, *,
                    radii: np.ndarray | None = None) -> BranchPoint:
    """The steady state of ``plan`` at time ``t`` [s] of its references (module docstring);
    ``radii`` [m], one per ``plan.line.rolls``, put the rolls elsewhere on their course than
    their start (the modes across the roll, ``analysis.branch_across_roll``)."""
    n_n, n_d = plan.nodes.shape[0], plan.di.shape[0]
    off_w, off_r, off_tq = (plan.offsets[B.O_OMEGA], plan.offsets[B.O_RADIUS],
                            plan.offsets[B.O_TORQUE])
    speed = plan.profile(0, t)
    if speed <= 0.0 and plan.cores.shape[0]:
        raise SimulationError(f"{plan.line.name}: a differential shaft's lanes need the line "
                              f"running at t = {t:g} s (a start from rest with slip clutches is "
                              "not modelled: their clutches would not slip)")
    top = float(np.max(np.abs(plan.prof_v[plan.prof_off[0]:plan.prof_off[1]])))
    at = _solve(plan, speed if speed > 0.0 else max(top, 1.0), plan.nodes, t, radii)
    ratio = np.empty(n_d)
    for d in range(n_d):
        i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
        arm = at[off_r + j] if j >= 0 else plan.nodes[i, B.N_RADIUS]
        ratio[d] = arm * at[off_w + i] / (speed if speed > 0.0 else max(top, 1.0))
    if plan.offsets[B.O_SENSORS]:  # the drives' references: the speeds as the master's
        ratio *= master_scale(plan)  # encoder sees them (spec.sensors)
    if speed <= 0.0:  # at rest: frictionless tensions, no motion, torques that hold it
        nodes = plan.nodes.copy()
        nodes[:, B.N_VISCOUS] = nodes[:, B.N_COULOMB] = 0.0
        at = _solve(plan, max(top, 1.0), nodes, t, radii)
        at[off_w:off_w + n_n] = 0.0
        dx = np.zeros(plan.n_x)
        cmd = np.zeros(n_d)
        at[off_tq:off_tq + n_d] = 0.0
        steady_trains(at, plan.offsets, plan.di, plan.df, plan.rolls)
        rhs(at, cmd, plan.held(t), *plan.tables(), dx, plan.scratch())
        for d in range(n_d):  # J dω/dt = web torque + n τ = 0
            i = plan.di[d, B.DI_NODE]
            web_torque = dx[off_w + i] * node_inertia(i, at, plan.const.offsets, plan.nodes,
                                                      plan.rolls)
            at[off_tq + d] = -web_torque / plan.df[d, B.D_RATIO]
        steady_trains(at, plan.offsets, plan.di, plan.df, plan.rolls)
    return BranchPoint(at, at[off_tq:off_tq + n_d].copy(), ratio, speed)


def analysis_time(line: BranchedLine) -> float:
    """Time [s] at which to analyse ``line``: 0, or for a start from rest the end of the
    speed ramp (the chain's rule, ``model.operating_point.analysis_time``: a line standing
    still has no web transport, so its span modes lose their damping)."""
    times, values = breakpoints(line.spec.speed)
    return 0.0 if values[0] > 0.01 * float(np.max(values)) else float(times[-1])
