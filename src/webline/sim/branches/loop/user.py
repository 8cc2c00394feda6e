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

Users' compiled laws (``sim.core.laws``) run inside the loop: ``law_step`` (compiled into
the loop with the laws, ``kernel.compiled_advance``) gathers the readings ``user_command``
stored, calls the laws and writes their commands into ``I_UCMD``; ``law_commands`` then issues
them as ``user_command`` issues a Python controller's (the compensation it kept in
``I_UCOMP``; a holding drive keeps its hold).
"""

from __future__ import annotations

import functools
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
from webline.sim.core.laws import LawKey, buffer_layout, chained_laws, law_njit
from webline.sim.drives.user_loop import N_MEASURED, N_REFERENCES
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
    istate[d, B.I_UCOMP] = comp
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
        istate[d, B.I_UCOMP] = math.nan  # (a compiled law's command does not replace it)
        return held_command(d, dt, v_meas, gain, istate, df)
    comp = 0.0
    if di[d, B.DI_WINDER] != B.WINDER_NONE:  # a centre winder (docs/winder.md W3)
        comp = compensation(d, i, radius, v_meas / radius, a_line, nodes, rolls, df, prof_t,
                            prof_v, prof_off)
    return user_command(d, t, tick, v_meas, radius, inertia, v_line * df[d, B.D_FF] + ripple,
                        factor, offsets[B.O_BREAK] != 0 and stopping < 1.0, comp, x, istate,
                        offsets, nodes, di, df, cells, dist, prof_t, prof_v, prof_off, sigma_t,
                        seed, noisy, sf)


@jit
def law_commands(cmd: np.ndarray, istate: np.ndarray, di: np.ndarray, df: np.ndarray) -> int:
    """Issue the commands compiled laws wrote into the user drives' ``I_UCMD`` at this tick
    (``kernel.advance`` calls the laws after ``control_tick`` has measured every drive):
    saturated, the tick's compensation added (``I_UCOMP``) as ``user_command`` adds it; a
    drive that holds (W8, ``I_UCOMP`` NaN) keeps its hold. Returns the first user drive whose
    command is not finite (-1: none): the loop stops there, as the chain's."""
    for d in range(di.shape[0]):
        if di[d, B.DI_FAMILY] != B.FAMILY_USER:
            continue
        if not math.isfinite(istate[d, B.I_UCMD]):
            return d
        comp = istate[d, B.I_UCOMP]
        if not math.isnan(comp):
            u = _saturate(istate[d, B.I_UCMD], df[d, B.D_LIMIT])
            cmd[d] = u if comp == 0.0 else _saturate(u + comp, df[d, B.D_LIMIT])
    return -1


@functools.cache
def law_step(n_drives: int, users: tuple[int, ...], laws: LawKey) -> Any:
    """The compiled laws' step of a run (``kernel.advance`` calls it each tick, after
    ``control_tick``): ``step(t, istate)`` gathers user drives ``users``' readings (stored by
    ``user_command`` in their memory rows) into the laws' arrays, calls ``laws``
    (``sim.core.laws.chained_laws``) and writes their commands into ``I_UCMD`` (NaN for every
    drive after a law raised). The laws' buffer (``sim.core.laws.LawBuffer``) lies in the
    rows of ``istate`` after its ``n_drives`` drives' (the run's controller memory)."""
    start = n_drives * B.I_COLS
    layout = buffer_layout(len(users), sum(p for _, _, p, _ in laws),
                           sum(s for _, _, _, s in laws))
    (m0, m1), (r0, r1), (c0, c1) = layout["meas"], layout["refs"], layout["commands"]
    (q0, q1), (s0, s1), (f0, f1) = layout["params"], layout["state"], layout["raised"]
    drive_of = np.array(users, dtype=np.int64)
    call = chained_laws(laws)

    @law_njit
    def step(t: float, istate: np.ndarray) -> None:
        flat = istate.reshape(istate.size)
        buf = flat[start:]
        meas, refs, commands = buf[m0:m1], buf[r0:r1], buf[c0:c1]
        for u in range(drive_of.shape[0]):
            for q in range(N_MEASURED):
                meas[N_MEASURED * u + q] = istate[drive_of[u], B.I_USPEED + q]
            for q in range(N_REFERENCES):
                refs[N_REFERENCES * u + q] = istate[drive_of[u], B.I_UVREF + q]
        call(t, meas, refs, buf[q0:q1], buf[s0:s1], commands, buf[f0:f1])
        for u in range(drive_of.shape[0]):
            istate[drive_of[u], B.I_UCMD] = commands[u] if buf[f0] == 0.0 else math.nan

    return step
