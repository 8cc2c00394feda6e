"""Centre-winder functions of a branched line's roll drives in the compiled loop: inertia and
friction compensation, open-loop (indirect) tension control with its speed limiter
(docs/winder.md W3, W4, W7) and the flying splices of unwinds and rewinds (S1), as the chain's
``sim.drives.winder_loop`` and ``sim.elements.splice`` do; tables in ``loop.layout``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from webline.physics import roll
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.dancer import span_motion
from webline.sim.branches.loop.transmission import motor_beyond
from webline.sim.elements.signals import jit, profile_at

_roll_inertia: Any = jit(roll.roll_inertia)


@jit
def known_inertia(i: int, radius: float, nodes: np.ndarray, rolls: np.ndarray) -> float:
    """Inertia [kg·m²] of node ``i`` as its drive knows it (W3): rotating parts and reflected
    motor, plus every roll wound on it (not on a clutch core) at the radius ``radius`` [m] the
    drive uses (the calculated one where it has a calculator): the drive knows one diameter,
    so every lane on a shaft is taken at it (6.1: π ρ w (R⁴ - R_c⁴) / 2)."""
    inertia = nodes[i, B.N_JCONST]
    for j in range(rolls.shape[0]):
        if int(rolls[j, B.R_NODE]) == i and rolls[j, B.R_CLUTCH] == 0.0:
            inertia += _roll_inertia(0.0, radius, rolls[j, B.R_CORE], rolls[j, B.R_WIDTH],
                                     rolls[j, B.R_RHO])
    return inertia


@jit
def compensation(d: int, i: int, radius: float, omega: float, a_line: float,
                 nodes: np.ndarray, rolls: np.ndarray, df: np.ndarray, prof_t: np.ndarray,
                 prof_v: np.ndarray, prof_off: np.ndarray) -> float:
    """Motor torque [N·m] drive ``d`` (on node ``i``) adds for its roll's inertia and
    friction (W3): (J(R) a_line / R + c_s sign(ω) + b ω + f(|ω|) sign(ω)) / n, R [m] the
    radius the drive uses, ω [rad/s] its measured speed, a_line [m/s²] the line-speed
    reference's slope, f the measured friction table (F1) where it has one."""
    inertia = known_inertia(i, radius, nodes, rolls) + motor_beyond(d, df)  # (a belt's motor)
    torque = df[d, B.D_COMPJ] * inertia * a_line / radius
    sign = 1.0 if omega > 0.0 else -1.0 if omega < 0.0 else 0.0
    torque += df[d, B.D_COMPCS] * sign + df[d, B.D_COMPB] * omega
    table = int(df[d, B.D_COMPFP])
    if table >= 0:
        torque += sign * profile_at(table, abs(omega), prof_t, prof_v, prof_off)
    return torque / df[d, B.D_RATIO]


@jit
def zone_reference(d: int, t: float, factor: float, di: np.ndarray, cells: np.ndarray,
                   prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray) -> float:
    """Drive ``d``'s zone reference [N] at ``t`` [s]: the sum of its loadcells' references
    (on a shaft with several lanes, the lanes'), times ``factor`` (taper, ramp)."""
    total = 0.0
    for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
        total += profile_at(cells[c, 1], t, prof_t, prof_v, prof_off)
    return factor * total


@jit
def open_loop(d: int, dt: float, radius: float, tension_ref: float, comp: float,
              v_meas: float, v_line: float, gain: float, istate: np.ndarray,
              df: np.ndarray) -> float:
    """Torque command [N·m] of open-loop drive ``d`` (W4) with its speed limiter (W7), as the
    chain's ``sim.drives.winder_loop.open_loop_command``: τ_T = ±T_ref R / n + comp clipped
    (+ rewind, - unwind), unless the speed PI on v_line ± offset, saturated at τ_T (its
    integrator clamped there), asks for less: a freed roll is held at its limit.
    ``tension_ref`` [N] the zone's reference, ``v_meas``, ``v_line`` [m/s]."""
    direction = df[d, B.D_DIR]
    limit = df[d, B.D_LIMIT]
    raw = direction * tension_ref * radius / df[d, B.D_RATIO] + comp
    tension_torque = min(max(raw, -limit), limit)
    error = v_line + direction * df[d, B.D_SPEEDLIM] - v_meas
    integral = istate[d, B.I_SPEED] + df[d, B.D_KIS] * gain * error * dt
    if direction * integral > direction * (tension_torque - comp):  # clamped at saturation
        integral = tension_torque - comp
    istate[d, B.I_SPEED] = integral
    speed_torque = df[d, B.D_KPS] * gain * error + integral + comp
    if direction * speed_torque >= direction * tension_torque:  # the tension torque acts
        return tension_torque
    return min(max(speed_torque, -limit), limit)  # the limiter holds the roll


@jit
def splice(e: int, x: np.ndarray, istate: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
           si: np.ndarray, sf: np.ndarray, rolls: np.ndarray, webs: np.ndarray, df: np.ndarray,
           events: np.ndarray) -> None:
    """Flying splice ``e`` (S1) of an unwind or a rewind, at its tick, in place on the plant
    state ``x`` and the controller memory ``istate``: the new roll (radius R_new) takes the
    old one's place at (1 + mismatch) times the web's speed at the old roll (the event's
    roll: on a shaft of lanes the one its drive measures speed on). Every roll wound on the
    node (an unwind's one; on a rewind's shaft each lane, its web cut and wound on onto its
    own new core of R_new) starts at R_new; the slack δ goes into the span next to it (its
    stretch drops by EA δ / L, L its length now) and into its web's counter: unwound + δ on
    an unwind, rewound - δ on a rewind (the balance Σ L (1 - s/EA) + out - in is unchanged;
    the web cut onto the old roll stays counted as rewound). The drive's speed integrator
    takes the tension torques' change ∓ Σ T (R_new - R_old)/n (- unwind, + rewind) and the
    viscous torque's, its motor the new roll's friction torque (it carried no web before),
    its calculated radius R_new."""
    j0 = int(events[e, B.E_ROLL])
    i = int(rolls[j0, B.R_NODE])
    direction = rolls[j0, B.R_DIR]  # -1 unwinding, +1 winding
    w_i = offsets[B.O_OMEGA] + i
    omega_old = x[w_i]
    r_new = events[e, B.E_RADIUS]
    x[w_i] = events[e, B.E_GAIN] * x[offsets[B.O_RADIUS] + j0] * omega_old / r_new
    slack = events[e, B.E_SLACK]
    torque = 0.0  # the change of the web's torque on the roll [N·m]
    for j in range(rolls.shape[0]):
        if int(rolls[j, B.R_NODE]) != i or rolls[j, B.R_CLUTCH] != 0.0:
            continue
        w = int(rolls[j, B.R_WEB])
        k = webs[w, B.WB_FIRST] if direction < 0.0 else webs[w, B.WB_LAST]
        r_j = offsets[B.O_RADIUS] + j
        carried = x[k] if x[k] > 0.0 else 0.0
        torque += direction * carried * (r_new - x[r_j])
        x[r_j] = r_new
        ea, length = sf[k, B.SF_EA], span_motion(k, x, nodes, si, sf)[0]
        if offsets[B.O_EXACT]:  # u = L/(1 + s/EA) grows by the slack (E-6.6)
            x[k] = length * ea / (length * ea / (ea + x[k]) + slack) - ea
        else:  # u = L (1 - s/EA)
            x[k] -= ea * slack / length
        x[offsets[B.O_WEB] + 2 * w + (0 if direction < 0.0 else 1)] -= direction * slack
    d = int(nodes[i, B.N_DRIVE])
    if d < 0:
        return
    n = df[d, B.D_RATIO]
    omega = x[w_i]
    viscous = nodes[i, B.N_VISCOUS] / n  # [N·m·s]: at the roll, seen by the motor
    istate[d, B.I_SPEED] += torque / n + viscous * (omega - omega_old)
    sign = 1.0 if omega > 0.0 else -1.0 if omega < 0.0 else 0.0
    x[offsets[B.O_TORQUE] + d] = viscous * omega + nodes[i, B.N_COULOMB] * sign / n
    if df[d, B.D_DCALC] != B.DCALC_NONE:
        istate[d, B.I_RADIUS] = r_new  # the diameter preset: the drive knows the new roll


@jit
def splices(t: float, dt: float, x: np.ndarray, istate: np.ndarray, done: np.ndarray,
            offsets: np.ndarray, nodes: np.ndarray, si: np.ndarray, sf: np.ndarray,
            rolls: np.ndarray, webs: np.ndarray, df: np.ndarray, events: np.ndarray) -> None:
    """Every flying splice not yet made whose tick (the first at or after its time, ``t``
    [s] the tick's time, ``dt`` [s] the period) has come (``splice``)."""
    for e in range(events.shape[0]):
        if (done[e] == 0.0 and events[e, B.E_KIND] == B.EVENT_SPLICE
                and t >= events[e, B.E_TIME] - 0.5 * dt):
            done[e] = 1.0
            splice(e, x, istate, offsets, nodes, si, sf, rolls, webs, df, events)
