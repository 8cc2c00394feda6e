"""Taper through a dancer (issue 21, docs/winder.md W1): in dancer position control the taper
sets the dancer's load, so the tension follows the taper; a setting where a taper cannot act
is reported by validate."""

from __future__ import annotations

import pytest

import webline
from webline.physics.taper import spec_factor

REWIND_DANCER = {"mass": "10 kg", "travel": "0.3 m", "position": "0.15 m",
                 "damping": "500 N*s/m", "use": "position"}


def rewind_dancer_line(radius: float, **carriage: object) -> webline.Line:
    """converter whose guide roller before the rewind is a dancer in position control (the
    rewind's zone tension is then its load / 2), the rewind at ``radius`` [m]."""
    data = webline.load_line("converter").spec.model_dump(exclude_none=True)
    guide = data["rollers"][6]
    assert guide["name"] == "guide_out"
    data["rollers"][6] = {**guide, "type": "dancer", "dancer": {**REWIND_DANCER, **carriage}}
    data["rollers"][-1]["radius"] = radius
    return webline.load_line(data)


@pytest.mark.parametrize("radius", [0.2, 0.35])
def test_taper_through_a_dancer_sets_the_tension(radius):
    line = rewind_dancer_line(radius)
    rewind = line.rewind
    factor = spec_factor(rewind.taper, rewind.core_radius, radius)
    assert factor < 0.9  # the taper asks 11-25 % less than the 150 N at the core here
    result = webline.simulate(line, 2.0)
    # the dancer's load follows the taper (2 x 150 N x f): with the carriage at rest the
    # spans carry load/2; the web's friction at the rollers moves it by < 0.5 % (1 % kept)
    for span in ("exit_span", "rewind_span"):
        k = [line.span_name(j) for j in range(line.n_spans)].index(span)
        assert result.tension[-1, k] == pytest.approx(150.0 * factor, rel=0.01)
    assert result.verdict.status == "ok"


def test_taper_that_cannot_act_is_reported():
    # an air-loaded dancer in a loadcell zone sets the tension by its load, which the
    # taper does not change: validate says so (a warning naming the dancer and the taper)
    line = rewind_dancer_line(0.2, use="none")
    assert any("taper" in w and "guide_out" in w for w in line.warnings), line.warnings
    # a taper of 0 does nothing
    plain = webline.load_line("converter").replace({"rollers.rewind.taper.taper": 0.0})
    assert any("rollers[7].taper" in w for w in plain.warnings), plain.warnings
    assert not webline.load_line("converter").warnings


def test_a_dancer_as_tension_sensor_needs_a_spring():
    from webline.errors import LineFileError

    with pytest.raises(LineFileError) as info:
        webline.load_line("converter").replace({"rollers.dancer.dancer.use": "tension"})
    assert info.value.key == "rollers[1].dancer.stiffness"


def test_validate_prints_the_winder_and_tuning_warnings(tmp_path):
    from typer.testing import CliRunner

    from webline.cli import app

    result = CliRunner().invoke(app, ["validate", "converter"])
    assert result.exit_code == 0, result.output
    # converter's infeed on its 20 rad/s speed loop leaks 79 % (test_dancer_tuning)
    assert "rollers.infeed.controller.speed_bandwidth" in result.output
