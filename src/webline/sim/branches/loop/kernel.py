"""The compiled loop of a branched line: events, sampled controller ticks
(``loop.control``) and RK4 sub-steps of the plant (``loop.plant``) between them, as the chain
kernel (``sim.core.kernel``) does; compiled once per line structure.
"""

from __future__ import annotations

import functools
import math
from typing import Any

import numba as nb
import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.breaks import cut
from webline.sim.branches.loop.control import control_tick, held_inputs, held_wound, wound_ripples
from webline.sim.branches.loop.dancer_taper import taper_loads
from webline.sim.branches.loop.laminate import beyond_strength, cut_layers
from webline.sim.branches.loop.plant import rhs
from webline.sim.branches.loop.traction import update_slip
from webline.sim.branches.loop.user import law_commands, law_step
from webline.sim.branches.loop.web_law import felt_start_jit
from webline.sim.branches.loop.winder import splices
from webline.sim.core.laws import LawKey
from webline.sim.drives.user_loop import STATUS_USER_NONFINITE
from webline.sim.elements.signals import _NO_NRT, FAST, jit, loop_njit


@jit
def roll_change(t: float, x: np.ndarray, wound: np.ndarray, done: np.ndarray,
                offsets: np.ndarray, rolls: np.ndarray, events: np.ndarray) -> None:
    """A new roll takes over at its event's time: new radius and wound-in tension, brought
    to the old roll's surface speed first (a flying splice)."""
    for e in range(events.shape[0]):
        if done[e] == 0.0 and t >= events[e, B.E_TIME] and (
                events[e, B.E_KIND] == B.EVENT_ROLL_CHANGE):
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
            prof_v: np.ndarray, prof_off: np.ndarray, lawi: np.ndarray, lawf: np.ndarray,
            laws: np.ndarray, kv: np.ndarray, fb: np.ndarray,
            refs: np.ndarray, law: Any) -> tuple[int, int, float]:
    """Advance ``n_ticks`` controller periods from tick ``tick0``, recording ``new_records``'
    rows every ``record_every`` ticks and, with ``include_end``, the state after the last (a
    chunked run leaves that tick to the next chunk); returns (records, status, time of
    failure). Stops at a non-finite state, an empty unwind, a runaway or a span beyond its
    web's strength (``layout``). With web laws or Kelvin-Voigt spans the loadcells read the
    tension the rollers feel (``loop.web_law``).
    ``held``: scratch for the inputs held over a period (``held_inputs``); ``fb``, ``refs``:
    the decentralized drives' tables (``loop.decentral``). ``law``: the users' compiled laws
    (``loop.user.law_step``, called each tick after every drive is measured; their buffer in
    ``istate``'s rows after the drives'), or None (folded away); a law's non-finite command
    stops the run before its tick is recorded, status ``user_loop.STATUS_USER_NONFINITE``."""
    n_x = x.shape[0]
    n_d = di.shape[0]
    n_s = si.shape[0]
    tmp = stages[4]
    h = dt / substeps
    n_rec = 0
    off_w, off_r = offsets[B.O_OMEGA], offsets[B.O_RADIUS]
    rippled = wound_ripples(dist)  # wound-in ripples: evaluated at each RK4 stage's time
    for j in range(n_ticks + 1):
        t = (tick0 + j) * dt
        if j == n_ticks and not include_end:  # the next chunk starts with this tick
            break
        roll_change(t, x, wound, done, offsets, rolls, events)
        splices(t, dt, x, istate, done, offsets, nodes, si, sf, rolls, webs, df, events)
        if offsets[B.O_BREAK]:  # a web break: its spans carry nothing from their time on
            cut(t, x, wound, sf, webs.shape[0], nodes.shape[0], istate, di, df)
            if offsets[B.O_LAYER] < offsets[B.O_LAYER_END]:  # (and its layers' offsets)
                cut_layers(x, wound, webs.shape[0] + nodes.shape[0], lawi)
        held_inputs(t, wound, held, webs.shape[0], dist, prof_t, prof_v, prof_off)
        measured = x
        if lawi.shape[0] > 0 or kv.shape[0] > 0:  # the loadcells feel F(s) + τ ds/dt
            rhs(x, cmd, held, offsets, nodes, si, sf, layers, rolls, webs, di, df, cores,
                clutch, lawi, lawf, laws, kv, stages[0], work)
            measured = tmp
            start = felt_start_jit(n_s, nodes.shape[0], lawi.shape[0] > 0, kv.shape[0] > 0)
            for m in range(n_x):
                measured[m] = work[start + m] if m < n_s else x[m]
        control_tick(t, tick0 + j, dt, measured, istate, cmd, offsets, nodes, rolls, di, df,
                     cells, dist, prof_t, prof_v, prof_off, si, fb, refs, sf, layers)
        if law is not None:  # users' compiled laws: their commands replace the held ones
            law(t, istate)
            if law_commands(cmd, istate, di, df) >= 0:
                return n_rec, STATUS_USER_NONFINITE, t
        if offsets[B.O_DANCER] < offsets[B.O_DANCER_END]:  # taper through a dancer (frozen: folds)
            taper_loads(held, istate, x, offsets, nodes, di, df, cells, prof_t, prof_v,
                        prof_off)
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
        if offsets[B.O_SLIP]:  # stick or slip for this tick, held over its stages
            update_slip(t, dt, measured, offsets, nodes)
        for s in range(substeps):
            for stage in range(4):
                state = x if stage == 0 else tmp
                if rippled:  # (the stage's time: t_s, t_s + h/2 twice, t_s + h)
                    at = 0.0 if stage == 0 else 1.0 if stage == 3 else 0.5
                    held_wound(t + (s + at) * h, wound, held, dist)
                rhs(state, cmd, held, offsets, nodes, si, sf, layers, rolls, webs, di, df,
                    cores, clutch, lawi, lawf, laws, kv, stages[stage], work)
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
            if x[k] > sf[k, B.SF_STRENGTH]:  # (inf where the web gives no strength)
                return n_rec, B.STATUS_STRENGTH, t + dt
        if offsets[B.O_LAYER] < offsets[B.O_LAYER_END] and beyond_strength(x, lawi, lawf):
            return n_rec, B.STATUS_STRENGTH, t + dt  # a bonded layer at its own strength
        for i in range(nodes.shape[0]):
            r_i = nodes[i, B.N_RADIUS]
            if nodes[i, B.N_ROLLS] == 0.0 and abs(x[off_w + i]) * r_i > speed_max:
                return n_rec, B.STATUS_RUNAWAY, t + dt
        for r in range(rolls.shape[0]):  # a roll's surface at its radius now (a new core)
            if rolls[r, B.R_CLUTCH] == 0.0 and (
                    abs(x[off_w + int(rolls[r, B.R_NODE])]) * x[off_r + r] > speed_max):
                return n_rec, B.STATUS_RUNAWAY, t + dt
    return n_rec, B.STATUS_OK, math.nan


def compiled_advance(offsets: np.ndarray, si: np.ndarray, layers: np.ndarray,
                     webs: np.ndarray, di: np.ndarray, cells: np.ndarray,
                     cores: np.ndarray, lawi: np.ndarray, kv: np.ndarray,
                     law: tuple[tuple[int, ...], LawKey] | None = None) -> Any:
    """``advance`` compiled for one line structure: its integer tables frozen into the loop
    as constants (as the chain's ``sim.core.kernel.compiled_loop``), so the loops over spans,
    nodes and drives have known trip counts and table look-ups fold away. Called with the
    remaining arguments of ``advance`` (the float tables stay run-time arrays), the same
    for every line. ``law``: the users' compiled laws (their drives in group order and
    ``sim.core.laws.LawBuffer.key``), compiled into the loop (``loop.user.law_step``): part
    of the cache key, compiled once per process (not disk-cached: a law has no stable key);
    None: the built-in loop, disk-cached."""
    return _compiled(*structure_key(offsets, si, layers, webs, di, cells, cores, lawi, kv),
                     law=law)


def structure_key(*tables: np.ndarray) -> tuple[tuple[Any, ...], ...]:
    """The integer tables of a structure as a hashable key: each table's values, then its
    shape (``structure_tables`` reads them back)."""
    return tuple((*np.asarray(a).ravel().tolist(), np.asarray(a).shape) for a in tables)


def structure_tables(key: tuple[tuple[Any, ...], ...]) -> tuple[np.ndarray, ...]:
    """The integer tables of ``structure_key``'s key, as int64 arrays."""
    return tuple(np.array(t[:-1], dtype=np.int64).reshape(t[-1]) for t in key)


@functools.cache
def _compiled(*tables: tuple[Any, ...],
              law: tuple[tuple[int, ...], LawKey] | None = None) -> Any:
    offsets, si, layers, webs, di, cells, cores, lawi, kv = structure_tables(tables)
    if law is not None:
        return _with_laws(offsets, si, layers, webs, di, cells, cores, lawi, kv,
                          law_step(di.shape[0], *law))

    @loop_njit
    def loop(x: np.ndarray, istate: np.ndarray, wound: np.ndarray, done: np.ndarray,
             rec: np.ndarray, stages: np.ndarray, cmd: np.ndarray, work: np.ndarray,
             held: np.ndarray,
             tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
             include_end: bool, speed_max: float, nodes: np.ndarray, sf: np.ndarray,
             rolls: np.ndarray, df: np.ndarray, clutch: np.ndarray, events: np.ndarray,
             dist: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
             prof_off: np.ndarray, lawf: np.ndarray, laws: np.ndarray, fb: np.ndarray,
             refs: np.ndarray) -> tuple[int, int, float]:
        return advance(x, istate, wound, done, rec, stages, cmd, work, held, tick0, n_ticks, dt,
                       substeps, record_every, include_end, speed_max, offsets, nodes, si, sf,
                       layers, rolls, webs, di, df, cores, clutch, cells, events, dist, prof_t,
                       prof_v, prof_off, lawi, lawf, laws, kv, fb, refs, None)

    return loop


#: the loop with users' laws and its ``advance``: as ``loop_njit`` and ``advance``, without
#: numba's disk cache (a cached function given the laws would pickle a reference to the
#: user's module into its cache index, which another process cannot load)
_law_loop_njit = nb.njit(fastmath=FAST, error_model="numpy", **_NO_NRT)
_advance_with_laws: Any = nb.njit(fastmath=FAST, error_model="numpy", forceinline=True,
                                  **_NO_NRT)(advance.py_func)


def _with_laws(offsets: np.ndarray, si: np.ndarray, layers: np.ndarray, webs: np.ndarray,
               di: np.ndarray, cells: np.ndarray, cores: np.ndarray, lawi: np.ndarray,
               kv: np.ndarray, step: Any) -> Any:
    """``_compiled``'s loop with the laws' ``step`` (``loop.user.law_step``) in it; the same
    call."""

    @_law_loop_njit
    def loop(x: np.ndarray, istate: np.ndarray, wound: np.ndarray, done: np.ndarray,
             rec: np.ndarray, stages: np.ndarray, cmd: np.ndarray, work: np.ndarray,
             held: np.ndarray,
             tick0: int, n_ticks: int, dt: float, substeps: int, record_every: int,
             include_end: bool, speed_max: float, nodes: np.ndarray, sf: np.ndarray,
             rolls: np.ndarray, df: np.ndarray, clutch: np.ndarray, events: np.ndarray,
             dist: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
             prof_off: np.ndarray, lawf: np.ndarray, laws: np.ndarray, fb: np.ndarray,
             refs: np.ndarray) -> tuple[int, int, float]:
        return _advance_with_laws(
            x, istate, wound, done, rec, stages, cmd, work, held, tick0, n_ticks, dt, substeps,
            record_every, include_end, speed_max, offsets, nodes, si, sf, layers, rolls, webs,
            di, df, cores, clutch, cells, events, dist, prof_t, prof_v, prof_off, lawi, lawf,
            laws, kv, fb, refs, step)

    return loop


def new_records(n_ticks: int, record_every: int, n_x: int, n_d: int) -> np.ndarray:
    """A record buffer for ``advance``: rows [t, x..., torque commands..., calculated
    radii...]."""
    return np.empty((n_ticks // record_every + 2, 1 + n_x + 2 * n_d))
