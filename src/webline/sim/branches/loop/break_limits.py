"""A stopping line's limits on its centre winders after a web break of a branched line, as
the chain's ``sim.drives.winder_loop.over_limit`` and ``sim.elements.break_hold``
(docs/winder.md W7, W8; docs/branching.md "Web breaks"): the monitor's overspeed watch of
an open-loop roll beyond its speed limiter's limit, the stop ramp's deceleration that the
inertia compensation takes, and the standstill torque of the hold. Columns in
``loop.layout`` (D_BOVER, D_BSTALL)."""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.elements.signals import jit


@jit
def overspeed_drive(x: np.ndarray, istate: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
                    di: np.ndarray, df: np.ndarray, v_line: float) -> int:
    """The first open-loop drive whose roll is beyond its speed limit (W7), -1 if none (or
    the watch is off): a rewind's surface speed above, an unwind's below the line-speed
    reference ``v_line`` [m/s] by more than its limiter's offset. The surface speed is the
    radius the drive uses (its calculator's, else its roll's true one) times the roller's
    ω, as the chain's monitor reads it."""
    if df[0, B.D_BOVER] == 0.0:
        return -1
    for d in range(di.shape[0]):
        if di[d, B.DI_WINDER] != B.WINDER_OPEN:
            continue
        i, j = di[d, B.DI_NODE], di[d, B.DI_ROLL]
        if df[d, B.D_DCALC] != B.DCALC_NONE:
            radius = istate[d, B.I_RADIUS]
        elif j >= 0:
            radius = x[offsets[B.O_RADIUS] + j]
        else:
            radius = nodes[i, B.N_RADIUS]
        v_meas = radius * x[offsets[B.O_OMEGA] + i]
        if df[d, B.D_DIR] * (v_meas - v_line) > df[d, B.D_SPEEDLIM]:
            return d
    return -1


@jit
def stop_acceleration(a_line: float, v_line: float, stopping: float, df: np.ndarray) -> float:
    """Acceleration [m/s²] of the line-speed reference s(t) v(t) while it ramps to a stop
    (``stopping`` s from 1 to 0 in the stop time T): s a - v / T, ``a_line`` and ``v_line``
    the profile's own acceleration [m/s²] and speed [m/s]; 0 once stopped, ``a_line``
    before the break is found. A centre winder's inertia compensation takes it, so that its
    roll decelerates with the ramp (W8)."""
    if stopping >= 1.0:
        return a_line
    return stopping * a_line - v_line / df[0, B.D_BSTOP] if stopping > 0.0 else 0.0


@jit
def standstill_hold(d: int, di: np.ndarray, df: np.ndarray) -> bool:
    """Whether drive ``d`` holds with a standstill torque once stopped: an open-loop drive
    in the ``zero_speed`` hold (W8)."""
    return di[d, B.DI_WINDER] == B.WINDER_OPEN and df[d, B.D_BHOLD] == B.HOLD_ZERO_SPEED


@jit
def held_open_loop(d: int, dt: float, v_meas: float, gain: float, radius: float,
                   tension_ref: float, istate: np.ndarray, df: np.ndarray) -> float:
    """Open-loop drive ``d``'s torque command [N·m] once stopped in the ``zero_speed`` hold
    (W8): its speed PI on 0 - ``v_meas`` [m/s], the integrator carrying on from the torque
    of the stop, the command limited on the tension side (+ a rewind, - an unwind) to the
    standstill torque σ T_ref R / n (``tension_ref`` [N] the zone's set tension, ``radius``
    [m] the one the drive uses): an intact web then pays out until T <= σ T_ref and is held
    there, a freed roll is held at rest. Conditional integration against the limits, as
    the chain's ``break_hold.held_command``."""
    limit = df[d, B.D_LIMIT]
    low, high = -limit, limit
    stall = df[d, B.D_BSTALL] * tension_ref * radius / df[d, B.D_RATIO]
    if df[d, B.D_DIR] > 0.0:
        high = min(stall, limit)
    else:
        low = max(-stall, -limit)
    error = -v_meas
    raw = df[d, B.D_KPS] * gain * error + istate[d, B.I_SPEED]
    u = min(max(raw, low), high)
    if not (u != raw and error * (raw - u) > 0.0):  # no windup against the limit
        istate[d, B.I_SPEED] += df[d, B.D_KIS] * gain * error * dt
    return u
