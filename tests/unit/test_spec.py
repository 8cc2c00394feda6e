"""Line files: the built-in HSWL, topology derived from a spec, round trips, and one clear
``LineFileError`` (file, key path, problem) for each kind of malformed input."""

from __future__ import annotations

import copy
import re
import tomllib
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

import pytest

import webline
from webline.errors import LineFileError
from webline.line import Line, Zone, load_line
from webline.spec.load import builtin_lines, dump_spec, read_spec, spec_from_dict
from webline.spec.schema import LineSpec

FT = 0.3048
INCH = 0.0254
LB = 0.45359237
LBF = 4.4482216152605

HSWL_TEXT = resources.files("webline.data.lines").joinpath("hswl.toml").read_text("utf-8")


def hswl_dict() -> dict[str, Any]:
    """A fresh copy of the built-in HSWL line file as plain TOML data."""
    return tomllib.loads(HSWL_TEXT)


def six_section_dict() -> dict[str, Any]:
    """A 7-roller, 6-span line written in Python: mixed SI numbers and unit strings, all
    profile kinds, disturbances and a scenario. Driven nodes 0, 1, 3, 4, 6 (master 3)."""
    drive = {"torque_limit": 50.0}
    return {
        "name": "six",
        "description": "dict-built test line",
        "web": {"thickness": 25e-6, "width": 1.0, "density": 1400.0, "modulus": "4 GPa"},
        "speed": {"type": "table", "time": [0.0, 5.0, 10.0], "value": [0.0, 2.0, "600 ft/min"]},
        "control": {"sample_rate": 500.0},
        "rollers": [
            {"name": "unwind", "type": "unwind", "radius": 0.5, "core_radius": 0.08,
             "inertia": 2.0, "wound_in_tension": 90.0,
             "drive": {"torque_limit": 200.0, "ratio": 2.0}},
            {"name": "infeed", "type": "driven", "role": "tension", "radius": 0.1,
             "inertia": 0.05, "drive": drive},
            {"name": "idle1", "type": "idle", "radius": 0.05, "inertia": 0.001,
             "friction": 1e-4},
            {"name": "master", "type": "driven", "role": "master", "radius": 0.1,
             "inertia": 0.05, "drive": drive},
            {"name": "outfeed", "type": "driven", "role": "tension", "radius": "4 in",
             "inertia": "1 lb*ft**2", "coulomb_friction": 0.01, "drive": drive,
             "controller": {"type": "cascaded_pi", "tension_bandwidth": "5 rad/s",
                            "inertia_adaptive": False}},
            {"name": "idle2", "type": "idle", "radius": 0.05, "inertia": 0.001},
            {"name": "rewind", "type": "rewind", "radius": 0.2, "core_radius": 0.08,
             "inertia": 1.0, "drive": {"torque_limit": 200.0, "motor_inertia": 0.01},
             "controller": {"type": "cascaded_pi", "speed_kp": 5.0, "speed_ki": 20.0}},
        ],
        "spans": [
            {"length": 2.0, "tension": 100.0},
            {"length": 3.0},
            {"name": "long", "length": "10 ft",
             "tension": {"type": "ramp", "initial": 50.0, "final": "30 lbf", "duration": 2.0}},
            {"length": 1.5, "tension": {"type": "steps", "initial": 80.0,
                                         "steps": [{"time": 1.0, "value": 90.0}]}},
            {"length": 4.0, "tension": {"type": "table", "time": [0, 1], "value": [70, 75]}},
            {"length": 2.0},
        ],
        "disturbances": [
            {"type": "speed_ripple", "roller": "master", "amplitude": 0.01, "frequency": 2.0},
            {"type": "eccentric_roller", "roller": "idle1", "eccentricity": 1e-5},
        ],
        "scenarios": {
            "fast": {"duration": 10.0, "speed": 5.0, "rewind_radius": 0.3,
                     "disturbances": [{"type": "wound_in_ripple", "amplitude": 1.0,
                                       "frequency": 1.0, "phase": "90 deg"}]},
        },
    }


def reload(spec: LineSpec) -> LineSpec:
    return spec_from_dict(tomllib.loads(dump_spec(spec)), "dumped.toml")


# --- the built-in HSWL -----------------------------------------------------------------------


@pytest.fixture(scope="module")
def hswl() -> Line:
    return load_line("hswl")


def test_hswl_is_a_builtin_line() -> None:
    lines = builtin_lines()
    assert "hswl" in lines
    assert lines["hswl"].startswith("High Speed Web Line")


def test_hswl_loads_with_its_label(hswl: Line) -> None:
    assert hswl.name == "hswl"
    assert hswl.source == "hswl.toml (built-in)"
    assert webline.load_line("hswl").spec == hswl.spec


def test_hswl_table_6_1_values_in_si(hswl: Line) -> None:
    spec = hswl.spec
    assert spec.speed == pytest.approx(500 * FT / 60, rel=1e-15)
    assert hswl.ea == pytest.approx(2000 * LBF, rel=1e-15)
    assert [s.length for s in spec.spans] == pytest.approx(
        [20 * FT, 33 * FT, 33.5 * FT, 33.5 * FT], rel=1e-15)
    assert spec.spans[2].tension is None  # span3a: the idler splits zone 3, no loadcell
    for k in (0, 1, 3):
        assert spec.spans[k].tension == pytest.approx(14.35 * LBF, rel=1e-15)
    assert [r.radius for r in spec.rollers] == pytest.approx(
        [1.25 * FT, 0.339 * FT, 0.339 * FT, 1.5 * INCH, 0.67 * FT], rel=1e-15)
    assert [r.inertia for r in spec.rollers] == pytest.approx(
        [8 * LB * FT**2, 2 * LB * FT**2, 2 * LB * FT**2, 0.001, 4 * LB * FT**2], rel=1e-15)
    assert spec.rollers[0].friction == pytest.approx(0.5 * LBF * FT, rel=1e-15)
    assert spec.rollers[0].drive.ratio == 0.5
    assert spec.rollers[0].drive.torque_lag == pytest.approx(0.002, rel=1e-15)
    assert spec.control.sample_rate == 1000.0


def test_hswl_topology(hswl: Line) -> None:
    assert hswl.n_nodes == 5
    assert hswl.n_spans == 4
    assert [hswl.node_name(i) for i in range(5)] == [
        "unwind", "master", "process", "idler", "rewind"]
    assert hswl.master == 1
    assert hswl.drives == (0, 1, 2, 4)
    assert hswl.unwind.name == "unwind"
    assert hswl.rewind.name == "rewind"


def test_hswl_zones_and_who_controls_them(hswl: Line) -> None:
    # Unwind regulates span1 (upstream of the master); the process roller regulates span2
    # and the rewind regulates the idler-split zone span3a+span3b, measured on span3b.
    assert hswl.zones == (
        Zone(first=0, last=1, loadcell=0, controller=0),
        Zone(first=1, last=2, loadcell=1, controller=2),
        Zone(first=2, last=4, loadcell=3, controller=4),
    )
    assert [hswl.controlled_zone(i) for i in range(5)] == [0, None, 1, None, 2]
    assert [hswl.zone_of_span(k) for k in range(4)] == [0, 1, 2, 2]
    assert list(hswl.zones[2].spans) == [2, 3]
    assert [hswl.span_name(k) for k in range(4)] == ["span1", "span2", "span3a", "span3b"]


def test_hswl_scenarios(hswl: Line) -> None:
    assert list(hswl.spec.scenarios) == ["startup", "speed-change", "disturbance",
                                         "roll-change", "tension-step", "speed-change-surge"]
    startup = hswl.with_scenario("startup")
    assert startup.spec.speed.type == "ramp"
    assert startup.spec.speed.initial == 0.0
    assert startup.spec.speed.final == pytest.approx(2.54, rel=1e-15)
    assert (startup.spec.speed.start, startup.spec.speed.duration) == (1.0, 10.0)
    assert startup.spec.rollers == hswl.spec.rollers

    disturbed = hswl.with_scenario("disturbance")
    assert [d.type for d in disturbed.spec.disturbances] == [
        "wound_in_ripple", "eccentric_roller"]
    assert disturbed.spec.disturbances[0].amplitude == pytest.approx(LBF, rel=1e-15)
    assert disturbed.spec.speed == hswl.spec.speed

    roll_change = hswl.with_scenario("roll-change")
    assert roll_change.unwind.radius == pytest.approx(3.6 * INCH, rel=1e-15)
    assert roll_change.rewind.radius == hswl.rewind.radius


def test_unknown_scenario_names_the_scenarios_there_are(hswl: Line) -> None:
    with pytest.raises(LineFileError) as info:
        hswl.with_scenario("nope")
    err = info.value
    assert (err.file, err.key) == ("hswl.toml (built-in)", "scenarios.nope")
    assert err.problem == ("no such scenario (this line has: startup, speed-change, "
                           "disturbance, roll-change, tension-step, speed-change-surge)")


def test_replace_validates_the_new_value(hswl: Line) -> None:
    faster = hswl.replace(speed="1000 ft/min")
    assert faster.spec.speed == pytest.approx(5.08, rel=1e-15)
    assert faster.spec.rollers == hswl.spec.rollers
    with pytest.raises(LineFileError, match=r"^hswl\.toml \(built-in\): speed: must be >= 0"):
        hswl.replace(speed="-1 m/s")


# --- a dict-built 6-section line -----------------------------------------------------------


def test_six_section_topology() -> None:
    line = load_line(six_section_dict())
    assert line.source == "<dict>"
    assert (line.n_nodes, line.n_spans, line.master) == (7, 6, 3)
    assert line.drives == (0, 1, 3, 4, 6)
    assert line.zones == (
        Zone(first=0, last=1, loadcell=0, controller=0),
        Zone(first=1, last=3, loadcell=2, controller=1),
        Zone(first=3, last=4, loadcell=3, controller=4),
        Zone(first=4, last=6, loadcell=4, controller=6),
    )
    assert [line.controlled_zone(i) for i in range(7)] == [0, 1, None, None, 2, None, 3]
    assert line.span_name(0) == "span1"
    assert line.span_name(2) == "long"
    assert line.ea == pytest.approx(4e9 * 25e-6 * 1.0, rel=1e-15)


def test_six_section_units_and_defaults() -> None:
    spec = spec_from_dict(six_section_dict())
    outfeed = spec.rollers[4]
    assert outfeed.radius == pytest.approx(4 * INCH, rel=1e-15)
    assert outfeed.inertia == pytest.approx(LB * FT**2, rel=1e-15)
    assert outfeed.controller.tension_bandwidth == 5.0
    assert outfeed.controller.speed_bandwidth == 40.0  # default
    assert outfeed.drive.ratio == 1.0  # default
    assert outfeed.drive.torque_lag == 0.002  # default
    assert spec.spans[2].tension.final == pytest.approx(30 * LBF, rel=1e-15)
    assert spec.speed.value[-1] == pytest.approx(3.048, rel=1e-15)
    assert spec.scenarios["fast"].disturbances[0].phase == pytest.approx(1.5707963267948966)


def test_six_section_scenario() -> None:
    fast = load_line(six_section_dict()).with_scenario("fast")
    assert fast.spec.speed == 5.0
    assert fast.rewind.radius == 0.3
    assert [d.type for d in fast.spec.disturbances] == ["wound_in_ripple"]


# --- round trips -----------------------------------------------------------------------------


def test_hswl_round_trips(hswl: Line) -> None:
    again = reload(hswl.spec)
    assert again == hswl.spec
    assert dump_spec(again) == dump_spec(hswl.spec)


def test_dump_writes_plain_si_numbers(hswl: Line) -> None:
    data = tomllib.loads(dump_spec(hswl.spec))
    assert data["speed"] == hswl.spec.speed
    assert data["spans"][0]["length"] == hswl.spec.spans[0].length
    assert data["spans"][0]["length"] == pytest.approx(20 * FT, rel=1e-15)
    assert data["web"]["ea"] == hswl.ea
    assert data["rollers"][0]["type"] == "unwind"
    assert "modulus" not in data["web"]  # None values are left out, not written


def test_six_section_round_trips() -> None:
    spec = spec_from_dict(six_section_dict())
    assert reload(spec) == spec
    assert dump_spec(reload(spec)) == dump_spec(spec)


@pytest.mark.parametrize("scenario", ["startup", "speed-change", "disturbance", "roll-change"])
def test_scenario_lines_round_trip(hswl: Line, scenario: str) -> None:
    spec = hswl.with_scenario(scenario).spec
    assert reload(spec) == spec


def test_round_trip_through_a_file(hswl: Line, tmp_path: Path) -> None:
    path = tmp_path / "copy.toml"
    path.write_text(dump_spec(hswl.spec), encoding="utf-8")
    line = load_line(path)
    assert line.spec == hswl.spec
    assert line.source == str(path)
    assert load_line(str(path)).spec == hswl.spec


# --- malformed specs: one error type naming file, key path and problem ----------------------


def _set(path: str, value: object) -> Callable[[dict[str, Any]], None]:
    """Mutation that sets a dotted path ('spans.2.length') to ``value``."""

    def apply(data: dict[str, Any]) -> None:
        *head, last = (int(p) if p.isdigit() else p for p in path.split("."))
        node: Any = data
        for part in head:
            node = node[part]
        node[last] = value

    return apply


def _del(path: str) -> Callable[[dict[str, Any]], None]:
    def apply(data: dict[str, Any]) -> None:
        *head, last = (int(p) if p.isdigit() else p for p in path.split("."))
        node: Any = data
        for part in head:
            node = node[part]
        del node[last]

    return apply


IDLE = {"name": "plain", "type": "idle", "radius": 0.05, "inertia": 0.001}


def _open_loop_under(family: str) -> Callable[[dict[str, Any]], None]:
    """The rewind in open-loop tension control under a ``family`` controller."""

    def apply(data: dict[str, Any]) -> None:
        data["rollers"][4]["winder"] = {"mode": "open_loop"}
        data["rollers"][4]["controller"] = {"type": family}

    return apply

MALFORMED: dict[str, tuple[Callable[[dict[str, Any]], None], str, str]] = {
    # id: (mutation of hswl, exact key path, regex the problem must match)
    "missing span length": (_del("spans.1.length"), "spans[1].length", "required key is missing"),
    "missing web": (_del("web"), "web", "required key is missing"),
    "missing drive": (_del("rollers.2.drive"), "rollers[2].drive", "required key is missing"),
    "missing name": (_del("name"), "name", "required key is missing"),
    "negative length": (_set("spans.2.length", "-3 m"), "spans[2].length",
                        r"must be > 0, got '-3 m'"),
    "negative plain length": (_set("spans.2.length", -3), "spans[2].length",
                              "must be > 0, got -3"),
    "zero radius": (_set("rollers.3.radius", 0), "rollers[3].radius", "must be > 0"),
    "negative friction": (_set("rollers.1.friction", "-1 N*m*s"), "rollers[1].friction",
                          "must be >= 0"),
    "unknown roller key": (_set("rollers.1.colour", "red"), "rollers[1].colour",
                           "^unknown key$"),
    "unknown top-level key": (_set("colour", "red"), "colour", "^unknown key$"),
    "unknown drive key": (_set("rollers.0.drive.gear", 2), "rollers[0].drive.gear",
                          "^unknown key$"),
    "unknown span key": (_set("spans.0.lenght", 2.0), "spans[0].lenght",
                         r"^unknown key; did you mean 'length'\?$"),
    "key of another roller type": (_set("rollers.3.core_radius", 0.01),
                                   "rollers[3].core_radius", "^unknown key$"),
    "unknown roller type": (_set("rollers.3.type", "festoon"), "rollers[3].type",
                            r"unknown type 'festoon'; expected one of 'unwind', 'rewind', "
                            r"'driven', 'idle', 'dancer'"),
    "missing roller type": (_del("rollers.3.type"), "rollers[3]", "'type' key is required"),
    "unknown role": (_set("rollers.2.role", "boss"), "rollers[2].role",
                     "'master' or 'tension'"),
    # open loop replaces the controller and its speed limiter runs on the PI's speed gains,
    # which a decentralized drive leaves at 0: a freed roll would never be held (W7)
    "open loop under state feedback": (_open_loop_under("state_feedback"),
                                       "rollers[4].winder.mode",
                                       "open_loop replaces the drive's 'state_feedback'"),
    "open loop under mrac": (_open_loop_under("mrac"), "rollers[4].winder.mode",
                             "speed limiter on the cascaded PI's speed gains"),
    "unknown controller type": (_set("rollers.2.controller.type", "pid"),
                                "rollers[2].controller.type", "'cascaded_pi'"),
    "unknown profile type": (_set("speed", {"type": "sine", "amplitude": 1.0}), "speed",
                             "type = 'ramp', 'steps' or 'table'"),
    "unknown disturbance type": (_set("disturbances", [{"type": "wobble"}]),
                                 "disturbances[0].type", "unknown type 'wobble'"),
    "length in seconds": (_set("spans.0.length", "3 s"), "spans[0].length",
                          r"expected a length .*got '3 s'"),
    "speed in feet": (_set("speed", "500 ft"), "speed", "expected a speed"),
    "unreadable quantity": (_set("web.width", "six inches"), "web.width", "cannot read"),
    "nan quantity": (_set("web.width", "nan m"), "web.width", "must be finite"),
    "bool quantity": (_set("web.width", True), "web.width", "expected a length"),
    "list quantity": (_set("web.width", [1, 2]), "web.width", "expected a length"),
    "string name expected": (_set("rollers.1.name", 3), "rollers[1].name", "valid string"),
    "empty name": (_set("rollers.1.name", ""), "rollers[1].name", "at least 1 character"),
    "ramp field": (_set("scenarios.startup.speed.duration", "0 s"),
                   "scenarios.startup.speed.duration", "must be > 0"),
    "rollers not a list": (_set("rollers", {"a": 1}), "rollers", "valid list"),
    "one roller": (lambda d: d.__setitem__("rollers", d["rollers"][:1]), "rollers",
                   "at least 2 items"),
    "tension equal to EA": (_set("spans.0.tension", "2000 lbf"), "spans[0].tension",
                            r"reference 8896.44 N must be below EA = 8896.44 N"),
    "tension above EA": (_set("spans.3.tension", "3000 lbf"), "spans[3].tension",
                         "must be below EA"),
    "ramp tension above EA": (_set("spans.1.tension", {"type": "ramp", "initial": 50,
                                                       "final": 1e5, "duration": 1}),
                              "spans[1].tension", "must be below EA"),
    "core radius equal to radius": (_set("rollers.0.core_radius", "1.25 ft"),
                                    "rollers[0].core_radius", "must be below the roll radius"),
    "core radius above radius": (_set("rollers.4.core_radius", "1 ft"),
                                 "rollers[4].core_radius",
                                 r"must be below the roll radius 0.204216 m, got 0.3048 m"),
    "wound-in tension at EA": (_set("rollers.0.wound_in_tension", "2000 lbf"),
                               "rollers[0].wound_in_tension", "must be below EA = 8896.44 N"),
    "first roller not unwind": (_set("rollers.0", IDLE), "rollers[0].type",
                                "first roller must be the unwind roll"),
    "last roller not rewind": (_set("rollers.4", IDLE), "rollers[4].type",
                               "last roller must be the rewind roll"),
    "unwind in the middle": (lambda d: d["rollers"].insert(2, copy.deepcopy(d["rollers"][0])),
                             "rollers[2].type", "'unwind' may only be the first/last roller"),
    "too few spans": (_del("spans.3"), "spans", "5 rollers need 4 spans, got 3"),
    "too many spans": (lambda d: d["spans"].append({"length": 1.0}), "spans",
                       "5 rollers need 4 spans, got 5"),
    "two masters": (_set("rollers.2.role", "master"), "rollers",
                    "exactly one driven roller must have role = 'master', got 2"),
    "no master": (_set("rollers.1.role", "tension"), "rollers",
                  "exactly one driven roller must have role = 'master', got 0"),
    "zone without loadcell": (_del("spans.0.tension"), "spans[0]",
                              r"tension zone 1 \(unwind to master\) needs exactly one span "
                              r"with a 'tension' reference, got 0"),
    "zone with two loadcells": (_set("spans.2.tension", "10 lbf"), "spans[2]..spans[3]",
                                r"tension zone 3 \(process to rewind\) .* got 2"),
    "duplicate roller names": (_set("rollers.3.name", "master"), "rollers[3].name",
                               "duplicate name 'master'"),
    "duplicate span names": (_set("spans.1.name", "span1"), "spans[1].name",
                             "duplicate name 'span1'"),
    "web modulus and ea": (_set("web.modulus", "4.6 GPa"), "web",
                           "exactly one of 'modulus' or 'ea'"),
    "web neither modulus nor ea": (_del("web.ea"), "web", "exactly one of 'modulus' or 'ea'"),
    "eccentric missing roller": (
        _set("disturbances", [{"type": "eccentric_roller", "roller": "nope",
                               "eccentricity": "0.05 mm"}]),
        "disturbances[0].roller", "no roller named 'nope'"),
    "eccentric missing roller in scenario": (
        _set("scenarios.disturbance.disturbances.1.roller", "nope"),
        "scenarios.disturbance.disturbances[1].roller", "no roller named 'nope'"),
    # an out-of-round roll (issue 21, docs/winder.md E1) is allowed, up to its core radius
    "eccentric roll": (_set("scenarios.disturbance.disturbances.1", {
                           "type": "eccentric_roller", "roller": "unwind",
                           "eccentricity": "4 in"}),
                       "scenarios.disturbance.disturbances[1].eccentricity",
                       "below the roll's core radius"),
    "eccentricity above radius": (_set("scenarios.disturbance.disturbances.1.eccentricity",
                                       "2 in"),
                                  "scenarios.disturbance.disturbances[1].eccentricity",
                                  "must be below the roller radius"),
    "speed ripple on idle roller": (
        _set("disturbances", [{"type": "speed_ripple", "roller": "idler", "amplitude": 0.1,
                               "frequency": 1.0}]),
        "disturbances[0].roller", "needs a driven roller"),
    "ripple amplitude at wound-in tension": (
        _set("disturbances", [{"type": "wound_in_ripple", "amplitude": "12 lbf",
                               "frequency": 1.0}]),
        "disturbances[0].amplitude", "must be below the unwind's wound-in tension"),
    "ripple on no unwind": (
        _set("disturbances", [{"type": "wound_in_ripple", "amplitude": "1 lbf",
                               "frequency": 1.0, "roller": "idler"}]),
        "disturbances[0].roller", "the unwind of this line is"),
    "differential shaft on a single path": (
        _set("rollers.4.shaft", {"type": "differential", "slip_torque": 1.0,
                                  "core_inertia": 0.01}),
        "rollers[4].shaft", "only on a branched line"),
    "scenario radius below core": (_set("scenarios.roll-change.unwind_radius", "2 in"),
                                   "scenarios.roll-change.unwind_radius",
                                   "must be above the core radius 0.0762 m"),
    "table lengths differ": (_set("speed", {"type": "table", "time": [0, 1], "value": [1]}),
                             "speed", "'time' and 'value' must have the same length"),
    "table times decrease": (_set("speed", {"type": "table", "time": [0, 2, 1],
                                            "value": [1, 1, 1]}),
                             "speed.time", "must not decrease"),
    "step times decrease": (_set("speed", {"type": "steps", "initial": 1,
                                           "steps": [{"time": 2, "value": 2},
                                                     {"time": 1, "value": 3}]}),
                            "speed.steps", "must not decrease"),
    "controller gain": (_set("rollers.2.controller.damping", -1), "rollers[2].controller.damping",
                        "must be > 0, got -1"),
    "steps value": (_set("spans.0.tension", {"type": "steps", "initial": 1,
                                             "steps": [{"time": 1, "value": "-1 N"}]}),
                    "spans[0].tension.steps[0].value", "must be > 0"),
    "negative eccentricity": (_set("scenarios.disturbance.disturbances.1.eccentricity", -1),
                              "scenarios.disturbance.disturbances[1].eccentricity",
                              "must be > 0"),
    # A scenario named like a union tag kept its name out of the key path (fixed in
    # spec/load.py: _format_loc now walks the input data).
    "scenario named like a tag": (_set("scenarios.ramp", {"description": "no duration"}),
                                  "scenarios.ramp.duration", "required key is missing"),
    "scenario named like a roller type": (_set("scenarios.unwind", {"duration": "-1 s"}),
                                          "scenarios.unwind.duration", "must be > 0"),
    # An int beyond float range used to escape to_si as OverflowError and was reported
    # against "(top level)" (fixed in units.py).
    "huge integer": (_set("spans.0.length", 10**400), "spans[0].length", "must be finite"),
}


@pytest.mark.parametrize("case", list(MALFORMED))
def test_malformed_spec_raises_line_file_error(case: str) -> None:
    mutate, key, problem = MALFORMED[case]
    data = hswl_dict()
    mutate(data)
    with pytest.raises(LineFileError) as info:
        spec_from_dict(data, "line.toml")
    err = info.value
    assert err.file == "line.toml"
    assert err.key == key, str(err)
    assert re.search(problem, err.problem), str(err)
    assert str(err) == f"line.toml: {key}: {err.problem}"
    assert isinstance(err, webline.WeblineError)
    assert err.exit_code == 2


def test_not_a_table_is_rejected() -> None:
    with pytest.raises(LineFileError) as info:
        spec_from_dict([1, 2], "line.toml")
    assert str(info.value) == "line.toml: (top level): a line file must be a table of keys"


def test_plain_number_string_for_a_frequency_is_accepted() -> None:
    # "1000" for sample_rate used to escape to_si as pint's DimensionalityError (reported
    # against "(top level)"); a plain number is SI.
    data = hswl_dict()
    data["control"]["sample_rate"] = "1000"
    assert spec_from_dict(data).control.sample_rate == 1000.0


def test_dict_source_is_labelled_dict() -> None:
    data = hswl_dict()
    data["spans"][0]["length"] = -1
    with pytest.raises(LineFileError, match=r"^<dict>: spans\[0\]\.length: must be > 0"):
        load_line(data)


# --- files on disk ------------------------------------------------------------------------


def test_error_in_a_file_names_its_path(tmp_path: Path) -> None:
    path = tmp_path / "bad line.toml"
    path.write_text(HSWL_TEXT.replace('length = "33 ft"', 'length = "-33 ft"'),
                    encoding="utf-8")
    with pytest.raises(LineFileError) as info:
        load_line(path)
    # the TOML line of the key (line 104 of the HSWL file) follows the path
    assert str(info.value) == f"{path}:104: spans[1].length: must be > 0, got '-33 ft'"


def test_valid_file_on_disk_loads(tmp_path: Path) -> None:
    path = tmp_path / "mine.toml"
    path.write_text(HSWL_TEXT.replace('name = "hswl"', 'name = "mine"'), encoding="utf-8")
    spec, label = read_spec(path)
    assert label == str(path)
    assert spec.name == "mine"
    assert spec.model_copy(update={"name": "hswl"}) == load_line("hswl").spec


def test_toml_syntax_error(tmp_path: Path) -> None:
    path = tmp_path / "broken.toml"
    path.write_text('name = "x"\nspeed = \n', encoding="utf-8")
    with pytest.raises(LineFileError) as info:
        read_spec(path)
    err = info.value
    assert (err.file, err.key) == (str(path), "(syntax)")
    assert "line 2" in err.problem
    assert str(err).startswith(f"{path}: (syntax): ")


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nope.toml"
    with pytest.raises(LineFileError) as info:
        load_line(path)
    assert str(info.value) == f"{path}: (file): no such file"


def test_directory_is_not_a_line_file(tmp_path: Path) -> None:
    with pytest.raises(LineFileError) as info:
        read_spec(tmp_path)
    assert (info.value.file, info.value.key) == (str(tmp_path), "(file)")
    assert info.value.problem.startswith("cannot read")


def test_undecodable_file(tmp_path: Path) -> None:
    path = tmp_path / "latin1.toml"
    path.write_bytes(b'name = "caf\xe9"\n')
    with pytest.raises(LineFileError) as info:
        read_spec(path)
    assert (info.value.file, info.value.key) == (str(path), "(file)")


def test_unknown_builtin_name_lists_the_builtins() -> None:
    with pytest.raises(LineFileError) as info:
        load_line("no-such-line")
    err = info.value
    assert (err.file, err.key) == ("no-such-line", "(name)")
    listed = err.problem.split("(built-in: ")[1].rstrip(")").split(", ")
    assert {"hswl", "rockwell", "converter"} <= set(listed)


def test_every_built_in_line_and_scenario_pickles_to_an_equal_line() -> None:
    """A ``Line`` goes to another process (the report's, a Dask worker) as its validated data
    (``Line.__reduce__``): every built-in line and scenario comes back equal, steps profiles
    (generic pydantic classes pickle cannot find by name) and scenario breaks included."""
    import pickle

    import webline

    for name in ("hswl", "rockwell", "converter"):
        line = webline.load_line(name)
        for scenario in (None, *line.spec.scenarios):
            sent = line if scenario is None else line.with_scenario(scenario)
            back = pickle.loads(pickle.dumps(sent))
            assert back.spec == sent.spec and back.source == sent.source, (name, scenario)


def test_a_dancers_key_is_named_once_although_its_type_is_its_table() -> None:
    """A dancer roller has ``type = "dancer"`` and a ``dancer`` table: pydantic's location
    repeats "dancer" (the union's tag, then the field), which the key path once showed twice
    (``rollers[1].dancer.dancer.angle_in``)."""
    data = webline.load_line("converter").spec.model_dump(exclude_none=True)
    index = next(i for i, r in enumerate(data["rollers"]) if r["type"] == "dancer")
    data["rollers"][index]["dancer"]["angle_in"] = "100 deg"
    with pytest.raises(LineFileError) as info:
        spec_from_dict(data, "line.toml")
    assert f"rollers[{index}].dancer.angle_in: " in str(info.value)
