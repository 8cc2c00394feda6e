"""The built-in `converter` line (issue 15 item 9): each scenario ends with its expected
verdict through the command line (`webline run converter --scenario NAME`)."""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app


def run(scenario: str, out) -> dict:
    """`webline run converter --scenario NAME`: its exit code must be 0 (ok or warning);
    returns summary.json."""
    result = CliRunner().invoke(app, ["run", "converter", "--scenario", scenario, "--out",
                                      str(out), "--quiet"])
    assert result.exit_code == 0, result.output
    return json.loads((out / "summary.json").read_text())


def test_startup_is_ok(tmp_path):
    """From rest to 300 m/min in 20 s: ok with no finding at all (no slack, no torque at its
    limit, no tension over the limit; the linear model at line speed is stable)."""
    verdict = run("startup", tmp_path)["verdict"]
    assert verdict["status"] == "ok" and verdict["findings"] == []


@pytest.mark.slow  # 4000 s of line (4 million ticks) and its report: ~35 s on a shared core
def test_roll_change_is_ok_and_winds_a_whole_roll(tmp_path):
    written = run("roll-change", tmp_path)
    assert written["verdict"]["status"] == "ok", written["verdict"]


def test_roll_change_winds_the_rewind_from_core_to_full():
    """The same scenario through the API: the unwind ends near its core, the rewind near
    0.4 m, its calculated diameter within 1 % of the true one after the first revolutions and
    the taper lowering its zone's reference by 30 % x (D - D_c)/(0.8 m - D_c)."""
    line = webline.load_line("converter")
    result = webline.simulate(line, scenario="roll-change")
    radius = result.radius
    assert radius[-1, 0] < 0.13 and radius[-1, -1] > 0.39  # a whole roll
    winding = result.time > 30.0
    error = result.control_radius[winding, -1] / radius[winding, -1] - 1.0
    assert abs(error).max() < 0.01
    core = line.rewind.core_radius
    factor = 1 - 0.3 * (radius[-1, -1] - core) / (0.4 - core)
    assert result.tension_ref[-1, -1] == pytest.approx(150.0 * factor, rel=1e-3)


def test_web_break_is_a_warning_detected_by_tension_within_50_ms(tmp_path):
    verdict = run("web-break", tmp_path)["verdict"]
    assert verdict["status"] == "warning"
    found = [f for f in verdict["findings"] if f["kind"] == "web_break"]
    assert len(found) == 1
    details = found[0]["details"]
    assert details["span"] == "rewind_span" and details["break_s"] == 5.0
    assert details["method"] == "tension below its threshold"
    assert 0.0 <= details["time_to_detect_s"] < 0.05
    assert "detected by tension below its threshold" in found[0]["message"]
    assert all(f["level"] == "warning" for f in verdict["findings"])


def test_flying_splice_is_ok_and_its_report_shows_both_splices(tmp_path):
    """Both rolls spliced on the run (docs/winder.md, Flying splice): ok, and the report's
    splice figure says, from the run, what each splice did to the tension."""
    verdict = run("flying-splice", tmp_path)["verdict"]
    assert verdict["status"] == "ok", verdict
    report = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "Flying splices: unwind spliced onto a 0.8 m roll at t = 4 s" in report
    assert "rewind spliced onto a 0.19 m roll at t = 12 s" in report
    assert (tmp_path / "figures" / "splice.png").exists()
    # the line section shows the zones with what sets their tension, and the winder functions
    assert "Tension zones" in report and "Winder functions" in report
    assert "dancer dancer (its load / 2; drive unwind holds the dancer&#x27;s position)" in report
