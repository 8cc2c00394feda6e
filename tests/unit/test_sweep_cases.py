"""The per-case Python of a batch (issue 14, ``webline.sim.sweeps.cases``): a case's line
re-validates
only what its paths touch yet equals ``Line.replace``'s, bad values give ``Line.replace``'s error,
and the batched eigenvalues give each case the fastest mode and RK4 sub-steps that
``simulate`` chooses."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.errors import LineFileError
from webline.sim.core.plan import compile_plan
from webline.sim.linear.linearize import fastest_mode, plan_linear_model
from webline.sim.simulate import choose_substeps
from webline.sim.sweeps.blocks import BLOCK, FIRST_BLOCK, blocks_of
from webline.sim.sweeps.cases import batch_rates, case_value, derive_line

CHANGES = [
    {"web.ea": "1800 lbf"},
    {"rollers.process.controller.tension_bandwidth": "2 Hz", "web.ea": 9000.0},
    {"spans.span2.length": 3.0, "spans[0].length": "2 ft"},
    {"rollers[2].drive.torque_limit": "3 N*m", "rollers[2].drive.torque_lag": "1 ms"},
    {"rollers.idler.friction": 1e-4, "rollers.unwind.inertia": 0.05},
    {"control.sample_rate": "500 Hz"},
    {"disturbances[0].amplitude": "2 lbf"},
    # a change of structure (a controller type) goes the same way
    {"rollers.process.controller": {"type": "state_feedback"}},
    # not inside one element: Line.replace's route
    {"speed": "800 ft/min"},
]


@pytest.fixture(scope="module")
def line():
    return webline.load_line("hswl").with_scenario("disturbance")


@pytest.mark.parametrize("changes", CHANGES, ids=lambda c: ",".join(c))
def test_derived_line_equals_replace(line, changes) -> None:
    derived = derive_line(line, changes)
    assert derived.spec.model_dump() == line.replace(changes).spec.model_dump()
    assert derived.source == line.source
    for path, value in changes.items():
        if isinstance(value, float):  # SI numbers come back as given
            assert case_value(derived, path) == value


@pytest.mark.parametrize("bad", [
    {"web.ea": "-3 kN"},                      # schema bound
    {"web.ea": "1e20 N"},                     # hard physical range
    {"web.eaa": 3.0},                         # unknown key
    {"rollers.nope.radius": 0.1},             # unknown element
    {"rollers.unwind.radius": "2 in"},        # check across keys: below the core radius
    {"rollers[9].radius": 0.1},               # index out of range
])
def test_bad_value_gives_replace_error(line, bad) -> None:
    with pytest.raises(LineFileError) as expected:
        line.replace(bad)
    with pytest.raises(LineFileError) as got:
        derive_line(line, bad)
    assert str(got.value) == str(expected.value)
    assert next(iter(bad)).split(".")[0].split("[")[0] in str(got.value)


def test_batched_rates_are_the_fastest_mode_and_substeps_agree() -> None:
    hswl = webline.load_line("hswl")
    lines = [hswl, hswl.replace({"web.ea": "1800 lbf"}),
             hswl.replace({"rollers.process.drive.torque_lag": "0.2 ms"}),  # a faster mode
             hswl.replace({"rollers.process.controller": {"type": "state_feedback"}}),
             webline.load_line("rockwell")]
    fresh = [compile_plan(derive_line(x, {})) for x in lines]
    rates = batch_rates(fresh)
    for line_, plan, rate in zip(lines, fresh, rates, strict=True):
        # a new plan of the same line, whose fastest mode comes from fastest.py's blocks
        reference = compile_plan(line_.replace({}))
        assert rate == pytest.approx(fastest_mode(reference), rel=1e-12)
        assert choose_substeps(plan, rate) == choose_substeps(reference)
        # the verdict's eigenvalues were left on the plan: the closed loop's own
        expected = np.linalg.eigvals(plan_linear_model(plan, loop="closed").a)
        cached = plan.memo[("eigenvalues", "closed", 0.0)]
        np.testing.assert_allclose(np.sort_complex(cached), np.sort_complex(expected),
                                   rtol=1e-12, atol=1e-9)
    steps = [choose_substeps(p, r) for p, r in zip(fresh, rates, strict=True)]
    assert steps[0] == 1 and steps[2] > 1  # the fast lag needs more sub-steps


def test_blocks_cover_every_case_once_and_grow() -> None:
    for n in (0, 1, FIRST_BLOCK, FIRST_BLOCK + 1, 5000):
        blocks = blocks_of(n)
        assert [c for b in blocks for c in b] == list(range(n))
        sizes = [len(b) for b in blocks]
        assert all(s <= BLOCK for s in sizes)
        if n > FIRST_BLOCK:
            assert sizes[0] == FIRST_BLOCK and sizes[1] == min(2 * FIRST_BLOCK, n - FIRST_BLOCK)
    assert max(len(b) for b in blocks_of(5000)) == BLOCK
    # a cap below the first block (a branched study's records: ``branch_batch.block_size``)
    assert [len(b) for b in blocks_of(7, largest=3)] == [3, 3, 1]
    assert [len(b) for b in blocks_of(100, largest=20)][:3] == [FIRST_BLOCK, 20, 20]
