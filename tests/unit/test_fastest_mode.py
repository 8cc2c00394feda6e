"""The fastest mode that sets the RK4 step (``webline.sim.linear.fastest``): a rigorous upper bound
of
max |λ|, exact on small blocks, within ~10 % on a 64-span line."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import webline
from webline.sim.core.plan import compile_plan
from webline.sim.linear import fastest
from webline.sim.linear.linearize import fastest_mode, plan_linear_model

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from long_line import long_line


def exact(a: np.ndarray) -> float:
    return float(np.abs(np.linalg.eigvals(a)).max())


@pytest.mark.parametrize("name", ["hswl", "rockwell"])
def test_built_in_lines_get_their_exact_fastest_mode(name: str) -> None:
    """Their blocks are small: the bound is the dense eigenvalue solve's value, to rounding."""
    plan = compile_plan(webline.load_line(name))
    largest = max(exact(np.asarray(plan_linear_model(plan, loop=loop).a))
                  for loop in ("open", "closed"))
    assert fastest_mode(plan) == pytest.approx(largest, rel=1e-12)


def test_long_line_bound_is_above_and_close() -> None:
    """64 spans, 230 closed-loop states (over ``DENSE_STATES``): never below max|λ| (a step
    from it is as safe as from the eigenvalues), and within 10 % of it so that it rarely adds
    a sub-step (measured: 5 % in closed loop; exact 500 1/s in open loop from the lags)."""
    plan = compile_plan(long_line(31))
    for loop in ("open", "closed"):
        a = np.asarray(plan_linear_model(plan, loop=loop).a)
        assert a.shape[0] > fastest.DENSE_STATES
        true = exact(a)
        assert true <= fastest.spectral_radius_bound(a) <= 1.10 * true


def test_bound_holds_on_random_matrices(monkeypatch: pytest.MonkeyPatch) -> None:
    """Rigour of the Gelfand/Collatz-Wielandt path on non-normal sparse matrices with complex
    eigenvalues (all blocks forced through it)."""
    monkeypatch.setattr(fastest, "DENSE_STATES", 0)
    rng = np.random.default_rng(12)
    for _ in range(20):
        n = int(rng.integers(5, 60))
        a = rng.standard_normal((n, n)) * (rng.random((n, n)) < 0.1)
        a += np.diag(rng.uniform(-50, 0, n)) + np.diag(rng.uniform(-30, 30, n - 1), 1)
        assert fastest.spectral_radius_bound(a) >= exact(a) * (1 - 1e-12)
