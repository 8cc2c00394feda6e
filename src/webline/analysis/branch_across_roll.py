"""Closed-loop modes across the rolls of a branched line (docs/branching.md, "Modes across the
rolls"): the chain's ``sim.linear.roll_modes`` on a tree of webs. The line is linearized
(``sim.branches.linear``) at a modest number of points along the rolls' course, with the
controllers as the run has them: gains designed once, at the start (the plan's), a speed
loop that follows its roll's inertia does so (J/r at the point), a state-feedback drive's
g = J/(nR) too.

The course. Every roll on the line passes the same length s of web (all webs run at the
line speed, to their strains' 1e-3), so with its own web's thickness h (a laminate's: the
sum of its layers'; a lane's: its own) each roll's radius follows (6.6), d(R²)/ds = ∓h/π:

    R_u² = R_u0² - h s / π,    R_r² = R_r0² + h s / π                              (A1)

for every unwind and every rewind (each lane on a shared shaft its own radius). Without a
scenario, s runs from 0 until the first unwind reaches its core, at the analysis time's
references; along a scenario, s(t) = ∫ |v_ref| dt over its duration and each point is
linearized at the references of its time; a roll change (``roll_change``) or an unwind's
flying splice puts its unwind back to its new radius at its time.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from webline.errors import ArgumentError
from webline.model.web_graph import BranchedLine, load_branched
from webline.profiles import breakpoints
from webline.sim.branches.equilibrium import analysis_time, operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.plan import BranchPlan, compile_branches
from webline.sim.linear.roll_modes import (
    DAMPING_THRESHOLD,
    POINTS,
    RollModes,
    classified_modes,
)
from webline.spec.schema import RewindSpec, UnwindSpec
from webline.verdict import Finding


@dataclass(frozen=True)
class BranchRollModes(RollModes):
    """``RollModes`` of a branched line: ``unwind_radius`` and ``rewind_radius`` [m] are the
    first unwind's and first rewind's (the map's axis); ``rolls`` names every roll
    (``node/web``), ``radius`` [m] holds each one's per point (points × rolls), ``length`` [m]
    the web run through the line at each point."""

    rolls: tuple[str, ...] = ()
    radius: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    length: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def findings(self) -> list[Finding]:
        """The chain's warning where a loop mode's damping falls below the threshold, with
        every roll's diameter where it is least damped."""
        found = super().findings()
        if not found:
            return found
        worst = int(np.argmin(np.nan_to_num(self.least_damping(), nan=np.inf)))
        first = found[0]
        diameters = ", ".join(f"{name} {2 * r:.3g} m" for name, r in
                              zip(self.rolls, self.radius[worst], strict=True))
        message = first.message.split(" with the rewind at")[0]
        low = int(np.sum(self.least_damping() < self.threshold))
        return [Finding(first.level, first.kind, first.where,
                        f"{message} with the rolls at {diameters} (diameters); below the "
                        f"threshold at {low} of {len(self.time)} points along the rolls",
                        first.time, {**first.details, "diameters_m": {
                            name: 2 * float(r) for name, r in
                            zip(self.rolls, self.radius[worst], strict=True)}})]


def roll_names(line: BranchedLine) -> tuple[str, ...]:
    """``node/web`` of every roll of ``line`` (``BranchedLine.rolls`` order)."""
    return tuple(f"{line.spec.rollers[r.node].name}/{line.spec.webs[r.web].name}"
                 for r in line.rolls)


def branch_roll_course(line: BranchedLine, points: int = POINTS, duration: float | None = None
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(time [s], web length run [m], radii [m] points × rolls) along the course (A1): from
    the rolls as loaded until the first unwind is at its core, or along ``duration`` [s] of
    the line's speed reference."""
    rolls = line.rolls
    start = np.array([r.radius for r in rolls])
    per_length = np.array([line.materials[r.web].thickness / math.pi for r in rolls])
    core = np.array([_core(line, r.node) for r in rolls])
    unwinding = np.array([r.direction < 0 for r in rolls])
    if duration is None:
        empty = (start**2 - core**2)[unwinding] / per_length[unwinding]
        length = np.linspace(0.0, float(np.min(empty)) if empty.size else 0.0, points)
        time = np.full(points, analysis_time(line))
        changed = np.full((points, len(rolls)), np.nan)
    else:
        times, values = breakpoints(line.spec.speed)
        fine = np.union1d(np.linspace(0.0, duration, 20 * points), times[times <= duration])
        speed = np.abs(np.interp(fine, times, values))
        wound = np.r_[0.0, np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(fine))]
        time = np.linspace(0.0, duration, points)
        length = np.interp(time, fine, wound)
        changed = _roll_changes(line, time, fine, wound)
    sign = np.where(unwinding, -1.0, 1.0)
    squared = start**2 + sign * per_length * length[:, None]
    renewed = np.isfinite(changed)  # after a roll change: the new roll from its own start
    squared[renewed] = changed[renewed]
    radius = np.sqrt(np.maximum(squared, core**2))
    return time, length, radius


def _core(line: BranchedLine, node: int) -> float:
    roller = line.spec.rollers[node]
    assert isinstance(roller, UnwindSpec | RewindSpec)
    return float(roller.core_radius)


def _roll_changes(line: BranchedLine, time: np.ndarray, fine: np.ndarray,
                  wound: np.ndarray) -> np.ndarray:
    """R² [m²] per point and roll of an unwind renewed by the scenario's ``roll_change`` or
    a ``flying_splice`` disturbance (NaN where none): the new radius at its time, unwinding
    from there (A1)."""
    out = np.full((len(time), len(line.rolls)), np.nan)
    renewals = [] if line.roll_change is None else [
        (line.roll_change.roller, line.roll_change.time, line.roll_change.radius)]
    renewals += [(item.roll, item.at, 0.5 * item.new_diameter)
                 for item in line.spec.disturbances if item.type == "flying_splice"]
    for name, at, radius in renewals:
        run = float(np.interp(at, fine, wound))
        for j, roll in enumerate(line.rolls):
            if line.spec.rollers[roll.node].name != name or roll.direction > 0:
                continue
            h = line.materials[roll.web].thickness / math.pi
            after = time >= at
            out[after, j] = radius**2 - h * (np.interp(time[after], fine, wound) - run)
    return out


def branch_roll_modes(plan: BranchPlan, time: np.ndarray, radius: np.ndarray,
                      length: np.ndarray, threshold: float = DAMPING_THRESHOLD
                      ) -> BranchRollModes:
    """The closed-loop modes of ``plan`` at each time [s] with the rolls at ``radius`` [m]
    (points × rolls), ordered, kept and classified as the chain's ``roll_modes``."""
    line = plan.line
    driven = {f"{line.spec.rollers[i].name}_omega" for i in line.drives}
    eigenvalues, dominant, loops = [], [], []
    for t, radii in zip(time, radius, strict=True):
        model = branch_linear_model(plan, operating_point(plan, float(t), radii=radii),
                                    "closed")
        values, names, in_loop = classified_modes(model, driven)
        eigenvalues.append(values)
        dominant.append(names)
        loops.append(in_loop)
    first_unwind = next((j for j, r in enumerate(line.rolls) if r.direction < 0), 0)
    first_rewind = next((j for j, r in enumerate(line.rolls) if r.direction > 0), 0)
    return BranchRollModes(np.asarray(time, dtype=float), radius[:, first_unwind].copy(),
                           radius[:, first_rewind].copy(), tuple(eigenvalues),
                           tuple(dominant), tuple(loops), threshold, roll_names(line),
                           np.asarray(radius, dtype=float), np.asarray(length, dtype=float))


def modes_across_rolls(line: BranchedLine | str, points: int = POINTS, *,
                       scenario: str | None = None,
                       threshold: float = DAMPING_THRESHOLD) -> BranchRollModes:
    """Closed-loop modes of branched ``line`` at ``points`` points along its rolls' course
    (module docstring): from the rolls as loaded until the first unwind is empty, or along
    ``scenario``'s duration. Loop modes damped less than ``threshold`` somewhere make
    ``findings()`` a warning naming the rolls' diameters."""
    line = load_branched(line)
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise ArgumentError(f"points: expected a whole number >= 2, got {points!r}")
    if not threshold >= 0.0:
        raise ArgumentError(f"threshold: must be >= 0, got {threshold!r}")
    duration = None
    if scenario is not None:
        line = line.with_scenario(scenario)
        duration = float(line.spec.scenarios[scenario].duration)
    if not any(r.direction < 0 for r in line.rolls) and duration is None:
        raise ArgumentError(f"{line.name}: no unwind to run empty; give a scenario to follow "
                            "its course")
    time, length, radius = branch_roll_course(line, points, duration)
    return branch_roll_modes(compile_branches(line), time, radius, length, threshold)
