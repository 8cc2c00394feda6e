"""hswl written as a line of one web (``tests/data/hswl_one_web.toml``) runs through the
general (branched) loop as the single-path hswl runs through the chain's (issue 33): the same
step, the same trajectories."""

from __future__ import annotations

from pathlib import Path

import pytest

import webline
from webline.model.web_graph import load_branched
from webline.sim.branches.linear import fastest_rate
from webline.sim.branches.run import plan_and_step
from webline.sim.core.plan import compile_plan
from webline.sim.linear.linearize import fastest_mode
from webline.sim.simulate import choose_substeps
from webline.sim.user_control import builtin_stand_in

ONE_WEB = Path(__file__).parents[1] / "data" / "hswl_one_web.toml"


@pytest.fixture(scope="module")
def one_web():
    return load_branched(ONE_WEB)


def test_one_web_takes_the_chains_sub_steps(one_web):
    """Both loops' fastest mode is the unwind's 500 1/s torque lag (1 / 2 ms); the branched
    eigen-solve rounds it to 500.000000002, which took two RK4 sub-steps per 1 ms tick
    where the chain took one (issue 33). One rule (``sim.linear.steps``) takes one for both."""
    plan, point, substeps = plan_and_step(one_web, None, None)
    chain = compile_plan(webline.load_line("hswl"))
    assert fastest_rate(plan, point) == pytest.approx(fastest_mode(chain), rel=1e-9)
    assert substeps == choose_substeps(builtin_stand_in(chain)) == 1
