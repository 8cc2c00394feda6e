"""A web break on a branched line in the compiled loop (docs/branching.md, "Web breaks"): the
cut (its spans carry nothing from their break time on), the monitor that looks for it, the
ramp to a stop with the tension loops frozen and faded, and the hold after the stop, as the
chain's ``sim.drives.winder_loop.break_monitor`` and ``sim.elements.break_hold`` (docs/
winder.md W5-W8). Tables in ``sim.branches.loop.layout`` (SF_BREAK, D_B*, I_DETECT...).
"""

from __future__ import annotations

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.break_limits import overspeed_drive
from webline.sim.elements.break_hold import STALL_SPEED_LIMIT
from webline.sim.elements.signals import jit, profile_at


@jit
def cut(t: float, x: np.ndarray, wound: np.ndarray, sf: np.ndarray, n_w: int, n_n: int,
        istate: np.ndarray, di: np.ndarray, df: np.ndarray) -> None:
    """Break every span whose break time is at or before ``t`` [s] and not yet broken: its
    flag (``wound[n_w + n_n + k]``, held over the period into ``rhs``) set to 1 and its
    stretch to 0: from then on it carries no tension and its stretch stays frozen (W5).
    Once stopped with ``hold = "brakes"``, set every drive's holding brake on its roller
    (``wound[n_w + n_n + n_s + node]`` [N·m], W8)."""
    n_s = sf.shape[0]
    for k in range(n_s):
        if t >= sf[k, B.SF_BREAK] and wound[n_w + n_n + k] == 0.0:
            wound[n_w + n_n + k] = 1.0
            x[k] = 0.0
    detected = istate[0, B.I_DETECT]
    if df[0, B.D_BHOLD] == B.HOLD_BRAKES and detected >= 0.0 and (
            t - detected >= df[0, B.D_BSTOP]):
        for d in range(di.shape[0]):
            wound[n_w + n_n + n_s + di[d, B.DI_NODE]] = (
                df[d, B.D_BBRAKE] * df[d, B.D_LIMIT] * df[d, B.D_RATIO])


@jit
def break_monitor(t: float, x: np.ndarray, istate: np.ndarray, di: np.ndarray,
                  df: np.ndarray, cells: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                  prof_off: np.ndarray, offsets: np.ndarray, nodes: np.ndarray) -> float:
    """Look for a break once per tick, before the drives (W5): a loadcell's tension below the
    threshold x its reference (every loadcell of every zone, in the drives' order, but an
    open-loop drive's: it reads none), a speed-ratio diameter that has run the wrong way
    (an unwind's grown, a rewind's shrunk) by more than the diameter threshold [m] from its
    extreme so far (W6; the radius the calculator gave last tick), or an open-loop roll
    beyond its speed limit (W7, ``loop.break_limits``). The first found is kept in
    ``istate`` (time, method, where: the loadcell's span or the drive). Returns the
    line-speed factor of the ramp to a stop, 1 before the detection, falling to 0 in the
    stop time."""
    if istate[0, B.I_DETECT] < 0.0:
        method, where = 0, -1
        threshold = df[0, B.D_BTHRESH]
        for d in range(di.shape[0]):
            if di[d, B.DI_WINDER] == B.WINDER_OPEN:  # (no loadcell read: W5)
                continue
            for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
                tension = x[cells[c, 0]] if x[cells[c, 0]] > 0.0 else 0.0
                reference = profile_at(cells[c, 1], t, prof_t, prof_v, prof_off)
                if method == 0 and tension < threshold * reference:
                    method, where = B.BREAK_TENSION, cells[c, 0]
        for d in range(di.shape[0]):  # every calculator keeps its extreme, found or not
            if df[d, B.D_DCALC] == B.DCALC_SPEED_RATIO and df[d, B.D_BDIAM] > 0.0:
                radius = istate[d, B.I_RADIUS]
                extreme = istate[d, B.I_REXTREME]
                unwind = df[d, B.D_DDIR] < 0.0
                if extreme <= 0.0 or (radius < extreme if unwind else radius > extreme):
                    extreme = radius
                istate[d, B.I_REXTREME] = extreme
                grown = 2.0 * (radius - extreme) if unwind else 2.0 * (extreme - radius)
                if method == 0 and grown > df[d, B.D_BDIAM]:
                    method, where = B.BREAK_DIAMETER, d
        if method == 0:
            where = overspeed_drive(x, istate, offsets, nodes, di, df,
                                    profile_at(0, t, prof_t, prof_v, prof_off))
            if where < 0:
                return 1.0
            method = B.BREAK_OVERSPEED
        for d in range(di.shape[0]):
            istate[d, B.I_DETECT] = t
            istate[d, B.I_METHOD] = method
            istate[d, B.I_WHERE] = where
    factor = 1.0 - (t - istate[0, B.I_DETECT]) / df[0, B.D_BSTOP]
    return factor if factor > 0.0 else 0.0


@jit
def fade_trim(d: int, dt: float, stopping: float, istate: np.ndarray, df: np.ndarray) -> None:
    """Drive ``d``'s frozen tension trim falls with the line speed while it ramps to a stop
    (``stopping`` in [0, 1) this tick, ``dt`` [s]): the tension integrator times
    s(t) / s(t - dt), so it is its value at the detection times s(t), zero at the stop (W8)."""
    previous = stopping + dt / df[d, B.D_BSTOP]
    istate[d, B.I_TENSION] *= stopping / previous if previous > 0.0 else 0.0


@jit
def held_command(d: int, dt: float, v_meas: float, gain: float, istate: np.ndarray,
                 df: np.ndarray) -> float:
    """Drive ``d``'s torque command [N·m] once the line has stopped (W8): ``zero_speed``: its
    speed PI on 0 - ``v_meas`` [m/s] (trim and feed-forward off, the integrator carrying on
    from the torque of the stop, conditional integration as running, ``gain`` the adaptive
    factor; also a drive other than a roll's in the ``stall_tension`` hold); ``off`` and
    ``brakes``: no torque (the brake acts in the plant)."""
    if df[d, B.D_BHOLD] != B.HOLD_ZERO_SPEED and df[d, B.D_BHOLD] != B.HOLD_STALL:
        return 0.0
    limit = df[d, B.D_LIMIT]
    error = -v_meas
    raw = df[d, B.D_KPS] * gain * error + istate[d, B.I_SPEED]
    u = min(max(raw, -limit), limit)
    if not (u != raw and error * raw > 0.0):  # no windup against the limit
        istate[d, B.I_SPEED] += df[d, B.D_KIS] * gain * error * dt
    return u


@jit
def stall_command(d: int, dt: float, v_meas: float, gain: float, radius: float,
                  tension_ref: float, istate: np.ndarray, df: np.ndarray) -> float:
    """Torque command [N·m] of roll drive ``d`` holding its stall tension after the stop (W8
    ``"stall_tension"``), as the chain's ``break_hold.stall_command``: D_DIR x σ T_ref R / n
    (``tension_ref`` [N] its zone's set tension, ``radius`` [m] the one the drive uses), the
    speed loop's proportional gain damping the roll about rest, less what a speed limiter
    takes off where the roll runs away faster than ``STALL_SPEED_LIMIT`` (integral, in the
    tension integrator, faded to zero by the stop)."""
    direction, limit = df[d, B.D_DIR], df[d, B.D_LIMIT]
    stall = min(df[d, B.D_BSTALL] * tension_ref * radius / df[d, B.D_RATIO], limit)
    excess = direction * v_meas - STALL_SPEED_LIMIT
    trim = istate[d, B.I_TENSION] - df[d, B.D_KIS] * gain * excess * dt
    istate[d, B.I_TENSION] = min(trim, 0.0)
    torque = direction * max(stall + istate[d, B.I_TENSION], 0.0) - df[d, B.D_KPS] * gain * v_meas
    return min(max(torque, -limit), limit)


@jit
def web_flows(dx: np.ndarray, off_q: int, webs: np.ndarray, sf: np.ndarray,
              broken: np.ndarray, v_a: np.ndarray, v_b: np.ndarray, s_in: np.ndarray,
              tension: np.ndarray, exact: bool) -> None:
    """The web-length counters of a line with a break (``rhs``): per web, the unstrained web
    entering its intact spans where they start after the web's start or a broken span,
    v_a (1 - s_in/EA), and leaving them where they end before its end or a broken span,
    v_b (1 - T/EA). So Σ_intact L (1 - x/EA) + out - in stays constant once cut: the web in
    a broken span (frozen, x = 0) no longer counts, and what crosses the cut ends is counted
    as it leaves or joins the intact web. ``broken``: 1 per broken span [-]; ``exact``:
    v/(1 + ε) in place of v (1 - ε) (``physics.span.unstrained_flow``)."""
    for w in range(webs.shape[0]):
        first, last = webs[w, B.WB_FIRST], webs[w, B.WB_LAST]
        inv_ea = sf[first, B.SF_INVEA]
        flow_in, flow_out = 0.0, 0.0
        for k in range(first, last + 1):
            if broken[k] != 0.0:
                continue
            if k == first or broken[k - 1] != 0.0:
                flow_in += (v_a[k] / (1.0 + s_in[k] * inv_ea) if exact
                            else v_a[k] * (1.0 - s_in[k] * inv_ea))
            if k == last or broken[k + 1] != 0.0:
                flow_out += (v_b[k] / (1.0 + tension[k] * inv_ea) if exact
                             else v_b[k] * (1.0 - tension[k] * inv_ea))
        dx[off_q + 2 * w] = flow_in
        dx[off_q + 2 * w + 1] = flow_out
