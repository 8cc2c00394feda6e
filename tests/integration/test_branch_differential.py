"""Differential (slip) shafts on a branched line (docs/branching.md, "Differential shafts"):
each lane's core is driven through a slip clutch that passes its slip torque Q, so each
lane's tension is set by Q / its radius, not by its kinematics."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import LineFileError, SimulationError
from webline.model.web_graph import load_branched
from webline.sim.branches.result import BranchResult

SLIP_TORQUE = 8.0  # N·m: 100 N at the lanes' starting radius of 80 mm
CORE_INERTIA = 0.005  # kg·m²: a 400 mm cardboard core with its friction ring


def _slitter(shaft: dict | None = None) -> dict:
    data = load_branched("slitter").spec.model_dump(exclude_none=True)
    for roller in data["rollers"]:
        if roller["name"] == "rewind_shaft":
            roller["shaft"] = shaft or {"type": "differential", "slip_torque": SLIP_TORQUE,
                                        "overspeed": 0.02, "core_inertia": CORE_INERTIA}
    return data


@pytest.fixture(scope="module")
def profile_run() -> BranchResult:
    return webline.simulate(load_branched(_slitter()), scenario="thickness-profile")


def test_a_differential_shaft_holds_each_lane_at_slip_torque_over_its_radius(profile_run):
    """Thickness profile (lane_1 1 % thicker): on a rigid shaft the lanes diverge at ~5 N/s
    (47 N apart after 20 s, test_branches.py); on slip clutches each lane's core balances
    J_j dω_j/dt = Q - r_j T_j, so T_j = (Q - J_j dω_j/dt) / r_j and the lanes differ only by
    their radii's ratio."""
    ds = profile_run.dataset
    assert profile_run.failure is None
    lanes = ["lane_1_span", "lane_2_span"]
    tension = ds.tension.sel(span=lanes).values
    radius = ds.radius.sel(roll=["rewind_shaft/lane_1", "rewind_shaft/lane_2"]).values
    late = ds.time.values > 1.0  # after the start's transient (the spans' lag L/v = 0.4 s)
    # r_j T_j = Q - J_j dω_j/dt; the core decelerates as its roll grows (dω/dt = -ω ṙ/r,
    # J_j <= 0.032 kg·m² at the end): at most 0.009 N·m, so 0.2 % of Q bounds it
    torque = tension[late] * radius[late]
    assert np.max(np.abs(torque - SLIP_TORQUE)) < 2e-3 * SLIP_TORQUE
    # the lanes differ by Q (1/r_1 - 1/r_2) (-0.089 N at 20 s) up to the inertia terms'
    # difference (1 % of 0.1 N): 0.01 N
    spread = tension[-1, 0] - tension[-1, 1]
    assert abs(spread - SLIP_TORQUE * (1 / radius[-1, 0] - 1 / radius[-1, 1])) < 0.01
    assert abs(spread) < 0.2  # where the rigid shaft's lanes are 47 N apart


def test_a_differential_shaft_overspeeds_its_fastest_core(profile_run):
    """The shaft's speed loop holds it ``overspeed`` above the lanes' cores, so every clutch
    slips (forward) all run long: shaft ω / fastest core ω = 1.02 to the speed loop's error
    (the feed-forward ratio follows the measuring lane's radius: < 0.1 %)."""
    ds = profile_run.dataset
    shaft = ds.omega.sel(node="rewind_shaft").values
    fastest = ds.core_omega.max("core").values
    late = ds.time.values > 1.0
    assert np.max(np.abs(shaft[late] / fastest[late] - 1.02)) < 1e-3


def test_a_differential_shaft_starts_at_its_operating_point():
    """The operating point solves the cores' balance too: a run started there stays there.
    The lane's tension then follows Q / r as its roll grows (0.6 N/s at 80 mm), so what
    stays put is the lane's torque r T: within 1e-3 N·m (0.01 % of Q) over 20 ms, the
    amount r T would move by were T held while the roll grows 0.01 mm (measured 3.7e-4: the
    span's tension starts following Q / r with its lag L/v = 0.4 s)."""
    result = webline.simulate(load_branched(_slitter()), 0.02)
    ds = result.dataset
    tension = ds.tension.sel(span="lane_1_span").values
    radius = ds.radius.sel(roll="rewind_shaft/lane_1").values
    assert abs(tension[0] - SLIP_TORQUE / 0.08) < 0.1  # J dω/dt/r: 0.006 N·m / 0.08 m
    assert np.ptp(tension * radius) < 1e-3


def test_a_differential_shaft_is_refused_on_a_single_path_line():
    data = webline.load_line("hswl").spec.model_dump(exclude_none=True)
    data["rollers"][-1]["shaft"] = {"type": "differential", "slip_torque": 8.0,
                                    "core_inertia": 0.005}
    with pytest.raises(LineFileError, match=r"rollers\[\d+\]\.shaft.*only on a branched"):
        webline.load_line(data)


@pytest.mark.parametrize("key, value, problem", [
    ("slip_torque", -1.0, "slip_torque"), ("overspeed", 0.0, "overspeed"),
    ("core_inertia", 0.0, "core_inertia")])
def test_a_bad_differential_shaft_key_is_one_line(key, value, problem):
    shaft = {"type": "differential", "slip_torque": 8.0, "core_inertia": 0.005, key: value}
    with pytest.raises(LineFileError, match=rf"rollers\[4\]\.shaft\.{problem}"):
        load_branched(_slitter(shaft))


def test_a_differential_shaft_refuses_a_start_from_rest():
    with pytest.raises(SimulationError, match="differential shaft"):
        webline.simulate(load_branched(_slitter()), 0.01, scenario="start-up")


def test_the_linear_model_has_each_core_hanging_on_its_lane():
    """With slipping clutches (no torque change with slip) each core is a mass on its lane's
    span: J = J_c + (π/2) w ρ (r⁴ - r_c⁴) = 0.0113 kg·m², spring EA_lane / L = 45 kN/m at
    r = 80 mm. Lanes 1 and 2 in opposite phase leave the slitter roller still: ω = r √(EA /
    (L J)) = 159.4 rad/s, damped by the span's transport, σ = v / 2L = 1.25 1/s (to 0.5 %:
    the tension-dependent terms of (B1) are 1e-3 of EA). In phase they swing the slitter
    roller (J/r² = 0.8 kg on the knife span's 187 kN/m and lane_3's 45 kN/m): a three-mass
    estimate gives 134 rad/s; the rest of the line moves it by a few %: within 5 %."""
    from webline.sim.branches.linear import linear_model

    model = linear_model(load_branched(_slitter()), loop="open")
    assert "rewind_shaft/lane_1_core_omega" in model.states
    modes = sorted((e for e in np.linalg.eigvals(model.a) if 100 < e.imag < 300),
                   key=lambda e: e.imag)
    j = CORE_INERTIA + np.pi / 2 * 0.4 * 1390 * (0.08**4 - 0.0762**4)
    assert len(modes) == 2
    assert modes[1].imag == pytest.approx(0.08 * np.sqrt(90e3 / (2.0 * j)), rel=5e-3)
    assert -modes[1].real == pytest.approx(5.0 / (2 * 2.0), rel=1e-2)
    assert modes[0].imag == pytest.approx(134.0, rel=0.05)
