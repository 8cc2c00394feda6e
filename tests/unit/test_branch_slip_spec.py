"""A branched line's traction contacts, nips, friction tables and break-away torques take the
chain's keys with the chain's checks, plus where a traction contact may sit on a branched
line (inside one web's path, not at a junction); each problem one line naming the key."""

from __future__ import annotations

import copy
import tomllib
from importlib import resources

import pytest

from webline.errors import LineFileError
from webline.model.web_graph import load_branched

SLITTER = tomllib.loads(resources.files("webline.data.lines").joinpath("slitter.toml")
                        .read_text("utf-8"))
TRACTION = {"type": "traction", "friction": 0.2, "viscous": "1e4 N*s/m"}


def _set(i, **keys):
    def change(d):
        d["rollers"][i].update(copy.deepcopy(keys))
    return change


def _kelvin_voigt(d):
    _set(2, wrap="1 rad", contact=TRACTION)(d)
    d["webs"][0]["spans"][2].update(model="kelvin-voigt", retardation="5 ms")


CASES = [  # (change, key in the message, fragment of the problem)
    (_set(2, contact=TRACTION), "rollers[2].wrap", "needs the wrap angle"),
    (_set(2, wrap="1 rad", contact=dict(TRACTION, kinetic_friction=0.3)),
     "rollers[2].contact.kinetic_friction", "must not exceed the static friction 0.2"),
    (_set(3, wrap="1 rad", contact=TRACTION), "rollers[3].contact",
     "'slitter' is a junction"),
    (_kelvin_voigt, "webs[0].spans[2].model", "kelvin-voigt span next to a traction contact"),
    (_set(2, nip={"load": "100 N", "radius": "4 cm", "inertia": "1e-3 kg*m**2",
                  "grip": "traction", "friction": 0.3}), "rollers[2].nip.grip",
     "give the roller a traction contact"),
    (_set(2, wrap="1 rad", contact=TRACTION,
          nip={"load": "100 N", "radius": "4 cm", "inertia": "1e-3 kg*m**2"}),
     "rollers[2].nip.grip", "contradicts the roller's traction contact"),
    (_set(1, friction_table={"speed": ["10 rad/s", "5 rad/s"], "torque": ["1 N*m", "1 N*m"]}),
     "rollers[1].friction_table.speed", "speeds must increase"),
    (_set(1, friction_table={"speed": ["10 rad/s"], "torque": ["1 N*m", "2 N*m"]}),
     "rollers[1].friction_table.torque", "needs as many torques as speeds"),
    (_set(1, breakaway_torque="0.5 N*m", coulomb_friction="1 N*m"),
     "rollers[1].breakaway_torque", "must exceed the running friction at rest"),
]


@pytest.mark.parametrize(("change", "key", "fragment"), CASES,
                         ids=[c[1] + ":" + c[2][:20] for c in CASES])
def test_each_problem_is_one_line_naming_key_and_problem(change, key, fragment):
    data = copy.deepcopy(SLITTER)
    change(data)
    with pytest.raises(LineFileError) as caught:
        load_branched(data)
    error = caught.value
    assert len(str(error).splitlines()) == 1, str(error)
    assert error.key == key, str(error)
    assert fragment in error.problem, str(error)


def test_a_gripped_nip_adds_its_pressure_rollers_reflected_inertia():
    from webline.sim.branches.loop import layout as B
    from webline.sim.branches.plan import compile_branches

    data = copy.deepcopy(SLITTER)
    plain = compile_branches(load_branched(data))
    _set(1, nip={"load": "100 N", "radius": "25 mm", "inertia": "1e-3 kg*m**2",
                 "bearing_friction": "1e-4 N*m*s"})(data)
    nipped = compile_branches(load_branched(data))
    # the pressure roller turns at ω R/R_n = 2 ω: kinetic energy J_n (2ω)²/2, so 4 J_n at
    # the guide's shaft, and 4 b_n of viscous friction (dissipated power b_n (2ω)²)
    assert nipped.nodes[1, B.N_JCONST] - plain.nodes[1, B.N_JCONST] == pytest.approx(4e-3)
    assert nipped.nodes[1, B.N_VISCOUS] - plain.nodes[1, B.N_VISCOUS] == pytest.approx(4e-4)
