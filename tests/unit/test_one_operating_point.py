"""A plan computes its line's operating point once and hands it to everything that needs it
(drive table, section models, initial state, linear models, sub-step choice): issue 12."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import webline
from webline.control.select import with_controller
from webline.model import operating_point as op_module
from webline.sim.core.plan import compile_plan
from webline.sim.linear.linearize import (
    fastest_mode,
    linear_model,
    plan_eigenvalues,
    plan_linear_model,
)


def count_calls(monkeypatch: pytest.MonkeyPatch) -> list[tuple[object, ...]]:
    """Replace ``operating_point`` wherever a webline module bound it; return the call log."""
    real = op_module.operating_point
    calls: list[tuple[object, ...]] = []

    def counted(*args: object, **kwargs: object) -> object:
        calls.append(args)
        return real(*args, **kwargs)  # type: ignore[arg-type]

    for name, module in list(sys.modules.items()):
        if name.startswith("webline") and getattr(module, "operating_point", None) is real:
            monkeypatch.setattr(module, "operating_point", counted)
    return calls


@pytest.mark.parametrize("family", ["cascaded_pi", "state_feedback", "adaptive"])
def test_simulate_of_a_newly_loaded_line_computes_its_operating_point_once(
        monkeypatch: pytest.MonkeyPatch, family: str) -> None:
    def make() -> webline.Line:
        return with_controller(webline.load_line("hswl"), family)

    webline.simulate(make(), 0.01)  # the loop of this structure compiled (or loaded) first
    calls = count_calls(monkeypatch)
    line = make()
    webline.simulate(line, 1.0)
    assert len(calls) == 1
    webline.simulate(line, 1.0)  # the same line again: its plan (and operating point) is kept
    assert len(calls) == 1


def test_the_plans_linear_model_is_the_one_at_its_operating_point() -> None:
    """``plan_linear_model`` (cached, at ``plan.op``) equals a model built at a freshly computed
    operating point at t = 0, and the fastest mode is the largest |eigenvalue| of both loops."""
    line = webline.load_line("hswl")
    plan = compile_plan(line)
    fresh = op_module.operating_point(webline.load_line("hswl"))
    np.testing.assert_array_equal(plan.op.tension, fresh.tension)
    for loop in ("open", "closed"):
        assert plan_linear_model(plan, loop=loop) is linear_model(line, loop=loop)
    # at t = 1 ns (built anew, not from the plan) the modes are those of t = 0 to ~1e-9
    largest = max(np.abs(np.linalg.eigvals(webline.linearize(line, 1e-9, loop=loop).A)).max()
                  for loop in ("open", "closed"))
    assert fastest_mode(plan) == pytest.approx(largest, rel=1e-6)


def test_a_stability_check_reuses_the_plans_model_and_eigenvalues(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """What a verdict's linear-stability check asks of a simulated plan costs nothing more at
    t = 0, and one operating point at another instant; the modes are those of ``linearize``."""
    line = webline.load_line("hswl")
    result = webline.simulate(line, 0.1)
    calls = count_calls(monkeypatch)
    eig = plan_eigenvalues(result.plan, loop="closed")
    assert len(calls) == 0 and eig is plan_eigenvalues(result.plan, loop="closed")
    assert np.sort_complex(eig) == pytest.approx(
        np.sort_complex(np.linalg.eigvals(webline.linearize(line).A)), rel=1e-9)
    later = plan_eigenvalues(result.plan, loop="closed", t=5.0)
    plan_eigenvalues(result.plan, loop="closed", t=5.0)
    assert len(calls) == 1 and later.shape == eig.shape
