"""Compiled controllers: one sample of every drive's controller per tick.

Families (column ``D_FAMILY`` of the drive table):

* cascaded PI (thesis Fig. 4.3): a tension PI trims the speed reference of a speed PI;
* decentralized state feedback (6.39-6.42): u = u_eq + f + U with U = -K x on the section's
  own deviations x = (T - T_ref, V - V_ref), u_eq the equilibrium input recomputed every tick
  from the current roll radius and inertia (6.20-6.37, re-derived), f the cancellation of the
  roll's velocity-squared term;
* decentralized adaptive control (6.62-6.68, re-derived, E-6.8): the state feedback with the
  section's one unknown, its friction coefficient, estimated on line: u = u_eq(b̂) + b̂ (ω -
  ω_ref)/n + f - K x, with db̂/dt = -γ g K_V n ω (V - V_ref) / max(ω_ref², 1) (+ leakage),
  projected onto [0, b_max].

Measurements may carry white Gaussian noise; all controllers see the same noisy signals.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import motor, roll, roller, span, taper
from webline.sim.drives.diameter import preset_radius, update_radius
from webline.sim.drives.feedforward import speed_feedforward
from webline.sim.drives.measure import measured_speed
from webline.sim.drives.mrac import mrac_adapt, mrac_feedback
from webline.sim.drives.observer import observe
from webline.sim.drives.user_loop import U_COMP, user_command, user_law_commands
from webline.sim.drives.winder_loop import break_monitor, compensation, open_loop_command
from webline.sim.elements import layout as L
from webline.sim.elements.break_hold import fade_trim, held_command, stop_acceleration
from webline.sim.elements.dancer_loop import dancer_measurement
from webline.sim.elements.envelope import node_radius
from webline.sim.elements.friction_loop import table_torque
from webline.sim.elements.sensor_loop import delayed, loadcell_reading
from webline.sim.elements.signals import gaussian, jit, profile_at, profile_slope_at

_tension: Any = jit(span.tension)
_draw: Any = jit(span.draw_ratio)
_roll_inertia: Any = jit(roll.roll_inertia)
_radius_rate: Any = jit(roll.radius_rate)
_friction: Any = jit(roller.friction_torque)
_saturate: Any = jit(motor.saturate)
_taper: Any = jit(taper.taper_factor)
_TABLE = taper.TABLE


@jit
def node_inertia(i: int, radius: float, ns: np.ndarray, nodes: np.ndarray,
                 web: np.ndarray) -> float:
    """Inertia [kg·m²] at the shaft of node ``i`` whose radius is ``radius`` [m]."""
    kind = ns[i, L.NS_KIND]
    if kind == L.KIND_UNWIND or kind == L.KIND_REWIND:
        return _roll_inertia(nodes[i, L.N_JCONST], radius, nodes[i, L.N_CORE], web[L.W_WIDTH],
                             nodes[i, L.N_RHO])
    return nodes[i, L.N_JCONST]


@jit
def web_density_inertia(d: int, i: int, radius: float, ns: np.ndarray, ds: np.ndarray,
                        nodes: np.ndarray, drives: np.ndarray, web: np.ndarray) -> float:
    """``drive_inertia`` of a line whose rolls all carry the web's density (written apart so
    that the decentralized controllers of such a line compile as they did before J1)."""
    inertia = nodes[i, L.N_JCONST]
    kind = ns[i, L.NS_KIND]
    if kind == L.KIND_UNWIND or kind == L.KIND_REWIND:
        inertia = _roll_inertia(nodes[i, L.N_JCONST], radius, nodes[i, L.N_CORE],
                                web[L.W_WIDTH], web[L.W_DENSITY])
    if ds[d, L.DS_TSTATE] >= 0:
        inertia += drives[d, L.D_RATIO] ** 2 * drives[d, L.D_JMOTOR]
    return inertia


@jit
def drive_inertia(d: int, i: int, radius: float, ns: np.ndarray, ds: np.ndarray,
                  nodes: np.ndarray, drives: np.ndarray, web: np.ndarray) -> float:
    """Inertia [kg·m²] drive ``d`` accelerates, seen at its roller: the node's, plus the
    reflected motor across a compliant transmission (a rigid one already includes it)."""
    inertia = node_inertia(i, radius, ns, nodes, web)
    if ds[d, L.DS_TSTATE] >= 0:
        inertia += drives[d, L.D_RATIO] ** 2 * drives[d, L.D_JMOTOR]
    return inertia


@jit
def roll_direction(i: int, ns: np.ndarray) -> float:
    kind = ns[i, L.NS_KIND]
    return -1.0 if kind == L.KIND_UNWIND else (1.0 if kind == L.KIND_REWIND else 0.0)


@jit
def reference_state(a_line: float, refs: np.ndarray, ds: np.ndarray, offsets: np.ndarray,
                    nodes: np.ndarray, web: np.ndarray, span_ref: np.ndarray,
                    v_ref: np.ndarray, a_ref: np.ndarray) -> None:
    """Reference tension of every span, web speed and acceleration of every node [SI].

    As ``webline.operating_point``: loadcell spans at their zone reference, tension carried
    across idle rollers by their friction and inertia, speeds from mass flow (E-6.5). Two passes
    of the speed/tension coupling (its effect is of order (friction/EA)²).
    """
    ea = web[L.W_EA]
    n_spans = span_ref.shape[0]
    master = offsets[L.O_MASTER]
    for d in range(ds.shape[0]):
        if ds[d, L.DS_ROLE] == L.ROLE_TENSION:
            for k in range(ds[d, L.DS_ZFIRST], ds[d, L.DS_ZLAST]):
                span_ref[k] = refs[ds[d, L.DS_REF]]
    for sweep in range(2):
        t_master = web[L.W_T0] if master == 0 else span_ref[master - 1]
        for i in range(n_spans + 1):
            t_up = web[L.W_T0] if i == 0 else span_ref[i - 1]
            ratio = _draw(ea, t_up, t_master, offsets[L.O_EXACT] != 0)
            v_ref[i] = refs[0] * ratio
            a_ref[i] = a_line * ratio
        if sweep == 1:
            break
        for d in range(ds.shape[0]):
            if ds[d, L.DS_ROLE] != L.ROLE_TENSION:
                continue
            first, last = ds[d, L.DS_ZFIRST], ds[d, L.DS_ZLAST]
            loadcell = ds[d, L.DS_LOADCELL]
            for k in range(loadcell + 1, last):
                span_ref[k] = span_ref[k - 1] + _idle_drop(k, v_ref, a_ref, nodes)
                if offsets[L.O_FRICTION]:  # a measured friction table (F1)
                    span_ref[k] += _table_drop(k, v_ref, nodes)
            for k in range(loadcell, first, -1):
                span_ref[k - 1] = span_ref[k] - _idle_drop(k, v_ref, a_ref, nodes)
                if offsets[L.O_FRICTION]:
                    span_ref[k - 1] -= _table_drop(k, v_ref, nodes)


@jit
def _idle_drop(i: int, v_ref: np.ndarray, a_ref: np.ndarray, nodes: np.ndarray) -> float:
    """Tension rise [N] across idle roller ``i`` at the reference motion."""
    r = nodes[i, L.N_RADIUS]
    omega = v_ref[i] / r
    torque = nodes[i, L.N_JCONST] * a_ref[i] / r
    torque += _friction(omega, nodes[i, L.N_VISCOUS], nodes[i, L.N_COULOMB])
    return torque / r


@jit
def _table_drop(i: int, v_ref: np.ndarray, nodes: np.ndarray) -> float:
    """Tension rise [N] across idle roller ``i`` from its friction table (F1)."""
    r = nodes[i, L.N_RADIUS]
    return table_torque(i, v_ref[i] / r, nodes) / r


@jit
def equilibrium_input(i: int, radius: float, inertia: float, friction: float,
                      ns: np.ndarray, nodes: np.ndarray, web: np.ndarray, span_ref: np.ndarray,
                      v_ref: np.ndarray, a_ref: np.ndarray) -> float:
    """Motor torque [N·m] that holds node ``i`` on its reference (6.20, 6.28, 6.32, 6.37 with
    E-6.1, E-6.2), for a viscous friction coefficient ``friction`` [N·m·s]."""
    omega = v_ref[i] / radius
    r_dot = _radius_rate(v_ref[i], radius, web[L.W_THICK], roll_direction(i, ns))
    accel = a_ref[i] / radius - v_ref[i] * r_dot / (radius * radius)
    t_out = span_ref[i] if i < span_ref.shape[0] else 0.0
    t_in = span_ref[i - 1] if i > 0 else 0.0
    torque = inertia * accel - radius * (t_out - t_in)
    torque += _friction(omega, friction, nodes[i, L.N_COULOMB])
    return torque / nodes[i, L.N_RATIO]


@jit
def control_tick(tick: int, dt: float, x: np.ndarray, istate: np.ndarray, ns: np.ndarray,
                 ds: np.ndarray, offsets: np.ndarray, nodes: np.ndarray, drives: np.ndarray,
                 web: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                 prof_off: np.ndarray, speed_ripple: np.ndarray, out: np.ndarray,
                 refs: np.ndarray, span_ref: np.ndarray, v_ref: np.ndarray,
                 a_ref: np.ndarray, law: Any, law_buf: Any) -> None:
    """One sample of every drive's controller at tick ``tick`` (t = tick·dt [s]).

    ``istate`` (drive x I_COLS) holds PI integrators, adaptive estimates and the radius each
    drive's controller uses (``sim.drives.diameter``, updated first); ``out`` (4 x
    drives) receives the torque command [N·m], the speed reference [m/s], the PI trim [m/s]
    and the equilibrium input [N·m]; ``refs`` (one per profile), ``span_ref`` (spans),
    ``v_ref`` and ``a_ref`` (nodes) are scratch for the references. ``law``: None, or the
    compiled user laws of the user drives (``sim.drives.user_loop.user_law_commands``),
    called once all drives are measured, with their scratch ``law_buf``; None folds away.
    """
    t = tick * dt
    for p in range(prof_off.shape[0] - 1):
        refs[p] = profile_at(p, t, prof_t, prof_v, prof_off)
    for d in range(ds.shape[0]):  # the radius each controller uses (calculated or true)
        i = ds[d, L.DS_NODE]
        if drives[d, L.D_PRESETN] > 0.0:  # set while running (docs/winder.md W2a)
            preset_radius(d, t, dt, node_radius(i, x, ns, offsets, nodes), istate, drives)
        update_radius(d, i, tick, dt, node_radius(i, x, ns, offsets, nodes), x, istate, ns,
                      ds, offsets, nodes, drives, web, refs)
        if drives[d, L.D_TAPER] > 0.0:
            refs[ds[d, L.DS_REF]] *= taper_at(d, istate[d, L.I_RADIUS], drives, prof_t, prof_v,
                                              prof_off)
    if web[L.W_TRAMP] > 0.0:  # the tension ramp at start and stop (docs/winder.md R1)
        ramp = refs[int(web[L.W_TRAMP])]
        for d in range(ds.shape[0]):
            if ds[d, L.DS_ROLE] == L.ROLE_TENSION:
                refs[ds[d, L.DS_REF]] *= ramp
    stopping = 1.0  # the line-speed factor of a ramp to stop after a detected web break
    a_line = profile_slope_at(0, t, prof_t, prof_v, prof_off)  # line acceleration [m/s²]
    if offsets[L.O_BREAK]:
        stopping = break_monitor(t, x, istate, ns, ds, nodes, drives, web, refs,
                                 offsets[L.O_OMEGA])
        if stopping < 1.0:
            a_line = stop_acceleration(a_line, refs[0], stopping, web)
        refs[0] *= stopping
    if offsets[L.O_NEED_EQ]:
        reference_state(a_line, refs, ds, offsets, nodes, web, span_ref, v_ref, a_ref)
    seed = int(web[L.W_SEED])
    if law is not None:  # a user drive the laws may command (a held one is not: W8)
        for d in range(ds.shape[0]):
            if ds[d, L.DS_FAMILY] == L.FAMILY_USER:
                out[U_COMP, d] = math.nan
    for d in range(ds.shape[0]):
        i = ds[d, L.DS_NODE]
        radius = istate[d, L.I_RADIUS]
        # the motor's encoder, across a compliant transmission (a rigid drive has no motor
        # state: its motor speed is ratio x roller speed, the same measurement as the load's)
        v_meas = measured_speed(d, i, tick, radius, x, ds, offsets, drives, web)
        if offsets[L.O_SENSORS]:  # the encoder's delay (spec.sensors)
            v_meas = delayed(d, tick, v_meas, L.I_VBUF, drives[d, L.D_VDELAY], istate)
        loadcell = ds[d, L.DS_LOADCELL]
        t_meas = 0.0
        if loadcell >= 0:
            t_meas = _tension(x[loadcell])
            if offsets[L.O_SENSORS]:  # the loadcell's calibration and delay (spec.sensors)
                t_meas = delayed(d, tick, loadcell_reading(d, t_meas, drives), L.I_TBUF,
                                 drives[d, L.D_TDELAY], istate)
            if offsets[L.O_NOISE] and web[L.W_NOISE_T] > 0.0:
                t_meas += web[L.W_NOISE_T] * gaussian(seed, tick, 2 * d + 1)
        if drives[d, L.D_OBS] > 0.0:  # a section observer replaces the loadcell
            inertia_d = drive_inertia(d, i, radius, ns, ds, nodes, drives, web)
            t_meas = observe(d, i, dt, tick, radius, inertia_d, v_meas / radius, x, istate,
                             ds, offsets, nodes, drives, web, span_ref)
        if ds[d, L.DS_DANCER] >= 0:
            t_meas = dancer_measurement(d, x, ns, ds, nodes, refs)
        if stopping < 1.0 and ds[d, L.DS_ROLE] == L.ROLE_TENSION:  # tension loops frozen
            t_meas = refs[ds[d, L.DS_REF]]
            if stopping > 0.0 or web[L.W_BHOLD] != L.HOLD_STALL:  # (the stall hold's
                fade_trim(d, dt, stopping, istate, web)  # speed limiter integrates there)
        gain = 1.0
        if ds[d, L.DS_ADAPTIVE] > 0:
            inertia = drive_inertia(d, i, radius, ns, ds, nodes, drives, web)
            gain = inertia / (nodes[i, L.N_RATIO] * radius) / drives[d, L.D_GAINNORM]
        if offsets[L.O_BREAK] and stopping == 0.0 and held_command(  # stopped: hold (W8)
                d, dt, roll_direction(i, ns), radius, v_meas, gain, refs[ds[d, L.DS_REF]],
                istate, ds, drives, web, out):
            continue
        comp = 0.0  # a centre winder's compensations (docs/winder.md W3)
        if (drives[d, L.D_COMPJ] + drives[d, L.D_COMPCS] + drives[d, L.D_COMPB]
                + drives[d, L.D_COMPFN] > 0.0):
            comp = compensation(d, drive_inertia(d, i, radius, ns, ds, nodes, drives, web),
                                radius, v_meas / radius, a_line, drives)
        if ds[d, L.DS_FAMILY] == L.FAMILY_PI:
            pi_command(d, t, dt, v_meas, t_meas, gain, istate, ds, offsets, drives, web, refs,
                       speed_ripple, out)
        elif ds[d, L.DS_FAMILY] == L.FAMILY_OPEN_LOOP:
            open_loop_command(d, dt, roll_direction(i, ns), radius, refs[ds[d, L.DS_REF]],
                              comp, v_meas, refs[0], gain, istate, drives, out)
            continue
        elif ds[d, L.DS_FAMILY] == L.FAMILY_USER:  # the command a user's controller wrote
            user_command(d, t, v_meas, t_meas, radius,
                         drive_inertia(d, i, radius, ns, ds, nodes, drives, web), ds, offsets,
                         drives, web, refs, speed_ripple, out)
            if law is not None:
                out[U_COMP, d] = comp
        else:
            decentralized_command(d, i, dt, radius, v_meas, t_meas, gain, istate, ns, ds, offsets,
                                  nodes, drives, web, span_ref, v_ref, a_ref, out)
        if comp != 0.0:
            out[0, d] = _saturate(out[0, d] + comp, drives[d, L.D_LIMIT])
    if law is not None:
        law(t, out, law_buf)
        user_law_commands(ds, drives, out)


@jit
def taper_at(d: int, radius: float, drives: np.ndarray, prof_t: np.ndarray,
             prof_v: np.ndarray, prof_off: np.ndarray) -> float:
    """Taper factor [-] of drive ``d``'s tension reference at roll radius ``radius`` [m]
    (docs/winder.md W1): a table's profile read at the diameter, else ``physics.taper``."""
    kind = int(drives[d, L.D_TAPER])
    if kind == _TABLE:
        return profile_at(int(drives[d, L.D_TAPERP]), 2.0 * radius, prof_t, prof_v, prof_off)
    return _taper(kind, drives[d, L.D_TAPERK], drives[d, L.D_TAPERDC], drives[d, L.D_TAPERDM],
                  2.0 * radius)


@jit
def pi_command(d: int, t: float, dt: float, v_meas: float, t_meas: float, gain: float,
               istate: np.ndarray, ds: np.ndarray, offsets: np.ndarray, drives: np.ndarray,
               web: np.ndarray, refs: np.ndarray, speed_ripple: np.ndarray,
               out: np.ndarray) -> None:
    """Cascaded PI of drive ``d`` (thesis 4.1i-j, trim sign per E-4.1).

    Line speed x draw (from the tension references) + ripple is the speed feedforward; the
    tension PI trims it; the speed PI gives the torque, clipped to the limit. Integrators hold
    torque [N·m] and trim [m/s] and stop while the torque saturates in the direction they push
    (conditional integration).
    """
    ref = speed_feedforward(d, t, ds, offsets, web, refs, speed_ripple)
    e_t = 0.0
    trim = 0.0
    if ds[d, L.DS_ROLE] == L.ROLE_TENSION:
        e_t = refs[ds[d, L.DS_REF]] - t_meas
        trim = drives[d, L.D_SIGMA] * (drives[d, L.D_KPT] * e_t + istate[d, L.I_TENSION])
    e_v = ref + trim - v_meas
    raw = drives[d, L.D_KPS] * gain * e_v + istate[d, L.I_SPEED]
    u = _saturate(raw, drives[d, L.D_LIMIT])
    saturated = raw != u
    if not (saturated and e_v * raw > 0.0):
        istate[d, L.I_SPEED] += drives[d, L.D_KIS] * gain * e_v * dt
    if not (saturated and drives[d, L.D_SIGMA] * e_t * raw > 0.0):
        istate[d, L.I_TENSION] += drives[d, L.D_KIT] * e_t * dt
    out[0, d] = u
    out[1, d] = ref
    out[2, d] = trim
    out[3, d] = 0.0


@jit
def decentralized_command(d: int, i: int, dt: float, radius: float, v_meas: float,
                          t_meas: float, gain: float, istate: np.ndarray, ns: np.ndarray,
                          ds: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
                          drives: np.ndarray, web: np.ndarray, span_ref: np.ndarray,
                          v_ref: np.ndarray, a_ref: np.ndarray, out: np.ndarray) -> None:
    """State feedback, adaptive control or MRAC (``sim.drives.mrac``) of drive ``d`` on node ``i``
    (module docstring)."""
    if offsets[L.O_OWNRHO]:  # a roll given by its totals (J1)
        inertia = drive_inertia(d, i, radius, ns, ds, nodes, drives, web)
    else:
        inertia = web_density_inertia(d, i, radius, ns, ds, nodes, drives, web)
    ratio = nodes[i, L.N_RATIO]
    adaptive = ds[d, L.DS_FAMILY] == L.FAMILY_ADAPTIVE
    friction = istate[d, L.I_FRICTION] if adaptive else drives[d, L.D_BMODEL]
    u_eq = equilibrium_input(i, radius, inertia, friction, ns, nodes, web, span_ref, v_ref,
                             a_ref)
    if offsets[L.O_FRICTION] and nodes[i, L.N_FRICN] > 0.0:  # a measured friction table (F1)
        u_eq += table_torque(i, v_ref[i] / radius, nodes) / ratio
    u_eq += drives[d, L.D_BMOTOR] * ratio * v_ref[i] / radius  # the motor's own friction
    loadcell = ds[d, L.DS_LOADCELL]
    x_t = t_meas - span_ref[loadcell] if loadcell >= 0 else 0.0
    x_v = v_meas - v_ref[i]
    # cancel the roll's velocity-squared term around the reference (the f_i of 6.39, 6.42)
    direction = roll_direction(i, ns)
    comp = 0.0
    if direction != 0.0:
        scale = direction * inertia * web[L.W_THICK] / (2.0 * math.pi * radius**3)
        comp = -scale * (v_meas * v_meas - v_ref[i] * v_ref[i]) / ratio
    mrac = ds[d, L.DS_FAMILY] == L.FAMILY_MRAC
    if mrac:
        feedback = mrac_feedback(d, x_t, x_v, gain, istate)
    else:
        feedback = -gain * (drives[d, L.D_KT] * x_t + drives[d, L.D_KV] * x_v)
    if adaptive:  # friction felt at the measured speed, not only at the reference
        feedback += friction * x_v / (radius * ratio)
    raw = u_eq + comp + feedback
    u = _saturate(raw, drives[d, L.D_LIMIT])
    # the estimates freeze at a break's detection, as a branched line's: a stop is not the
    # running line they learn (the laminator's b̂ ran from 0.05 to 24 N·m·s in one)
    learning = u == raw and not (offsets[L.O_BREAK] and istate[d, L.I_DETECT] >= 0.0)
    if adaptive and learning:
        adapt(d, dt, x_v, v_ref[i] / radius, gain, ratio, istate, drives)
    if mrac and learning:
        mrac_adapt(d, dt, x_t, x_v, istate, drives)
    out[0, d] = u
    out[1, d] = v_ref[i]
    out[2, d] = 0.0
    out[3, d] = u_eq


@jit
def adapt(d: int, dt: float, x_v: float, omega_ref: float, gain: float, ratio: float,
          istate: np.ndarray, drives: np.ndarray) -> None:
    """One Euler step of the friction estimate b̂ [N·m·s] (E-6.8), leakage and projection.

    With b̂ = b the section closes exactly as the state feedback does; the error b̂ - b enters
    the speed equation through B·ω/n, and the section's speed response is strictly positive
    real, so (KYP lemma) V = eᵀPe + (b̂ - b)²/γ' decreases along db̂/dt = -γ' ω x_V, with
    ``x_v`` the speed deviation [m/s]. The regressor is the reference speed ω_ref [rad/s]
    (= ω at the equilibrium): the measured ω carries the same noise as x_V, and their product
    would bias the estimate by the noise variance. γ' = γ g K_V n / max(ω_ref², 1) makes the
    estimate act as an integral on the speed error with corner frequency γ [rad/s].
    """
    rate = drives[d, L.D_GAMMA] * gain * drives[d, L.D_KV] * ratio / max(omega_ref**2, 1.0)
    b_hat = istate[d, L.I_FRICTION]
    b_hat += dt * (-rate * omega_ref * x_v - drives[d, L.D_LEAK] * drives[d, L.D_GAMMA]
                   * (b_hat - drives[d, L.D_BMODEL]))
    istate[d, L.I_FRICTION] = min(max(b_hat, 0.0), drives[d, L.D_BMAX])
