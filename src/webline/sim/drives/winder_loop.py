"""Centre-winder torque functions in the compiled loop (docs/winder.md, W3-W4): inertia and
friction compensation, and open-loop (indirect) tension control."""

from __future__ import annotations

import numpy as np

from webline.sim.elements import layout as L
from webline.sim.elements.friction_loop import compensation_table
from webline.sim.elements.sensor_loop import loadcell_reading
from webline.sim.elements.signals import jit


@jit
def compensation(d: int, inertia: float, radius: float, omega: float, a_line: float,
                 drives: np.ndarray) -> float:
    """Motor torque [N·m] drive ``d`` adds for its roll's inertia and friction (W3):
    (J a_line / R + c_s sign(ω) + b ω) / n, J [kg·m²] and R [m] as the controller knows them,
    a_line [m/s²] the line-speed reference's acceleration, ω [rad/s] the measured speed."""
    torque = drives[d, L.D_COMPJ] * inertia * a_line / radius
    if omega > 0.0:
        torque += drives[d, L.D_COMPCS]
    elif omega < 0.0:
        torque -= drives[d, L.D_COMPCS]
    torque += drives[d, L.D_COMPB] * omega
    if drives[d, L.D_COMPFN] > 0.0:  # the measured friction table (F1)
        torque += compensation_table(d, omega, drives)
    return torque / drives[d, L.D_RATIO]


@jit
def open_loop_command(d: int, dt: float, direction: float, radius: float,
                      tension_ref: float, comp: float, v_meas: float, v_line: float,
                      gain: float, istate: np.ndarray, drives: np.ndarray,
                      out: np.ndarray) -> None:
    """Indirect tension control (W4) with its speed limiter (W7): τ = ±T_ref R / n +
    compensation, + on a rewind (the web pulls it back), - on an unwind (the motor brakes
    it), clipped to the torque limit; ``v_meas`` [m/s] the drive's measured surface speed,
    ``v_line`` [m/s] the line-speed reference.

    The limiter is a speed PI on the limit v_line ± offset (+ rewind, - unwind) whose output
    is saturated at the tension torque: while the web holds the roll below the limit the PI
    asks for more (its integrator clamped at the saturation, its proportional part k_p x
    offset beyond it) and the tension torque acts, bit for bit; a freed roll that reaches
    the limit brings the PI below the tension torque at once and the PI holds the limit, the
    compensation ``comp`` [N·m] (the line's acceleration, friction) its feedforward."""
    raw = direction * tension_ref * radius / drives[d, L.D_RATIO] + comp
    limit = drives[d, L.D_LIMIT]
    tension_torque = min(max(raw, -limit), limit)
    v_limit = v_line + direction * drives[d, L.D_SPEEDLIM]
    error = v_limit - v_meas
    kp = drives[d, L.D_KPS] * gain
    integral = istate[d, L.I_SPEED] + drives[d, L.D_KIS] * gain * error * dt
    if direction * integral > direction * (tension_torque - comp):  # clamped at saturation
        integral = tension_torque - comp
    istate[d, L.I_SPEED] = integral
    speed_torque = kp * error + integral + comp  # compensation: feedforward
    if direction * speed_torque >= direction * tension_torque:  # the tension torque acts
        out[0, d] = tension_torque
    else:  # the limiter holds the roll at its limit
        out[0, d] = min(max(speed_torque, -limit), limit)
    out[1, d] = v_limit
    out[2, d] = 0.0
    out[3, d] = raw


@jit
def over_limit(d: int, direction: float, v_meas: float, v_line: float,
               drives: np.ndarray) -> bool:
    """True when open-loop drive ``d``'s roll is beyond its speed limit (W7): a rewind
    faster, an unwind slower than the line reference by more than the limiter's offset."""
    return direction * (v_meas - v_line) > drives[d, L.D_SPEEDLIM]


@jit
def break_monitor(t: float, x: np.ndarray, istate: np.ndarray, ns: np.ndarray,
                  ds: np.ndarray, nodes: np.ndarray, drives: np.ndarray, web: np.ndarray,
                  refs: np.ndarray, offsets_omega: int) -> float:
    """Web-break monitor and reaction (W5), once per tick before the controllers and after
    the diameter calculators: detect a loadcell tension below the threshold x its reference,
    a dancer at an end stop, a speed-ratio diameter running the wrong way or an open-loop
    roll beyond its speed limit (W7; node speeds start at ``offsets_omega`` in ``x``) (the
    first found is kept with its time in ``istate``; every zone's loadcell counts, also
    where a dancer controls the zone, but not an open-loop drive's: it has none); once
    detected, return the factor [0, 1] of the line-speed ramp to a
    stop (1 before)."""
    if istate[0, L.I_DETECT] < 0.0:
        method = 0
        for d in range(ds.shape[0]):
            loadcell = ds[d, L.DS_LOADCELL]
            closed = ds[d, L.DS_FAMILY] != L.FAMILY_OPEN_LOOP  # open loop reads no loadcell
            if loadcell >= 0 and ds[d, L.DS_ROLE] == L.ROLE_TENSION and closed:  # dancers too
                tension = x[loadcell] if x[loadcell] > 0.0 else 0.0
                tension = loadcell_reading(d, tension, drives)  # what it shows (1 T + 0: T)
                if tension < web[L.W_BTHRESH] * refs[ds[d, L.DS_REF]]:
                    method = L.BREAK_TENSION
        for i in range(ns.shape[0]):
            state = ns[i, L.NS_DANCER]
            if state >= 0 and method == 0 and (x[state] <= 0.0
                                               or x[state] >= nodes[i, L.N_DTRAVEL]):
                method = L.BREAK_DANCER
        for d in range(ds.shape[0]):  # every calculator keeps its extreme, found or not
            watched = drives[d, L.D_DCALC] == L.DCALC_SPEED_RATIO and web[L.W_BDIAM] > 0.0
            unwind = ns[ds[d, L.DS_NODE], L.NS_KIND] == L.KIND_UNWIND
            if watched and diameter_runs_off(d, unwind, web[L.W_BDIAM], istate) and method == 0:
                method = L.BREAK_DIAMETER
        for d in range(ds.shape[0]):  # a freed open-loop roll at its speed limit
            i = ds[d, L.DS_NODE]
            if ds[d, L.DS_FAMILY] == L.FAMILY_OPEN_LOOP and web[L.W_BOVER] > 0.0:
                direction = -1.0 if ns[i, L.NS_KIND] == L.KIND_UNWIND else 1.0
                v_meas = istate[d, L.I_RADIUS] * x[offsets_omega + i]
                if over_limit(d, direction, v_meas, refs[0], drives) and method == 0:
                    method = L.BREAK_OVERSPEED
        if method == 0:
            return 1.0
        for d in range(ds.shape[0]):
            istate[d, L.I_DETECT] = t
            istate[d, L.I_METHOD] = method
    factor = 1.0 - (t - istate[0, L.I_DETECT]) / web[L.W_BSTOP]
    return factor if factor > 0.0 else 0.0


@jit
def diameter_runs_off(d: int, unwind: bool, threshold: float, istate: np.ndarray) -> bool:
    """True when drive ``d``'s calculated diameter has moved the wrong way (an unwind's
    grown, a rewind's shrunk) by more than ``threshold`` [m] from its extreme so far, as the
    speed-ratio diameter runs off when the web is lost: an unwind's spindle slows under its
    braking torque while the line runs on (R = v_line / ω grows), a rewind's spins up. Keeps
    the extreme radius in ``istate``."""
    radius = istate[d, L.I_RADIUS]
    extreme = istate[d, L.I_REXTREME]
    if extreme <= 0.0 or (radius < extreme if unwind else radius > extreme):
        extreme = radius
    istate[d, L.I_REXTREME] = extreme
    grown = 2.0 * (radius - extreme) if unwind else 2.0 * (extreme - radius)
    return grown > threshold
