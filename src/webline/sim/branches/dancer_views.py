"""A dancer's part in what is made of a branched plan (docs/branching.md, "Dancers"): the
carriages' place at the operating point, the spans' lengths in the records, the end-stop
findings and the linear model's dancer rows (the plan's tables: ``sim.branches.dancers``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.dancers import dancer_nodes, dancer_spans
from webline.sim.branches.loop import layout as B
from webline.sim.results.winder_states import interval_stats
from webline.spec.branched.check import kind_of
from webline.spec.winder import WebBreak
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan


def place_carriages(plan: BranchPlan, x: np.ndarray, refs: np.ndarray,
                    held: np.ndarray) -> None:
    """Every carriage at rest in the state ``x``: at its set position, or a tension sensor's
    where it reads its loop's reference, y = y_set + (load - G T_ref)/k (D2 with the loop at
    rest: G = g_in + g_out); ``refs`` [N] the loadcell spans' references, ``held`` the held
    inputs (``BranchPlan.held``: the loads last). A passive carriage is placed after the
    solve (``settle_passive``): its place follows from the tensions."""
    dancers = dancer_nodes(plan.line)
    for n, i in enumerate(dancers):
        state = int(plan.nodes[i, B.N_DSTATE])
        x[state], x[state + 1] = plan.nodes[i, B.N_DSET], 0.0
        read = np.flatnonzero((plan.cells[:, B.CELL_DANCER] == i)
                              & (plan.cells[:, B.CELL_SENSOR] == 1))
        if len(read):
            load = held[len(held) - len(dancers) + n]
            k = int(plan.cells[read[0], 0])
            x[state] += (load - plan.nodes[i, B.N_DGSUM] * refs[k]) / plan.nodes[i, B.N_DK]


def settle_passive(plan: BranchPlan, x: np.ndarray, dx: np.ndarray) -> None:
    """Move each passive sprung carriage (read by no drive) of the steady state ``x`` to
    where its forces balance: ``dx`` the rates at x, its carriage's M dv/dt = load - g_in T_in
    - g_out T_out - k (y - y_set) linear in y (the steady tensions do not depend on the
    spans' lengths), so y += M dv/dt / k. An air-loaded one (k = 0) stays at its set position
    (its load balances the tensions there, or nowhere within its travel)."""
    for i in dancer_nodes(plan.line):
        if i in plan.cells[:, B.CELL_DANCER] or plan.nodes[i, B.N_DK] == 0.0:
            continue
        state = int(plan.nodes[i, B.N_DSTATE])
        x[state] += dx[state + 1] / plan.nodes[i, B.N_DINVM] / plan.nodes[i, B.N_DK]


def span_lengths(plan: BranchPlan, states: np.ndarray) -> np.ndarray:
    """Length [m] of every span per record of ``states`` (rows: records): the file length,
    plus g (y - y_set) beside a dancer (D0)."""
    lengths = np.tile(plan.sf[:, B.SF_LENGTH], (states.shape[0], 1))
    for k in range(plan.si.shape[0]):
        for end, col, gain in ((B.S_A, B.S_DANCEA, B.SF_GAINA), (B.S_B, B.S_DANCEB, B.SF_GAINB)):
            state = plan.si[k, col]
            if state >= 0:
                lengths[:, k] += plan.sf[k, gain] * (
                    states[:, state] - plan.nodes[plan.si[k, end], B.N_DSET])
    return lengths


def end_stop_findings(plan: BranchPlan, time: np.ndarray, states: np.ndarray) -> list[Finding]:
    """A ``warning`` ``dancer_end_stop`` per dancer whose carriage rested on an end stop (y
    <= 0 or >= its travel) in the records ``time`` [s], ``states`` (the chain's check, with
    the line file's ``checks.end_stop_time``, up to a web break: after it the break's finding
    speaks), named by the web or lane it rides on: when, how long, which stop."""
    line = plan.line
    if len(time) < 2:
        return []
    duration = float(time[-1] - time[0])
    before = time < min((b.at for b in line.spec.disturbances if isinstance(b, WebBreak)),
                        default=np.inf)
    out = []
    for i in dancer_nodes(line):
        y = states[:, int(plan.nodes[i, B.N_DSTATE])]
        travel = float(plan.nodes[i, B.N_DTRAVEL])
        stats = interval_stats(time, before & ((y <= 0.0) | (y >= travel)),
                               line.spec.checks.end_stop_time)
        if stats is None:
            continue
        web = line.spec.webs[line.spans[dancer_spans(line, i)[0]].web]
        low = bool(np.any(before & (y <= 0.0)))
        times = "once" if stats.count == 1 else f"{stats.count} times"
        out.append(Finding(
            "warning", "dancer_end_stop", web.name,
            f"dancer {line.spec.rollers[i].name} on {kind_of(web)} {web.name} rested on its "
            f"{'low' if low else 'high'} end stop {times}, first from t = {stats.first:.4g} s "
            f"to {stats.first_end:.4g} s, {stats.total:.3g} s in all "
            f"({stats.total / duration:.1%} of the run)", stats.first,
            {"dancer": line.spec.rollers[i].name, "first_s": stats.first,
             "total_s": stats.total, "longest_s": stats.longest, "count": stats.count,
             "travel_m": travel, "low_stop": low}))
    return out


def linear_states(plan: BranchPlan) -> tuple[np.ndarray, list[str]]:
    """The dancer states of the linear model (after the others) and their names:
    ``<dancer>_position`` [m], ``<dancer>_velocity`` [m/s]."""
    names = [f"{plan.line.spec.rollers[i].name}_{part}" for i in dancer_nodes(plan.line)
             for part in ("position", "velocity")]
    return np.arange(plan.offsets[B.O_DANCER], plan.offsets[B.O_DANCER_END], dtype=np.int64), names


def reading_row(plan: BranchPlan, c: int,
                keep: np.ndarray) -> tuple[np.ndarray, float] | None:
    """What cell ``c``'s drive adds to its loop's error from its dancer, linear over the kept
    states ``keep`` and the cell's reference: (row, coefficient on the reference). Position
    control: e_t = y - y_set; a tension sensor: e_t = T_ref - (load - k (y - y_set))/G, the
    default load G T_ref (``load_rows``) cancelling the reference. None for a loadcell."""
    node = int(plan.cells[c, B.CELL_DANCER])
    if node < 0:
        return None
    row = np.zeros(len(keep))
    row[int(np.flatnonzero(keep == int(plan.nodes[node, B.N_DSTATE]))[0])] = 1.0
    if not plan.cells[c, B.CELL_SENSOR]:
        return row, 0.0
    gain = plan.nodes[node, B.N_DGSUM]
    load = _load_row(plan, node)
    follows = load[B.DS_B] if int(load[B.DS_A]) == int(plan.cells[c, 1]) else 0.0
    return plan.nodes[node, B.N_DK] / gain * row, 1.0 - follows / gain


def _load_row(plan: BranchPlan, node: int) -> np.ndarray:
    """The ``DIST_DANCER_LOAD`` row of the dancer on ``node`` (the loads come last)."""
    rows = plan.dist[plan.dist[:, B.DS_KIND] == B.DIST_DANCER_LOAD]
    return rows[dancer_nodes(plan.line).index(node)]


def load_column(plan: BranchPlan, c: int, keep: np.ndarray) -> np.ndarray:
    """d(dx/dt)/d(reference of cell ``c``) over the kept states through the default loads
    that follow it, (g_in + g_out) x the zone's reference (``load_rows``; through a taper, x
    f(D) at the rolls' starting radii): (g_in + g_out) f / M on each such carriage's speed,
    whatever the dancer's use; zeros where no load follows it (a load given in the file)."""
    column = np.zeros(len(keep))
    dancers = dancer_nodes(plan.line)
    held = plan.held(0.0)
    for n, node in enumerate(dancers):
        row = _load_row(plan, node)
        if int(row[B.DS_A]) != int(plan.cells[c, 1]):
            continue
        slot = len(plan.wound) - len(dancers) + n
        speed = int(plan.nodes[node, B.N_DSTATE]) + 1
        reference = plan.profile(int(row[B.DS_A]), 0.0)
        taper = held[slot] / (row[B.DS_B] * reference) if reference else 1.0
        column[int(np.flatnonzero(keep == speed)[0])] = (
            taper * row[B.DS_B] * plan.nodes[node, B.N_DINVM])
    return column
