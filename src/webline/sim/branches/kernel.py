"""The compiled loop of a branched line: the plant of docs/branching.md and sampled cascaded
PI controllers, RK4 sub-steps between controller ticks as the chain kernel
(``sim.core.kernel``) does. Physics from ``webline.physics`` (span 6.8, rolls 6.1-6.6,
rollers 6.9/6.11); tables in ``sim.branches.layout``.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numpy as np

from webline.physics import motor, roll, roller, span, taper
from webline.sim.branches import layout as B
from webline.sim.drives.measure import quantized
from webline.sim.elements.signals import gaussian, jit, loop_njit, profile_at, sines

_tension: Any = jit(span.tension)
_stretch_rate: Any = jit(span.stretch_rate)
_roll_inertia: Any = jit(roll.roll_inertia)
_radius_rate: Any = jit(roll.radius_rate)
_friction: Any = jit(roller.friction_torque)
_saturate: Any = jit(motor.saturate)
_taper_factor: Any = jit(taper.taper_factor)


@jit
def arm(end_roll: int, node: int, x: np.ndarray, offsets: np.ndarray,
        nodes: np.ndarray) -> float:
    """Lever arm [m] of a span's end on ``node``: its web's roll radius, or the roller's."""
    if end_roll >= 0:
        return x[offsets[B.O_RADIUS] + end_roll]
    return nodes[node, B.N_RADIUS]


@jit
def carried_in(k: int, x: np.ndarray, tension: np.ndarray, wound: np.ndarray,
               si: np.ndarray, sf: np.ndarray, layers: np.ndarray) -> float:
    """Stretch [N] the web carries into span ``k`` (docs/branching.md, s_in)."""
    src = si[k, B.S_SRC]
    frm = si[k, B.S_FROM]
    if src == B.SRC_PREVIOUS:
        return tension[frm]
    if src == B.SRC_WOUND:
        return wound[si[k, B.S_WEB]]
    if src == B.SRC_LAYERS:  # force continuity at the nip: the layers' tensions add up
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
    inertia = nodes[i, B.N_JCONST]
    off_r = offsets[B.O_RADIUS]
    for j in range(rolls.shape[0]):
        if int(rolls[j, B.R_NODE]) == i and rolls[j, B.R_CLUTCH] == 0.0:
            inertia += _roll_inertia(0.0, x[off_r + j], rolls[j, B.R_CORE],
                                     rolls[j, B.R_WIDTH], rolls[j, B.R_RHO])
    return inertia


@jit
def rhs(x: np.ndarray, cmd: np.ndarray, wound: np.ndarray, offsets: np.ndarray,
        nodes: np.ndarray, si: np.ndarray, sf: np.ndarray, layers: np.ndarray,
        rolls: np.ndarray, webs: np.ndarray, di: np.ndarray, df: np.ndarray,
        cores: np.ndarray, clutch: np.ndarray, dx: np.ndarray, work: np.ndarray) -> None:
    """dx/dt of a branched line into ``dx`` with held motor-torque commands ``cmd`` [N·m] and
    held inputs ``wound``: the wound-in tension [N] per web, then the drag torque [N·m] per
    node (``roller_drag``, added to its Coulomb friction). ``work``: scratch of 4 x spans +
    2 x nodes (``work_size``). A lane on a differential shaft winds on its own core, which
    its slip clutch drives from the shaft with the smoothed Coulomb torque of
    ``physics.roller`` (docs/branching.md, "Differential shafts")."""
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
    for k in range(n_s):
        tension[k] = _tension(x[k])
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
        s_in[k] = carried_in(k, x, tension, wound, si, sf, layers)
        dx[k] = _stretch_rate(sf[k, B.SF_LENGTH], sf[k, B.SF_EA], v_a[k], v_b[k], s_in[k],
                              tension[k])
        torque[a] += arm_a * tension[k]  # the span pulls its upstream roller forward
        if core < 0:  # (a lane on a clutch core pulls its core, below)
            torque[b] -= arm_b * tension[k]
    for c in range(cores.shape[0]):  # a lane's core: clutch torque in, the lane's r T out
        j, i, k = cores[c, B.C_ROLL], cores[c, B.C_NODE], cores[c, B.C_SPAN]
        radius, omega_core = x[off_r + j], x[off_c + c]
        passed = _friction(x[off_w + i] - omega_core, 0.0, clutch[c, B.CF_SLIP])
        torque[i] -= passed
        inertia_core = clutch[c, B.CF_INERTIA] + _roll_inertia(
            0.0, radius, rolls[j, B.R_CORE], rolls[j, B.R_WIDTH], rolls[j, B.R_RHO])
        dx[off_c + c] = (passed - radius * tension[k]) / inertia_core
        dx[off_r + j] = _radius_rate(radius * omega_core, radius, rolls[j, B.R_THICK],
                                     rolls[j, B.R_DIR])
    n_w = webs.shape[0]
    for i in range(n_n):
        omega = x[off_w + i]
        total = torque[i] - nodes[i, B.N_VISCOUS] * omega
        coulomb = nodes[i, B.N_COULOMB] + wound[n_w + i]  # a drag acts as dry friction does
        if coulomb != 0.0:  # (a tanh costs more than the rest of the node)
            total -= _friction(omega, 0.0, coulomb)
        d = int(nodes[i, B.N_DRIVE])
        if d >= 0:
            total += nodes[i, B.N_RATIO] * x[off_tq + d]
        if nodes[i, B.N_ROLLS] > 0.0:  # J(R) of the rolls on it (6.1)
            dx[off_w + i] = total / inertia[i]
        else:
            dx[off_w + i] = total * nodes[i, B.N_INVJ]
    for d in range(di.shape[0]):
        dx[off_tq + d] = (cmd[d] - x[off_tq + d]) * df[d, B.D_INVLAG]
    for w in range(webs.shape[0]):  # unstrained web in and out: v (1 - ε) at each end
        first, last = webs[w, B.WB_FIRST], webs[w, B.WB_LAST]
        inv_ea = sf[first, B.SF_INVEA]
        dx[off_q + 2 * w] = v_a[first] * (1.0 - s_in[first] * inv_ea)
        dx[off_q + 2 * w + 1] = v_b[last] * (1.0 - tension[last] * inv_ea)


def work_size(n_spans: int, n_nodes: int) -> int:
    """Length of ``rhs``'s scratch array."""
    return 4 * n_spans + 2 * n_nodes


@jit
def held_inputs(t: float, wound: np.ndarray, held: np.ndarray, n_w: int, dist: np.ndarray,
                prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray) -> None:
    """The inputs ``rhs`` holds over a controller period from ``t`` [s]: each web's wound-in
    tension ``wound`` plus its ripple, each node's drag torque profile (``layout`` DS_*)."""
    for m in range(held.shape[0]):
        held[m] = wound[m]
    for r in range(dist.shape[0]):
        kind, index = int(dist[r, B.DS_KIND]), int(dist[r, B.DS_INDEX])
        if kind == B.DIST_WOUND_RIPPLE:
            held[index] += sines(dist[r:r + 1, B.DS_A:B.DS_C + 1], t)
        elif kind == B.DIST_DRAG:
            held[n_w + index] += profile_at(int(dist[r, B.DS_A]), t, prof_t, prof_v, prof_off)


@jit
def calculated_radius(d: int, radius: float, omega: float, dt: float, v_line: float,
                      x: np.ndarray, offsets: np.ndarray, nodes: np.ndarray,
                      df: np.ndarray) -> float:
    """Drive ``d``'s diameter calculator one tick ``dt`` [s] on (docs/winder.md W2, as the
    chain's ``sim.drives.diameter.update_radius``): from ``radius`` [m] and the measured
    spindle speed ``omega`` [rad/s]. Speed ratio: R_raw = v_line / ω through a first-order
    filter, its step limited to rate_limit dt / 2, held while |v_line| < hold_below; v_line
    the reference ``v_line`` [m/s] or the source roller's surface speed. Thickness: R grows
    (winding) or shrinks by h |ω| dt / 2π."""
    if df[d, B.D_DCALC] == B.DCALC_THICKNESS:
        return radius + df[d, B.D_DDIR] * df[d, B.D_DTHICK] * abs(omega) * dt / (2.0 * math.pi)
    src = int(df[d, B.D_DSOURCE])
    v_src = v_line if src < 0 else nodes[src, B.N_RADIUS] * x[offsets[B.O_OMEGA] + src]
    if abs(v_src) < df[d, B.D_DHOLD] or abs(omega) <= 1e-9:
        return radius
    step = (abs(v_src / omega) - radius) * min(dt / df[d, B.D_DFILTER], 1.0)
    limit = 0.5 * df[d, B.D_DRATE] * dt
    return radius + min(max(step, -limit), limit)


@jit
def taper_at(d: int, radius: float, core_radius: float, df: np.ndarray, prof_t: np.ndarray,
             prof_v: np.ndarray, prof_off: np.ndarray) -> float:
    """Factor [-] on drive ``d``'s tension reference at its roll's ``radius`` [m] (a rewind's
    taper, docs/winder.md W1; 1 without one): a table's profile is over the diameter."""
    kind = int(df[d, B.D_TAPER_KIND])
    if kind == 0:
        return 1.0
    if kind == taper.TABLE:
        return profile_at(int(df[d, B.D_TAPER_PROF]), 2.0 * radius, prof_t, prof_v, prof_off)
    return _taper_factor(kind, df[d, B.D_TAPER], 2.0 * core_radius, df[d, B.D_TAPER_DMAX],
                         2.0 * radius)


@jit
def control_tick(t: float, tick: int, dt: float, x: np.ndarray, istate: np.ndarray,
                 cmd: np.ndarray, offsets: np.ndarray, nodes: np.ndarray, rolls: np.ndarray,
                 di: np.ndarray, df: np.ndarray, cells: np.ndarray, dist: np.ndarray,
                 prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray) -> None:
    """One sample ``tick`` of every drive's cascaded PI (thesis Fig. 4.3, as the chain's
    ``sim.drives.controllers.pi_command``): line speed x draw is the speed feedforward, a
    tension PI on the zone's loadcell (or the sum of its loadcells) trims it, a speed PI gives
    the torque, clipped, with conditional integration. ``cells`` rows: (span, profile).
    ``dist``: a drive's speed ripple adds to its speed reference; measurement noise to the
    measured speed (channel 2 d, then rounded to the resolution) and each loadcell's tension
    (channel 2 c + 1), as the chain's ``sim.drives.measure``."""
    v_line = profile_at(0, t, prof_t, prof_v, prof_off)
    off_w, off_r = offsets[B.O_OMEGA], offsets[B.O_RADIUS]
    sigma_t, sigma_v, resolution, seed, noisy = 0.0, 0.0, 0.0, 0, False
    for r in range(dist.shape[0]):
        if int(dist[r, B.DS_KIND]) == B.DIST_NOISE:
            seed, noisy = int(dist[r, B.DS_INDEX]), True
            sigma_t, sigma_v, resolution = dist[r, B.DS_A], dist[r, B.DS_B], dist[r, B.DS_C]
    for d in range(di.shape[0]):
        i = di[d, B.DI_NODE]
        j = di[d, B.DI_ROLL]
        radius = x[off_r + j] if j >= 0 else nodes[i, B.N_RADIUS]  # true radius
        if df[d, B.D_DCALC] != B.DCALC_NONE:
            for p in range(int(df[d, B.D_PRESETN])):  # W2a: set at the first tick at or after
                if t - dt < df[d, B.D_PRESETT + p] <= t:
                    preset = 0.5 * df[d, B.D_PRESETD + p]
                    istate[d, B.I_RADIUS] = radius if preset <= 0.0 else preset
            radius = istate[d, B.I_RADIUS]
        v_meas = radius * x[off_w + i]
        if noisy:
            v_meas = quantized(v_meas + sigma_v * gaussian(seed, tick, 2 * d), resolution)
        if df[d, B.D_DCALC] != B.DCALC_NONE:  # W2: the radius the controllers use
            omega_meas = v_meas / radius
            radius = calculated_radius(d, radius, omega_meas, dt, v_line, x, offsets, nodes,
                                       df)
            istate[d, B.I_RADIUS] = radius
            v_meas = radius * omega_meas
        e_t = 0.0
        factor = taper_at(d, radius, nodes[i, B.N_CORE], df, prof_t, prof_v, prof_off)
        for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
            measured = _tension(x[cells[c, 0]])
            if noisy:
                measured += sigma_t * gaussian(seed, tick, 2 * c + 1)
            e_t += factor * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off) - measured
        trim = df[d, B.D_SIGMA] * (df[d, B.D_KPT] * e_t + istate[d, B.I_TENSION])
        ripple = 0.0
        for r in range(dist.shape[0]):
            if int(dist[r, B.DS_KIND]) == B.DIST_SPEED_RIPPLE and int(dist[r, B.DS_INDEX]) == d:
                ripple += sines(dist[r:r + 1, B.DS_A:B.DS_C + 1], t)
        e_v = v_line * df[d, B.D_FF] + ripple + trim - v_meas
        gain = 1.0
        if df[d, B.D_ADAPTIVE] > 0.0:  # speed gains follow the roll's inertia
            gain = node_inertia(i, x, offsets, nodes, rolls) / (
                df[d, B.D_RATIO] * radius) / df[d, B.D_GAINNORM]
        raw = df[d, B.D_KPS] * gain * e_v + istate[d, B.I_SPEED]
        u = _saturate(raw, df[d, B.D_LIMIT])
        saturated = raw != u
        if not (saturated and e_v * raw > 0.0):
            istate[d, B.I_SPEED] += df[d, B.D_KIS] * gain * e_v * dt
        if not (saturated and df[d, B.D_SIGMA] * e_t * raw > 0.0):
            istate[d, B.I_TENSION] += df[d, B.D_KIT] * e_t * dt
        cmd[d] = u


@jit
def roll_change(t: float, x: np.ndarray, wound: np.ndarray, done: np.ndarray,
                offsets: np.ndarray, rolls: np.ndarray, events: np.ndarray) -> None:
    """A new roll takes over at its event's time: new radius and wound-in tension, brought
    to the old roll's surface speed first (a flying splice)."""
    for e in range(events.shape[0]):
        if done[e] == 0.0 and t >= events[e, B.E_TIME]:
            done[e] = 1.0
            j = int(events[e, B.E_ROLL])
            i = int(rolls[j, B.R_NODE])
            w_i = offsets[B.O_OMEGA] + i
            r_i = offsets[B.O_RADIUS] + j
            x[w_i] = x[w_i] * x[r_i] / events[e, B.E_RADIUS]
            x[r_i] = events[e, B.E_RADIUS]
            wound[int(events[e, B.E_WEB])] = events[e, B.E_WOUND]


@jit
def advance(x: np.ndarray, istate: np.ndarray, wound: np.ndarray, done: np.ndarray,
            rec: np.ndarray, stages: np.ndarray, cmd: np.ndarray, work: np.ndarray,
            held: np.ndarray,
            tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
            include_end: bool, speed_max: float, offsets: np.ndarray, nodes: np.ndarray,
            si: np.ndarray,
            sf: np.ndarray, layers: np.ndarray, rolls: np.ndarray, webs: np.ndarray,
            di: np.ndarray, df: np.ndarray, cores: np.ndarray, clutch: np.ndarray,
            cells: np.ndarray, events: np.ndarray, dist: np.ndarray, prof_t: np.ndarray,
            prof_v: np.ndarray, prof_off: np.ndarray) -> tuple[int, int, float]:
    """Advance ``n_ticks`` controller periods from tick ``tick0``, recording ``new_records``'
    rows every ``record_every`` ticks and, with ``include_end``, the state after the last (a
    chunked run leaves that tick to the next chunk); returns (records, status, time of
    failure). Stops at a non-finite state, an empty unwind or a runaway (``layout``).
    ``held``: scratch for the inputs held over a period (``held_inputs``)."""
    n_x = x.shape[0]
    n_d = di.shape[0]
    n_s = si.shape[0]
    tmp = stages[4]
    h = dt / substeps
    n_rec = 0
    off_w, off_r = offsets[B.O_OMEGA], offsets[B.O_RADIUS]
    for j in range(n_ticks + 1):
        t = (tick0 + j) * dt
        if j == n_ticks and not include_end:  # the next chunk starts with this tick
            break
        roll_change(t, x, wound, done, offsets, rolls, events)
        held_inputs(t, wound, held, webs.shape[0], dist, prof_t, prof_v, prof_off)
        control_tick(t, tick0 + j, dt, x, istate, cmd, offsets, nodes, rolls, di, df, cells,
                     dist, prof_t, prof_v, prof_off)
        if (tick0 + j) % record_every == 0 or j == n_ticks:
            rec[n_rec, 0] = t
            for m in range(n_x):
                rec[n_rec, 1 + m] = x[m]
            for d in range(n_d):
                rec[n_rec, 1 + n_x + d] = cmd[d]
                rec[n_rec, 1 + n_x + n_d + d] = istate[d, B.I_RADIUS]
            n_rec += 1
        if j == n_ticks:
            break
        for _ in range(substeps):
            for stage in range(4):
                state = x if stage == 0 else tmp
                rhs(state, cmd, held, offsets, nodes, si, sf, layers, rolls, webs, di, df,
                    cores, clutch, stages[stage], work)
                if stage < 3:
                    c = h if stage == 2 else 0.5 * h
                    for m in range(n_x):
                        tmp[m] = x[m] + c * stages[stage, m]
            for m in range(n_x):
                x[m] += h / 6.0 * (stages[0, m] + 2.0 * stages[1, m] + 2.0 * stages[2, m]
                                   + stages[3, m])
        for m in range(n_x):
            if not math.isfinite(x[m]):
                return n_rec, B.STATUS_NONFINITE, t + dt
        for r in range(rolls.shape[0]):
            if rolls[r, B.R_DIR] < 0.0 and x[off_r + r] <= rolls[r, B.R_CORE]:
                return n_rec, B.STATUS_UNWIND_EMPTY, t + dt
        for k in range(n_s):
            if x[k] > B.RUNAWAY_STRAIN * sf[k, B.SF_EA]:
                return n_rec, B.STATUS_RUNAWAY, t + dt
        for i in range(nodes.shape[0]):
            r_i = nodes[i, B.N_RADIUS]
            if abs(x[off_w + i]) * r_i > speed_max:
                return n_rec, B.STATUS_RUNAWAY, t + dt
    return n_rec, B.STATUS_OK, math.nan


def compiled_advance(offsets: np.ndarray, si: np.ndarray, layers: np.ndarray,
                     webs: np.ndarray, di: np.ndarray, cells: np.ndarray,
                     cores: np.ndarray) -> Any:
    """``advance`` compiled for one line structure: its integer tables frozen into the loop
    as constants (as the chain's ``sim.core.kernel.compiled_loop``), so the loops over spans,
    nodes and drives have known trip counts and table look-ups fold away. Called with the
    remaining arguments of ``advance`` (the float tables stay run-time arrays)."""
    return _compiled(*((*np.asarray(a).ravel().tolist(), np.asarray(a).shape)
                       for a in (offsets, si, layers, webs, di, cells, cores)))


@functools.cache
def _compiled(*tables: tuple[Any, ...]) -> Any:
    offsets, si, layers, webs, di, cells, cores = (
        np.array(t[:-1], dtype=np.int64).reshape(t[-1]) for t in tables)

    @loop_njit
    def loop(x: np.ndarray, istate: np.ndarray, wound: np.ndarray, done: np.ndarray,
             rec: np.ndarray, stages: np.ndarray, cmd: np.ndarray, work: np.ndarray,
             held: np.ndarray,
             tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
             include_end: bool, speed_max: float, nodes: np.ndarray, sf: np.ndarray,
             rolls: np.ndarray, df: np.ndarray, clutch: np.ndarray, events: np.ndarray,
             dist: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
             prof_off: np.ndarray) -> tuple[int, int, float]:
        return advance(x, istate, wound, done, rec, stages, cmd, work, held, tick0, n_ticks, dt,
                       substeps, record_every, include_end, speed_max, offsets, nodes, si, sf,
                       layers, rolls, webs, di, df, cores, clutch, cells, events, dist, prof_t,
                       prof_v, prof_off)

    return loop


def new_records(n_ticks: int, record_every: int, n_x: int, n_d: int) -> np.ndarray:
    """A record buffer for ``advance``: rows [t, x..., torque commands..., calculated
    radii...]."""
    return np.empty((n_ticks // record_every + 2, 1 + n_x + 2 * n_d))
