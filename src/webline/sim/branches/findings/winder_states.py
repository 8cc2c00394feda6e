"""The winder-state findings of a branched run (docs/branching.md, "Winder states in the
verdict"; the chain's ``sim.results.winder_states``, docs/winder.md W9), with the line
file's ``[checks]`` thresholds: a web's or lane's tension zone off its set tension and a
diameter calculator off its roll's true diameter, each for ``min_duration`` in one go,
looked for up to a web break (after it the break's finding speaks). A dancer on its end
stop is ``dancer_views.end_stop_findings``, with ``end_stop_time``."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from webline.sim.branches.loop import layout as B
from webline.sim.branches.loop.control import taper_at
from webline.sim.results.winder_states import IntervalStats, interval_stats
from webline.spec.branched.check import kind_of
from webline.spec.winder import WebBreak
from webline.verdict import Finding

if TYPE_CHECKING:
    from webline.sim.branches.plan import BranchPlan


def window_end(plan: BranchPlan) -> float:
    """The time [s] the checks stop looking: the web break (inf: none)."""
    return min((b.at for b in plan.line.spec.disturbances if isinstance(b, WebBreak)),
               default=math.inf)


def drive_radius(plan: BranchPlan, d: int, radius: np.ndarray,
                 control_radius: np.ndarray) -> np.ndarray:
    """The radius [m] drive ``d`` uses at each record: its calculator's (``control_radius``,
    records x drives) where it has one, else its roll's true one (``radius``, records x
    rolls; the lane it measures speed on), else its roller's."""
    if plan.df[d, B.D_DCALC] != B.DCALC_NONE:
        return control_radius[:, d]
    j = int(plan.di[d, B.DI_ROLL])
    if j >= 0:
        return radius[:, j]
    return np.full(len(radius), plan.nodes[int(plan.di[d, B.DI_NODE]), B.N_RADIUS])


def set_tension(plan: BranchPlan, d: int, cell: int, time: np.ndarray,
                used: np.ndarray) -> np.ndarray:
    """Set tension [N] of drive ``d``'s loadcell row ``cell`` at each record, as the drive
    has it at that tick: its reference profile times the taper at the radius the drive uses
    (``used`` [m]) and the tension ramp's factor (``loop.control.control_tick``)."""
    def values(p: int) -> np.ndarray:
        a, b = plan.prof_off[p], plan.prof_off[p + 1]
        return np.interp(time, plan.prof_t[a:b], plan.prof_v[a:b])

    out = values(int(plan.cells[cell, 1]))
    if plan.df[d, B.D_TAPER_KIND] != 0:
        core = plan.nodes[int(plan.di[d, B.DI_NODE]), B.N_CORE]
        out = out * np.array([taper_at(d, float(r), core, plan.df, plan.prof_t, plan.prof_v,
                                       plan.prof_off) for r in used])
    if plan.offsets[B.O_RAMP] >= 0:  # the tension ramp at start and stop (R1)
        out = out * values(int(plan.offsets[B.O_RAMP]))
    return out


def _sentence(stats: IntervalStats, duration: float) -> tuple[str, dict[str, object]]:
    """When and how long (the chain's words) and those numbers."""
    times = "once" if stats.count == 1 else f"{stats.count} times"
    return (f"{times}, first from t = {stats.first:.4g} s to {stats.first_end:.4g} s, "
            f"{stats.total:.3g} s in all ({stats.total / duration:.1%} of the run)",
            {"first_s": stats.first, "total_s": stats.total, "longest_s": stats.longest,
             "count": stats.count, "fraction": stats.total / duration})


def tension_findings(plan: BranchPlan, time: np.ndarray, tension: np.ndarray,
                     radius: np.ndarray, control_radius: np.ndarray) -> list[Finding]:
    """A ``warning`` ``tension_off_set`` per tension zone (each loadcell or dancer row of a
    drive: a web's or lane's zone) whose span tension stays more than ``tension_tolerance``
    x its set tension off it for at least ``min_duration`` in one go before a break. A
    drive that reads its loadcell is "measured" (the reading without its noise); an
    open-loop drive or a dancer in position control reads none: "true (no loadcell read)".
    ``tension`` [N] records x spans, ``radius``, ``control_radius`` [m] the dataset's."""
    line, checks = plan.line, plan.line.spec.checks
    if len(time) < 2:
        return []
    before = time < window_end(plan)
    duration = float(time[-1] - time[0])
    out = []
    for d, i in enumerate(line.drives):
        used = drive_radius(plan, d, radius, control_radius)
        first, count = int(plan.di[d, B.DI_CELLS]), int(plan.di[d, B.DI_NCELLS])
        for c in range(first, first + count):
            k = int(plan.cells[c, 0])
            ref = set_tension(plan, d, c, time, used)
            error = np.abs(tension[:, k] - ref)
            mask = before & (error > checks.tension_tolerance * np.abs(ref))
            stats = interval_stats(time, mask, checks.min_duration)
            if stats is None:
                continue
            worst = int(np.argmax(np.where(mask, error, -1.0)))
            ratio = tension[worst, k] / ref[worst] if ref[worst] else math.nan
            dancer = plan.cells.shape[1] > B.CELL_DANCER and plan.cells[c, B.CELL_DANCER] >= 0
            read = not dancer and plan.di[d, B.DI_WINDER] != B.WINDER_OPEN
            web = line.spec.webs[line.spans[k].web]
            words = "measured" if read else "true (no loadcell read)"
            when, numbers = _sentence(stats, duration)
            out.append(Finding(
                "warning", "tension_off_set", web.name,
                f"{kind_of(web)} {web.name}: {line.spans[k].name}'s {words} tension stayed "
                f"more than {checks.tension_tolerance:.0%} off its set tension (the zone of "
                f"{line.spec.rollers[i].name}) {when}", stats.first,
                {**numbers, "span": line.spans[k].name, "drive": line.spec.rollers[i].name,
                 "source": "measured (loadcell)" if read else "true tension",
                 "tolerance": checks.tension_tolerance, "largest_error_N": float(error[worst]),
                 "largest_ratio": None if math.isnan(ratio) else float(ratio)}))
    return out


def diameter_findings(plan: BranchPlan, time: np.ndarray, radius: np.ndarray,
                      control_radius: np.ndarray) -> list[Finding]:
    """A ``warning`` ``diameter_error`` per diameter calculator whose diameter stays more
    than ``diameter_tolerance`` x its roll's true one off it for at least ``min_duration``
    in one go before a break (the roll: the lane its drive measures speed on), named by the
    drive: when, how long, the largest signed error [m]."""
    line, checks = plan.line, plan.line.spec.checks
    if len(time) < 2:
        return []
    before = time < window_end(plan)
    duration = float(time[-1] - time[0])
    out = []
    for d, i in enumerate(line.drives):
        j = int(plan.di[d, B.DI_ROLL])
        if plan.df[d, B.D_DCALC] == B.DCALC_NONE or j < 0 or not before.any():
            continue
        true = radius[:, j]
        error = 2.0 * (control_radius[:, d] - true)
        mask = before & (np.abs(error) > checks.diameter_tolerance * 2.0 * true)
        stats = interval_stats(time, mask, checks.min_duration)
        if stats is None:
            continue
        worst = int(np.argmax(np.where(before, np.abs(error), -1.0)))
        name = line.spec.rollers[i].name
        roll = f"{name}/{line.spec.webs[line.rolls[j].web].name}"
        when, numbers = _sentence(stats, duration)
        out.append(Finding(
            "warning", "diameter_error", name,
            f"{name}'s calculated diameter stayed more than {checks.diameter_tolerance:.0%} "
            f"off the true one of roll {roll} (largest {1000 * error[worst]:+.3g} mm) {when}",
            stats.first, {**numbers, "roll": roll, "tolerance": checks.diameter_tolerance,
                          "largest_error_m": float(abs(error[worst]))}))
    return out
