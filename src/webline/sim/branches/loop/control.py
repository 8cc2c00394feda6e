"""What a branched line's drives do each controller tick: the inputs held over the period,
the diameter calculator, taper and the sampled cascaded PI (thesis Fig. 4.3, as the chain's
``sim.drives``); tables in ``sim.branches.loop.layout``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import motor, span, taper
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop import transmission as TR
from webline.sim.branches.loop.break_limits import (
    held_open_loop,
    standstill_hold,
    stop_acceleration,
)
from webline.sim.branches.loop.breaks import (
    break_monitor,
    fade_trim,
    held_command,
    stall_command,
)
from webline.sim.branches.loop.dancer import position_error, sensed_tension
from webline.sim.branches.loop.decentral import decentral_command, reference_changes
from webline.sim.branches.loop.draw import draw_factor, start_references
from webline.sim.branches.loop.loadcell import loadcell_reading
from webline.sim.branches.loop.observer import observe
from webline.sim.branches.loop.plant import inertia_seen
from webline.sim.branches.loop.user import user_tick
from webline.sim.branches.loop.winder import compensation, open_loop, zone_reference
from webline.sim.drives.measure import quantized
from webline.sim.elements.sensor_loop import delayed
from webline.sim.elements.signals import gaussian, jit, profile_at, profile_slope_at, sines

_tension: Any = jit(span.tension)
_saturate: Any = jit(motor.saturate)
_taper_factor: Any = jit(taper.taper_factor)


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
        elif kind == B.DIST_DANCER_LOAD:  # a dancer's load: slot index (docs/branching.md)
            held[index] = dist[r, B.DS_B] * profile_at(int(dist[r, B.DS_A]), t, prof_t, prof_v,
                                                        prof_off)


@jit
def wound_ripples(dist: np.ndarray) -> bool:
    """Whether any web's wound-in tension carries a ripple (``held_wound`` then has work)."""
    for r in range(dist.shape[0]):  # noqa: SIM110 (compiled: no generator)
        if int(dist[r, B.DS_KIND]) == B.DIST_WOUND_RIPPLE:
            return True
    return False


@jit
def held_wound(t: float, wound: np.ndarray, held: np.ndarray, dist: np.ndarray) -> None:
    """The wound-in tension of each web with a ripple at ``t`` [s], into ``held``: a roll's
    wound-in tension is a continuous function of time, so each RK4 stage reads it at its own
    time (as the chain's ``wound_in``; held over a tick it lags by half a tick and costs RK4
    its order, docs/errata.md, issue 33). Drags and dancer loads stay held over the tick,
    like the commands."""
    for r in range(dist.shape[0]):
        if int(dist[r, B.DS_KIND]) == B.DIST_WOUND_RIPPLE:
            held[int(dist[r, B.DS_INDEX])] = wound[int(dist[r, B.DS_INDEX])]
    for r in range(dist.shape[0]):
        if int(dist[r, B.DS_KIND]) == B.DIST_WOUND_RIPPLE:
            held[int(dist[r, B.DS_INDEX])] += sines(dist[r:r + 1, B.DS_A:B.DS_C + 1], t)


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
                 prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray,
                 si: np.ndarray, fb: np.ndarray, refs: np.ndarray, sf: np.ndarray,
                 layers: np.ndarray) -> None:
    """One sample ``tick`` of every drive's cascaded PI (thesis Fig. 4.3, as the chain's
    ``sim.drives.controllers.pi_command``): line speed x draw is the speed feedforward, a
    tension PI on the zone's loadcell's reading (or the sum of its loadcells'; calibrated in
    ``sf``, ``loop.loadcell``; its encoder's scale and both signals' delays in ``df``,
    ``sim.branches.sensors``) trims it, a speed PI gives
    the torque, clipped, with conditional integration. ``cells`` rows: (span, profile).
    ``dist``: a drive's speed ripple adds to its speed reference; measurement noise to the
    measured speed (channel 2 d, then rounded to the resolution) and each loadcell's tension
    (channel 2 c + 1), as the chain's ``sim.drives.measure``. A decentralized drive
    (``DI_FAMILY``) takes ``loop.decentral``'s command instead of the PI's (``fb``, ``refs``);
    one with a section observer (``DI_OBS``) feeds back its T̂ (``loop.observer``)."""
    v_line = profile_at(0, t, prof_t, prof_v, prof_off)
    a_line = profile_slope_at(0, t, prof_t, prof_v, prof_off)  # (a centre winder's)
    stopping = 1.0  # the line-speed factor of the ramp to a stop after a web break (W5)
    if offsets[B.O_BREAK]:
        stopping = break_monitor(t, x, istate, di, df, cells, prof_t, prof_v, prof_off,
                                 offsets, nodes)
        a_line = stop_acceleration(a_line, v_line, stopping, df)  # the ramp's (W8)
        v_line *= stopping
    off_r = offsets[B.O_RADIUS]
    sigma_t, sigma_v, resolution, seed, noisy = 0.0, 0.0, 0.0, 0, False
    for r in range(dist.shape[0]):
        if int(dist[r, B.DS_KIND]) == B.DIST_NOISE:
            seed, noisy = int(dist[r, B.DS_INDEX]), True
            sigma_t, sigma_v, resolution = dist[r, B.DS_A], dist[r, B.DS_B], dist[r, B.DS_C]
    decentral = False
    for d in range(di.shape[0]):  # (frozen table: folds away on a line of PI drives)
        decentral = decentral or di[d, B.DI_FAMILY] != B.FAMILY_PI
    if decentral:
        reference_changes(t, istate, di, cells, refs, prof_t, prof_v, prof_off)
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
        v_meas = radius * TR.measured_omega(d, i, x, offsets, di, df)  # (a motor encoder)
        if offsets[B.O_SENSORS]:  # the encoder's scale (spec.sensors)
            v_meas *= df[d, B.D_VSCALE]
        if noisy:
            v_meas = quantized(v_meas + sigma_v * gaussian(seed, tick, 2 * d), resolution)
        if df[d, B.D_DCALC] != B.DCALC_NONE:  # W2: the radius the controllers use
            omega_meas = v_meas / radius
            radius = calculated_radius(d, radius, omega_meas, dt, v_line, x, offsets, nodes,
                                       df)
            istate[d, B.I_RADIUS] = radius
            v_meas = radius * omega_meas
        if offsets[B.O_SENSORS]:  # the encoder's delay (spec.sensors)
            v_meas = delayed(d, tick, v_meas, B.I_VBUF, df[d, B.D_VDELAY], istate)
        e_t = measured = 0.0
        reading, noise, wanted, read = 0.0, 0.0, 0.0, False  # (sensors: the loadcells' sum)
        factor = taper_at(d, radius, nodes[i, B.N_CORE], df, prof_t, prof_v, prof_off)
        if offsets[B.O_RAMP] >= 0:  # the tension ramp at start and stop (docs/winder.md R1)
            factor *= profile_at(offsets[B.O_RAMP], t, prof_t, prof_v, prof_off)
        for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
            if cells.shape[1] > B.CELL_DANCER and cells[c, B.CELL_DANCER] >= 0:
                if cells[c, B.CELL_SENSOR]:  # the dancer as tension sensor (D3)
                    e_t += factor * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off) - (
                        sensed_tension(cells[c, B.CELL_DANCER], t, x, offsets, nodes, dist,
                                       prof_t, prof_v, prof_off))
                    continue
                e_t += position_error(cells[c, B.CELL_DANCER], x, nodes)  # dancer position
                continue
            measured = loadcell_reading(cells[c, 0], _tension(x[cells[c, 0]]), offsets, sf)
            if offsets[B.O_SENSORS]:  # summed, then delayed below (spec.sensors)
                reading += measured
                wanted += factor * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off)
                if noisy:
                    noise += sigma_t * gaussian(seed, tick, 2 * c + 1)
                read = True
                continue
            if noisy:
                measured += sigma_t * gaussian(seed, tick, 2 * c + 1)
            e_t += factor * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off) - measured
        if offsets[B.O_SENSORS] and read:  # the zone's reading, its delay late (noise after)
            measured = delayed(d, tick, reading, B.I_TBUF, df[d, B.D_TDELAY], istate) + noise
            e_t += wanted - measured
        if offsets[B.O_BREAK] and stopping < 1.0:  # tension loops frozen, trims faded
            e_t = 0.0
            if stopping > 0.0 or df[d, B.D_BHOLD] != B.HOLD_STALL:  # (the stall hold's
                fade_trim(d, dt, stopping, istate, df)  # speed limiter integrates there)
        istate[d, B.I_FACTOR] = factor  # (the decentralized drives' references read it)
        if di[d, B.DI_FAMILY] != B.FAMILY_PI:  # state feedback, adaptive, MRAC
            if di[d, B.DI_FAMILY] == B.FAMILY_USER:  # a user's Python controller (loop.user)
                draw = draw_factor(d, t, tick, istate, di, cells, refs, prof_t, prof_v, prof_off)
                cmd[d] = user_tick(d, i, t, tick, dt, v_meas, radius, v_line * draw, a_line,
                                   factor,
                                   stopping, x, istate, offsets, nodes, rolls, di, df, cells,
                                   dist, prof_t, prof_v, prof_off, sigma_t, seed, noisy, sf)
                continue
            if offsets[B.O_BREAK] and stopping == 0.0 and df[d, B.D_BHOLD] != (
                    B.HOLD_ZERO_SPEED) and df[d, B.D_BHOLD] != B.HOLD_STALL:  # "off", "brakes":
                # no torque (W8; in the zero-speed and stall holds: their law at rest)
                cmd[d] = 0.0
                continue
            x_t = -e_t
            if di[d, B.DI_OBS] > 0:  # a section observer's T̂ replaces the loadcell
                estimate = observe(d, i, dt, v_meas / radius, x, istate, offsets, nodes, rolls,
                                   si, sf, layers, di, fb, refs)
                if not (offsets[B.O_BREAK] and stopping < 1.0):  # (frozen with the loops)
                    x_t += estimate - measured
            adapting = not (offsets[B.O_BREAK] and istate[0, B.I_DETECT] >= 0.0)
            cmd[d] = decentral_command(d, di[d, B.DI_FAMILY], i, t, dt, radius, v_meas, x_t,
                                       stopping, adapting, x, istate, offsets, nodes, rolls,
                                       si, df, fb, refs, prof_t, prof_v, prof_off)
            if di[d, B.DI_WINDER] != B.WINDER_NONE:  # a centre winder's compensation (W3),
                # added to the law's torque as the chain's control_tick adds it
                cmd[d] = _saturate(cmd[d] + compensation(
                    d, i, radius, v_meas / radius, a_line, nodes, rolls, df, prof_t, prof_v,
                    prof_off), df[d, B.D_LIMIT])
            continue
        trim = df[d, B.D_SIGMA] * (df[d, B.D_KPT] * e_t + istate[d, B.I_TENSION])
        ripple = 0.0
        for r in range(dist.shape[0]):
            if int(dist[r, B.DS_KIND]) == B.DIST_SPEED_RIPPLE and int(dist[r, B.DS_INDEX]) == d:
                ripple += sines(dist[r:r + 1, B.DS_A:B.DS_C + 1], t)
        draw = draw_factor(d, t, tick, istate, di, cells, refs, prof_t, prof_v, prof_off)
        e_v = v_line * df[d, B.D_FF] * draw + ripple + trim - v_meas
        gain = 1.0
        if df[d, B.D_ADAPTIVE] > 0.0:  # speed gains follow the roll's inertia
            # (at the radius it knows: its calculator's, as the chain's controller)
            inertia = inertia_seen(i, j if df[d, B.D_DCALC] != B.DCALC_NONE else -1, radius,
                                   x, offsets, nodes, rolls) + TR.reflected_motor(d, di, df)
            gain = inertia / (
                df[d, B.D_RATIO] * radius) / df[d, B.D_GAINNORM]
        if offsets[B.O_BREAK] and stopping == 0.0:  # stopped: the drives hold (W8)
            if df[d, B.D_BHOLD] == B.HOLD_STALL and df[d, B.D_DIR] != 0.0:  # a roll
                cmd[d] = stall_command(d, dt, v_meas, gain, radius, zone_reference(
                    d, t, factor, di, cells, prof_t, prof_v, prof_off), istate, df)
            elif standstill_hold(d, di, df):  # an open-loop roll: its standstill torque
                cmd[d] = held_open_loop(d, dt, v_meas, gain, radius, zone_reference(
                    d, t, factor, di, cells, prof_t, prof_v, prof_off), istate, df)
            else:
                cmd[d] = held_command(d, dt, v_meas, gain, istate, df)
            continue
        comp = 0.0
        if di[d, B.DI_WINDER] != B.WINDER_NONE:  # a centre winder (docs/winder.md W3, W4)
            comp = compensation(d, i, radius, v_meas / radius, a_line, nodes, rolls, df,
                                prof_t, prof_v, prof_off)
            if di[d, B.DI_WINDER] == B.WINDER_OPEN:
                cmd[d] = open_loop(d, dt, radius, zone_reference(d, t, factor, di, cells, prof_t,
                                                                 prof_v, prof_off),
                                   comp, v_meas, v_line, gain, istate, df)
                continue
        raw = df[d, B.D_KPS] * gain * e_v + istate[d, B.I_SPEED]
        u = _saturate(raw, df[d, B.D_LIMIT])
        saturated = raw != u
        if not (saturated and e_v * raw > 0.0):
            istate[d, B.I_SPEED] += df[d, B.D_KIS] * gain * e_v * dt
        if not (saturated and df[d, B.D_SIGMA] * e_t * raw > 0.0):
            istate[d, B.I_TENSION] += df[d, B.D_KIT] * e_t * dt
        cmd[d] = u if comp == 0.0 else _saturate(u + comp, df[d, B.D_LIMIT])
    start_references(t, tick, istate, di, cells, refs, prof_t, prof_v, prof_off)
