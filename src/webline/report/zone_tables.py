"""The zone loops' table (docs/winder.md, Z1-Z4): each tension loop's plant, the bandwidth and
damping asked of it and those of its closed-loop mode, and the speed loops that let tension
leak through their rollers (Z3), as the terminal and the report show them."""

from __future__ import annotations

from collections.abc import Sequence

from webline.analysis.zone_loops import ZoneLoop
from webline.control.zone_tuning import SpeedLoopLeak
from webline.report.display import number_text
from webline.report.tables import Table, make_table


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
