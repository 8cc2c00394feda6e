"""The [[webs]] line-file format of a branched line (docs/line-file.md "webs",
docs/branching.md): topology checks and stage-1 feature checks, each one line naming the
file, the key and the problem."""

from __future__ import annotations

import copy
import tomllib
from importlib import resources
from typing import Any

import pytest

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched

LAMINATOR = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                          .read_text("utf-8"))
SLITTER = tomllib.loads(resources.files("webline.data.lines").joinpath("slitter.toml")
                        .read_text("utf-8"))


def changed(base: dict[str, Any], change) -> dict[str, Any]:
    data = copy.deepcopy(base)
    change(data)
    return data


def problem(data: dict[str, Any]) -> LineFileError:
    with pytest.raises(LineFileError) as caught:
        load_branched(data)
    assert len(str(caught.value).splitlines()) == 1, str(caught.value)
    return caught.value


def test_builtin_branched_lines_load_with_their_topology():
    laminator = load_branched("laminator")
    assert [w.name for w in laminator.spec.webs] == ["film", "foil", "laminate"]
    names = [r.name for r in laminator.spec.rollers]
    zones = {names[i]: [laminator.spans[k].name for k in z.loadcells]
             for i, z in laminator.zones.items()}
    assert zones == {"unwind_film": ["film_zone"], "unwind_foil": ["foil_zone"],
                     "rewind": ["laminate_zone"]}
    # the laminate's material: EA and thickness summed, mass per length kept
    film, foil, laminate = laminator.materials
    assert laminate.ea == film.ea + foil.ea
    assert laminate.thickness == pytest.approx(film.thickness + foil.thickness, rel=1e-15)
    assert laminate.density * laminate.thickness * laminate.width == pytest.approx(
        film.density * film.thickness * film.width + foil.density * foil.thickness * foil.width,
        rel=1e-12)
    slitter = load_branched("slitter")
    shaft = slitter.node_index["rewind_shaft"]
    assert [slitter.spans[k].name for k in slitter.zones[shaft].loadcells] == [
        "lane_1_span", "lane_2_span"]  # lanes on one shaft: their sum is controlled
    assert [r.radius for r in slitter.rolls if r.node == shaft] == [0.08, 0.08]
    base, lane = slitter.materials[0], slitter.materials[1]
    assert lane.ea == pytest.approx(base.ea * 0.4 / 1.25, rel=1e-15)


def test_load_line_loads_every_built_in_line_and_says_its_kind(tmp_path):
    """The front door reads every line file; the file's format ([[webs]]) alone makes a
    branched line, and the line says which it is (``branched``), the same as the file read
    through the branched loader."""
    from webline.line import Line
    from webline.model.web_graph import BranchedLine
    from webline.spec.load import builtin_lines

    kinds = {name: webline.load_line(name).branched for name in builtin_lines()}
    assert {name for name, branched in kinds.items() if branched} >= {"laminator", "slitter"}
    assert kinds["hswl"] is False and kinds["converter"] is False
    for name, branched in kinds.items():
        assert isinstance(webline.load_line(name), BranchedLine if branched else Line)
    assert webline.load_line("laminator").spec == load_branched("laminator").spec
    path = tmp_path / "lam.toml"
    path.write_text(resources.files("webline.data.lines").joinpath("laminator.toml")
                    .read_text("utf-8"))
    from_file = webline.load_line(path)
    assert from_file.branched and from_file.source == str(path)
    assert webline.load_line(LAMINATOR).branched  # a dict as read from TOML
    assert webline.load_line(from_file.spec).spec == from_file.spec
    with pytest.raises(webline.ArgumentError, match="line: expected"):
        webline.load_line(3.5)  # type: ignore[arg-type]
    assert "load_branched" not in dir(webline)


def test_a_bad_branched_file_names_its_line_through_the_front_door(tmp_path):
    data = changed(LAMINATOR, lambda d: d["webs"][0]["spans"][0].update(length="-1 m"))
    import tomli_w

    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    with pytest.raises(LineFileError) as info:
        webline.load_line(path)
    assert str(path) in str(info.value) and "length" in str(info.value)


def _set_dancer(d):
    d["rollers"][1]["type"] = "dancer"
    d["rollers"][1]["dancer"] = {"mass": "5 kg", "travel": "0.2 m", "position": "0.1 m",
                                 "use": "tension"}  # (a sensor without its spring)


CASES = [  # (base, change, key in the message, fragment of the problem)
    (LAMINATOR, lambda d: d.__setitem__("spans", [{"length": "1 m"}]), "spans",
     "in each of its [[webs]]"),
    (LAMINATOR, lambda d: d["webs"][1].__setitem__("name", "film"), "webs",
     "web names must be unique"),
    (LAMINATOR, lambda d: d["webs"][0]["path"].__setitem__(1, "nowhere"), "webs[0].path[1]",
     "no roller named 'nowhere'"),
    (LAMINATOR, lambda d: d["webs"][0]["spans"].pop(), "webs[0].spans", "has 2 spans, got 1"),
    (LAMINATOR, lambda d: d["webs"][0]["path"].__setitem__(0, "guide_foil"),
     "webs[0].path[0]", "starts at an unwind"),
    (LAMINATOR, lambda d: (d["webs"][2].__setitem__("path", ["guide_laminate", "rewind"]),
                           d["webs"][2]["spans"].pop()),
     "webs[2].path[0]", "starts at the roller where its layers end"),
    (LAMINATOR, lambda d: d["rollers"][4].update(role="tension"), "rollers",
     "exactly one master roller, found 0"),
    (LAMINATOR, _set_dancer, "rollers[1].dancer.stiffness",
     "a dancer as tension sensor needs a spring (stiffness > 0)"),
    (LAMINATOR, lambda d: (d["rollers"][0].__setitem__("controller", {
        "type": "python", "object": "m:f"}), d["rollers"][0].__setitem__("winder", {
            "mode": "open_loop"})),
     "rollers[0].winder.mode", "open-loop tension control takes no command from a python"),
    (LAMINATOR, lambda d: (d["rollers"][0].__setitem__("controller", {
        "type": "state_feedback"}), d["rollers"][0].__setitem__("winder", {
            "mode": "open_loop"})),
     "rollers[0].winder.mode", "open_loop replaces the drive's 'state_feedback' controller"),
    (LAMINATOR, lambda d: d["rollers"][0].__setitem__("controller", {
        "type": "adaptive", "leakage": -1}), "rollers[0].controller.leakage", "must be >= 0"),
    (SLITTER, lambda d: (d["rollers"][4].__setitem__("shaft", {
        "type": "differential", "slip_torque": "8 N*m", "overspeed": 0.02,
        "core_inertia": "0.005 kg*m**2"}), d["rollers"][4].__setitem__(
            "controller", {"type": "state_feedback"})),
     "rollers[4].controller.type", "a differential shaft runs in speed control"),
    (LAMINATOR, lambda d: d["webs"][0]["spans"][1].pop("tension"), "rollers[0]",
     "no loadcell span"),
    (LAMINATOR, lambda d: d["webs"][2]["spans"][1].__setitem__("tension", "180 N"),
     "rollers[6]", "two loadcell spans in series"),
    (LAMINATOR, lambda d: d.__setitem__("checks", {"tension_tolerance": 0}),
     "checks.tension_tolerance", "greater than 0"),
    (LAMINATOR, lambda d: d.__setitem__("checks", {"min_duration": "-1 s"}),
     "checks.min_duration", ">= 0"),
    (LAMINATOR, lambda d: d.__setitem__("checks", {"end_stop": "1 s"}), "checks.end_stop",
     "unknown key"),
    (LAMINATOR, lambda d: d["scenarios"]["start-up"].__setitem__("unwind_radius", "76 mm"),
     "scenarios.start-up.unwind_radius", "must be above the core radius of every unwind"),
    (LAMINATOR, lambda d: d["control"].__setitem__("tension_ramp", {"time": "2 s"}),
     "control.tension_ramp.standstill", "required key is missing"),
    (LAMINATOR, lambda d: d["webs"][2].__setitem__("layers", ["foil", "foil"]),
     "webs[0].path[-1]", "neither a layer of the laminate"),
    (LAMINATOR, lambda d: d["webs"][0]["web"].__setitem__("modulus", "4.5 GPa"),
     "webs[0].web", "give exactly one of 'modulus' or 'ea'"),
    (LAMINATOR, lambda d: d["webs"][1]["web"].pop("ea"), "webs[1].web",
     "give exactly one of 'modulus' or 'ea'"),
    (SLITTER, lambda d: d["web"].__setitem__("modulus", "2 GPa"), "web",
     "give exactly one of 'modulus' or 'ea'"),
    (SLITTER, lambda d: d["webs"].append({"name": "second", "path": ["unwind", "guide"],
                                          "spans": [{"length": "1 m"}]}),
     "webs[0].path[0]", "several webs start at unwind"),
    (SLITTER, lambda d: d["webs"][1].__setitem__("width", "600 mm"), "webs[0]",
     "wider than the web"),
    (SLITTER, lambda d: d["webs"][1].pop("width"), "webs[1].width", "required"),
    (SLITTER, lambda d: d["webs"][2]["path"].__setitem__(0, "pull"), "webs[2].path[0]",
     "where web 'base' ends"),
    (SLITTER, lambda d: d["rollers"].append({"name": "extra", "type": "idle", "radius": "1 cm",
                                             "inertia": "1e-4 kg*m**2"}),
     "rollers[6]", "is on no web's path"),
    (SLITTER, lambda d: (d["webs"][3].__setitem__("path", ["slitter", "rewind_3", "pull"]),
                         d["webs"][3]["spans"].append({"length": "1 m"})),
     "webs[3].path[1]", "can only start or end a path"),
]


@pytest.mark.parametrize(("base", "change", "key", "fragment"), CASES,
                         ids=[c[2] + ":" + c[3][:20] for c in CASES])
def test_each_problem_is_one_line_naming_key_and_problem(base, change, key, fragment):
    error = problem(changed(base, change))
    assert error.key == key, str(error)
    assert fragment in error.problem, str(error)


def test_a_scenario_changes_a_web_by_its_path():
    slitter = load_branched("slitter").with_scenario("thickness-profile")
    assert slitter.materials[1].thickness == pytest.approx(50.5e-6, rel=1e-12)
    assert slitter.materials[2].thickness == pytest.approx(50e-6, rel=1e-12)
    change = load_branched("laminator").with_scenario("roll-change").roll_change
    assert change is not None and change.radius == 0.3 and change.wound_in_tension == 45.0


def _driven_guide(d):
    """The slitter's guide roller driven in tension control, with a loadcell before it."""
    d["rollers"][1] = {"name": "guide", "type": "driven", "role": "tension", "radius": "50 mm",
                       "inertia": "0.01 kg*m**2",
                       "drive": {"ratio": 1.0, "torque_limit": "20 N*m"}}
    d["webs"][0]["spans"][0]["tension"] = "300 N"


def test_a_driven_roller_controls_the_zone_towards_the_master():
    line = load_branched(changed(SLITTER, _driven_guide))
    names = {r.name: i for i, r in enumerate(line.spec.rollers)}
    unwind, guide = line.zones[names["unwind"]], line.zones[names["guide"]]
    # the unwind now holds only the span to the guide; the guide, upstream of the master,
    # holds the span downstream of it, towards the master (it feeds its zone: sigma -1)
    assert [line.spans[k].name for k in unwind.spans] == ["base[0]"]
    assert [line.spans[k].name for k in guide.spans] == ["unwind_zone"] and guide.sigma == -1.0
    # a rewind pulls its zone (upstream of it): sigma +1
    assert line.zones[names["rewind_3"]].sigma == 1.0
    result = webline.simulate(line, 1.0)
    assert result.failure is None
    tension = result.dataset["tension"].sel(span=["base[0]", "unwind_zone"])
    assert float(abs(tension - 300.0).max()) < 0.5  # both zones held at their 300 N


def _leaves(node: Any, path: tuple = ()):
    if isinstance(node, dict):
        for key, value in node.items():
            yield from _leaves(value, (*path, key))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from _leaves(value, (*path, i))
    else:
        yield path


def _set(data: Any, path: tuple, value: object) -> None:
    for part in path[:-1]:
        data = data[part]
    data[path[-1]] = value


@pytest.mark.parametrize("base", [LAMINATOR, SLITTER], ids=["laminator", "slitter"])
def test_no_mutation_of_a_branched_file_gives_a_traceback(base):
    """Every value of the file replaced by a wrong one (wrong type, negative, a name of
    nothing, empty): a LineFileError naming a key, or a line that still loads; never another
    exception (the checks read names and indices the schema let through)."""
    loaded = 0
    for path in _leaves(base):
        for value in (None, -1.0, "nowhere", [], "0 m"):
            data = copy.deepcopy(base)
            if value is None:
                parent = data
                for part in path[:-1]:
                    parent = parent[part]
                parent.pop(path[-1]) if isinstance(parent, dict) else parent.pop()
            else:
                _set(data, path, value)
            try:
                load_branched(data)
                loaded += 1
            except LineFileError as exc:
                assert exc.key and exc.problem
    assert loaded > 0  # some changes are harmless (a description, an optional name)


def test_front_door_routes_each_kind_of_line_and_names_what_stage_1_lacks(tmp_path):
    from importlib import resources as res

    with pytest.raises(LineFileError, match="not a branched line"):
        load_branched("hswl")
    path = tmp_path / "mine.toml"
    path.write_text(res.files("webline.data.lines").joinpath("slitter.toml").read_text("utf-8"),
                    encoding="utf-8")
    result = webline.simulate(path, 0.05)  # a file path: dispatched on its [[webs]]
    assert type(result).__name__ == "BranchResult" and result.time[-1] == pytest.approx(0.05)
    shares: list[float] = []  # progress(share of the run done), as on a single-path run
    webline.simulate(path, 0.05, progress=shares.append)
    assert shares and shares[-1] == pytest.approx(1.0) and shares == sorted(shares)
    with pytest.raises(webline.ArgumentError, match="controller: object is not a controller"):
        webline.simulate(path, 0.05, controller=object())
