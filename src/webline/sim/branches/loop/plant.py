"""The plant of a branched line as the compiled loop integrates it (docs/branching.md,
"Physics"): dx/dt of span stretches, node speeds, roll radii, motor torques, web lengths and
clutch cores. Physics from ``webline.physics`` (span 6.8, rolls 6.1-6.6, rollers 6.9/6.11);
tables in ``sim.branches.loop.layout``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import roll, roller, span
from webline.sim.branches.loop import dancer as D
from webline.sim.branches.loop import laminate as L
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop import traction as T
from webline.sim.branches.loop import transmission as TR
from webline.sim.branches.loop import web_law as W
from webline.sim.branches.loop.breaks import web_flows
from webline.sim.elements.break_hold import brake_band
from webline.sim.elements.friction_loop import stick
from webline.sim.elements.signals import jit

_tension: Any = jit(span.tension)
_stretch_rate: Any = jit(span.stretch_rate)
_exact_rate: Any = jit(span.exact_stretch_rate)
_unstrained_flow: Any = jit(span.unstrained_flow)
_roll_inertia: Any = jit(roll.roll_inertia)
_radius_rate: Any = jit(roll.radius_rate)
_friction: Any = jit(roller.friction_torque)


@jit
def arm(end_roll: int, node: int, x: np.ndarray, offsets: np.ndarray,
        nodes: np.ndarray) -> float:
    """Lever arm [m] of a span's end on ``node``: its web's roll radius, or the roller's."""
    if end_roll >= 0:
        return x[offsets[B.O_RADIUS] + end_roll]
    return nodes[node, B.N_RADIUS]


@jit
def carried_in(k: int, x: np.ndarray, tension: np.ndarray, wound: np.ndarray,
               si: np.ndarray, sf: np.ndarray, layers: np.ndarray,
               elastic: np.ndarray) -> float:
    """Stretch [N] the web carries into span ``k`` (docs/branching.md, s_in); a nip sums
    its layers' clipped stretches Σ EA_i ε_i, each layer's own strain carried on by its
    offset (``loop.laminate``). With web laws the wound-in tension is a tension, turned into
    the span's stretch by ``web_law.law_stretch`` in ``rhs``."""
    src = si[k, B.S_SRC]
    frm = si[k, B.S_FROM]
    if src == B.SRC_PREVIOUS:
        return tension[frm]
    if src == B.SRC_WOUND:
        return wound[si[k, B.S_WEB]]
    if src == B.SRC_LAYERS:  # the layers' stretches add up (their offsets: loop.laminate)
        total = 0.0
        for j in range(si[k, B.S_COUNT]):
            total += tension[layers[frm + j]]
        return total
    return sf[k, B.SF_SHARE] * tension[frm]  # a lane: the base web's strain at the knife


@jit
def node_inertia(i: int, x: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
                 rolls: np.ndarray) -> float:
    """Inertia [kg·m²] of node ``i``: rotating parts plus every roll wound on it (6.1), but
    for the lanes on its clutch cores (a differential shaft: they turn on their own)."""
    return inertia_seen(i, -1, 0.0, x, offsets, nodes, rolls)


@jit
def inertia_seen(i: int, own: int, radius: float, x: np.ndarray, offsets: np.ndarray,
                 nodes: np.ndarray, rolls: np.ndarray) -> float:
    """Inertia [kg·m²] of node ``i`` as its drive's controller knows it: ``node_inertia``
    with roll ``own`` at ``radius`` [m] (its diameter calculator's, docs/winder.md W2: a
    drive does not know the true radius; ``own`` < 0: every roll at its true radius)."""
    inertia = nodes[i, B.N_JCONST]
    off_r = offsets[B.O_RADIUS]
    for j in range(rolls.shape[0]):
        if int(rolls[j, B.R_NODE]) == i and rolls[j, B.R_CLUTCH] == 0.0:
            r = radius if j == own else x[off_r + j]
            inertia += _roll_inertia(0.0, r, rolls[j, B.R_CORE], rolls[j, B.R_WIDTH],
                                     rolls[j, B.R_RHO])
    return inertia


@jit
def rhs(x: np.ndarray, cmd: np.ndarray, wound: np.ndarray, offsets: np.ndarray,
        nodes: np.ndarray, si: np.ndarray, sf: np.ndarray, layers: np.ndarray,
        rolls: np.ndarray, webs: np.ndarray, di: np.ndarray, df: np.ndarray,
        cores: np.ndarray, clutch: np.ndarray, lawi: np.ndarray, lawf: np.ndarray,
        laws: np.ndarray, kv: np.ndarray, dx: np.ndarray, work: np.ndarray) -> None:
    """dx/dt of a branched line into ``dx`` with held motor-torque commands ``cmd`` [N·m] and
    held inputs ``wound``: the wound-in tension [N] per web, then the drag torque [N·m] per
    node (``roller_drag``, added to its Coulomb friction). ``work``: scratch of 6 x spans +
    3 x nodes (``work_size``). Web laws (``lawi``, ``lawf``, ``laws``: the terms of
    ``loop.web_law``) and Kelvin-Voigt spans (``kv``: their numbers) set the tension the
    rollers feel; without them (empty tables, frozen into the loop) that code folds away.
    A lane on a differential shaft winds on its own core, which its slip clutch drives from
    the shaft with the smoothed Coulomb torque of ``physics.roller`` (docs/branching.md,
    "Differential shafts")."""
    n_s, n_n = si.shape[0], nodes.shape[0]
    off_w, off_r = offsets[B.O_OMEGA], offsets[B.O_RADIUS]
    off_tq, off_q, off_c = offsets[B.O_TORQUE], offsets[B.O_WEB], offsets[B.O_CORE]
    off_e = offsets[B.O_ANGLE]
    tension = work[:n_s]
    s_in = work[n_s:2 * n_s]
    v_a = work[2 * n_s:3 * n_s]
    v_b = work[3 * n_s:4 * n_s]
    torque = work[4 * n_s:4 * n_s + n_n]
    inertia = work[4 * n_s + n_n:4 * n_s + 2 * n_n]
    has_law, has_kv = lawi.shape[0] > 0, kv.shape[0] > 0
    n_w = webs.shape[0]
    has_dancer = offsets[B.O_DANCER] < offsets[B.O_DANCER_END]  # (frozen: folds away without one)
    for k in range(n_s):
        tension[k] = _tension(x[k])
        if offsets[B.O_BREAK] and wound[n_w + n_n + k] != 0.0:  # broken: carries nothing
            tension[k] = 0.0
    elastic = work[4 * n_s + 2 * n_n:5 * n_s + 2 * n_n] if has_law else tension
    felt = work[5 * n_s + 2 * n_n:6 * n_s + 2 * n_n] if has_kv else elastic
    if has_law:  # the web laws' tensions F(s) (docs/branching.md, "Web laws")
        W.law_tensions(x, elastic, si, lawi, lawf, laws)
        if offsets[B.O_BREAK]:  # a broken span carries nothing (nor do its layers)
            for k in range(n_s):
                if wound[n_w + n_n + k] != 0.0:
                    elastic[k] = 0.0
    slip = work[6 * n_s + 2 * n_n:6 * n_s + 3 * n_n]
    if offsets[B.O_SLIP]:  # the web over a slipping roller moves at r ω - s (Ch. 5)
        T.slip_speeds(x, elastic, offsets, nodes, slip)
    for i in range(n_n):
        torque[i] = 0.0
        inertia[i] = nodes[i, B.N_JCONST]
    for j in range(rolls.shape[0]):  # every roll wound on a node adds its web's inertia
        if cores.shape[0] > 0 and rolls[j, B.R_CLUTCH] != 0.0:  # on its own core: below
            continue  # (cores is frozen into the loop: without clutches this folds away)
        i = int(rolls[j, B.R_NODE])
        radius = x[off_r + j]
        inertia[i] += _roll_inertia(0.0, radius, rolls[j, B.R_CORE], rolls[j, B.R_WIDTH],
                                    rolls[j, B.R_RHO])
        dx[off_r + j] = _radius_rate(radius * x[off_w + i], radius, rolls[j, B.R_THICK],
                                     rolls[j, B.R_DIR])
    for k in range(n_s):
        a, b = si[k, B.S_A], si[k, B.S_B]
        arm_a = arm(si[k, B.S_ARMA], a, x, offsets, nodes)
        arm_b = arm(si[k, B.S_ARMB], b, x, offsets, nodes)
        if si[k, B.S_ECCA] >= 0:  # an out-of-round roller: r + e cos(angle) (docs/winder.md E1)
            arm_a += nodes[a, B.N_ECC] * math.cos(x[off_e + si[k, B.S_ECCA]])
            dx[off_e + si[k, B.S_ECCA]] = x[off_w + a]  # dθ/dt = ω (set once per span end)
        if si[k, B.S_ECCB] >= 0:
            arm_b += nodes[b, B.N_ECC] * math.cos(x[off_e + si[k, B.S_ECCB]])
            dx[off_e + si[k, B.S_ECCB]] = x[off_w + b]
        v_a[k] = arm_a * x[off_w + a]
        core = si[k, B.S_CORE]
        v_b[k] = arm_b * x[off_w + b] if core < 0 else arm_b * x[off_c + core]
        if offsets[B.O_SLIP]:
            v_a[k] -= slip[a]
            v_b[k] -= slip[b]
        s_in[k] = carried_in(k, x, tension, wound, si, sf, layers, elastic)
        if has_law and si[k, B.S_SRC] == B.SRC_WOUND:
            s_in[k] = W.law_stretch(k, s_in[k], si, lawi, lawf, laws)  # a tension in: F⁻¹
        if offsets[B.O_EXACT]:  # exact mass conservation (docs/errata.md E-6.6)
            dx[k] = _exact_rate(sf[k, B.SF_LENGTH], sf[k, B.SF_EA], v_a[k], v_b[k], s_in[k],
                                tension[k], x[k])
        else:  # 6.8 per unit length (the division by 1 folds away) times 1/length: a
            # multiply where a divide took ~20 cycles each stage, as the chain's S_INVLENGTH
            dx[k] = _stretch_rate(1.0, sf[k, B.SF_EA], v_a[k], v_b[k], s_in[k],
                                  tension[k]) * sf[k, B.SF_INVLENGTH]
        if has_dancer and (si[k, B.S_DANCEA] >= 0 or si[k, B.S_DANCEB] >= 0):
            dx[k] = D.moving_span_rate(k, x, dx[k], nodes, si, sf,
                                       offsets[B.O_EXACT] != 0)  # its length moves (D1)
        if has_kv:
            felt[k] = W.felt(k, x, dx, elastic, sf)
        if offsets[B.O_BREAK] and wound[n_w + n_n + k] != 0.0:  # cut: frozen, carries nothing
            dx[k] = 0.0
            felt[k] = 0.0  # (its stretch is 0 from the cut on: so are F(0) and the damper's)
        torque[a] += arm_a * felt[k]  # the span pulls its upstream roller forward
        if core < 0:  # (a lane on a clutch core pulls its core, below)
            torque[b] -= arm_b * felt[k]
    for c in range(cores.shape[0]):  # a lane's core: clutch torque in, the lane's r T out
        j, i, k = cores[c, B.C_ROLL], cores[c, B.C_NODE], cores[c, B.C_SPAN]
        radius, omega_core = x[off_r + j], x[off_c + c]
        passed = _friction(x[off_w + i] - omega_core, 0.0, clutch[c, B.CF_SLIP])
        torque[i] -= passed
        inertia_core = clutch[c, B.CF_INERTIA] + _roll_inertia(
            0.0, radius, rolls[j, B.R_CORE], rolls[j, B.R_WIDTH], rolls[j, B.R_RHO])
        dx[off_c + c] = (passed - radius * felt[k]) / inertia_core
        dx[off_r + j] = _radius_rate(radius * omega_core, radius, rolls[j, B.R_THICK],
                                     rolls[j, B.R_DIR])
    if has_dancer:  # the carriages (D2), their loads held at the end of the inputs
        D.carriage_rates(x, felt, wound, offsets, nodes, si, sf, dx)
    TR.drive_trains(x, di, df, offsets, torque, dx)  # compliant drives (folds away without)
    for i in range(n_n):
        omega = x[off_w + i]
        total = torque[i] - nodes[i, B.N_VISCOUS] * omega
        coulomb = nodes[i, B.N_COULOMB] + wound[n_w + i]  # a drag acts as dry friction does
        if coulomb != 0.0:  # (a tanh costs more than the rest of the node)
            total -= _friction(omega, 0.0, coulomb)
        d = int(nodes[i, B.N_DRIVE])
        if d >= 0:
            total += nodes[i, B.N_RATIO] * x[off_tq + d]
        set_brake = wound[n_w + n_n + n_s + i] if offsets[B.O_BREAK] and d >= 0 else 0.0
        holding = set_brake + wound[n_w + i]  # a holding brake (W8) and a drag (4.12)
        if holding != 0.0 and abs(omega) < brake_band(holding, 1.0 / (
                inertia[i] if nodes[i, B.N_ROLLS] > 0.0 else nodes[i, B.N_JCONST])):
            limit = set_brake + coulomb  # at rest a brake is static friction (W8, F2)
            applied = total + (_friction(omega, 0.0, coulomb) if coulomb != 0.0 else 0.0)
            if offsets[B.O_FRICTION]:  # (a friction table is dry friction too)
                limit += nodes[i, B.N_BREAKAWAY]
                applied += T.table_torque(i, omega, nodes)
            held, total = stick(applied, limit)
            if held:  # ω decays to 0 in a control period
                dx[off_w + i] = -omega / nodes[i, B.N_STICKTAU]
                continue
        elif set_brake != 0.0:  # turning: Coulomb friction of the set brake
            total -= set_brake if omega > 0.0 else -set_brake
        elif offsets[B.O_FRICTION]:  # a friction table; held at rest by a break-away torque
            held, total = T.measured_friction(i, omega, total, coulomb, nodes)
            if held:  # ω decays to 0 in a control period
                dx[off_w + i] = -omega / nodes[i, B.N_STICKTAU]
                continue
        if nodes[i, B.N_ROLLS] > 0.0:  # J(R) of the rolls on it (6.1)
            dx[off_w + i] = total / inertia[i]
        else:
            dx[off_w + i] = total * nodes[i, B.N_INVJ]
    for d in range(di.shape[0]):
        dx[off_tq + d] = (cmd[d] - x[off_tq + d]) * df[d, B.D_INVLAG]
    if offsets[B.O_LAYER] < offsets[B.O_LAYER_END]:  # bonded layers (frozen: folds away)
        L.layer_rates(x, dx, lawi, lawf, sf, tension, s_in, v_a, v_b, wound,
                      n_w + n_n if offsets[B.O_BREAK] else -1, nodes, si, has_dancer,
                      offsets[B.O_EXACT] != 0)
    if offsets[B.O_BREAK]:  # a cut web: its intact spans' ends (sim.branches.disturb)
        web_flows(dx, off_q, webs, sf, wound[n_w + n_n:], v_a, v_b, s_in, tension,
                  offsets[B.O_EXACT] != 0)
        return
    for w in range(webs.shape[0]):  # unstrained web in and out: v (1 - ε) at each end
        first, last = webs[w, B.WB_FIRST], webs[w, B.WB_LAST]
        if offsets[B.O_EXACT]:  # v/(1 + ε)
            ea = sf[first, B.SF_EA]
            dx[off_q + 2 * w] = _unstrained_flow(v_a[first], ea, s_in[first], True)
            dx[off_q + 2 * w + 1] = _unstrained_flow(v_b[last], ea, tension[last], True)
            continue
        inv_ea = sf[first, B.SF_INVEA]
        dx[off_q + 2 * w] = v_a[first] * (1.0 - s_in[first] * inv_ea)
        dx[off_q + 2 * w + 1] = v_b[last] * (1.0 - tension[last] * inv_ea)


def work_size(n_spans: int, n_nodes: int) -> int:
    """Length of ``rhs``'s scratch array (2 x spans for web laws' tensions, then the slip
    speed per node)."""
    return 6 * n_spans + 3 * n_nodes
