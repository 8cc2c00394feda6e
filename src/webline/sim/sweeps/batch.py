"""Batched simulation: many cases of one line structure in one compiled call per thread.

The cases' plans are built in Python once each (their operating points, designs and RK4
sub-steps differ); their parameter tables are stacked along a leading ``case`` axis and one
compiled function (``batch_loop``, compiled once per line structure, releasing the GIL) runs
a range of cases without returning to Python: each case runs ``kernel.advance`` chunk by
chunk into a small record buffer, and every chunk's records are reduced at once into the
case's metric accumulators, so memory stays O(cases x metrics). Threads run disjoint case
ranges, so a batch uses all cores.

The reductions follow the definitions of a single run (``webline.sim.results.metrics``): the records
are those ``simulate`` stores by default, events are intervals of records
(``webline.sim.results.events``), the tension reference is the loadcell profile at each record (a
taper rewind's tapered at the radius its controller uses, and every zone's scaled by a
start/stop tension ramp, as ``Result.tension_ref``), and
the tension of a Kelvin-Voigt span is what its rollers feel, s + τ ds/dt, from the kernel's
right-hand side at each record (``webline.sim.core.viscoelastic``).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numba as nb
import numpy as np

from webline.errors import LineFileError
from webline.sim.core.kernel import advance
from webline.sim.core.plan import Plan
from webline.sim.core.viscoelastic import felt_records
from webline.sim.drives.controllers import taper_at
from webline.sim.elements import layout as L
from webline.sim.elements.signals import _NO_NRT, FAST, jit, profile_at
from webline.sim.elements.web_state import compiled_slip_column, record_width
from webline.sim.results.metrics import SETTLE_BAND
from webline.sim.results.winder_findings import rest_limits
from webline.sim.results.winder_states import window_end
from webline.sim.sweeps import batch_states as S
from webline.sim.sweeps.batch_layout import (
    A_LASTOUT,
    A_PEAK,
    A_SETTLE,
    A_SUMSQ,
    A_TMAX,
    A_TMIN,
    EV_BLOCKS,
    SPAN_BLOCKS,
    Layout,
)
from webline.sim.sweeps.blocks import over_ranges

#: Ticks per chunk of a case: the record buffer holds this many rows (x ~30 columns), small
#: enough to stay in cache, large enough that a chunk's call overhead (ns) is negligible.
CHUNK_TICKS = 512

batch_njit = nb.njit(cache=True, fastmath=FAST, error_model="numpy", nogil=True, **_NO_NRT)

# conditions of an event element on one record column (``_intervals``)
BELOW, ABOVE, BEYOND, WITHIN, NONZERO = range(5)


@jit
def _intervals(acc: np.ndarray, base: int, n_ev: int, e: int, rec: np.ndarray, src: np.ndarray,
               n_rec: int, col: int, kind: int, lo: float, hi: float) -> None:
    """Advance the interval bookkeeping of event element ``e`` over ``n_rec`` records (times
    in ``rec``): an interval starts at the first record where the condition ``kind`` on
    column ``col`` of ``src`` (the records, or the felt tensions) holds
    (``BELOW``: v < lo, ``ABOVE``: v > lo, ``BEYOND``: |v| >= lo, ``WITHIN``: lo <= v <= hi,
    ``NONZERO``: v != 0) and ends at the first where it does not
    (``webline.sim.results.events.intervals``). Column by column, so the running values stay in
    registers (``kind`` is a constant at each call site: the branches fold away)."""
    total, first, start = acc[base + e], acc[base + n_ev + e], acc[base + 2 * n_ev + e]
    count, longest = acc[base + 3 * n_ev + e], acc[base + 4 * n_ev + e]
    for r in range(n_rec):
        v = src[r, col]
        if kind == BELOW:
            cond = v < lo
        elif kind == ABOVE:
            cond = v > lo
        elif kind == BEYOND:
            cond = abs(v) >= lo
        elif kind == WITHIN:
            cond = lo <= v <= hi
        else:
            cond = v != 0.0
        if cond:
            if math.isnan(start):
                start = rec[r, 0]
                count += 1.0
                if math.isnan(first):
                    first = start
        elif not math.isnan(start):
            length = rec[r, 0] - start
            total += length
            longest = max(longest, length)
            start = math.nan
    acc[base + e], acc[base + n_ev + e], acc[base + 2 * n_ev + e] = total, first, start
    acc[base + 3 * n_ev + e], acc[base + 4 * n_ev + e] = count, longest


@jit
def _tension(rec: np.ndarray, felt: np.ndarray, kv: bool, r: int, k: int) -> float:
    """Tension [N] of span ``k`` at record ``r``: its stretch while taut, or for a line with
    Kelvin-Voigt spans what the rollers feel (``felt``, ``viscoelastic.felt_records``)."""
    return felt[r, k] if kv else max(rec[r, 1 + k], 0.0)


@jit
def _tension_error(acc: np.ndarray, n_s: int, k: int, p: int, rec: np.ndarray,
                   felt: np.ndarray, kv: bool, n_rec: int, prof_t: np.ndarray,
                   prof_v: np.ndarray, prof_off: np.ndarray, taper_drive: int,
                   radius_column: int, drives: np.ndarray, ramp_profile: int) -> None:
    """Fold span ``k``'s error from its reference profile ``p`` over ``n_rec`` records into
    its sum of squares, peak and settling columns; with ``taper_drive`` >= 0 the reference
    is tapered at the radius the rewind's controller uses (record column
    ``radius_column``), as ``Result.tension_ref`` tapers it (docs/winder.md W1); with
    ``ramp_profile`` > 0 it is scaled by that profile, the start/stop tension ramp (R1)."""
    sumsq, peak = acc[A_SUMSQ * n_s + k], acc[A_PEAK * n_s + k]
    settle, lastout = acc[A_SETTLE * n_s + k], acc[A_LASTOUT * n_s + k]
    for r in range(n_rec):
        t = rec[r, 0]
        ref = profile_at(p, t, prof_t, prof_v, prof_off)
        if taper_drive >= 0:
            ref *= taper_at(taper_drive, rec[r, radius_column], drives, prof_t, prof_v,
                            prof_off)
        if ramp_profile > 0:
            ref *= profile_at(ramp_profile, t, prof_t, prof_v, prof_off)
        err = _tension(rec, felt, kv, r, k) - ref
        sumsq += err * err
        peak = max(peak, abs(err))
        if abs(err) > SETTLE_BAND * abs(ref):
            settle, lastout = t, 1.0
        else:
            lastout = 0.0
    acc[A_SUMSQ * n_s + k], acc[A_PEAK * n_s + k] = sumsq, peak
    acc[A_SETTLE * n_s + k], acc[A_LASTOUT * n_s + k] = settle, lastout


@jit
def _reduce(rec: np.ndarray, felt: np.ndarray, kv: bool, n_rec: int, acc: np.ndarray,
            trace: np.ndarray, trace_every: int, dt: float, n_x: int, n_s: int, n_d: int,
            n_n: int, nodes: np.ndarray, drives: np.ndarray, prof_t: np.ndarray,
            prof_v: np.ndarray, prof_off: np.ndarray, span_prof: np.ndarray,
            tension_limit: float, ramp_profile: int) -> None:
    """Fold ``n_rec`` record rows (``kernel.run``'s layout) into the accumulators ``acc``,
    one column at a time; with ``kv`` the tensions are the felt ones in ``felt``. Events
    that cannot occur (no tension limit, no backlash gap, no traction) are skipped: their
    condition never holds, so their columns stay as they are."""
    base = SPAN_BLOCKS * n_s
    n_ev = 2 * n_s + 2 * n_d + n_n
    col_cmd = 1 + n_x
    col_slip = compiled_slip_column(n_x, n_d)
    # the rewind's zone loadcell under a taper: its reference follows the rewind radius
    taper_drive, taper_span = -1, -1
    if n_d > 0 and drives[n_d - 1, L.D_NODE] == n_n - 1 and drives[n_d - 1, L.D_TAPER] > 0.0:
        taper_drive, taper_span = n_d - 1, int(drives[n_d - 1, L.D_LOADCELL])
    # the radius the rewind's controller uses (calculated or true): the record's column of
    # controller radii (``web_state.slip_column``: time, states, six columns per drive)
    radius_column = 1 + n_x + 5 * n_d + taper_drive
    for k in range(n_s):
        tmin, tmax = acc[A_TMIN * n_s + k], acc[A_TMAX * n_s + k]
        for r in range(n_rec):
            tension = _tension(rec, felt, kv, r, k)
            tmin, tmax = min(tmin, tension), max(tmax, tension)
        acc[A_TMIN * n_s + k], acc[A_TMAX * n_s + k] = tmin, tmax
        if span_prof[k] >= 0:
            _tension_error(acc, n_s, k, span_prof[k], rec, felt, kv, n_rec, prof_t, prof_v,
                           prof_off, taper_drive if k == taper_span else -1, radius_column,
                           drives, ramp_profile)
        _intervals(acc, base, n_ev, k, rec, rec, n_rec, 1 + k, BELOW, 0.0, 0.0)  # stretch < 0
        if tension_limit < math.inf:  # (a limit >= 0: the stretch above it is the tension)
            if kv:
                _intervals(acc, base, n_ev, n_s + k, rec, felt, n_rec, k, ABOVE, tension_limit,
                           0.0)
            else:
                _intervals(acc, base, n_ev, n_s + k, rec, rec, n_rec, 1 + k, ABOVE,
                           tension_limit, 0.0)
    for d in range(n_d):
        limit = drives[d, L.D_LIMIT] * (1.0 - 1e-6)  # events.TORQUE_LIMIT_RTOL
        _intervals(acc, base, n_ev, 2 * n_s + d, rec, rec, n_rec, col_cmd + d, BEYOND, limit,
                   0.0)
        state = int(drives[d, L.D_TSTATE])
        gap_neg, gap_pos = drives[d, L.D_GAPNEG], drives[d, L.D_GAPPOS]
        if state >= 0 and gap_neg + gap_pos > 0:
            _intervals(acc, base, n_ev, 2 * n_s + n_d + d, rec, rec, n_rec, 1 + state + 1,
                       WITHIN, -gap_neg, gap_pos)
    for i in range(n_n):
        if nodes[i, L.N_TRACTION] != 0.0:
            _intervals(acc, base, n_ev, 2 * n_s + 2 * n_d + i, rec, rec, n_rec, col_slip + i,
                       NONZERO, 0.0, 0.0)
    if trace.shape[0] > 0:
        for r in range(n_rec):
            tick = round(rec[r, 0] / dt)
            if tick % trace_every == 0 and tick // trace_every < trace.shape[0]:
                for k in range(n_s):
                    trace[tick // trace_every, k] = _tension(rec, felt, kv, r, k)
    acc[base + EV_BLOCKS * n_ev + 1] += n_rec


@jit
def _finish(acc: np.ndarray, n_s: int, n_d: int, n_n: int, t_last: float) -> None:
    """Close intervals still open at the last record (they end there) and keep its time."""
    base = SPAN_BLOCKS * n_s
    n_ev = 2 * n_s + 2 * n_d + n_n
    for e in range(n_ev):
        start = base + 2 * n_ev + e
        if not math.isnan(acc[start]):
            length = t_last - acc[start]
            acc[base + e] += length
            acc[base + 4 * n_ev + e] = max(acc[base + 4 * n_ev + e], length)
            acc[start] = math.nan
    acc[base + EV_BLOCKS * n_ev] = t_last


def batch_loop(plan: Plan) -> Any:
    """The batch function compiled for ``plan``'s structure (``kernel.compiled_loop``'s key)."""
    ns, ds, offsets = plan.structure()
    return _compiled_batch(tuple(map(tuple, ns.tolist())), tuple(map(tuple, ds.tolist())),
                           tuple(offsets.tolist()))


@functools.cache
def _compiled_batch(node_rows: tuple[tuple[int, ...], ...],
                    drive_rows: tuple[tuple[int, ...], ...], offset_row: tuple[int, ...]) -> Any:
    ns = np.array(node_rows, dtype=np.int64).reshape(len(node_rows), L.NS_COLS)
    ds = np.array(drive_rows, dtype=np.int64).reshape(len(drive_rows), L.DS_COLS)
    offsets = np.array(offset_row, dtype=np.int64)

    @batch_njit
    def run_cases(lo: int, hi: int, x: np.ndarray, istate: np.ndarray, slipping: np.ndarray,
                  nodes: np.ndarray, spans: np.ndarray, drives: np.ndarray, web: np.ndarray,
                  wound_ripple: np.ndarray, speed_ripple: np.ndarray, prof_t: np.ndarray,
                  prof_v: np.ndarray, prof_off: np.ndarray, dt: np.ndarray,
                  substeps: np.ndarray, n_ticks: np.ndarray, every: np.ndarray,
                  span_prof: np.ndarray, tension_limit: np.ndarray, trace_every: np.ndarray,
                  states: np.ndarray, window: np.ndarray, stops: np.ndarray, state_base: int,
                  stop_base: int, rec: np.ndarray, out: np.ndarray, stages: np.ndarray,
                  refs: np.ndarray, work: np.ndarray, felt: np.ndarray, slip: np.ndarray,
                  kv_scratch: np.ndarray, acc: np.ndarray, traces: np.ndarray, status: np.ndarray,
                  t_fail: np.ndarray, where: np.ndarray) -> None:
        n_x = offsets[L.O_WEB] + 2
        kv = offsets[L.O_KV] != 0  # Kelvin-Voigt spans: metrics of the felt tensions
        n_n = ns.shape[0]
        n_d = ds.shape[0]
        col_slip = compiled_slip_column(n_x, n_d)
        n_s = n_n - 1
        for c in range(lo, hi):
            done = 0
            st = L.STATUS_OK
            tf = math.nan
            wh = -1
            t_last = 0.0
            while done < n_ticks[c] and st == L.STATUS_OK:
                count = min(CHUNK_TICKS, n_ticks[c] - done)
                last = done + count == n_ticks[c]
                out[:] = 0.0  # as kernel.run gives every chunk
                work[:] = 0.0
                n_rec, st, tf, wh = advance(
                    x[c], istate[c], slipping[c], rec, out, stages, refs, work, done, count,
                    dt[c], substeps[c], every[c], last, ns, ds, offsets, nodes[c], spans[c],
                    drives[c], web[c], wound_ripple[c], speed_ripple[c], prof_t[c], prof_v[c],
                    prof_off[c], None, None)
                if kv:
                    felt_records(rec[:n_rec, 0], rec[:n_rec, 1:1 + n_x],
                                 rec[:n_rec, col_slip:col_slip + n_n], felt, slip, kv_scratch,
                                 ns, ds, offsets, nodes[c], spans[c], drives[c], web[c],
                                 wound_ripple[c])
                _reduce(rec, felt, kv, n_rec, acc[c], traces[c], trace_every[c], dt[c], n_x,
                        n_s, n_d, n_n, nodes[c], drives[c], prof_t[c], prof_v[c],
                        prof_off[c], span_prof, tension_limit[c], int(web[c][L.W_TRAMP]))
                S.reduce_states(rec, felt, kv, n_rec, acc[c], state_base, states[c], window[c],
                                n_x, n_d, ns, offsets, nodes[c], drives[c], web[c], prof_t[c],
                                prof_v[c], prof_off[c])
                if offsets[L.O_BREAK] and n_d > 0:  # the rollers after a break's stop
                    S.reduce_after_stop(rec, felt, kv, n_rec, acc[c], stop_base, stops[c],
                                        istate[c, 0, L.I_DETECT], ds, ns, offsets, nodes[c])
                if n_rec > 0:
                    t_last = rec[n_rec - 1, 0]
                done += count
            _finish(acc[c], n_s, n_d, n_n, t_last)
            S.finish_states(acc[c], state_base, states[c], t_last)
            status[c], t_fail[c], where[c] = st, tf, wh

    return run_cases


@dataclass
class BatchOutput:
    """What ``run_batch`` computed per case: accumulators (``Layout``), kernel status, time
    [s] and place of a failure, final state, tension traces [N] (case, time, span) and the
    web-break monitor at the end (its detection time [s], -1 for none, and method)."""

    layout: Layout
    acc: np.ndarray
    status: np.ndarray
    t_fail: np.ndarray
    where: np.ndarray
    x: np.ndarray
    traces: np.ndarray
    monitor: np.ndarray


def stack_cases(arrays: list[np.ndarray]) -> np.ndarray:
    """Stack per-case arrays of one shape; pad 1-D ones of different lengths (profiles)."""
    if all(a.shape == arrays[0].shape for a in arrays):
        return np.ascontiguousarray(np.stack(arrays))
    width = max(a.shape[0] for a in arrays)
    out = np.zeros((len(arrays), width, *arrays[0].shape[1:]))
    for c, a in enumerate(arrays):
        out[c, :a.shape[0]] = a
    return out


def run_batch(plans: list[Plan], states: list[tuple[np.ndarray, np.ndarray, np.ndarray]],
              n_ticks: np.ndarray, substeps: np.ndarray, every: np.ndarray,
              trace_every: int = 0, n_trace: int = 0, workers: int | None = None,
              ) -> BatchOutput:
    """Run cases that share one line structure (and ripple table shapes) from their initial
    (state, controller memory, stick/slip) ``states``, ``n_ticks`` controller periods each
    with ``substeps`` RK4 sub-steps, reducing the records taken every ``every`` ticks.
    ``trace_every`` > 0 keeps the span tensions every that many ticks (``n_trace`` rows).
    ``workers`` threads (default: the cores) run disjoint ranges of cases."""
    first = plans[0]
    n_c = len(plans)
    line = first.line
    for user in np.flatnonzero(first.drives[:, L.D_FAMILY] == L.FAMILY_USER):
        raise LineFileError(line.source, f"rollers[{line.drives[int(user)]}].controller",
                            "a study runs its cases compiled: a python controller runs "
                            "with simulate or Session, one case at a time")
    stop_rows = max(len(rest_limits(p.line)) for p in plans)
    lay = Layout(line.n_spans, first.drives.shape[0], line.n_nodes, stop_rows)
    if any(p.wound_ripple.shape != first.wound_ripple.shape
           or p.speed_ripple.shape != first.speed_ripple.shape
           or p.prof_off.shape != first.prof_off.shape for p in plans):
        raise ValueError("cases of one batch must share their ripple and profile tables' shapes")
    x = np.ascontiguousarray(np.stack([s[0] for s in states]))
    istate = np.ascontiguousarray(np.stack([s[1] for s in states]))
    slipping = np.ascontiguousarray(np.stack([s[2] for s in states]))
    tables = [stack_cases([getattr(p, name) for p in plans]) for name in (
        "nodes", "spans", "drives", "web", "wound_ripple", "speed_ripple", "prof_t", "prof_v")]
    prof_off = np.ascontiguousarray(np.stack([p.prof_off for p in plans]))
    dt = np.array([p.dt for p in plans])
    span_prof = np.full(lay.n_spans, -1, dtype=np.int64)
    for z, zone in enumerate(line.zones):
        span_prof[zone.loadcell] = 1 + z  # plan profiles: speed, then each zone's loadcell
    tension_limit = np.array([math.inf if p.line.spec.web.tension_limit is None
                              else float(p.line.spec.web.tension_limit) for p in plans])
    acc = np.zeros((n_c, lay.width))
    acc[:, A_TMIN * lay.n_spans:(A_TMIN + 1) * lay.n_spans] = math.inf
    acc[:, A_TMAX * lay.n_spans:(A_TMAX + 1) * lay.n_spans] = -math.inf
    base = lay.event_base
    acc[:, base + lay.n_events:base + 3 * lay.n_events] = math.nan  # first, open start
    S.start_columns(acc, lay.state_base, lay.n_slots)
    lay.stop_columns(acc)  # settled: not yet; no tension at a stop yet
    traces = np.full((n_c, n_trace if trace_every > 0 else 0, lay.n_spans), math.nan)
    status = np.zeros(n_c, dtype=np.int64)
    t_fail = np.full(n_c, math.nan)
    where = np.full(n_c, -1, dtype=np.int64)
    loop = batch_loop(first)
    every = np.asarray(every, dtype=np.int64)
    args = (x, istate, slipping, *tables, prof_off, dt,
            np.asarray(substeps, dtype=np.int64), np.asarray(n_ticks, dtype=np.int64),
            every, span_prof, tension_limit,
            np.full(n_c, max(trace_every, 1), dtype=np.int64),
            np.stack([S.state_table(p) for p in plans]),
            np.array([window_end(p.line) for p in plans]),
            np.stack([S.stop_table(p, stop_rows) for p in plans]), lay.state_base,
            lay.stop_base)
    n_x, n_d, n_n = first.n_x, lay.n_drives, lay.n_nodes
    n_prof = prof_off.shape[1] - 1

    def task(lo: int, hi: int) -> None:
        rows = CHUNK_TICKS // int(np.min(every[lo:hi])) + 2
        kv = bool(first.offsets[L.O_KV])  # felt tensions of Kelvin-Voigt spans, per record
        scratch = (np.empty((rows, record_width(n_x, n_d, n_n))), np.zeros((4, n_d)),
                   np.empty((5, n_x)), np.empty((4, max(n_prof, n_n))),
                   np.zeros((2, 3 * n_n)), np.empty((rows if kv else 0, n_n - 1)),
                   np.zeros(n_n, dtype=np.int64), np.zeros((4, max(n_x, 3 * n_n))))
        loop(lo, hi, *args, *scratch, acc, traces, status, t_fail, where)

    over_ranges(n_c, workers, task)
    monitor = (istate[:, 0, [L.I_DETECT, L.I_METHOD]] if istate.shape[1]
               else np.tile([-1.0, 0.0], (n_c, 1)))  # as ``simulate`` reads it
    return BatchOutput(lay, acc, status, t_fail, where, x, traces, monitor)
