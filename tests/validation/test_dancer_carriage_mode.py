"""``webline validate`` warns when a dancer carriage's closed-loop mode grows (issue 35 item
5, docs/winder.md D2): a carriage without damping beside a strong tension-to-torque path is
driven unstable by the torque lag, which a run shows only as it grows."""

from __future__ import annotations

import numpy as np
import pytest
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


def _undamped_laminator_dancer() -> dict:
    """The laminator with its film guide a dancer (5 kg, no damping, 500 N/m, read as the
    film zone's tension sensor) and the film unwind's tension loop at 40 rad/s."""
    import copy
    import tomllib
    from importlib import resources

    data = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                         .read_text("utf-8"))
    data = copy.deepcopy(data)
    guide = data["rollers"][1]
    guide["type"] = "dancer"
    guide["dancer"] = {"mass": "5 kg", "travel": "0.2 m", "position": "0.1 m",
                       "damping": "0 N*s/m", "stiffness": "500 N/m", "use": "tension"}
    data["rollers"][0]["controller"]["tension_bandwidth"] = "40 rad/s"
    return data


def test_a_branched_lines_growing_carriage_is_flagged_and_grows_in_its_run(tmp_path):
    """The same check on a branched line (its own linear model, same state names): the
    carriage-led mode grows (Re λ ≈ +9.3 1/s at 18.7 Hz), and the run's carriage swing grows
    at that rate (the envelope over 0.3-0.5 s against 0.5-0.7 s; within 25 %: the run's
    controller is sampled at 1 kHz and the early windows still hold the start's transient)."""
    line = webline.load_line(_undamped_laminator_dancer())
    (mode,) = unstable_carriages(line)
    assert mode.dancer == "guide_film" and mode.damping < 0.0 and mode.share > 0.3
    run = webline.simulate(line, 0.7)
    swing = np.abs(np.ravel(run.dataset["dancer_position"].values) - 0.1)
    t = run.time
    early = swing[(t >= 0.3) & (t < 0.5)].max()
    late = swing[(t >= 0.5) & (t < 0.7)].max()
    assert np.log(late / early) / 0.2 == pytest.approx(mode.eigenvalue.real, rel=0.25)
    path = tmp_path / "undamped-laminator.toml"
    path.write_text(dump_spec(line.spec), encoding="utf-8")
    result = CliRunner().invoke(app, ["validate", str(path)])
    assert result.exit_code == 0, result.output
    assert "dancer guide_film: its carriage's closed-loop mode" in result.stderr
    assert "damping ζ = -" in result.stderr


def test_the_laminator_as_shipped_has_no_carriage_warning():
    result = CliRunner().invoke(app, ["validate", "laminator"])
    assert result.exit_code == 0 and "carriage" not in result.output + result.stderr
