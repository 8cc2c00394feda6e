"""The compiled simulation loop: plant and sampled cascaded-PI controllers in one numba loop.

Between controller ticks the torque commands are held (zero-order hold) and the plant is
integrated with fixed-step RK4 sub-steps; at each tick every controller samples the state,
updates its integrators with anti-windup, and issues a saturated torque command.

State vector layout (offsets from ``plan.Offsets``): span stretch forces [N], node angular
speeds [rad/s], unwind and rewind radii [m], motor torques [N·m], eccentric-roller angles
[rad], and two web-length integrals [m] (unstrained web unwound and rewound).
"""

from __future__ import annotations

import math
from typing import Any

import numba as nb
import numpy as np

from webline.physics import motor, roll, roller, span
from webline.sim import layout as L

#: Fast-math flags that keep NaN/inf semantics (the loop checks finiteness), and numpy's error
#: model (no Python ZeroDivisionError branch on every division).
_FAST = {"nsz", "arcp", "contract", "afn", "reassoc"}
_njit = nb.njit(cache=True, fastmath=_FAST, error_model="numpy")
_jit = nb.njit(cache=True, fastmath=_FAST, error_model="numpy", inline="always")
_tension: Any = _jit(span.tension)
_roll_inertia: Any = _jit(roll.roll_inertia)
_radius_rate: Any = _jit(roll.radius_rate)
_friction: Any = _jit(roller.friction_torque)
_saturate: Any = _jit(motor.saturate)


@_jit
def profile_at(p: int, t: float, prof_t: np.ndarray, prof_v: np.ndarray,
               prof_off: np.ndarray) -> float:
    """Value at ``t`` [s] of profile ``p`` of the concatenated breakpoint arrays: the same
    rule as ``webline.profiles.pwl_value``, by bisection without array views."""
    lo, hi = prof_off[p], prof_off[p + 1] - 1
    if t >= prof_t[hi]:
        return prof_v[hi]
    if t < prof_t[lo]:
        return prof_v[lo]
    while hi - lo > 1:  # invariant: prof_t[lo] <= t < prof_t[hi]
        mid = (lo + hi) // 2
        if prof_t[mid] <= t:
            lo = mid
        else:
            hi = mid
    return prof_v[lo] + (prof_v[hi] - prof_v[lo]) * (t - prof_t[lo]) / (prof_t[hi] - prof_t[lo])


@_jit
def sines(table: np.ndarray, t: float) -> float:
    """Sum of amplitude·sin(2π f t + phase) over rows (amplitude, frequency, phase)."""
    total = 0.0
    for r in range(table.shape[0]):
        total += table[r, 0] * math.sin(2.0 * math.pi * table[r, 1] * t + table[r, 2])
    return total


@_jit
def node_arm(i: int, x: np.ndarray, nodes: np.ndarray, off_w: int, off_r: int) -> float:
    """Effective radius [m] of node ``i``: roll radius state, or roller radius + eccentricity."""
    kind = int(nodes[i, L.N_KIND])
    if kind == L.KIND_UNWIND:
        return x[off_r]
    if kind == L.KIND_REWIND:
        return x[off_r + 1]
    ecc_state = int(nodes[i, L.N_ECCSTATE])
    if ecc_state >= 0:
        return nodes[i, L.N_RADIUS] + nodes[i, L.N_ECC] * math.cos(x[ecc_state])
    return nodes[i, L.N_RADIUS]


@_jit
def node_inertia(i: int, x: np.ndarray, nodes: np.ndarray, web: np.ndarray, off_r: int) -> float:
    kind = int(nodes[i, L.N_KIND])
    if kind == L.KIND_UNWIND or kind == L.KIND_REWIND:
        radius = x[off_r] if kind == L.KIND_UNWIND else x[off_r + 1]
        return _roll_inertia(nodes[i, L.N_JCONST], radius, nodes[i, L.N_CORE], web[L.W_WIDTH],
                             web[L.W_DENSITY])
    return nodes[i, L.N_JCONST]


@_jit
def rhs(t: float, x: np.ndarray, cmd: np.ndarray, nodes: np.ndarray, spans: np.ndarray,
        drives: np.ndarray, web: np.ndarray, wound_ripple: np.ndarray,
        offsets: np.ndarray, dx: np.ndarray, work: np.ndarray) -> None:
    """Plant derivative dx/dt into ``dx`` at time ``t`` [s] with held torque commands ``cmd``.

    Physics as in ``webline.physics`` (span 6.8 with slack, rollers 6.9/6.11, rolls 6.1-6.6
    with J dω/dt = torque, motor lag 4.1k), written out with precomputed reciprocals because
    this function is the simulation's inner loop. ``work`` is scratch of 3 x nodes.
    """
    n_spans = spans.shape[0]
    n_nodes = nodes.shape[0]
    last = n_nodes - 1
    off_w, off_r, off_tq, off_q = offsets[1], offsets[2], offsets[3], offsets[5]
    ea = web[L.W_EA]
    t0 = web[L.W_T0]
    if wound_ripple.shape[0] > 0:
        t0 += sines(wound_ripple, t)
    # work = [arm of each node | web speed of each node | tension of each span]
    sp, te = n_nodes, 2 * n_nodes
    for i in range(n_nodes):
        work[i] = node_arm(i, x, nodes, off_w, off_r)
        work[sp + i] = work[i] * x[off_w + i]
    for k in range(n_spans):
        work[te + k] = _tension(x[k])

    t_in = t0
    for k in range(n_spans):
        v_in, v_out, t_out = work[sp + k], work[sp + k + 1], work[te + k]
        dx[k] = (ea * (v_out - v_in) + t_in * v_in - t_out * v_out) * spans[k, L.S_INVLENGTH]
        t_in = t_out

    width, density = web[L.W_WIDTH], web[L.W_DENSITY]
    for i in range(n_nodes):
        omega = x[off_w + i]
        t_out = work[te + i] if i < n_spans else 0.0
        t_up = work[te + i - 1] if i > 0 else 0.0
        torque = work[i] * (t_out - t_up) - nodes[i, L.N_VISCOUS] * omega
        coulomb = nodes[i, L.N_COULOMB]
        if coulomb != 0.0:
            torque -= _friction(omega, 0.0, coulomb)
        drive = int(nodes[i, L.N_DRIVE])
        if drive >= 0:
            torque += nodes[i, L.N_RATIO] * x[off_tq + drive]
        if i == 0 or i == last:
            inertia = _roll_inertia(nodes[i, L.N_JCONST], work[i], nodes[i, L.N_CORE], width,
                                    density)
            dx[off_w + i] = torque / inertia
        else:
            dx[off_w + i] = torque * nodes[i, L.N_INVJ]
            ecc_state = int(nodes[i, L.N_ECCSTATE])
            if ecc_state >= 0:
                dx[ecc_state] = omega

    v_unwind, v_rewind = work[sp], work[sp + last]
    dx[off_r] = _radius_rate(v_unwind, x[off_r], web[L.W_THICK], -1.0)
    dx[off_r + 1] = _radius_rate(v_rewind, x[off_r + 1], web[L.W_THICK], 1.0)

    for d in range(drives.shape[0]):
        dx[off_tq + d] = (cmd[d] - x[off_tq + d]) * drives[d, L.D_INVLAG]

    inv_ea = 1.0 / ea
    dx[off_q] = v_unwind * (1.0 - t0 * inv_ea)
    dx[off_q + 1] = v_rewind * (1.0 - work[te + n_spans - 1] * inv_ea)


@_jit
def control_tick(t: float, dt: float, x: np.ndarray, istate: np.ndarray, nodes: np.ndarray,
                 drives: np.ndarray, web: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                 prof_off: np.ndarray, speed_ripple: np.ndarray, offsets: np.ndarray,
                 cmd: np.ndarray, vref: np.ndarray, trim: np.ndarray, refs: np.ndarray) -> None:
    """One sample of every drive's cascaded PI (thesis Fig. 4.3, 4.1i-j).

    The tension PI trims the speed reference (line speed x draw from the tension references,
    plus any ripple); the speed PI gives the torque command, clipped to the torque limit.
    Integrators hold torque [N·m] and trim [m/s] and stop while the torque saturates in the
    direction they push (conditional-integration anti-windup). ``istate[d]`` = (speed, tension)
    integrators; ``cmd``, ``vref``, ``trim`` and the scratch ``refs`` (one per profile) are
    written.
    """
    off_w, off_r = offsets[1], offsets[2]
    ea = web[L.W_EA]
    for p in range(prof_off.shape[0] - 1):
        refs[p] = profile_at(p, t, prof_t, prof_v, prof_off)
    v_line = refs[0]
    t_master = refs[offsets[6]]
    for d in range(drives.shape[0]):
        i = int(drives[d, L.D_NODE])
        kind = int(nodes[i, L.N_KIND])
        up = int(drives[d, L.D_UPREF])
        t_up = web[L.W_T0] if up < 0 else refs[up]
        ref = v_line * (ea - t_master) / (ea - t_up)
        for r in range(speed_ripple.shape[0]):
            if int(speed_ripple[r, 0]) == d:
                ref += speed_ripple[r, 1] * math.sin(2.0 * math.pi * speed_ripple[r, 2] * t
                                                     + speed_ripple[r, 3])
        radius = x[off_r] if kind == L.KIND_UNWIND else (
            x[off_r + 1] if kind == L.KIND_REWIND else nodes[i, L.N_RADIUS])
        v_meas = radius * x[off_w + i]

        e_t = 0.0
        tr = 0.0
        if int(drives[d, L.D_ROLE]) == L.ROLE_TENSION:
            t_ref = refs[int(drives[d, L.D_REF])]
            e_t = t_ref - _tension(x[int(drives[d, L.D_LOADCELL])])
            tr = drives[d, L.D_SIGMA] * (drives[d, L.D_KPT] * e_t + istate[d, 1])
        gain = 1.0
        if drives[d, L.D_ADAPTIVE] > 0.0:
            n = nodes[i, L.N_RATIO]
            gain = node_inertia(i, x, nodes, web, off_r) / (n * radius) / drives[d, L.D_GAINNORM]
        e_v = ref + tr - v_meas
        raw = drives[d, L.D_KPS] * gain * e_v + istate[d, 0]
        limit = drives[d, L.D_LIMIT]
        u = _saturate(raw, limit)
        saturated = raw != u
        if not (saturated and e_v * raw > 0.0):
            istate[d, 0] += drives[d, L.D_KIS] * gain * e_v * dt
        if not (saturated and drives[d, L.D_SIGMA] * e_t * raw > 0.0):
            istate[d, 1] += drives[d, L.D_KIT] * e_t * dt
        cmd[d] = u
        vref[d] = ref
        trim[d] = tr


@_njit
def run(x0: np.ndarray, istate0: np.ndarray, tick0: int, n_ticks: int, dt: float, substeps: int,
        record_every: int, include_end: bool, nodes: np.ndarray, spans: np.ndarray,
        drives: np.ndarray, web: np.ndarray, wound_ripple: np.ndarray,
        speed_ripple: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray,
        offsets: np.ndarray) -> tuple[np.ndarray, int, int, float, np.ndarray, np.ndarray]:
    """Simulate ``n_ticks`` controller periods of ``dt`` [s] from tick ``tick0``.

    A tick is recorded when its global index is a multiple of ``record_every``; with
    ``include_end`` the state after the last period is recorded too (a chunked run leaves it
    to the next chunk). Returns (records, number of records, status, time of failure, final
    state, final integrators). Each record row is [t, x..., cmd..., vref..., trim...]. The
    run stops early, keeping what it computed, if the state stops being finite or the unwind
    roll runs out of web.
    """
    n_x = x0.shape[0]
    n_d = drives.shape[0]
    width = 1 + n_x + 3 * n_d
    rec = np.empty((n_ticks // record_every + 2, width))
    x = x0.copy()
    istate = istate0.copy()
    cmd = np.zeros(n_d)
    vref = np.zeros(n_d)
    trim = np.zeros(n_d)
    k1 = np.empty(n_x)
    k2 = np.empty(n_x)
    k3 = np.empty(n_x)
    k4 = np.empty(n_x)
    tmp = np.empty(n_x)
    work = np.empty(3 * nodes.shape[0])
    refs = np.empty(prof_off.shape[0] - 1)
    h = dt / substeps
    n_rec = 0
    status = L.STATUS_OK
    t_fail = math.nan
    off_r = offsets[2]
    core = nodes[0, L.N_CORE]
    for j in range(n_ticks + 1):
        tick = tick0 + j
        t = tick * dt
        if j == n_ticks and not include_end:
            break
        control_tick(t, dt, x, istate, nodes, drives, web, prof_t, prof_v, prof_off,
                     speed_ripple, offsets, cmd, vref, trim, refs)
        if tick % record_every == 0 or j == n_ticks:
            rec[n_rec, 0] = t
            rec[n_rec, 1:1 + n_x] = x
            rec[n_rec, 1 + n_x:1 + n_x + n_d] = cmd
            rec[n_rec, 1 + n_x + n_d:1 + n_x + 2 * n_d] = vref
            rec[n_rec, 1 + n_x + 2 * n_d:width] = trim
            n_rec += 1
        if j == n_ticks:
            break
        for s in range(substeps):
            ts = t + s * h
            rhs(ts, x, cmd, nodes, spans, drives, web, wound_ripple, offsets, k1, work)
            for m in range(n_x):
                tmp[m] = x[m] + 0.5 * h * k1[m]
            rhs(ts + 0.5 * h, tmp, cmd, nodes, spans, drives, web, wound_ripple, offsets, k2,
                work)
            for m in range(n_x):
                tmp[m] = x[m] + 0.5 * h * k2[m]
            rhs(ts + 0.5 * h, tmp, cmd, nodes, spans, drives, web, wound_ripple, offsets, k3,
                work)
            for m in range(n_x):
                tmp[m] = x[m] + h * k3[m]
            rhs(ts + h, tmp, cmd, nodes, spans, drives, web, wound_ripple, offsets, k4, work)
            for m in range(n_x):
                x[m] += h / 6.0 * (k1[m] + 2.0 * k2[m] + 2.0 * k3[m] + k4[m])
        finite = True
        for m in range(n_x):
            if not math.isfinite(x[m]):
                finite = False
        if not finite:
            status = L.STATUS_NONFINITE
            t_fail = t + dt
            break
        if x[off_r] <= core:
            status = L.STATUS_UNWIND_EMPTY
            t_fail = t + dt
            break
    return rec, n_rec, status, t_fail, x, istate
