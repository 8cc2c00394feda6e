"""The zone loops' table (docs/winder.md, Z1-Z4): each tension loop's plant, the bandwidth and
damping asked of it and those of its closed-loop mode, the speed loops that let tension leak
through their rollers (Z3), and the modes across the roll, as the terminal and the report
show them."""

from __future__ import annotations

from collections.abc import Sequence

from webline.analysis.zone_loops import ZoneLoop
from webline.control.zone_tuning import SpeedLoopLeak
from webline.report.text.display import Display, number_text
from webline.report.text.tables import Table, make_table
from webline.sim.linear.roll_modes import RollModes


def zone_loops_table(loops: Sequence[ZoneLoop]) -> Table:
    """One row per zone tension loop: drive, what it measures, plant gain per metre of web
    stored (N/m for a tension, m/m for a dancer position), asked and closed-loop ωn [rad/s]
    and ζ, and whether the loop meets what was asked (within 30 %, ζ >= 0.5)."""
    rows = []
    for loop in loops:
        unit = "m/m" if loop.measures == "dancer position" else "N/m"
        rows.append([str(loop.zone + 1), loop.drive, loop.measures,
                     f"{number_text(loop.plant_gain)} {unit}",
                     number_text(loop.asked_bandwidth), number_text(loop.asked_damping, 3),
                     number_text(loop.bandwidth), number_text(loop.damping, 3),
                     "yes" if loop.meets else "no"])
    return make_table("zone_loops", "Tension loops: asked against the closed-loop mode (the "
                      "one the loop's tension integrator takes the largest part in)",
                      ["zone", "drive", "measures", "plant", "asked ωn [rad/s]", "asked ζ",
                       "ωn [rad/s]", "ζ", "meets"], rows)


def leak_lines(leaks: Sequence[SpeedLoopLeak]) -> list[str]:
    """One 'warning: ...' line per speed loop that lets tension leak (Z3)."""
    return [f"warning: {leak.message()}" for leak in leaks]


def roll_modes_table(course: RollModes, display: Display) -> Table:
    """One row per point along the roll: time, diameters, and the least damped oscillatory
    loop mode (ωn [rad/s], ζ, dominant state)."""
    rows = []
    for p, j in enumerate(course.least_damped()):
        value = None if j is None else complex(course.eigenvalues[p][j])
        rows.append([str(p + 1), number_text(float(course.time[p])),
                     display.text(2 * float(course.unwind_radius[p]), "length"),
                     display.text(2 * float(course.rewind_radius[p]), "length"),
                     "–" if value is None else number_text(abs(value)),
                     "–" if value is None else number_text(-value.real / abs(value), 3),
                     "–" if j is None else course.dominant[p][j]])
    return make_table("across_roll", f"Modes across the roll: the least damped loop mode at "
                      f"each point (threshold ζ = {course.threshold:g})",
                      ["point", "time [s]", "unwind diameter", "rewind diameter",
                       "ωn [rad/s]", "ζ", "dominant state"], rows)


def roll_modes_values(course: RollModes) -> dict[str, object]:
    """Plain data (JSON, SI): per point its time, diameters and least damped loop mode."""
    points = []
    for p, j in enumerate(course.least_damped()):
        value = None if j is None else complex(course.eigenvalues[p][j])
        points.append({"time_s": float(course.time[p]),
                       "unwind_diameter_m": 2 * float(course.unwind_radius[p]),
                       "rewind_diameter_m": 2 * float(course.rewind_radius[p]),
                       "natural_frequency_rad_s": None if value is None else abs(value),
                       "damping_ratio": (None if value is None
                                         else -value.real / abs(value)),
                       "dominant_state": None if j is None else course.dominant[p][j]})
    return {"damping_threshold": course.threshold, "points": points}
