"""Each drive's train is shown in the drives table (`webline show`, the report) and the
schematic: transmission, backlash, the side its speed is measured on, brake (issue 11 item 2)."""

from __future__ import annotations

from importlib import resources

import webline
from webline.report.plots.schematic import schematic
from webline.report.text.describe import line_tables
from webline.report.text.display import Display

ROCKWELL = resources.files("webline.data.lines").joinpath("rockwell.toml").read_text("utf-8")
BELT = 'damping = "50 N*s/m" }'


def _drives(line, units="si"):
    table = next(t for t in line_tables(line, Display(units)) if t.key == "drives")
    return {row[0]: dict(zip(table.columns, row, strict=True)) for row in table.rows}


def _train_line(tmp_path):
    """rockwell with the rewind's belt given an asymmetric backlash and a 2 N·m brake."""
    assert BELT in ROCKWELL
    text = ROCKWELL.replace(BELT, 'damping = "50 N*s/m", backlash = { gap = "0.01 rad", '
                            'asymmetry = 0.3 } }\nbrake = "2 N*m"', 1)
    path = tmp_path / "train.toml"
    path.write_text(text, encoding="utf-8")
    return webline.load_line(str(path))


def test_rockwell_drives_table_shows_belt_and_motor_feedback():
    drives = _drives(webline.load_line("rockwell"))
    rewind, unwind = drives["rewind"], drives["unwind"]
    assert rewind["transmission"].startswith("belt 2e+05 N/m")
    assert "0.0508 m" in rewind["transmission"]  # 2 in load pulley
    assert rewind["speed measured on"] == "motor"
    assert rewind["backlash"] == "none" and rewind["brake"] == "none"
    assert unwind["transmission"] == "direct" and unwind["speed measured on"] == "load"


def test_belt_backlash_brake_line_in_table_and_schematic(tmp_path):
    line = _train_line(tmp_path)
    rewind = _drives(line)["rewind"]
    # asymmetry 0.3 of a 0.01 rad gap: free travel 2·0.01·0.3 back, 2·0.01·0.7 forward
    assert rewind["backlash"] == "-0.006 rad / +0.014 rad"
    assert rewind["brake"] == "2 N·m"
    assert _drives(line, "imperial")["rewind"]["brake"] == "1.475 lbf·ft"
    texts = [t.get_text() for t in schematic(line).axes[0].texts]
    label = next(t for t in texts if t.startswith("belt"))
    assert label.split("\n") == ["belt", "backlash -0.006 rad / +0.014 rad", "speed at motor",
                                 "brake"]
    assert sum(t.startswith("direct\n") for t in texts) == 2  # unwind and pull roll
