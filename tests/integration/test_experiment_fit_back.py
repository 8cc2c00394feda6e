"""Experiments that excite and can be fitted back (issue 36 item 7): hswl's tension-step
test, laid out from the linearized closed loop, keeps its drives inside their torque limits,
lasts 13 s where 10 L/v holds took 484 s, and its own record, logged at the rate the test
states, is fitted back to the noise floor."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import webline
from webline.cli import app
from webline.line import load_line
from webline.twin.fitting.fit import fit
from webline.twin.traces.synthetic import synthetic_csv
from webline.twin.tuning.experiment import plan_experiment
from webline.twin.tuning.experiment_design import TORQUE_SHARE

LINE = load_line("hswl")


@pytest.fixture(scope="module")
def plan():
    return plan_experiment(LINE, "tension-step")


def limits() -> np.ndarray:
    return np.array([LINE.spec.rollers[i].drive.torque_limit for i in LINE.drives])


def test_tension_step_keeps_every_drive_inside_its_torque_limit(plan):
    """The simulated torques (RK4, discrete controllers, the full nonlinear line) stay within
    the design's 80 % of each limit; the unwind, the drive the first step loads most, uses
    more than half of it (the ramp is short: 50 ms, the grid's least). The same step
    applied at once drives the unwind onto its limit (the issue's torque spikes)."""
    run = webline.simulate(plan.line, plan.duration)
    share = np.abs(run.torque).max(axis=0) / limits()
    assert share.max() <= TORQUE_SHARE and share[0] > 0.5, share
    ref = float(LINE.spec.spans[0].tension)
    instant = webline.simulate(LINE.replace({"spans.span1.tension": {
        "type": "steps", "initial": ref, "steps": [{"time": 0.5, "value": 1.1 * ref}]}}), 1.5)
    assert np.abs(instant.torque[:, 0]).max() >= 0.99 * limits()[0]


def test_tension_step_is_short(plan):
    """Three zones, each ramped up, held until settled to 1 % (1.8 s, from the closed loop's
    slowest excited mode at 5.7 rad/s) or the 2 s floor, ramped back and held again: 1 s of
    rest + 3 x 4 s = 13 s, where holds of 10 L/v = 80.5 s (the 20.4 m rewind zone at
    2.54 m/s) made it 484 s."""
    assert plan.duration == 13.0
    assert plan.logging_rate == 1000.0  # 10 samples per period of the 66 Hz torque modes
    assert "rewind_torque" in plan.rate_reason


def test_cli_states_the_logging_rate_in_terminal_and_file(tmp_path):
    result = CliRunner().invoke(app, ["experiment", "hswl", "tension-step", "-o",
                                      str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert "log at 1000 Hz or faster" in result.output
    data = json.loads((tmp_path / "experiment.json").read_text())
    assert data["logging_rate_hz"] == 1000.0 and "66.1 Hz" in data["logging_rate_reason"]
    time = np.loadtxt(tmp_path / "results.csv", delimiter=",", skiprows=1, usecols=0)
    assert np.diff(time).mean() == pytest.approx(1e-3)  # recorded at the stated rate


def test_a_fit_of_its_own_record_replays_the_truth_at_the_noise_floor(plan, tmp_path):
    """The test run on a line whose EA is 5 % above the file's and whose process roller is
    30 % heavier, logged at the stated 1 kHz with sensor noise, fitted from the file's
    values: residuals at the noise (white noise of the estimated levels gives ~1, the
    estimate from second differences is within ~15 %), both values inside their intervals."""
    truth = {"web.ea": 1.05 * float(LINE.spec.web.ea), "rollers.process.inertia": 0.11}
    path = synthetic_csv(tmp_path / "step.csv", plan.line, changes=truth,
                         duration=plan.duration, rate=plan.logging_rate, seed=1)
    result = fit(plan.line, path, {"web.ea": "5000 .. 20000 N",
                                   "rollers.process.inertia": "0.01 .. 0.5 kg*m**2"}, starts=1)
    assert 0.8 < result.residual_scale < 1.2, result
    for i, p in enumerate(result.parameters):
        low, high = result.ci95[i]
        assert low <= truth[p.path] <= high, (p.path, result)
