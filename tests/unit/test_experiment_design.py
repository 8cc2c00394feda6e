"""The step design of identification experiments (``twin.tuning.experiment_design``) on
systems whose answers are known in closed form."""

from __future__ import annotations

import math

import numpy as np
import pytest

from webline.sim.linear.linearize import LinearModel
from webline.twin.tuning.experiment_design import (
    RAMP_GRID,
    TORQUE_SHARE,
    design_step,
    nice_rate,
)


def first_order(tau: float, gain: float) -> LinearModel:
    """A drive's torque following its reference with time constant ``tau`` [s]: dx/dt =
    (gain u - x) / tau, the torque the only signal."""
    return LinearModel(np.array([[-1.0 / tau]]), np.array([[gain / tau]]),
                       np.zeros((0, 1)), ["d_torque"], ["ref"], [])


def second_order(wn: float, zeta: float, gain: float) -> LinearModel:
    """A torque with an underdamped response (overshoot exp(-π ζ / √(1-ζ²)))."""
    a = np.array([[0.0, 1.0], [-wn**2, -2 * zeta * wn]])
    b = np.array([[0.0], [gain * wn**2]])
    return LinearModel(a, b, np.zeros((0, 2)), ["d_torque", "d_rate"], ["ref"], [])


def test_first_order_settles_when_its_ramp_response_is_within_one_percent():
    """After a ramp of width T the response lags its final value by k (τ/T)(e^{T/τ} - 1)
    e^{-t/τ} (t from the ramp's start): within 1 % at t = τ ln(100 (τ/T)(e^{T/τ} - 1))."""
    tau, gain = 0.2, 10.0
    design = design_step(first_order(tau, gain), {"ref": 1.0}, ["d"], np.zeros(1),
                         np.array([100.0]))
    width = design.ramp
    assert width == pytest.approx(RAMP_GRID)  # no overshoot: 10 % of the limit at most
    exact = tau * math.log(100 * (tau / width) * (math.exp(width / tau) - 1))
    assert design.settle == pytest.approx(exact, abs=2e-3)  # the response's time step
    # its one mode (1/τ = 5 rad/s) moves the torque by ~10 N·m >> noise: 10 samples per
    # period of 0.8 Hz, or 10 across the 50 ms ramp (200 Hz) -> 200 Hz
    assert design.rate == 200.0 and design.fastest == pytest.approx(1 / tau)


def test_the_ramp_is_the_shortest_that_keeps_the_torque_inside_its_share():
    """An underdamped torque (ζ = 0.2: 53 % overshoot) with a final value of 60 % of the
    limit overshoots to 92 % on an instant step: the ramp must spread it below 80 %, and
    one grid step shorter would not."""
    model = second_order(20.0, 0.2, 60.0)
    limit = np.array([100.0])
    design = design_step(model, {"ref": 1.0}, ["d"], np.zeros(1), limit)
    assert design.ramp > RAMP_GRID and design.peak_share <= TORQUE_SHARE
    shorter = design_step(model, {"ref": 1.0}, ["d"], np.zeros(1), limit,
                          ramp=design.ramp - RAMP_GRID)
    assert shorter.peak_share > TORQUE_SHARE


def test_the_torque_at_the_operating_point_counts_against_the_limit():
    """A drive already at 50 % of its limit has 30 % left for the step: going up it peaks
    at 50 + 60 x (overshoot) %, coming back from 110 % it undershoots: the ramp is longer."""
    model = second_order(20.0, 0.2, 20.0)
    free = design_step(model, {"ref": 1.0}, ["d"], np.zeros(1), np.array([100.0]))
    loaded = design_step(model, {"ref": 1.0}, ["d"], np.array([50.0]), np.array([100.0]))
    assert loaded.ramp > free.ramp and loaded.peak_share <= TORQUE_SHARE


@pytest.mark.parametrize("rate, nice", [(660.0, 1000.0), (200.0, 200.0), (201.0, 500.0),
                                        (0.8, 1.0), (12.0, 20.0)])
def test_logging_rates_are_what_loggers_offer(rate, nice):
    assert nice_rate(rate) == nice
