"""The compiled side of a user's Python controller on a branched line (docs/controllers.md,
"On a branched line"; the Python side is ``sim.branches.user``).

A drive of family ``FAMILY_USER`` is measured at its tick exactly as the cascaded PI measures
it (``loop.control``: encoder, noise and resolution, calculated radius, loadcells or dancer),
then ``user_tick`` (called from the decentralized families' branch of ``control_tick``, so
that a line of built-in drives compiles to the very same code) adds what a PI drive's tick
adds and ``user_command`` stores those readings in the drive's memory row (``layout`` I_U*) and
issues the command the Python side wrote there (``I_UCMD``), saturated, plus a centre
winder's compensation as on a built-in command. A line without user drives never reaches it:
``DI_FAMILY`` is frozen into the compiled loop.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.physics import motor, span
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop import transmission as TR
from webline.sim.branches.loop.breaks import held_command
from webline.sim.branches.loop.dancer import position_error, sensed_tension
from webline.sim.branches.loop.loadcell import loadcell_reading
from webline.sim.branches.loop.plant import inertia_seen
from webline.sim.branches.loop.winder import compensation
from webline.sim.elements.sensor_loop import delayed
from webline.sim.elements.signals import gaussian, jit, profile_at, sines

_tension: Any = jit(span.tension)
_saturate: Any = jit(motor.saturate)


@jit
def user_command(d: int, t: float, tick: int, v_meas: float, radius: float, inertia: float,
                 speed_ref: float, factor: float, frozen: bool, comp: float, x: np.ndarray,
                 istate: np.ndarray, offsets: np.ndarray, nodes: np.ndarray, di: np.ndarray,
                 df: np.ndarray, cells: np.ndarray, dist: np.ndarray, prof_t: np.ndarray,
                 prof_v: np.ndarray, prof_off: np.ndarray, sigma_t: float, seed: int,
                 noisy: bool, sf: np.ndarray) -> float:
    """Store user drive ``d``'s readings at tick ``tick`` (time ``t`` [s]) and return its
    torque command [N·m]: the held ``I_UCMD`` saturated at the torque limit, plus ``comp``
    (a centre winder's compensation, saturated again). Its zone's tension is the sum of its
    loadcells' readings (calibrated in ``sf``, ``loop.loadcell``, delayed as the built-in
    loop delays them; a shaft of lanes: one per lane), with the same noise draws as the
    built-in
    loop; its reference the sum of theirs times the taper ``factor``; a dancer as tension
    sensor reads the tension it senses, one in position control reference - (y - y_set), so
    that reference - reading is the position error [m] the built-in loop uses; ``frozen``
    (after a detected break, W5): the tension reads its reference."""
    tension, reference = 0.0, 0.0
    reading, noise, read = 0.0, 0.0, False  # (sensors: the loadcells' sum)
    for c in range(di[d, B.DI_CELLS], di[d, B.DI_CELLS] + di[d, B.DI_NCELLS]):
        ref = factor * profile_at(cells[c, 1], t, prof_t, prof_v, prof_off)
        reference += ref
        if cells.shape[1] > B.CELL_DANCER and cells[c, B.CELL_DANCER] >= 0:
            if cells[c, B.CELL_SENSOR]:  # the dancer as tension sensor (D3)
                tension += sensed_tension(cells[c, B.CELL_DANCER], t, x, offsets, nodes, dist,
                                          prof_t, prof_v, prof_off)
                continue
            tension += ref - position_error(cells[c, B.CELL_DANCER], x, nodes)
            continue
        measured = loadcell_reading(cells[c, 0], _tension(x[cells[c, 0]]), offsets, sf)
        if offsets[B.O_SENSORS]:  # summed, then delayed below (spec.sensors)
            reading += measured
            if noisy:
                noise += sigma_t * gaussian(seed, tick, 2 * c + 1)
            read = True
            continue
        if noisy:
            measured += sigma_t * gaussian(seed, tick, 2 * c + 1)
        tension += measured
    if offsets[B.O_SENSORS] and read:  # the zone's reading its delay late, as the PI's
        tension += delayed(d, tick, reading, B.I_TBUF, df[d, B.D_TDELAY], istate) + noise
    if di[d, B.DI_NCELLS] == 0:
        tension, reference = math.nan, math.nan
    elif frozen:
        tension = reference
    istate[d, B.I_USPEED] = v_meas
    istate[d, B.I_UTENSION] = tension
    istate[d, B.I_URADIUS] = radius
    istate[d, B.I_UINERTIA] = inertia
    istate[d, B.I_UVREF] = speed_ref
    istate[d, B.I_UTREF] = reference
    u = _saturate(istate[d, B.I_UCMD], df[d, B.D_LIMIT])
    return u if comp == 0.0 else _saturate(u + comp, df[d, B.D_LIMIT])


@jit
def user_tick(d: int, i: int, t: float, tick: int, dt: float, v_meas: float, radius: float,
              v_line: float, a_line: float, factor: float, stopping: float, x: np.ndarray,
              istate: np.ndarray, offsets: np.ndarray, nodes: np.ndarray, rolls: np.ndarray,
              di: np.ndarray, df: np.ndarray, cells: np.ndarray, dist: np.ndarray,
              prof_t: np.ndarray, prof_v: np.ndarray, prof_off: np.ndarray, sigma_t: float,
              seed: int, noisy: bool, sf: np.ndarray) -> float:
    """User drive ``d``'s (node ``i``) command [N·m] at its tick, as ``control_tick`` issues a
    cascaded PI's: its speed reference line speed ``v_line`` (times the change of its draw,
    ``loop.draw``) x its draw at the start + its speed ripple
    [m/s]; once the line has stopped after a break, the hold (W8) instead; a centre winder's
    compensation at the line's acceleration ``a_line`` [m/s²] added (``user_command``)."""
    ripple = 0.0
    for r in range(dist.shape[0]):
        if int(dist[r, B.DS_KIND]) == B.DIST_SPEED_RIPPLE and int(dist[r, B.DS_INDEX]) == d:
            ripple += sines(dist[r:r + 1, B.DS_A:B.DS_C + 1], t)
    own = di[d, B.DI_ROLL] if df[d, B.D_DCALC] != B.DCALC_NONE else -1  # (the radius the
    inertia = inertia_seen(i, own, radius, x, offsets, nodes, rolls) + (  # drive knows)
        TR.reflected_motor(d, di, df))
    if offsets[B.O_BREAK] and stopping == 0.0:  # stopped: the drive holds (W8), as a PI's
        gain = 1.0
        if df[d, B.D_ADAPTIVE] > 0.0:
            gain = inertia / (df[d, B.D_RATIO] * radius) / df[d, B.D_GAINNORM]
        return held_command(d, dt, v_meas, gain, istate, df)
    comp = 0.0
    if di[d, B.DI_WINDER] != B.WINDER_NONE:  # a centre winder (docs/winder.md W3)
        comp = compensation(d, i, radius, v_meas / radius, a_line, nodes, rolls, df, prof_t,
                            prof_v, prof_off)
    return user_command(d, t, tick, v_meas, radius, inertia, v_line * df[d, B.D_FF] + ripple,
                        factor, offsets[B.O_BREAK] != 0 and stopping < 1.0, comp, x, istate,
                        offsets, nodes, di, df, cells, dist, prof_t, prof_v, prof_off, sigma_t,
                        seed, noisy, sf)
