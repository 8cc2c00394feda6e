"""hswl read as a line of one web (``spec.one_web``; the same line as the hand-written
``tests/data/hswl_one_web.toml``, tests/unit/test_one_web_spec.py) runs through the general
(branched) loop as the single-path hswl runs through the chain's (issue 33): the same step,
the same trajectories."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.model.one_web import load_one_web
from webline.sim.branches.linear import fastest_rate
from webline.sim.branches.run import plan_and_step
from webline.sim.core.plan import compile_plan
from webline.sim.linear.linearize import fastest_mode
from webline.sim.simulate import choose_substeps
from webline.sim.user_control import builtin_stand_in


@pytest.fixture(scope="module")
def one_web():
    return load_one_web("hswl")


def test_one_web_takes_one_sub_step_at_the_unwinds_torque_lag(one_web):
    """The general loop's fastest mode on hswl is the 500 1/s of its 2 ms torque lags (to
    the eigen-solve's 1e-9: it gives 500.000000002), so the one step rule
    (``sim.linear.steps``) takes one RK4 sub-step per 1 ms tick: the chain's count, and half
    the work of the two it took before (issue 33)."""
    plan, point, substeps = plan_and_step(one_web, None, None)
    assert fastest_rate(plan, point) == pytest.approx(1.0 / 2e-3, rel=1e-9)
    assert substeps == 1


@pytest.mark.chain_only("test_one_web_takes_one_sub_step_at_the_unwinds_torque_lag")
def test_one_web_takes_the_chains_sub_steps(one_web):
    """Both loops' fastest mode is the unwind's 500 1/s torque lag (1 / 2 ms); the branched
    eigen-solve rounds it to 500.000000002, which took two RK4 sub-steps per 1 ms tick
    where the chain took one (issue 33). One rule (``sim.linear.steps``) takes one for both."""
    plan, point, substeps = plan_and_step(one_web, None, None)
    chain = compile_plan(webline.load_line("hswl"))
    assert fastest_rate(plan, point) == pytest.approx(fastest_mode(chain), rel=1e-9)
    assert substeps == choose_substeps(builtin_stand_in(chain)) == 1


def _tension_gap(one_web, scenario: str, duration: float | None = None) -> float:
    """Largest |T_one-web - T_chain| [N] over the run and the four spans."""
    chain = webline.simulate("hswl", duration, scenario=scenario)
    general = webline.simulate(one_web, duration, scenario=scenario)
    return float(np.max(np.abs(general.dataset.tension.values - chain.tension)))


def test_one_web_reproduces_the_chain_with_a_ripple_and_an_eccentric_roller(one_web):
    """The disturbance scenario (1 lbf wound-in ripple at 1 Hz, 0.05 mm eccentric idler):
    both loops now evaluate the wound-in tension at each RK4 stage's time and start the
    out-of-round idler at the mean arm's speed v / r (docs/errata.md, "One loop"); before,
    the general loop held the ripple over a tick (3.4e-4 N apart) and started the idler at
    v / (r + e), 0.13 % slow (a 0.058 N transient). Same equations, same step, same
    order of operations: what is left is rounding, measured 1e-13 N; 1e-9 N (1e-11 of the
    64 N tension) allows for a different summation order."""
    assert _tension_gap(one_web, "disturbance") < 1e-9


def test_one_web_reproduces_the_chain_after_a_tension_step(one_web):
    """span2's reference steps 14.35 -> 18 lbf at 2 s: the process drive's draw is the
    mass-flow ratio (EA - T_1) / (EA - T_2) at the new reference (thesis 6.22), so its speed
    feedforward steps with it on both loops; the general loop kept the start's draw and left
    the step to the tension integrator (0.19 N apart). Measured 3e-13 N; 1e-9 N as above
    (the draw coefficient from two operating points is exact to the solver's 1e-13)."""
    assert _tension_gap(one_web, "tension-step") < 1e-9


@pytest.mark.parametrize("scenario", [None, "speed-change"])
def test_one_web_reproduces_the_chain_where_nothing_differed(one_web, scenario):
    """A steady run and a speed ramp (measured 4e-13 and 8e-13 N before and after)."""
    assert _tension_gap(one_web, scenario, 5.0) < 1e-9


def test_a_session_reference_step_moves_the_draw_as_in_the_chain(one_web):
    """``Session.set_reference`` steps span2's reference 25 % up mid-run: the general loop's
    session fills its draw coefficients whatever its file's references do, so its process
    drive's feedforward steps with the reference as the chain's does; 1 s on, the tensions
    agree to 1e-9 N as in the scenario above."""
    chain, general = webline.Session("hswl"), webline.Session(one_web)
    for session in (chain, general):
        session.step(200)
        session.set_reference("span2.tension", 80.0)
        session.step(1000)
    ran, held = general.result(), chain.result()
    n = min(len(ran.time), len(held.time))  # (one session also records the state at its end)
    assert np.array_equal(ran.time[:n], held.time[:n]) and n >= 1200
    gap = np.abs(ran.dataset.tension.values[:n] - held.tension[:n])
    assert float(np.max(gap)) < 1e-9


#: process drive's encoder 2 % high and 2 ms late, span2's loadcell 3 ms late, the master's
#: encoder 1 % low (the line runs 1 % fast): every sensor path of the loops (docs/line-file.md,
#: "sensors")
SENSORS = [
    {"name": "enc", "type": "encoder", "roller": "process", "scale": 1.02, "delay": "2 ms"},
    {"name": "lc2", "type": "loadcell", "span": "span2", "delay": "3 ms"},
    {"name": "enc_master", "type": "encoder", "roller": "master", "scale": 0.99},
]


@pytest.mark.chain_only("tests/integration/test_branch_sensors.py::"
                        "test_an_encoder_scale_and_delays_act_on_a_branched_line")
def test_one_web_reproduces_the_chain_with_encoder_scales_and_sensor_delays(one_web):
    """The same ``[[sensors]]`` on both lines over the tension step: the master's encoder
    scale moves the operating point's line speed (v_ref / 0.99), the process encoder's
    scale its tension integrator's start, the delays start filled with the initial
    readings (the run starts steady); from there both loops read the same late, scaled
    signals. 1e-9 N as the tests above (the step makes the delays act: the 3 ms late
    loadcell costs the process loop damping)."""
    chain_line = webline.load_line("hswl").replace({"sensors": SENSORS})
    chain = webline.simulate(chain_line, 4.0, scenario="tension-step")
    general = webline.simulate(one_web.replace({"sensors": SENSORS}), 4.0,
                               scenario="tension-step")
    ideal = webline.simulate("hswl", 4.0, scenario="tension-step")
    gap = np.abs(general.dataset.tension.values - chain.tension)
    assert float(np.max(gap)) < 1e-9
    # (the sensors act: the delays change the step's transient by far more than 1e-9 N)
    assert float(np.max(np.abs(chain.tension - ideal.tension))) > 1e-3
    assert np.allclose(general.dataset.speed.values, chain.speed, rtol=0.0, atol=1e-9)
