"""``webline validate`` warns when a dancer carriage's closed-loop mode grows (issue 35 item
5, docs/winder.md D2): a carriage without damping beside a strong tension-to-torque path is
driven unstable by the torque lag, which a run shows only as it grows."""

from __future__ import annotations

import numpy as np
from typer.testing import CliRunner

import webline
from webline.analysis.dancer_modes import carriage_modes, unstable_carriages
from webline.cli import app
from webline.spec.load import dump_spec

#: rockwell's dancer as the unwind zone's tension sensor (500 N/m), no damping, the unwind's
#: tension loop at 40 rad/s: its carriage mode at 7 Hz grows (Re λ = +12 1/s)
UNSTABLE = {"rollers.dancer.dancer.damping": 0.0, "rollers.dancer.dancer.use": "tension",
            "rollers.dancer.dancer.stiffness": "500 N/m",
            "rollers.unwind.controller.tension_bandwidth": "40 rad/s"}


def test_an_undamped_carriage_beside_a_fast_tension_loop_is_flagged(tmp_path):
    line = webline.load_line("rockwell").replace(UNSTABLE)
    (mode,) = unstable_carriages(line)
    assert mode.dancer == "dancer" and mode.damping < 0.0
    # it is the carriage's own mode: the closed-loop model's growing eigenvalue, carriage-led
    values = np.linalg.eigvals(webline.linearize(line).A)
    assert np.isclose(values, mode.eigenvalue).any() and mode.share > 0.3
    path = tmp_path / "undamped.toml"
    path.write_text(dump_spec(line.spec), encoding="utf-8")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 0, result.output
    assert "dancer dancer: its carriage's closed-loop mode" in result.stderr
    assert "damping ζ = -" in result.stderr


def test_rockwell_as_shipped_has_a_damped_carriage():
    (mode,) = carriage_modes("rockwell")
    assert mode.damping > 0.5  # 150 N·s/m on 3 kg, the position loop around it
    result = CliRunner().invoke(app, ["validate", "rockwell"])
    assert result.exit_code == 0 and "carriage" not in result.output
