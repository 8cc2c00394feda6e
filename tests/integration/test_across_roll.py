"""Modes across the roll (issue 21, docs/winder.md): the closed-loop modes from the rolls as
loaded to an empty unwind, along a scenario or along a run's rolls; a warning with the
diameter where a loop mode's damping falls below the threshold; the CLI and the report."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.analysis.across_roll import modes_across_roll, point_modes
from webline.analysis.modes import closed_loop_modes
from webline.cli import app
from webline.model.operating_point import analysis_time


def test_the_course_conserves_the_web_and_starts_at_the_line_as_loaded():
    line = webline.load_line("converter")
    course = modes_across_roll(line, 15)
    assert len(course.time) == 15
    # (A1): R_u² + R_r² stays what it was (every metre unwound is wound), the unwind ends on
    # its core
    total = course.unwind_radius**2 + course.rewind_radius**2
    np.testing.assert_allclose(total, 0.4**2 + 0.095**2, rtol=1e-12)
    assert course.unwind_radius[-1] == pytest.approx(line.unwind.core_radius, rel=1e-12)
    # the first point is the line as `analyze` sees it
    first = sorted(abs(m.eigenvalue) for m in point_modes(course, 0))
    expected = sorted(abs(m.eigenvalue) for m in closed_loop_modes(line, analysis_time(line)))
    np.testing.assert_allclose(first, expected, rtol=1e-9)


def test_low_damping_along_the_roll_is_a_warning_with_the_diameter():
    # rockwell's rewind speed loop on its belt: the least damped loop mode (rewind_omega,
    # 2.8 rad/s) has zeta 0.106 on the near-empty core and 0.22 on the full roll; with a
    # threshold of 0.15 the first points are below it, the last are not
    course = modes_across_roll("rockwell", 20, threshold=0.15)
    damping = course.least_damping()
    assert damping[0] == pytest.approx(0.106, abs=0.005) and damping[-1] > 0.15
    (finding,) = course.findings()
    assert finding.level == "warning" and finding.kind == "low_damping"
    assert "rewind at 0.178 m" in finding.message  # its 3.5 in core radius: 0.1778 m
    assert finding.details["rewind_diameter_m"] == pytest.approx(2 * 3.5 * 0.0254)
    assert not modes_across_roll("rockwell", 20, threshold=0.1).findings()


def test_analyze_across_roll_along_a_scenario(tmp_path):
    png = tmp_path / "map.png"
    result = CliRunner().invoke(app, ["analyze", "converter", "--scenario", "roll-change",
                                      "--across-roll", "--points", "15", "--json",
                                      "--figure", str(png)])
    assert result.exit_code == 0, result.output
    payload = json.loads(result.stdout)
    points = payload["modes_across_roll"]["points"]
    assert len(points) == 15
    # along the hour of the scenario the unwind empties to 0.24 m and the rewind fills
    assert points[0]["rewind_diameter_m"] == pytest.approx(0.19)
    assert points[-1]["unwind_diameter_m"] == pytest.approx(0.243, abs=0.002)
    assert min(p["damping_ratio"] for p in points) > 0.1
    assert payload["verdict"]["status"] == "ok"
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_a_run_across_a_roll_carries_its_map_into_the_verdict_and_report(tmp_path):
    # hswl winding a 2 mm web (as test_winder): 20 s take 12 % of the unwind's radius
    line = webline.load_line("hswl")
    line = line.replace({"web.thickness": "2 mm", "web.modulus": None, "web.ea": line.ea})
    result = webline.simulate(line, 20.0, record_interval=0.01)
    course = result.roll_modes
    assert course is not None and len(course.time) == 20
    radii = result.radius
    assert course.unwind_radius[-1] == pytest.approx(radii[-1, 0], rel=1e-3)
    from webline.report.writer import write_report

    files = write_report(result, tmp_path)
    html = files.report.read_text(encoding="utf-8")
    assert "Modes across the roll" in html
    assert (tmp_path / "figures" / "across_roll.png").exists()
    summary = json.loads(files.summary.read_text(encoding="utf-8"))
    assert len(summary["modes_across_roll"]["points"]) == 20
    # a short run leaves the rolls as they were: no map
    assert webline.simulate("hswl", 1.0).roll_modes is None
