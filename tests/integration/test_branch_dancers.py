"""A dancer on a branched line (docs/branching.md, "Dancers"; the chain's docs/winder.md
D0-D3): a dancer on the laminator's film, ahead of the nip, in position control of the film
zone. Its spans lengthen with the carriage (D1), its load sets the film's tension (D2), its
zone's drive holds its position (D3), web length stays conserved while it moves, and the
linear model's dancer mode and closed loop match the hand formula and the simulation."""

from __future__ import annotations

import copy
import math
import tomllib
from importlib import resources

import numpy as np
import pytest
from scipy.linalg import expm

import webline
from webline.errors import LineFileError
from webline.model.web_graph import load_branched
from webline.sim.branches.equilibrium import operating_point
from webline.sim.branches.linear import branch_linear_model
from webline.sim.branches.plan import compile_branches
from webline.sim.branches.run import simulate_branches

LAMINATOR = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                          .read_text("utf-8"))
MASS, TRAVEL, POSITION = 5.0, 0.2, 0.1  # [kg], [m], [m]
FILM_EA, FILM_T = 103.5e3, 120.0  # [N]: laminator.toml
STEP_AT, STEP, DURATION = 1.0, 2.0, 3.0  # [s], [N], [s]: the linear check's reference step


def dancer_laminator(heavy: bool = False, **carriage: object) -> dict:
    """The laminator with its film guide made a dancer (film spans: unwind -> dancer 1.5 m,
    dancer -> nip 2 m, the loadcell span); ``heavy``: both film spans 2 m and the unwind and
    nip of 1e4 kg m² (the spans' far ends stand still on the dancer's time scale)."""
    data = copy.deepcopy(LAMINATOR)
    guide = data["rollers"][1]
    guide["type"] = "dancer"
    guide["dancer"] = {"mass": f"{MASS} kg", "travel": f"{TRAVEL} m",
                       "position": f"{POSITION} m", **carriage}
    if heavy:
        data["webs"][0]["spans"][0]["length"] = "2 m"
        for i in (0, 4):
            data["rollers"][i]["inertia"] = "1e4 kg*m**2"
    return data


@pytest.fixture(scope="module")
def upset():
    return webline.simulate(load_branched(dancer_laminator()), 6.0,
                            scenario="layer-upset").dataset


def test_film_tension_is_the_dancers_load_over_its_strands(upset):
    # a plain dancer (2 strands, g = 1): at rest T_in + T_out = load = 2 x 120 N (D2); the
    # two spans differ by the dancer roller's bearing drag c ω / r = 1e-4 x 50 / 0.05 = 0.1 N
    tension = upset["tension"]
    t_in, t_out = (tension.sel(span=s).sel(time=1.9, method="nearest").item()
                   for s in ("film[0]", "film_zone"))
    omega = upset["omega"].sel(node="guide_film").sel(time=1.9, method="nearest").item()
    drag = 1e-4 * omega / 0.05
    # the run starts at the operating point (solver 1e-13) and stays: 1e-6 N of 240 N
    assert t_in + t_out == pytest.approx(2 * FILM_T, abs=1e-6)
    assert t_out - t_in == pytest.approx(drag, abs=1e-6)
    # after the upset (reference 150 N at 2 s, load 300 N), settled: 2 T = 300 N to 0.01 N
    # (the position loop's error has decayed to < 1e-4 of its peak by 6 s)
    final = [tension.sel(span=s).isel(time=-1).item() for s in ("film[0]", "film_zone")]
    assert sum(final) == pytest.approx(300.0, abs=1e-2)


def test_layer_upset_moves_the_dancer_and_the_position_loop_brings_it_back(upset):
    y = upset["dancer_position"].sel(dancer="guide_film").values
    time = upset["time"].values
    excursion = np.max(np.abs(y - POSITION))
    # the load steps by 60 N at 2 s: the carriage runs out until the unwind slows (mm)
    assert excursion > 1e-3
    assert float(time[np.argmax(np.abs(y - POSITION))]) > 2.0  # it moved after the step
    # 4 s later, 8 tension-loop time constants (8 rad/s bandwidth): back to 1 % of its peak
    assert abs(y[-1] - POSITION) < 0.01 * excursion
    assert "dancer_end_stop" not in [f.kind for f in webline.simulate(
        load_branched(dancer_laminator()), 0.5).verdict.findings]


def test_web_length_is_conserved_while_the_dancer_moves(upset):
    # stored = Σ L_k(y) (1 - s_k/EA) with L_k(y) = L_k + g (y - y_set) (D0, D1)
    balance = upset["web_stored"] + upset["web_out"] - upset["web_in"]
    moved = float(np.ptp(upset["dancer_position"].values))
    assert moved > 1e-3  # the carriage moved millimetres, each span by as much
    # 1e-7 m asked; D1 conserves it exactly, RK4 to its order in the bilinear L(y) s (~1e-12)
    assert float(np.max(np.abs(balance - balance.isel(time=0)))) < 1e-7


def test_dancer_mode_is_the_carriage_against_its_spans_stiffness():
    # far ends held (heavy unwind and nip), symmetric 2 m spans (the dancer roller does not
    # turn): the web is a spring (EA + T) (1/L_1 + 1/L_2) = 2 (EA + T)/L (D-spring-mass, the
    # span lengthening at constant stored web L/(1 + ε): E-6.6; first order: EA - T)
    plan = compile_branches(load_branched(dancer_laminator(heavy=True)))
    model = branch_linear_model(plan, operating_point(plan), "open")
    expected = math.sqrt(2 * (FILM_EA + FILM_T) / 2.0 / MASS)  # 144.0 rad/s
    eig = np.linalg.eigvals(model.a)
    nearest = eig[np.argmin(np.abs(np.abs(eig.imag) - expected))]
    # what remains of the coupling (transport terms T v / L, 1e4 kg m² ends): < 0.1 %
    assert abs(nearest.imag) == pytest.approx(expected, rel=1e-3)
    assert "guide_film_position" in model.states


def test_closed_loop_with_the_position_loop_matches_the_simulation():
    data = dancer_laminator()
    data.pop("scenarios")

    def stepped(step: float) -> dict:
        d = copy.deepcopy(data)
        d["webs"][0]["spans"][1]["tension"] = {
            "type": "steps", "initial": "120 N",
            "steps": [{"time": f"{STEP_AT} s", "value": f"{120 + step} N"}]}
        return d

    runs = [simulate_branches(stepped(step), DURATION) for step in (0.0, STEP)]
    ds0, ds1 = (r.dataset for r in runs)
    time = ds1["time"].values
    after = time >= STEP_AT
    plan = compile_branches(runs[1].plan.line)
    model = branch_linear_model(plan, operating_point(plan), "closed")
    n = model.a.shape[0]
    u = model.b[:, model.inputs.index("film_zone_tension_ref")] * STEP  # (the load's, 2x)
    augmented = np.zeros((n + 1, n + 1))
    augmented[:n, :n], augmented[:n, n] = model.a, u
    linear = np.array([expm(augmented * (t - STEP_AT))[:n, n] for t in time[after]])
    assert np.all(np.linalg.eigvals(model.a).real < 0.0)
    y = model.states.index("guide_film_position")
    k = model.outputs.index("film_zone_tension")
    pairs = [((ds1["dancer_position"] - ds0["dancer_position"]).values[after, 0], linear[:, y]),
             ((ds1["tension"] - ds0["tension"]).sel(span="film_zone").values[after],
              linear @ model.c[k])]
    for simulated, lin in pairs:
        peak = np.max(np.abs(lin))
        assert peak > 0.0
        # sampled 1 kHz controllers with a held torque and second-order terms (as
        # test_branch_linear_response): 5 % of the peak; a wrong gain or pole moves tens of %
        assert np.max(np.abs(simulated - lin)) < 0.05 * peak, np.max(np.abs(simulated - lin))


@pytest.mark.parametrize(("carriage", "key", "fragment"), [
    ({"use": "tension"}, "rollers[1].dancer.stiffness", "needs a spring (stiffness > 0)"),
    ({"position": "0.3 m"}, "rollers[1].dancer.position", "within the travel"),
    ({"angle_in": "90 deg"}, "rollers[1].dancer.angle_in", "below 90 deg"),
    ({"arm_length": "0.5 m"}, "rollers[1].dancer.arm_inertia", "both arm_length"),
])
def test_bad_dancer_keys_are_one_line_naming_the_key(carriage, key, fragment):
    with pytest.raises(LineFileError) as caught:
        load_branched(dancer_laminator(**carriage))
    assert len(str(caught.value).splitlines()) == 1
    assert caught.value.key == key and fragment in caught.value.problem


def test_a_span_too_short_for_the_set_position_is_one_line():
    data = dancer_laminator(position="0.19 m", strands=20)  # takes 10 x 0.19 m of 1.5 m
    with pytest.raises(LineFileError) as caught:
        compile_branches(load_branched(data))
    assert caught.value.key == "webs[0].spans[0].length"


SLITTER = tomllib.loads(resources.files("webline.data.lines").joinpath("slitter.toml")
                        .read_text("utf-8"))


def laminate_dancer() -> dict:
    """The laminator with its laminate guide a dancer (the rewind's zone)."""
    data = copy.deepcopy(LAMINATOR)
    data["rollers"][5]["type"] = "dancer"
    data["rollers"][5]["dancer"] = {"mass": "5 kg", "travel": "0.2 m", "position": "0.1 m"}
    return data


def lane_dancer() -> dict:
    """The slitter with a dancer on lane 3, ahead of its own rewind (that rewind's zone)."""
    data = copy.deepcopy(SLITTER)
    data["rollers"].append({"name": "dancer_3", "type": "dancer", "radius": "50 mm",
                            "inertia": "0.002 kg*m**2", "dancer": {
                                "mass": "3 kg", "travel": "0.2 m", "position": "0.1 m"}})
    data["webs"][3]["path"] = ["slitter", "dancer_3", "rewind_3"]
    data["webs"][3]["spans"] = [{"name": "lane_3_span", "length": "2 m", "tension": "100 N"},
                                {"length": "1.5 m"}]
    return data


@pytest.mark.parametrize(("data", "scenario", "duration", "spans", "load"), [
    (laminate_dancer(), "start-up", 13.0, ("laminate_zone", "laminate[1]"), 360.0),
    (lane_dancer(), None, 3.0, ("lane_3_span", "lane_3[1]"), 200.0),
])
def test_a_dancer_on_the_laminate_or_a_lane_sets_its_tension(data, scenario, duration, spans,
                                                             load):
    result = webline.simulate(load_branched(data), duration, scenario=scenario)
    ds = result.dataset
    assert result.failure is None
    tension = [ds["tension"].sel(span=s).isel(time=-1).item() for s in spans]
    # D2 at rest: T_in + T_out = load = 2 T_ref; the laminator has just finished its ramp
    # (11 s) and its rolls keep changing radius: 1e-3 N of hundreds
    assert sum(tension) == pytest.approx(load, abs=1e-3)
    balance = ds["web_stored"] + ds["web_out"] - ds["web_in"]
    assert float(np.max(np.abs(balance - balance.isel(time=0)))) < 1e-7


def test_a_dancer_on_its_end_stop_is_a_finding_of_its_web():
    # set 0.5 mm below the end of its travel: the layer upset runs it out by ~1 mm
    result = webline.simulate(load_branched(dancer_laminator(position="0.1995 m")), 4.0,
                              scenario="layer-upset")
    found = [f for f in result.verdict.findings if f.kind == "dancer_end_stop"]
    assert [f.where for f in found] == ["film"]
    assert found[0].time > 2.0 and found[0].details["low_stop"] is False
    y = result.dataset["dancer_position"].values[:, 0]
    # the stop (1e6 N/m) holds it: 60 N of extra load compresses it by < 0.1 mm
    assert 0.2 < float(np.max(y)) < 0.2 + 1e-4


def test_a_rewinds_taper_acts_through_its_dancers_load():
    # the laminate dancer in the rewind's zone, the rewind tapered: hyperbolic f = 1 - 0.5
    # (1 - D_c / D) (docs/winder.md W1). In position control the tension is the load over
    # the strands, so the taper scales the load: T_in + T_out = 2 x 180 N x f(D(t))
    data = laminate_dancer()
    data["rollers"][6]["taper"] = {"type": "hyperbolic", "taper": 0.5}
    data["rollers"][6]["radius"] = "0.2 m"  # (f = 0.69 at the start: the taper shows)
    ds = webline.simulate(load_branched(data), 3.0).dataset
    diameter = 2 * ds["radius"].sel(roll="rewind/laminate").values
    factor = 1 - 0.5 * (1 - 2 * 0.0762 / diameter)
    total = (ds["tension"].sel(span="laminate_zone") + ds["tension"].sel(span="laminate[1]"))
    assert factor[0] < 0.9
    # the load follows the controller's diameter each tick and the carriage follows the
    # load within its position loop's lag on a reference falling ~0.03 N/s: 1e-3 N
    assert np.max(np.abs(total.values - 360.0 * factor)) < 1e-3, np.max(
        np.abs(total.values - 360.0 * factor))


def test_position_control_on_a_drive_that_is_no_cascaded_pi_is_one_line():
    data = dancer_laminator()
    data["rollers"][0]["controller"] = {"type": "state_feedback"}
    with pytest.raises(LineFileError) as caught:
        compile_branches(load_branched(data))
    assert caught.value.key == "rollers[1].dancer.use"
    assert "cascaded PI" in caught.value.problem and len(str(caught.value).splitlines()) == 1
