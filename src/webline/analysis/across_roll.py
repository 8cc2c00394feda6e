"""Closed-loop modes across the roll, the public API (docs/winder.md, "Modes across the
roll"); the numbers come from ``webline.sim.linear.roll_modes`` (which the run's verdict uses
too)."""

from __future__ import annotations

from webline.analysis.modes import Mode
from webline.errors import ArgumentError
from webline.line import Line, load_line
from webline.sim.linear.roll_modes import (
    DAMPING_THRESHOLD,
    POINTS,
    RollModes,
    roll_course,
    roll_modes,
)


def modes_across_roll(line: Line | str, points: int = POINTS, *,
                      duration: float | None = None,
                      threshold: float = DAMPING_THRESHOLD) -> RollModes:
    """Closed-loop modes of ``line`` at ``points`` points along the roll: from the rolls as
    loaded until the unwind is empty (at the analysis time's references), or along
    ``duration`` [s] of its speed reference (a scenario's course: pass the scenario's line,
    ``line.with_scenario(name)``, and its duration). Loop modes damped less than
    ``threshold`` somewhere make ``RollModes.findings()`` a warning naming the diameters."""
    line = load_line(line)
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise ArgumentError(f"points: expected a whole number >= 2, got {points!r}")
    if not threshold >= 0.0:
        raise ArgumentError(f"threshold: must be >= 0, got {threshold!r}")
    time, unwind, rewind = roll_course(line, points, duration)
    return roll_modes(line, time, unwind, rewind, threshold)


def point_modes(course: RollModes, p: int) -> list[Mode]:
    """The modes at point ``p`` of ``course`` as ``Mode`` objects (slowest first)."""
    return [Mode(complex(v), name) for v, name in zip(course.eigenvalues[p], course.dominant[p],
                                                       strict=True)]
