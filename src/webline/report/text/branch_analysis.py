"""``webline analyze`` of a branched line as tables and plain data in the chosen units
(docs/branching.md, "Linear models"): the operating point's spans and rollers, and the modes
across the rolls.

Per-width systems: each web has its own width (a laminate the narrowest layer's, a lane its
own), so each span's tension is divided by its own web's width, which the spans table
shows beside it; everything else is in the per-width system's base (SI or imperial)."""

from __future__ import annotations

from typing import Any

from webline.analysis.branch_across_roll import BranchRollModes
from webline.report.text.branch_tables import small_length
from webline.report.text.display import Display, number_text
from webline.report.text.tables import Table, make_table


def web_display(display: Display, width: float) -> Display:
    """``display`` for the tensions of a web ``width`` [m] wide (its own per-width)."""
    return display.at_width(width)


def base_display(display: Display) -> Display:
    """``display`` without the per-width: the system that lengths, speeds, torques take."""
    return display.base()


def _tension_display(display: Display) -> Display:
    """A ``Display`` that names the tensions' unit (a per-width one with a unit width)."""
    return web_display(display, 1.0)


def point_values(spans: list[dict[str, Any]], rollers: list[dict[str, Any]],
                 display: Display) -> dict[str, Any]:
    """The operating point's rows (SI: ``cli_analyze._branch_point_rows``) in ``display``'s
    units: per span its web, the web's width and tension, per roller its surface speed,
    ω [rad/s] and motor torque; the units used."""
    base = base_display(display)
    return {
        "units": {"tension": _tension_display(display).plain_unit("force"),
                  "speed": base.plain_unit("speed"), "torque": base.plain_unit("torque"),
                  "width": small_length(display)[1]},
        "spans": [{"span": r["span"], "web": r["web"],
                   "web_width": small_length(display)[0] * r["width_m"],
                   "tension": web_display(display, r["width_m"]).value(r["tension_N"], "force")}
                  for r in spans],
        "rollers": [{"roller": r["roller"], "speed": base.value(r["speed_m_s"], "speed"),
                     "omega_rad_s": r["omega_rad_s"],
                     "torque": None if r["torque_Nm"] is None
                     else base.value(r["torque_Nm"], "torque")} for r in rollers]}


def point_tables(spans: list[dict[str, Any]], rollers: list[dict[str, Any]], t: float,
                 display: Display) -> list[Table]:
    """The spans' and rollers' tables of the operating point at ``t`` [s] in ``display``'s
    units (``point_values``); a per-width system adds each span's web width."""
    values = point_values(spans, rollers, display)
    base = base_display(display)
    span_columns = ["span", "web", _tension_display(display).label("tension", "force")]
    span_rows = [[r["span"], r["web"], number_text(r["tension"])] for r in values["spans"]]
    if display.per_width:  # each web its own width: say which one divides its tension
        span_columns.append(f"web width [{small_length(display)[1]}]")
        for row, r in zip(span_rows, values["spans"], strict=True):
            row.append(number_text(r["web_width"]))
    return [
        make_table("spans", f"Operating point at t = {t:g} s: spans", span_columns, span_rows),
        make_table("rollers", "Operating point: rollers",
                   ["roller", base.label("surface speed", "speed"), "ω [rad/s]",
                    base.label("torque", "torque")],
                   [[r["roller"], number_text(r["speed"]), number_text(r["omega_rad_s"]),
                     number_text(r["torque"])] for r in values["rollers"]])]


def rolls_modes_table(course: BranchRollModes, display: Display) -> Table:
    """One row per point along the rolls' course: time, web length run, every roll's
    diameter, and the least damped oscillatory loop mode (ωn [rad/s], ζ, dominant state)."""
    base = base_display(display)
    rows = []
    for p, j in enumerate(course.least_damped()):
        value = None if j is None else complex(course.eigenvalues[p][j])
        rows.append([str(p + 1), number_text(float(course.time[p])),
                     number_text(base.value(float(course.length[p]), "length")),
                     *(number_text(base.value(2 * float(r), "length"))
                       for r in course.radius[p]),
                     "–" if value is None else number_text(abs(value)),
                     "–" if value is None else number_text(-value.real / abs(value), 3),
                     "–" if j is None else course.dominant[p][j]])
    return make_table("across_roll", f"Modes across the rolls: the least damped loop mode at "
                      f"each point (threshold ζ = {course.threshold:g})",
                      ["point", "time [s]", base.label("web run", "length"),
                       *(base.label(f"{name} ⌀", "length") for name in course.rolls),
                       "ωn [rad/s]", "ζ", "dominant state"], rows)


def rolls_modes_values(course: BranchRollModes, display: Display) -> dict[str, Any]:
    """Plain data of the course in ``display``'s lengths: per point its time [s], web run,
    every roll's diameter and the least damped loop mode."""
    base = base_display(display)
    points = []
    for p, j in enumerate(course.least_damped()):
        value = None if j is None else complex(course.eigenvalues[p][j])
        points.append({"time_s": float(course.time[p]),
                       "web_run": base.value(float(course.length[p]), "length"),
                       "diameters": {name: base.value(2 * float(r), "length")
                                     for name, r in zip(course.rolls, course.radius[p],
                                                        strict=True)},
                       "natural_frequency_rad_s": None if value is None else abs(value),
                       "damping_ratio": (None if value is None
                                         else -value.real / abs(value)),
                       "dominant_state": None if j is None else course.dominant[p][j]})
    return {"damping_threshold": course.threshold, "length_unit": base.plain_unit("length"),
            "points": points}
