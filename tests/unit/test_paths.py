"""Nested key paths (``webline.spec.paths``) and ``Line.replace`` with them."""

from __future__ import annotations

import math

import pytest

from webline import LineFileError, load_line
from webline.spec.paths import parse_assignment, set_path, split_path
from webline.units import ureg


def test_split_path_names_and_indices() -> None:
    assert split_path("rollers[2].drive.ratio") == ["rollers", 2, "drive", "ratio"]
    assert split_path("spans.span3a.length") == ["spans", "span3a", "length"]
    with pytest.raises(ValueError):
        split_path("web..ea")


def test_replace_nested_paths_with_units() -> None:
    line = load_line("hswl")
    changed = line.replace({"rollers.process.controller.tension_bandwidth": "2 Hz",
                            "web.ea": "9 kN", "spans[1].length": "10 m"})
    process = changed.spec.rollers[2]
    # a bandwidth in Hz is cycles per second: 2 Hz = 4π rad/s (docs/line-file.md)
    assert process.controller.tension_bandwidth == pytest.approx(4.0 * math.pi, rel=1e-12)
    assert changed.ea == pytest.approx(9000.0, rel=1e-12)
    assert changed.spec.spans[1].length == pytest.approx(10.0, rel=1e-12)
    # the original is untouched, and everything else is carried over
    assert line.ea == pytest.approx(2000 * 4.4482216152605, rel=1e-9)
    assert changed.spec.spans[0] == line.spec.spans[0]


def test_replace_takes_pint_quantities_and_keywords() -> None:
    line = load_line("hswl").replace({"rollers.unwind.drive.torque_lag": ureg.Quantity(5, "ms")},
                                     speed="800 ft/min")
    assert line.spec.rollers[0].drive.torque_lag == pytest.approx(0.005, rel=1e-12)
    assert line.spec.speed == pytest.approx(800 * 0.3048 / 60, rel=1e-12)


@pytest.mark.parametrize(("path", "expected"), [
    ("rollers.proces.radius", "did you mean 'process'"),
    ("web.eaa.x", "did you mean 'ea'"),
    ("spans[9].length", "index out of range"),
    ("speed.value", "is a value, not a table"),
])
def test_replace_names_the_bad_path(path: str, expected: str) -> None:
    with pytest.raises(LineFileError, match=expected):
        load_line("hswl").replace({path: 1.0})


def test_replace_unknown_leaf_is_refused_by_the_schema() -> None:
    with pytest.raises(LineFileError, match="torque_limt"):
        load_line("hswl").replace({"rollers.unwind.drive.torque_limt": "10 N*m"})


def test_set_path_in_place_and_assignments() -> None:
    data = {"a": [{"name": "x", "v": 1}], "b": {"c": 2}}
    set_path(data, "a.x.v", 3)
    set_path(data, "b.c", {"type": "ramp"})
    assert data == {"a": [{"name": "x", "v": 3}], "b": {"c": {"type": "ramp"}}}
    assert parse_assignment("web.ea=9 kN") == ("web.ea", "9 kN")
    assert parse_assignment("control.sample_rate = 500") == ("control.sample_rate", 500)
    assert parse_assignment('x={type = "ramp", initial = 1}') == (
        "x", {"type": "ramp", "initial": 1})
    with pytest.raises(ValueError):
        parse_assignment("no-equals-sign")


def test_scenario_set_steps_a_tension_reference() -> None:
    line = load_line("hswl").with_scenario("tension-step")
    profile = line.spec.spans[1].tension
    assert profile.type == "steps"
    assert profile.initial == pytest.approx(14.35 * 4.4482216152605, rel=1e-12)
    assert profile.steps[0].time == 2.0
    assert profile.steps[0].value == pytest.approx(18 * 4.4482216152605, rel=1e-12)
    assert line.spec.spans[0].tension == load_line("hswl").spec.spans[0].tension


def test_scenario_set_with_a_bad_path_names_the_scenario() -> None:
    data = load_line("hswl").spec.model_dump(exclude_none=True)
    data["scenarios"] = {"bad": {"duration": 1.0, "set": {"spans.span9.tension": 10.0}}}
    with pytest.raises(LineFileError) as info:
        load_line(data).with_scenario("bad")
    assert info.value.file == "<dict>"
    assert info.value.key == "scenarios.bad.set: spans.span9"
    assert "no name 'span9' here; did you mean" in info.value.problem


def test_tension_step_scenario_is_tracked() -> None:
    """The process zone's PI (8 rad/s tension loop, critically damped) follows the stepped
    reference: 14.35 lbf before the step, 18 lbf to 0.1 % six seconds after it (many time
    constants of the 8 rad/s loop)."""
    from webline import simulate

    lbf = 4.4482216152605
    result = simulate("hswl", scenario="tension-step")
    span2 = result.tension[:, 1]
    before, after = result.time < 1.9, result.time > 8.0
    assert span2[before].mean() == pytest.approx(14.35 * lbf, rel=1e-3)
    assert span2[after].mean() == pytest.approx(18.0 * lbf, rel=1e-3)
    assert result.tension_ref[-1, 1] == pytest.approx(18.0 * lbf, rel=1e-12)
