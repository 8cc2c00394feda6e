"""What the drives do once the line has ramped to a stop after a web break (docs/winder.md
W8): hold zero speed with a standstill tension, set their brakes, or switch off."""

from __future__ import annotations

import numpy as np

from webline.sim.elements import layout as L
from webline.sim.elements.signals import jit

#: a brake is static friction below a speed band of at least the speed its torque gives the
#: roller in this time [s] (docs/winder.md W8): no RK4 sub-step (at most 1 ms) can carry a
#: braked roller across the band (its deceleration is below 2 x brake / J), so it is caught
#: by the stick test even on a light roller under a strong brake (rockwell's pull roll:
#: 40 N·m on 0.04 kg·m²)
BRAKE_SMOOTHING_TIME = 2e-3


@jit
def held(t: float, istate: np.ndarray, web: np.ndarray) -> bool:
    """True from the end of the stop ramp after a detected web break (time ``t`` [s])."""
    detected = istate[0, L.I_DETECT]
    return detected >= 0.0 and t - detected >= web[L.W_BSTOP]


@jit
def stop_acceleration(a_line: float, v_line: float, stopping: float, web: np.ndarray) -> float:
    """Acceleration [m/s²] of the line-speed reference s(t) v(t) while it ramps to a stop
    (s from 1 to 0 in the stop time T): s a - v / T, ``a_line`` and ``v_line`` the profile's
    own acceleration [m/s²] and speed [m/s]; 0 once stopped. The inertia compensation and
    the reference state take it, so that a roll decelerates with the ramp."""
    return stopping * a_line - v_line / web[L.W_BSTOP] if stopping > 0.0 else 0.0


@jit
def fade_trim(d: int, dt: float, stopping: float, istate: np.ndarray, web: np.ndarray) -> None:
    """Scale drive ``d``'s frozen tension trim [m/s] with the line speed while it ramps to a
    stop (``stopping`` [0, 1): the ramp's factor this tick, ``dt`` [s]), as a trim set in
    per cent of line speed does: the integrator is multiplied by s(t) / s(t - dt), so at
    every tick it is its value at the detection times s(t), and zero at the stop, where the
    drives hold zero speed without a leftover trim (W8)."""
    previous = stopping + dt / web[L.W_BSTOP]
    istate[d, L.I_TENSION] *= stopping / previous if previous > 0.0 else 0.0


@jit
def held_command(d: int, dt: float, direction: float, radius: float, v_meas: float,
                 gain: float, tension_ref: float, istate: np.ndarray, ds: np.ndarray,
                 drives: np.ndarray, web: np.ndarray, out: np.ndarray) -> bool:
    """Drive ``d``'s command once stopped (W8), True if it set one (a decentralized drive in
    zero-speed hold keeps its own law, at the zero speed reference, and gets False).

    ``"zero_speed"``: the speed PI on 0 - ``v_meas`` [m/s], tension trims off, its
    integrator carrying on from the torque of the stop (conditional integration as the
    running PI); an open-loop roll's command is limited on the tension side (``direction``:
    +1 rewind, -1 unwind) to the standstill torque s T_ref R / n (s the standstill
    fraction, ``tension_ref`` [N], ``radius`` [m]): an intact web then settles at s T_ref,
    a freed roll stays at rest. ``"brakes"`` and ``"off"``: no torque (the brake acts in
    the plant, ``brake_drag``)."""
    mode = web[L.W_BHOLD]
    family = ds[d, L.DS_FAMILY]
    holds_speed = mode == L.HOLD_ZERO_SPEED or mode == L.HOLD_STALL
    if holds_speed and family != L.FAMILY_PI and family != L.FAMILY_OPEN_LOOP:
        return False
    out[1, d] = 0.0
    out[2, d] = 0.0
    out[3, d] = 0.0
    if not holds_speed:
        out[0, d] = 0.0
        return True
    if mode == L.HOLD_STALL and direction != 0.0:  # a roll: its stall tension as a torque
        out[0, d] = stall_command(d, dt, direction, radius, v_meas, gain, tension_ref,
                                  istate, drives, web)
        return True
    limit = drives[d, L.D_LIMIT]
    low, high = -limit, limit
    if family == L.FAMILY_OPEN_LOOP:
        stall = web[L.W_BSTALL] * tension_ref * radius / drives[d, L.D_RATIO]
        if direction > 0.0:
            high = min(stall, limit)
        else:
            low = max(-stall, -limit)
    error = -v_meas
    raw = drives[d, L.D_KPS] * gain * error + istate[d, L.I_SPEED]
    u = min(max(raw, low), high)
    if not (u != raw and error * (raw - u) > 0.0):  # no windup against the limit
        istate[d, L.I_SPEED] += drives[d, L.D_KIS] * gain * error * dt
    out[0, d] = u
    return True


#: a roll holding its stall tension is caught by its speed loop beyond this surface speed
#: [m/s] (a web that no longer holds it: docs/winder.md W8), well under the verdict's rest
#: limit (2 % of line speed) on any line faster than 0.5 m/s
STALL_SPEED_LIMIT = 0.01


@jit
def stall_command(d: int, dt: float, direction: float, radius: float, v_meas: float,
                  gain: float, tension_ref: float, istate: np.ndarray, drives: np.ndarray,
                  web: np.ndarray) -> float:
    """Torque command [N·m] of roll drive ``d`` holding its stall tension after the stop
    (W8 ``"stall_tension"``): the torque direction x s T_ref R / n (s the standstill
    fraction, ``tension_ref`` [N], ``radius`` [m], ``direction`` +1 rewind, -1 unwind), as
    drives hold a stall tension: the web at rest then sits at s T_ref within what the
    rollers' static friction holds. At rest the sign of the roll's own friction is unknown,
    so no friction term is added; the speed loop's proportional gain damps the roll about
    rest (- k_p v: nothing at rest) where a bare torque would ring on the web's spring.

    A speed limiter takes torque off where the roll turns the way its torque drives it
    faster than ``STALL_SPEED_LIMIT``: it integrates the excess with the speed PI's integral
    gain into the tension integrator (frozen since the detection, faded to zero by the
    stop), never adding torque, so a roll the web no longer holds turns at the limit."""
    limit = drives[d, L.D_LIMIT]
    stall = min(web[L.W_BSTALL] * tension_ref * radius / drives[d, L.D_RATIO], limit)
    excess = direction * v_meas - STALL_SPEED_LIMIT  # > 0: running away
    trim = istate[d, L.I_TENSION] - drives[d, L.D_KIS] * gain * excess * dt
    istate[d, L.I_TENSION] = min(trim, 0.0)  # it takes torque off, never adds
    torque = (direction * max(stall + istate[d, L.I_TENSION], 0.0)
              - drives[d, L.D_KPS] * gain * v_meas)
    return min(max(torque, -limit), limit)


@jit
def brake_drag(i: int, t: float, istate: np.ndarray, ns: np.ndarray, drives: np.ndarray,
               web: np.ndarray) -> float:
    """Holding-brake torque [N·m at the roller] on node ``i`` at time ``t`` [s]: the set
    brake (fraction x the drive's torque limit x ratio) on a driven roller once stopped
    with ``hold = "brakes"``, else 0."""
    d = ns[i, L.NS_DRIVE]
    if d < 0 or web[L.W_BHOLD] != L.HOLD_BRAKES or not held(t, istate, web):
        return 0.0
    return web[L.W_BBRAKE] * drives[d, L.D_LIMIT] * drives[d, L.D_RATIO]


@jit
def brake_band(brake: float, inv_inertia: float) -> float:
    """Speed [rad/s] below which a brake of ``brake`` [N·m] on a roller of 1/inertia
    ``inv_inertia`` [1/(kg·m²)] sticks unless its load exceeds it: max(0.1 rad/s, the
    Coulomb smoothing of bearings, ``BRAKE_SMOOTHING_TIME`` x brake / J)."""
    return max(0.1, BRAKE_SMOOTHING_TIME * brake * inv_inertia)
