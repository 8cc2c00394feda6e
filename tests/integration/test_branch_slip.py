"""Slip over traction rollers, nips and measured friction on a branched line (docs/branching.md,
"Slip and measured friction"; the chain's model, docs/slip.md): on the slitter's pull roll
the web sticks in steady running exactly as on an adhered roll, breaks away at the tick the
capstan ratio is passed, keeps the web length while it slips, a traction nip holds it, a
friction table sets an idler's tension difference, and a break-away torque holds an idler
at rest."""

from __future__ import annotations

import copy
import math
import tomllib
from importlib import resources

import numpy as np
import pytest

from webline.model.web_graph import load_branched
from webline.sim.branches.loop import layout as B
from webline.sim.branches.run import simulate_branches

SLITTER = tomllib.loads(resources.files("webline.data.lines").joinpath("slitter.toml")
                        .read_text("utf-8"))
MU, WRAP = 0.2, 1.0  # e^{μθ} = 1.2214: the pull roll holds a draw of 22 % at most
PULL, GUIDE = 2, 1  # rollers: the master pull roll, the idle guide before it
IN_SPAN, OUT_SPAN = 1, 2  # the unwind zone (guide -> pull) and the knife span (pull -> slitter)


def slitter(traction: bool = True, lanes: str | None = None, nip: bool = False):
    """The slitter, its pull roll on a traction contact; ``lanes``: each lane's tension
    reference steps to it at 0.5 s (from 100 N); ``nip``: a traction nip on the pull roll."""
    d = copy.deepcopy(SLITTER)
    if traction:
        d["rollers"][PULL]["wrap"] = f"{WRAP} rad"
        d["rollers"][PULL]["contact"] = {"type": "traction", "friction": MU,
                                         "viscous": "1e4 N*s/m"}
    if nip:
        d["rollers"][PULL]["nip"] = {"load": "200 N", "radius": "40 mm",
                                     "inertia": "1e-3 kg*m**2", "grip": "traction",
                                     "friction": 0.3}
    if lanes is not None:
        for w in (1, 2, 3):
            d["webs"][w]["spans"][0]["tension"] = {
                "type": "steps", "initial": "100 N", "steps": [{"time": "0.5 s", "value": lanes}]}
    return load_branched(d)


def capstan(result) -> np.ndarray:
    """(T_out - t_c)/(T_in - t_c) over the pull roll at every record [-]."""
    x = result.states
    plan = result.plan
    surface = plan.nodes[PULL, B.N_RADIUS] * x[:, plan.offsets[B.O_OMEGA] + PULL]
    t_c = plan.nodes[PULL, B.N_RHOA] * surface**2
    return (np.maximum(x[:, OUT_SPAN], 0.0) - t_c) / (np.maximum(x[:, IN_SPAN], 0.0) - t_c)


@pytest.fixture(scope="module")
def stepped():
    """The lanes' references step 100 -> 130 N: the knife span wants 390 N behind 300 N,
    ratio 1.3 > e^{μθ}; every tick recorded."""
    return simulate_branches(slitter(lanes="130 N"), 1.5, record_interval="1 ms")


def test_in_steady_running_a_traction_pull_roll_sticks_as_the_adhered_one():
    adhered = simulate_branches(slitter(traction=False), 1.0)
    traction = simulate_branches(slitter(), 1.0)
    ratio = capstan(traction)
    assert float(ratio.max()) < math.exp(MU * WRAP) - 0.2  # far inside the band: ~1.00
    # stuck, the slip speed is exactly 0 in every stage and nothing else differs (same
    # inertia and friction): the runs are equal to the last bit
    assert float(np.max(np.abs(traction.rec - adhered.rec))) == 0.0
    assert traction.plan.nodes[PULL, B.N_SLIPCOUNT] == 0.0
    assert not [f for f in traction.verdict.findings if f.kind == "slip"]


def test_a_tension_step_beyond_the_capstan_ratio_makes_the_web_slip_where_it_passes(stepped):
    ratio = capstan(stepped)
    limit = math.exp(MU * WRAP)
    first = stepped.plan.nodes[PULL, B.N_SLIPFIRST]
    tick = int(np.flatnonzero(np.isclose(stepped.time, first, rtol=0, atol=1e-9))[0])
    # the state is sampled per tick: the break-away is the first tick whose ratio passes
    # e^{μθ}, so it is late by less than one tick's change of the ratio
    assert ratio[tick - 1] <= limit < ratio[tick]
    assert ratio[tick] - limit <= ratio[tick] - ratio[tick - 1]
    assert float(ratio[:tick].max()) <= limit
    assert 0.5 < first < 1.0  # after the step, while the lanes' tension rises (8 rad/s)
    slip = [f for f in stepped.verdict.findings if f.kind == "slip"]
    assert len(slip) == 1 and slip[0].where == "base" and slip[0].time == pytest.approx(first)
    # slipping, the friction holds the ratio near e^{μθ}, the excess carried by the viscous
    # term b s: 390 N wanted, 300 e^{μθ} = 366 N held, so s ~ 24 N / 1e4 N·s/m ~ 2.4 mm/s
    peak = stepped.plan.nodes[PULL, B.N_SLIPPEAK]
    assert 1e-3 < peak < 5e-3


def test_web_length_is_conserved_while_the_web_slips(stepped):
    ds = stepped.dataset
    balance = ds["web_stored"] + ds["web_out"] - ds["web_in"]
    assert stepped.plan.nodes[PULL, B.N_SLIPTIME] > 0.5  # it slipped for most of a second
    # 1e-7 m asked; the slip speed enters the two spans at the roll with opposite signs, so
    # only float rounding of ~10 m sums remains (~1e-14 m per step)
    assert float(np.max(np.abs(balance - balance.isel(time=0)))) < 1e-7


def test_a_traction_nip_holds_the_web_the_wrap_alone_lets_slip():
    # the nip adds 2 μ_n N = 120 N to the stiction band, more than the 24 N beyond e^{μθ}
    result = simulate_branches(slitter(lanes="130 N", nip=True), 1.5)
    assert float(capstan(result).max()) > 1.25  # beyond what the wrap alone holds
    assert result.plan.nodes[PULL, B.N_SLIPCOUNT] == 0.0


def _guide(d, **keys):
    d["rollers"][GUIDE].update(keys)


def guide_line(traction: bool, drag: str | None = None):
    """The slitter with its idle guide on a traction contact of little friction, μθ = 0.005
    (it holds 1.5 N of tension difference at 300 N); ``drag``: a bearing drag stepped on at
    0.5 s, which asks more of the web than that."""
    d = copy.deepcopy(SLITTER)
    if traction:
        _guide(d, wrap="0.5 rad", contact={"type": "traction", "friction": 0.01,
                                           "viscous": "1e4 N*s/m"})
    if drag is not None:
        d["disturbances"] = [{"type": "roller_drag", "roller": "guide", "torque": {
            "type": "steps", "initial": "0 N*m", "steps": [{"time": "0.5 s", "value": drag}]}}]
    return load_branched(d)


def test_a_traction_idler_sticks_in_steady_running_and_slips_past_its_capstan_ratio():
    adhered = simulate_branches(guide_line(False), 0.5)
    stuck = simulate_branches(guide_line(True), 0.5)
    assert float(np.max(np.abs(stuck.rec - adhered.rec))) == 0.0  # s = 0 in every stage
    # a 0.2 N·m drag needs 4 N across the guide, beyond its 1.5 N: the web slips over it
    result = simulate_branches(guide_line(True, "0.2 N*m"), 1.0, record_interval="1 ms")
    x, plan = result.states, result.plan
    surface = 0.05 * x[:, plan.offsets[B.O_OMEGA] + GUIDE]
    t_c = plan.nodes[GUIDE, B.N_RHOA] * surface**2
    ratio = (np.maximum(x[:, 1], 0.0) - t_c) / (np.maximum(x[:, 0], 0.0) - t_c)
    first = plan.nodes[GUIDE, B.N_SLIPFIRST]
    tick = int(np.flatnonzero(np.isclose(result.time, first, rtol=0, atol=1e-9))[0])
    limit = math.exp(0.01 * 0.5)
    assert 0.5 <= first < 0.6 and ratio[tick - 1] <= limit < ratio[tick]
    ds = result.dataset  # and web length is kept through the slipping idler
    balance = ds["web_stored"] + ds["web_out"] - ds["web_in"]
    assert float(np.max(np.abs(balance - balance.isel(time=0)))) < 1e-7


def test_a_friction_table_sets_the_idlers_tension_difference():
    d = copy.deepcopy(SLITTER)
    _guide(d, friction="0 N*m*s",
           friction_table={"speed": ["0 rad/s", "50 rad/s", "200 rad/s"],
                           "torque": ["0.1 N*m", "0.2 N*m", "0.5 N*m"]})
    result = simulate_branches(load_branched(d), 0.5)
    x = result.states[-1]
    omega = x[result.plan.offsets[B.O_OMEGA] + GUIDE]  # 5 m/s / 50 mm = 100 rad/s
    table = (0.2 + (omega - 50.0) / 150.0 * 0.3) * math.tanh(omega / 0.1)  # F1: 0.3 N·m
    # J dω/dt = R (T_out - T_in) - f(ω): in steady running the span after the guide carries
    # f(ω)/R = 6 N more than the span before it (the run starts on its operating point,
    # solved on the loop's rhs, and the rolls' growth moves the tensions by < 1e-4 N here)
    assert x[1] - x[0] == pytest.approx(table / 0.05, abs=1e-4)


def test_a_breakaway_torque_holds_an_idler_at_rest_below_it():
    d = copy.deepcopy(SLITTER)
    _guide(d, breakaway_torque="2 N*m", coulomb_friction="1 N*m")
    line = load_branched(d).with_scenario("start-up")  # at rest until 1 s, then a ramp
    result = simulate_branches(line, 1.6, record_interval="1 ms")
    x = result.states
    omega = x[:, result.plan.offsets[B.O_OMEGA] + GUIDE]
    torque = 0.05 * (np.maximum(x[:, 1], 0) - np.maximum(x[:, 0], 0))  # R (T_out - T_in)
    held = np.abs(torque) <= 2.0
    assert held[: int(np.argmax(~held))].size > 1000  # held through the first second
    moved = int(np.argmax(np.abs(omega) > 1e-3))
    # at rest it stays at rest while the web's torque is within B, and it breaks away once
    # it passes: the first motion comes within a tick of the torque crossing 2 N·m
    assert float(np.max(np.abs(omega[:moved]))) < 1e-3
    assert np.all(held[:moved - 1])
    assert not held[moved - 1] or not held[moved]


def test_a_stiff_slip_mode_sets_the_rk4_step():
    from webline.physics.slip import slip_rate

    line = slitter(lanes="130 N")
    contact = dict(line.spec.rollers[PULL].contact.model_dump(), viscous=100.0)
    d = copy.deepcopy(SLITTER)
    d["rollers"][PULL].update(wrap=f"{WRAP} rad", contact=contact)
    for w in (1, 2, 3):
        d["webs"][w]["spans"][0]["tension"] = {
            "type": "steps", "initial": "100 N", "steps": [{"time": "0.5 s", "value": "130 N"}]}
    result = simulate_branches(load_branched(d), 1.0)
    # b = 100 N·s/m: the spans round the slipping roll decay at up to (EA/b)(κ/L_in +
    # 1/L_out) + v(...) ~ 3.6e3 1/s, which the stuck linear model does not hold: the step
    # resolves it (h·rate <= 0.5, as the chain's sim.linear.fastest.slip_rates)
    rate = slip_rate(281.25e3, 100.0, 2.0, 1.5, MU, MU, WRAP, 5.5)
    assert result.settings["substeps"] >= math.ceil(1e-3 * rate / 0.5) > 1
    assert result.plan.nodes[PULL, B.N_SLIPCOUNT] >= 1 and result.failure is None


def test_a_traction_idler_on_a_laminate_and_on_a_layer_sticks_as_the_adhered_ones():
    laminator = tomllib.loads(resources.files("webline.data.lines").joinpath("laminator.toml")
                              .read_text("utf-8"))
    d = copy.deepcopy(laminator)
    for i in (3, 5):  # guide_foil (a layer's path), guide_laminate (the laminate's)
        d["rollers"][i].update(wrap="2 rad", contact={"type": "traction", "friction": 0.3,
                                                      "viscous": "1e4 N*s/m"})
    adhered = simulate_branches(load_branched(laminator), 0.5)
    traction = simulate_branches(load_branched(d), 0.5)
    # stuck throughout: bit for bit the adhered run (s = 0 in every stage)
    assert float(np.max(np.abs(traction.rec - adhered.rec))) == 0.0
    assert traction.plan.nodes[[3, 5], B.N_SLIPCOUNT].sum() == 0.0
