"""The centre-winder keys of a branched line (docs/branching.md, "Centre winders and flying
splices"): a roll's ``winder``, ``control.tension_ramp`` and an unwind's flying splice load,
and each bad input is one line naming the key and the problem."""

from __future__ import annotations

import copy
import tomllib
from importlib import resources
from typing import Any

import pytest

from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.spec.splice import FlyingSplice

LAMINATOR = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                          .read_text("utf-8"))
SLITTER = tomllib.loads(resources.files("webline.data.lines").joinpath("slitter.toml")
                        .read_text("utf-8"))
REWIND = 6  # the laminator's rewind
SPLICE = {"roll": "unwind_film", "at": "2 s", "new_diameter": "0.6 m"}


def changed(base: dict[str, Any], change) -> dict[str, Any]:
    data = copy.deepcopy(base)
    change(data)
    return data


def _scenario_splice(**keys: Any):
    def change(d: dict[str, Any]) -> None:
        d["scenarios"]["splice"] = {"duration": "3 s", "splice": {**SPLICE, **keys}}
    return change


def _differential_winder(d: dict[str, Any]) -> None:
    d["rollers"][4]["shaft"] = {"type": "differential", "slip_torque": "8 N*m",
                                "core_inertia": "0.005 kg*m**2"}
    d["rollers"][4]["winder"] = {"inertia_compensation": True}


CASES = [
    (LAMINATOR, lambda d: d["rollers"][REWIND].__setitem__("winder", {"mode": "closed"}),
     f"rollers[{REWIND}].winder.mode", "closed_loop"),
    (LAMINATOR, lambda d: d["rollers"][REWIND].__setitem__("winder", {
        "friction_table": {"speed": ["0 rpm", "100 rpm"], "torque": ["1 N*m"]}}),
     f"rollers[{REWIND}].winder.friction_table.torque", "needs as many torques as speeds"),
    (LAMINATOR, lambda d: d["rollers"][REWIND].__setitem__("winder", {
        "static_friction": "-1 N*m"}), f"rollers[{REWIND}].winder.static_friction", ""),
    (SLITTER, _differential_winder, "rollers[4].winder", "differential shaft"),
    (LAMINATOR, lambda d: d["rollers"][REWIND].__setitem__("inertia", {
        "type": "totals", "empty": "2 kg*m**2", "full": "1 kg*m**2", "full_diameter": "0.6 m"}),
     f"rollers[{REWIND}].inertia.full", "must be heavier than the empty one"),
    (SLITTER, lambda d: (_differential_winder(d), d["rollers"][4].pop("winder"),
                         d["rollers"][4].__setitem__("inertia", {
                             "type": "total", "total": "5 kg*m**2", "diameter": "0.3 m"})),
     "rollers[4].inertia", "a differential shaft's lanes turn on their own cores"),
    (LAMINATOR, lambda d: d["control"].__setitem__("tension_ramp", {
        "standstill": 1.5, "time": "2 s"}), "control.tension_ramp.standstill", ""),
    (LAMINATOR, _scenario_splice(roll="nip"), "scenarios.splice.splice.roll",
     "must name an unwind or a rewind of this line ('unwind_film', 'unwind_foil', 'rewind')"),
    (LAMINATOR, _scenario_splice(new_diameter="0.1 m"),
     "scenarios.splice.splice.new_diameter", "must exceed the core's diameter 0.1524 m"),
    (LAMINATOR, _scenario_splice(speed_mismatch=0.9),
     "scenarios.splice.splice.speed_mismatch", ""),
    (LAMINATOR, lambda d: d.__setitem__("disturbances", [
        {"type": "flying_splice", **SPLICE}, {"type": "flying_splice", **SPLICE}]),
     "disturbances[1].at", "'unwind_film' is already spliced at 2 s"),
]


@pytest.mark.parametrize(("base", "change", "key", "fragment"), CASES,
                         ids=[c[2] + ":" + c[3][:20] for c in CASES])
def test_each_bad_winder_key_is_one_line_naming_it(base, change, key, fragment):
    with pytest.raises(LineFileError) as caught:
        load_branched(changed(base, change))
    error = caught.value
    assert len(str(error).splitlines()) == 1, str(error)
    assert error.key == key, str(error)
    assert fragment in error.problem, str(error)


def test_a_scenarios_splice_becomes_a_flying_splice_of_its_run():
    line = load_branched(changed(LAMINATOR, _scenario_splice(speed_mismatch=0.01)))
    splices = [d for d in line.with_scenario("splice").spec.disturbances
               if isinstance(d, FlyingSplice)]
    assert len(splices) == 1
    assert (splices[0].roll, splices[0].at, splices[0].new_diameter,
            splices[0].speed_mismatch) == ("unwind_film", 2.0, 0.6, 0.01)
    assert not any(isinstance(d, FlyingSplice) for d in line.spec.disturbances)
