"""The batch's reduction of what a run's verdict reads from its records beyond the events
(``webline.sim.sweeps.batch``): the winder-state checks (``sim.results.winder_states``) and the
driven
rollers after a web break's stop (``sim.results.winder_findings.AfterStop``).

Per case, each watched element has a slot of ``SLOT_COLS`` accumulator columns: its
intervals that lasted at least the minimum duration (count, first start and end, total,
longest; one still open) and its two extremes (``winder_states.Extremes``), the same
definitions ``winder_states.record_condition`` and ``interval_stats`` apply to a run's
records. Slots are fixed by the line structure (one per node for a dancer, two per drive for
a tension zone and a diameter calculator), so cases of one batch share their layout even if
one has a calculator and another none. Each web break has the largest |surface speed| of
every driven roller after its stop and the time from which all stayed below the rest limit.
The thresholds, the window and the stop times reach the compiled code as per-case tables
(``state_table``, ``stop_table``).
"""

from __future__ import annotations

import math

import numpy as np

from webline.sim.core.plan import Plan
from webline.sim.drives.controllers import taper_at
from webline.sim.elements import layout as L
from webline.sim.elements.envelope import node_arm
from webline.sim.elements.signals import jit, profile_at
from webline.sim.results.winder_findings import (
    AfterStop,
    AfterStopReader,
    intact_loadcells,
    rest_limits,
)
from webline.sim.results.winder_states import (
    DANCER,
    TENSION,
    IntervalStats,
    StateElement,
    state_elements,
    state_finding,
)
from webline.verdict import Finding

# accumulator columns of one slot
S_TOTAL, S_FIRST, S_FIRST_END, S_OPEN, S_COUNT, S_LONGEST, S_X1, S_X2 = range(8)
SLOT_COLS = 8
# columns of a slot's parameters (``state_table``): kind (-1: nothing watched), limit,
# minimum duration [s], record column (the dancer's position state, the zone's loadcell span,
# the calculator's node), drive (the calculator's; the drive whose taper sets the zone's
# tension, -1: none), the zone's tension profile
P_KIND, P_LIMIT, P_MIN, P_COL, P_DRIVE, P_PROF = range(6)
P_COLS = 6


def n_slots(n_nodes: int, n_drives: int) -> int:
    """Slots per case: a dancer per node, a tension zone and a calculator per drive."""
    return n_nodes + 2 * n_drives


def slot_of(element: StateElement, n_nodes: int, n_drives: int) -> int:
    """The slot of a watched element."""
    if element.kind == DANCER:
        return element.node
    return n_nodes + (element.drive if element.kind == TENSION else n_drives + element.drive)


def state_table(plan: Plan) -> np.ndarray:
    """The slots' parameters (``P_*``) of ``plan``: (slots, ``P_COLS``)."""
    line = plan.line
    n_n, n_d = line.n_nodes, plan.drives.shape[0]
    table = np.full((n_slots(n_n, n_d), P_COLS), -1.0)
    rewind_zone = line.controlled_zone(n_n - 1)
    # the rewind's taper sets its zone's tension at the radius its controller uses
    taper_drive, taper_span = -1, -1
    if line.rewind.taper is not None and rewind_zone is not None:
        taper_drive, taper_span = line.drives.index(n_n - 1), line.zones[rewind_zone].loadcell
    span_profile = {zone.loadcell: 1 + z for z, zone in enumerate(line.zones)}  # as run_batch
    for e in state_elements(plan):
        row = table[slot_of(e, n_n, n_d)]
        row[P_KIND], row[P_LIMIT], row[P_MIN] = e.kind, e.limit, e.min_duration
        if e.kind == DANCER:
            row[P_COL] = plan.state_names.index(f"{e.where}.position")
        elif e.kind == TENSION:
            row[P_COL], row[P_PROF] = e.span, span_profile[e.span]
            row[P_DRIVE] = taper_drive if e.span == taper_span else -1
        else:
            row[P_COL], row[P_DRIVE] = e.node, e.drive
    return table


def stop_table(plan: Plan, n_breaks: int) -> np.ndarray:
    """Each web break's (stop time after detection [s], rest limit [m/s]), padded to
    ``n_breaks`` rows with breaks that never stop."""
    table = np.full((n_breaks, 2), math.inf)
    for j, limits in enumerate(rest_limits(plan.line)):
        table[j] = limits
    return table


def start_columns(acc: np.ndarray, state_base: int, slots: int) -> None:
    """Set the slots' start values in the accumulators ``acc`` (cases x columns): nothing
    open or found yet; the stop columns start at 0 (speeds) and NaN (settled) elsewhere."""
    block = acc[:, state_base:state_base + slots * SLOT_COLS].reshape(len(acc), slots,
                                                                      SLOT_COLS)
    block[:, :, [S_FIRST, S_FIRST_END, S_OPEN, S_X2]] = math.nan
    block[:, :, S_X1] = -1.0


@jit
def _close(acc: np.ndarray, b: int, t: float, min_duration: float) -> None:
    """End slot ``b``'s open interval at ``t`` [s]; count it if it lasted long enough."""
    start = acc[b + S_OPEN]
    length = t - start
    if length >= min_duration:
        if math.isnan(acc[b + S_FIRST]):
            acc[b + S_FIRST], acc[b + S_FIRST_END] = start, t
        acc[b + S_COUNT] += 1.0
        acc[b + S_TOTAL] += length
        acc[b + S_LONGEST] = max(acc[b + S_LONGEST], length)
    acc[b + S_OPEN] = math.nan


@jit
def _step(acc: np.ndarray, b: int, cond: bool, t: float, min_duration: float) -> None:
    """Slot ``b``'s interval bookkeeping at a record at ``t`` [s] (``events.intervals``: an
    interval starts where ``cond`` holds and ends where it no longer does)."""
    if cond:
        if math.isnan(acc[b + S_OPEN]):
            acc[b + S_OPEN] = t
    elif not math.isnan(acc[b + S_OPEN]):
        _close(acc, b, t, min_duration)


@jit
def reduce_states(rec: np.ndarray, felt: np.ndarray, kv: bool, n_rec: int, acc: np.ndarray,
                  base: int, table: np.ndarray, window: float, n_x: int, n_d: int,
                  ns: np.ndarray, offsets: np.ndarray, nodes: np.ndarray, drives: np.ndarray,
                  web: np.ndarray, prof_t: np.ndarray, prof_v: np.ndarray,
                  prof_off: np.ndarray) -> None:
    """Fold ``n_rec`` records into the slots from column ``base`` of ``acc``
    (``winder_states.record_condition``'s definitions, records before ``window`` [s])."""
    col_radius = 1 + n_x + 5 * n_d  # the controllers' radii (``kernel.run``)
    ramp = int(web[L.W_TRAMP])
    for s in range(table.shape[0]):
        kind = int(table[s, P_KIND])
        if kind < 0:
            continue
        b = base + s * SLOT_COLS
        limit, min_duration = table[s, P_LIMIT], table[s, P_MIN]
        col, drive = int(table[s, P_COL]), int(table[s, P_DRIVE])
        x1, x2 = acc[b + S_X1], acc[b + S_X2]
        for r in range(n_rec):
            t = rec[r, 0]
            inside = t < window
            if kind == DANCER:
                y = rec[r, 1 + col]
                cond = inside and (y <= 0.0 or y >= limit)
                if inside and y <= 0.0:
                    x1 = 1.0
            elif kind == TENSION:  # ``Result.tension_ref``: profile x ramp x taper
                ref = profile_at(int(table[s, P_PROF]), t, prof_t, prof_v, prof_off)
                if ramp > 0:
                    ref *= profile_at(ramp, t, prof_t, prof_v, prof_off)
                if drive >= 0:
                    ref *= taper_at(drive, rec[r, col_radius + drive], drives, prof_t, prof_v,
                                    prof_off)
                tension = felt[r, col] if kv else max(rec[r, 1 + col], 0.0)
                error = abs(tension - ref)
                cond = inside and error > limit * abs(ref)
                if cond and error > x1:
                    x1, x2 = error, tension / ref if ref != 0.0 else math.nan
            else:
                true = node_arm(col, rec[r, 1:], ns, offsets, nodes)
                error = 2.0 * (rec[r, col_radius + drive] - true)
                cond = inside and abs(error) > limit * (2.0 * true)
                if inside and abs(error) > x1:
                    x1, x2 = abs(error), error
            _step(acc, b, cond, t, min_duration)
        acc[b + S_X1], acc[b + S_X2] = x1, x2


@jit
def finish_states(acc: np.ndarray, base: int, table: np.ndarray, t_last: float) -> None:
    """Close the intervals still open at the last record (they end there)."""
    for s in range(table.shape[0]):
        b = base + s * SLOT_COLS
        if table[s, P_KIND] >= 0 and not math.isnan(acc[b + S_OPEN]):
            _close(acc, b, t_last, table[s, P_MIN])


@jit
def stop_stride(n_drives: int, n_spans: int) -> int:
    """Accumulator columns per web break after its stop (``reduce_after_stop``)."""
    return n_drives + 1 + 2 * n_spans


@jit
def reduce_after_stop(rec: np.ndarray, felt: np.ndarray, kv: bool, n_rec: int,
                      acc: np.ndarray, base: int, stops: np.ndarray, detected: float,
                      ds: np.ndarray, ns: np.ndarray, offsets: np.ndarray,
                      nodes: np.ndarray) -> None:
    """Fold ``n_rec`` records into each break's columns from ``base`` of ``acc`` (per
    break, the driven rollers' largest |r ω| [m/s] at and after its stop, then the time [s]
    from which all stayed below its rest limit, then each span's tension [N] at the stop
    and its least after it: ``after_stop_from_records``), the monitor having detected the
    break at ``detected`` [s] (< 0: not yet); ``felt``: the felt tensions where ``kv``."""
    if detected < 0.0:
        return
    n_d = ds.shape[0]
    n_s = ns.shape[0] - 1
    omega = offsets[L.O_OMEGA]
    for j in range(stops.shape[0]):
        stop, limit = detected + stops[j, 0], stops[j, 1]
        b = base + j * stop_stride(n_d, n_s)
        for r in range(n_rec):
            t = rec[r, 0]
            if t < stop:
                continue
            for k in range(n_s):  # as a Result's tension: felt, or the clipped stretch
                tension = felt[r, k] if kv else max(rec[r, 1 + k], 0.0)
                if math.isnan(acc[b + n_d + 1 + k]):
                    acc[b + n_d + 1 + k] = tension
                acc[b + n_d + 1 + n_s + k] = min(acc[b + n_d + 1 + n_s + k], tension)
            fastest = 0.0
            for d in range(n_d):
                i = ds[d, L.DS_NODE]
                speed = abs(node_arm(i, rec[r, 1:], ns, offsets, nodes) * rec[r, 1 + omega + i])
                acc[b + d] = max(acc[b + d], speed)
                fastest = max(fastest, speed)
            if fastest >= limit:
                acc[b + n_d] = math.nan
            elif math.isnan(acc[b + n_d]):
                acc[b + n_d] = t


def batch_state_findings(plan: Plan, row: np.ndarray, base: int, n_records: int,
                         end: float) -> list[Finding]:
    """The winder-state findings of a case from its accumulator ``row`` (slots from
    ``base``), ``n_records`` records up to ``end`` [s]: ``winder_state_findings``' own."""
    n_n, n_d = plan.line.n_nodes, plan.drives.shape[0]
    counts = row[base + S_COUNT:base + n_slots(n_n, n_d) * SLOT_COLS:SLOT_COLS]
    if n_records < 2 or not np.any(counts > 0):  # nothing held long enough (most cases)
        return []
    out = []
    for element in state_elements(plan):
        b = base + slot_of(element, n_n, n_d) * SLOT_COLS
        if row[b + S_COUNT] > 0:
            stats = IntervalStats(int(row[b + S_COUNT]), float(row[b + S_FIRST]),
                                  float(row[b + S_FIRST_END]), float(row[b + S_TOTAL]),
                                  float(row[b + S_LONGEST]))
            out.append(state_finding(plan.line, element, stats,
                                     (float(row[b + S_X1]), float(row[b + S_X2])), end))
    return out


def batch_after_stop(plan: Plan, row: np.ndarray, base: int, detected: float
                     ) -> AfterStopReader | None:
    """``AfterStopReader`` of a case from its accumulator ``row`` (breaks from ``base``),
    the monitor having detected the break at ``detected`` [s]: the break whose stop and rest
    limit ``break_findings`` asks for (None where nothing was detected: it asks for none)."""
    if detected < 0.0:
        return None
    n_d, n_s = plan.drives.shape[0], plan.line.n_spans
    names = [plan.line.node_name(i) for i in plan.line.drives]
    kept = {(detected + stop_time, limit): j
            for j, (stop_time, limit) in enumerate(rest_limits(plan.line))}
    intact = intact_loadcells(plan)

    def read(stop: float, limit: float) -> AfterStop:
        b = base + kept[(stop, limit)] * stop_stride(n_d, n_s)
        settled = float(row[b + n_d])
        first, least = b + n_d + 1, b + n_d + 1 + n_s
        loss = {plan.line.span_name(k): float(row[first + k] - row[least + k]) for k in intact}
        return AfterStop(row[b:b + n_d].copy(), names, None if math.isnan(settled) else settled,
                         loss)
    return read

