"""Winder functions of a branched line in the plan (docs/branching.md, "Taper", "Diameter
calculation", "Centre winders and flying splices"): a rewind's taper (docs/winder.md W1), a
roll's diameter calculator (W2), its ``winder`` table (compensation, open-loop tension
control, W3, W4, W7), the tension ramp at start and stop (R1) and the flying splices of its
unwinds (S1), as columns and rows of the compiled loop's tables (``loop.layout``)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from webline.model.tension_ramp import ramp_profile
from webline.model.web_graph import BranchedLine
from webline.physics.taper import KINDS, TABLE
from webline.profiles import breakpoints
from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.plant import node_inertia
from webline.sim.branches.loop.winder import compensation
from webline.sim.elements.signals import profile_slope_at
from webline.spec.roll_inertia import roll_constants
from webline.spec.schema import RewindSpec, UnwindSpec
from webline.spec.splice import FlyingSplice
from webline.verdict import Finding

Profiles = list[tuple[np.ndarray, np.ndarray]]


def winder_columns(line: BranchedLine, di: np.ndarray, df: np.ndarray,
                   profiles: Profiles) -> None:
    """Fill each roll drive's ``winder`` columns (``layout`` D_COMP*, D_SPEEDLIM, D_DIR and
    DI_WINDER); a friction table is appended to ``profiles`` as a profile over |ω| [rad/s]."""
    top = float(np.max(np.abs(breakpoints(line.spec.speed)[1])))
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        spec = getattr(roller, "winder", None)
        df[d, B.D_COMPFP] = -1.0
        if isinstance(roller, UnwindSpec | RewindSpec):  # (a roll's stall tension uses it, W8)
            df[d, B.D_DIR] = -1.0 if isinstance(roller, UnwindSpec) else 1.0
        if spec is None:
            continue
        df[d, B.D_COMPJ] = 1.0 if spec.inertia_compensation else 0.0
        df[d, B.D_COMPCS], df[d, B.D_COMPB] = spec.static_friction, spec.viscous_friction
        if spec.friction_table is not None:
            df[d, B.D_COMPFP] = len(profiles)
            profiles.append(spec.friction_table.arrays())
        df[d, B.D_SPEEDLIM] = spec.speed_limit_offset * top
        di[d, B.DI_WINDER] = B.WINDER_OPEN if spec.mode == "open_loop" else B.WINDER_COMP


def ramp_column(line: BranchedLine, profiles: Profiles) -> int:
    """The tension ramp's profile (its factor on every zone's reference over time, R1),
    appended to ``profiles``; its index, -1 without a ramp."""
    ramp = line.spec.control.tension_ramp
    if ramp is None:
        return -1
    profiles.append(ramp_profile(line.spec.speed, ramp))
    return len(profiles) - 1


def splices(line: BranchedLine) -> list[FlyingSplice]:
    """The flying splices of ``line``'s run, in time order."""
    return sorted((d for d in line.spec.disturbances if isinstance(d, FlyingSplice)),
                  key=lambda s: s.at)


def splice_tick(at: float, dt: float) -> int:
    """The first controller tick at or after ``at`` [s] (period ``dt`` [s]), the splice's
    instant (1e-9 of a tick absorbs the rounding of at/dt), as the chain's."""
    return math.ceil(at / dt - 1e-9)


def splice_rows(line: BranchedLine, dt: float) -> list[list[float]]:
    """Event rows (``layout`` E_*) of ``line``'s flying splices, at their ticks' times."""
    rows = []
    for item in splices(line):
        j = spliced_roll(line, line.node_index[item.roll])
        rows.append([splice_tick(item.at, dt) * dt, j, item.new_diameter / 2.0, 0.0,
                     line.rolls[j].web, B.EVENT_SPLICE, 1.0 + item.speed_mismatch,
                     item.slack])
    return rows


def spliced_roll(line: BranchedLine, node: int) -> int:
    """The roll whose web speed a splice of the roll on ``node`` matches: the one its drive
    measures speed on (on a rewind's shaft of lanes, the first loadcell's lane), else the
    node's first roll."""
    zone = line.zones.get(node)
    for k in zone.loadcells if zone is not None else ():
        j = line.roll_of(node, line.spans[k].web)
        if j >= 0:
            return j
    return next(j for j, r in enumerate(line.rolls) if r.node == node)


def initial_compensation(plan: Any, point: Any) -> np.ndarray:
    """Each drive's compensation torque [N·m] at t = 0 (0 without a ``winder``): the run's
    speed integrators start that much lower, so that the run starts at its operating point
    (as on a chain, docs/winder.md W3). ``plan``: a ``plan.BranchPlan``, ``point``: an
    ``equilibrium.BranchPoint`` (not imported: they import this module)."""
    out = np.zeros(plan.di.shape[0])
    a_line = profile_slope_at(0, 0.0, plan.prof_t, plan.prof_v, plan.prof_off)
    for d in range(plan.di.shape[0]):
        if plan.di[d, B.DI_WINDER] == B.WINDER_NONE:
            continue
        i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
        radius = plan.radius0[d] if plan.df[d, B.D_DCALC] != B.DCALC_NONE else (
            point.x[plan.offsets[B.O_RADIUS] + j])
        omega = point.x[plan.offsets[B.O_OMEGA] + i]
        out[d] = compensation(d, i, radius, omega, a_line, plan.nodes, plan.rolls, plan.df,
                              plan.prof_t, plan.prof_v, plan.prof_off)
    return out



def splice_findings(line: BranchedLine, dt: float, time: np.ndarray,
                    tension: np.ndarray) -> list[Finding]:
    """A ``warning`` ``splice_slack`` for each flying splice after which a span of the
    spliced roll's tension zone went slack (tension <= 0 N) before the next splice or the
    end of the run (the chain's ``sim.results.splice_findings``): where, when (the first slack
    record [s]) and how long (the records' time slack, summed [s]). ``time`` [s] and
    ``tension`` [N] (records x spans) are the run's records."""
    out: list[Finding] = []
    if len(time) < 2:
        return out
    step = np.diff(time, append=time[-1])
    items = splices(line)
    for n, item in enumerate(items):
        start = splice_tick(item.at, dt) * dt
        until = items[n + 1].at if n + 1 < len(items) else float(time[-1])
        if start > time[-1]:
            continue
        inside = (time >= start) & (time <= until)
        for k in line.zones[line.node_index[item.roll]].spans:
            slack = inside & (tension[:, k] <= 0.0)
            if not slack.any():
                continue
            first, span = float(time[np.argmax(slack)]), line.spans[k].name
            duration = float(step[slack].sum())
            out.append(Finding(
                "warning", "splice_slack", span,
                f"the flying splice of {item.roll} at t = {start:.4g} s slackened {span}: "
                f"slack from t = {first:.4g} s, {1000 * duration:.4g} ms in all", first,
                {"roll": item.roll, "splice_s": start, "first_slack_s": first,
                 "slack_duration_s": duration, "speed_mismatch": item.speed_mismatch,
                 "slack_m": item.slack}))
    return out


def linear_winder_rows(plan: Any, d: int, radius: float, q_t: int | None,
                       kx: np.ndarray, ki: np.ndarray, kr: np.ndarray, gx: np.ndarray,
                       gi: np.ndarray, gr: np.ndarray) -> None:
    """Drive ``d``'s winder in the linear closed loop (``linear.controller_matrices``), as the
    chain's ``sim.core.winder.linear_rows``: its viscous compensation b_c ω / n (static
    friction and the line's acceleration are constant at an operating point); an open-loop
    drive's torque is ±R/n on each of its loadcells' references (``radius`` [m] at the
    point) plus that, its speed integrator (the limiter's, clamped while the web holds the
    roll) and tension integrator ``q_t`` (none) frozen."""
    row = plan.df[d]
    omega_state = plan.offsets[B.O_OMEGA] + plan.di[d, B.DI_NODE]
    if plan.di[d, B.DI_WINDER] == B.WINDER_OPEN:
        kx[d], ki[d], kr[d] = 0.0, 0.0, 0.0
        first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
        kr[d, 1 + first:1 + first + count] = row[B.D_DIR] * radius / row[B.D_RATIO]
        for q in (d, q_t):
            if q is not None:
                gx[q], gi[q], gr[q] = 0.0, 0.0, 0.0
    kx[d, omega_state] += row[B.D_COMPB] / row[B.D_RATIO]


def rotating_inertia(line: BranchedLine, i: int) -> float:
    """Inertia [kg·m²] of roller ``i``'s rotating parts without web and motor: its
    ``inertia``, or on a roll given as totals the core's they give (J1,
    ``spec.roll_inertia``; the web wound on it: ``BranchedLine.wound_web``)."""
    roller = line.spec.rollers[i]
    if isinstance(roller.inertia, float):
        return roller.inertia
    return roll_constants(roller, line.wound_web(i))[0]


def wound_density(line: BranchedLine, j: int) -> float:
    """Density [kg/m³] of roll ``j``'s wound web: its web's, or the one its roll's totals
    give (J1; every web wound on that roll takes it)."""
    roll = line.rolls[j]
    roller = line.spec.rollers[roll.node]
    if isinstance(roller.inertia, float):
        return line.materials[roll.web].density
    return roll_constants(roller, line.wound_web(roll.node))[1]


def splice_summary(result: Any) -> list[dict[str, object]]:
    """What each flying splice of a run (``result``: a ``BranchResult``) did, as the chain's
    report says it (docs/winder.md S4): its instant [s], the largest tension change [N] in the
    roll's zone after it (against the last record before it, up to the next splice or the
    end) with its span and delay [s]; the old roll as it left the web (radius [m], speed
    [rad/s], inertia [kg·m²]) and the least time its drive needs to stop it at its torque
    limit, J ω / (n τ_max) [s]; the least time the new roll's drive needs to bring it to its
    speed from rest, the same formula at the new roll (the run-up and the stop are not
    simulated: before the splice the new roll carries no web, after it the old one none)."""
    plan = result.plan
    line, time = plan.line, result.time
    tension = result.dataset["tension"].values
    states = result.states
    items = splices(line)
    out: list[dict[str, object]] = []
    for n, item in enumerate(items):
        start = splice_tick(item.at, plan.dt) * plan.dt
        if len(time) < 2 or start > time[-1] or start <= time[0]:
            continue
        before = int(np.searchsorted(time, start - 0.5 * plan.dt)) - 1
        until = items[n + 1].at if n + 1 < len(items) else float(time[-1])
        inside = (time >= start - 0.5 * plan.dt) & (time <= until)
        node = line.node_index[item.roll]
        spans = list(line.zones[node].spans)
        change = np.abs(tension[inside][:, spans] - tension[before, spans])
        row, col = np.unravel_index(int(np.argmax(change)), change.shape)
        j = spliced_roll(line, node)
        d = line.drives.index(node)
        stop = plan.df[d, B.D_RATIO] * plan.df[d, B.D_LIMIT]
        r_old = float(states[before, plan.offsets[B.O_RADIUS] + j])
        w_old = float(states[before, plan.offsets[B.O_OMEGA] + node])
        r_new = item.new_diameter / 2.0
        j_old, j_new = (_inertia_at(plan, states[before], node, j, r) for r in (r_old, r_new))
        w_new = abs(w_old) * r_old * (1.0 + item.speed_mismatch) / r_new
        out.append({
            "roll": item.roll, "time_s": start, "new_diameter_m": item.new_diameter,
            "speed_mismatch": item.speed_mismatch, "slack_m": item.slack,
            "largest_change_N": float(change[row, col]),
            "largest_change_span": line.spans[spans[col]].name,
            "largest_change_after_s": float(time[inside][row] - start),
            "old_radius_m": r_old, "old_omega_rad_s": w_old, "old_inertia_kg_m2": j_old,
            "old_stop_s": j_old * abs(w_old) / stop, "new_run_up_s": j_new * w_new / stop})
    return out


def _inertia_at(plan: Any, state: np.ndarray, node: int, j: int, radius: float) -> float:
    """Inertia [kg·m²] of ``node`` in ``state`` with its roll ``j`` at ``radius`` [m] (on a
    shaft of lanes every lane: they are spliced together)."""
    x = state.copy()
    for m, roll in enumerate(plan.line.rolls):
        if m == j or roll.node == node:
            x[plan.offsets[B.O_RADIUS] + m] = radius
    return float(node_inertia(node, x, plan.offsets, plan.nodes, plan.rolls))


def open_loop_torque(plan: Any, d: int, x: np.ndarray, refs: np.ndarray, t: float,
                     friction: bool = True) -> float:
    """The torque command [N·m] open-loop drive ``d`` holds in steady running (W4, its
    limiter idle) in state ``x`` at time ``t`` [s]: ±Σ T_ref R / n + the compensation, R its
    radius at the start (calculated or true), ``refs`` [N] each loadcell span's reference at
    ``t`` (taper and ramp applied); without ``friction`` (the operating point at rest, taken
    frictionless) the compensation's friction terms are left out."""
    i, j = plan.di[d, B.DI_NODE], plan.di[d, B.DI_ROLL]
    radius = plan.radius0[d] if plan.df[d, B.D_DCALC] != B.DCALC_NONE else (
        x[plan.offsets[B.O_RADIUS] + j])
    first, count = plan.di[d, B.DI_CELLS], plan.di[d, B.DI_NCELLS]
    reference = float(np.sum(refs[plan.cells[first:first + count, 0]]))
    df = plan.df if friction else _frictionless(plan.df, d)
    comp = compensation(d, i, radius, x[plan.offsets[B.O_OMEGA] + i],
                        profile_slope_at(0, t, plan.prof_t, plan.prof_v, plan.prof_off),
                        plan.nodes, plan.rolls, df, plan.prof_t, plan.prof_v, plan.prof_off)
    return float(plan.df[d, B.D_DIR] * reference * radius / plan.df[d, B.D_RATIO] + comp)


def _frictionless(df: np.ndarray, d: int) -> np.ndarray:
    out = df.copy()
    out[d, B.D_COMPCS] = out[d, B.D_COMPB] = 0.0
    out[d, B.D_COMPFP] = -1.0
    return out


def taper_columns(line: BranchedLine, df: np.ndarray,
                  profiles: list[tuple[np.ndarray, np.ndarray]]) -> None:
    """Fill the taper columns of the drive table ``df``; a table taper's (diameter [m],
    factor) points are appended to ``profiles`` (a profile over the diameter)."""
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        if not isinstance(roller, RewindSpec) or roller.taper is None:
            continue
        spec = roller.taper
        df[d, B.D_TAPER_KIND] = KINDS[spec.type]
        df[d, B.D_TAPER] = spec.taper
        df[d, B.D_TAPER_DMAX] = math.inf if spec.max_diameter is None else spec.max_diameter
        if KINDS[spec.type] == TABLE:
            df[d, B.D_TAPER_PROF] = len(profiles)
            profiles.append((np.array(spec.diameter, dtype=float),
                             np.array(spec.factor, dtype=float)))


def diameter_columns(line: BranchedLine, df: np.ndarray, di: np.ndarray) -> np.ndarray:
    """Fill the diameter-calculator columns of ``df`` (docs/winder.md W2) and return each
    drive's starting calculated radius [m] (0 without a calculator): ``initial`` = "measured"
    is the true radius of the lane the drive measures speed on."""
    start = np.zeros(len(line.drives))
    for d, i in enumerate(line.drives):
        roller = line.spec.rollers[i]
        spec = getattr(roller, "diameter", None)
        j = di[d, B.DI_ROLL]
        if spec is None or j < 0:
            continue
        roll = line.rolls[j]
        df[d, B.D_DCALC] = (B.DCALC_THICKNESS if spec.method == "thickness"
                            else B.DCALC_SPEED_RATIO)
        df[d, B.D_DFILTER] = spec.filter
        df[d, B.D_DRATE] = math.inf if spec.rate_limit is None else spec.rate_limit
        df[d, B.D_DHOLD] = spec.hold_below
        df[d, B.D_DSOURCE] = (-1 if spec.line_speed == "reference" else line.master
                              if spec.line_speed == "master"
                              else line.node_index[spec.line_speed])
        df[d, B.D_DTHICK] = line.materials[roll.web].thickness
        df[d, B.D_DDIR] = roll.direction
        start[d] = roll.radius if spec.initial == "measured" else 0.5 * spec.initial
        df[d, B.D_PRESETN] = len(spec.preset)
        for p, preset in enumerate(spec.preset):
            df[d, B.D_PRESETT + p] = preset.at
            df[d, B.D_PRESETD + p] = 0.0 if preset.diameter == "measured" else preset.diameter
    return start
