"""What ``webline show``, the report's tables and the schematic say about the winder functions
(issue 21, item 6): the element that sets each zone's tension, dancers, taper, diameter
calculation, compensation, open-loop mode and break monitoring."""

from __future__ import annotations

import webline
from webline.report.plots.schematic import schematic
from webline.report.text.describe import line_tables
from webline.report.text.display import Display


def _tables(line: webline.Line) -> dict[str, object]:
    return {t.key: t for t in line_tables(line, Display())}


def test_zone_table_names_the_dancer_that_sets_the_unwind_zones_tension():
    for name in ("rockwell", "converter"):
        zones = _tables(webline.load_line(name))["zones"]
        setter = zones.columns.index("tension set by")
        first = zones.rows[0]
        # the dancer in position control sets the tension (load / 2), not the unwind
        assert first[setter].startswith("dancer dancer"), (name, first)
        assert first[zones.columns.index("drive")] == "unwind"
        assert "monitors only" in first[zones.columns.index("loadcell on")]
        # a zone without a dancer: its drive on its loadcell
        assert zones.rows[-1][setter].startswith("drive rewind (loadcell on")


def test_winder_table_shows_dancer_taper_diameter_calculation_and_compensation():
    rows = _tables(webline.load_line("converter"))["winder"].rows
    by_function = {(element, function): setting for element, function, setting in rows}
    dancer = by_function[("dancer", "dancer")]
    for part in ("position control", "load 2 × the zone's reference 150 N", "stroke 0.3 m",
                 "position set point 0.15 m", "moving mass 10 kg"):
        assert part in dancer, dancer
    assert by_function[("rewind", "taper")].startswith("linear: 30 % less")
    calc = by_function[("rewind", "diameter calculation")]
    assert "speed ratio" in calc and "master roller drum" in calc and "filter 0.2 s" in calc
    assert by_function[("unwind", "compensation")] == "inertia J(D)·a_line/R"
    assert by_function[("rewind", "compensation")] == "inertia J(D)·a_line/R"


def test_open_loop_winder_and_break_monitoring_are_shown():
    line = webline.load_line("converter").with_scenario("web-break").replace(
        {"rollers.rewind.winder.mode": "open_loop"})
    tables = _tables(line)
    functions = {(row[0], row[1]) for row in tables["winder"].rows}
    assert ("rewind", "open-loop (indirect) tension") in functions
    assert ("rewind_span", "web break and break monitoring") in functions
    drives = tables["drives"]
    rewind = next(row for row in drives.rows if row[0] == "rewind")
    assert rewind[drives.columns.index("controller")].startswith("open loop")
    zones = tables["zones"]
    assert "open loop" in zones.rows[-1][zones.columns.index("tension set by")]


def test_schematic_shows_who_sets_each_zone_and_the_winder_functions():
    line = webline.load_line("converter").with_scenario("web-break")
    texts = [t.get_text() for t in schematic(line, Display()).axes[0].texts]
    assert "zone 1: tension set by dancer dancer" in texts
    assert "zone 4: tension set by rewind" in texts
    assert any(t.startswith("dancer: position") and "stroke 0.3 m" in t for t in texts)
    assert any("taper linear 30 %" in t and "D calc: speed ratio" in t for t in texts)
    assert "breaks at 5 s" in texts


def test_show_lists_each_flying_splice_with_the_time_its_new_roll_needs():
    """The new rewind core: J = 1.5 + 2.5² 0.05 kg·m² + web from 89 to 95 mm = 1.866 kg·m²,
    at 5 m/s / 0.095 m = 52.63 rad/s; at 2.5 x 150 N·m it takes J ω / 375 N·m = 0.262 s."""
    line = webline.load_line("converter").with_scenario("flying-splice")
    rows = {(row[0], row[1]): row[2] for row in _tables(line)["winder"].rows}
    text = rows[("rewind", "flying splice")]
    assert text.startswith("at 12 s onto a 0.19 m roll, surface speed +1 %, no slack")
    assert "(1.866 kg·m²) reaches 52.63 rad/s in 0.262 s" in text
    assert ("unwind", "flying splice") in rows
    labels = [t.get_text() for t in schematic(line, Display()).axes[0].texts]
    assert any("splice at 12 s" in t for t in labels)


def test_a_dancer_as_tension_sensor_is_what_its_drive_reads():
    line = webline.load_line("converter").replace({"rollers.dancer.dancer.use": "tension",
                                                   "rollers.dancer.dancer.stiffness": "2 kN/m"})
    zones = _tables(line)["zones"]
    first = zones.rows[0]
    assert first[zones.columns.index("tension set by")] == (
        "drive unwind, reading dancer dancer as its sensor")
    assert first[zones.columns.index("loadcell on")] == "unwind_span (monitors only)"
