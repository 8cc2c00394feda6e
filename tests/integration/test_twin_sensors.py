"""Sensors in the model (issue 36 item 3, "Must show": the in-loop loadcell gain error found
as a gain within 1 % with friction within 10 %). hswl's accel-ramps test run on a line whose
process-zone loadcell reads 3 % high inside its loop (the process drive holds the reading on
the 63.8 N set point, so the web carries 63.8 / 1.03 = 62.0 N) and whose process roller has
1.0 N·m·s of viscous friction (the file: 0.678), logged at 200 Hz with sensor noise."""

from __future__ import annotations

import pytest

import webline
from webline.line import load_line
from webline.twin.fitting.fit import fit
from webline.twin.traces.synthetic import synthetic_csv
from webline.twin.tuning.experiment import plan_experiment

TRUTH = {"sensors.lc2.gain": 1.03, "rollers.process.friction": 1.0}
FRICTION = {"rollers.process.friction": "0.05 .. 3 N*m*s"}
GAIN = {"sensors.lc2.gain": "0.9 .. 1.1"}


@pytest.fixture(scope="module")
def ramps(tmp_path_factory):
    """The first 8 s of accel-ramps (rest, the first ramp, its hold) on the changed line; and
    the line file's line, whose loadcell is declared ideal (gain 1)."""
    base = plan_experiment(load_line("hswl"), "accel-ramps").line
    line = base.replace({"sensors": [{"name": "lc2", "type": "loadcell", "span": "span2"}]})
    path = synthetic_csv(tmp_path_factory.mktemp("sensor") / "ramps.csv", line,
                         changes=TRUTH, duration=8.0, rate=200.0, seed=1)
    return line, path


def test_the_loadcell_gain_is_found_as_a_gain(ramps):
    """Gain and friction freed together: the drive torques carry the true tension (r ΔT,
    speed-independent) and the friction (b ω, growing along the ramp) apart, so both come
    back; the residuals reach the noise floor (~1)."""
    line, path = ramps
    result = fit(line, path, {**GAIN, **FRICTION}, starts=1)
    gain, friction = result.value
    assert gain == pytest.approx(1.03, rel=0.01)
    assert friction == pytest.approx(1.0, rel=0.10)
    assert result.residual_scale < 1.2, result
    assert result.verdict.status == "good", result.verdict
    for i, p in enumerate(result.parameters):  # the truth inside the reported interval
        assert result.ci95[i, 0] <= TRUTH[p.path] <= result.ci95[i, 1], p.path


def test_without_the_gain_the_fit_is_called_poor(ramps):
    """Friction alone cannot explain a tension 3 % below what the log shows: measured (seen
    while writing this test) the friction lands at 0.976 N·m·s, but the residuals stay ~3 x
    the noise, correlated on the process torque, and the verdict says poor with that
    reason, where the fit with the gain reached the noise."""
    line, path = ramps
    result = fit(line, path, FRICTION, starts=1)
    assert result.residual_scale > 1.5, result
    assert result.verdict.status == "poor", result.verdict
    assert any("torque[process]" in r for r in result.verdict.reasons), result.verdict


@pytest.fixture(scope="module")
def startup(tmp_path_factory):
    """The issue's case: 10 s of the converter's start-up, logged at 200 Hz with sensor
    noise, on a line whose process-span loadcell reads 3 % high inside the infeed's loop (the
    web at 194 N, the log at 200 N) and whose drum (the master) has 0.12 N·m·s of friction
    (the file: 0.05)."""
    line = webline.load_line("converter").replace(
        {"sensors": [{"name": "lc_process", "type": "loadcell", "span": "process_span"}]})
    path = synthetic_csv(tmp_path_factory.mktemp("startup") / "startup.csv", line,
                         changes={"sensors.lc_process.gain": 1.03,
                                  "rollers.drum.friction": 0.12},
                         duration=10.0, scenario="startup", seed=1)
    return line, path


DRUM = {"rollers.drum.friction": "0.005 .. 0.5 N*m*s"}


def test_the_converters_loadcell_gain_is_not_absorbed_into_the_drums_friction(startup):
    """With the gain free: gain and drum friction within 1 % (measured: 1.0300 and 0.1197);
    with the friction alone the drum's torque has to carry 6 N·r of missing tension: the
    friction runs to its lower bound (truth 0.12, 24 x above it), the verdict is poor and
    names the bound and the drum's correlated torque residual."""
    line, path = startup
    both = fit(line, path, {"sensors.lc_process.gain": "0.9 .. 1.1", **DRUM},
               scenario="startup", starts=1)
    assert both.value[0] == pytest.approx(1.03, rel=0.01)
    assert both.value[1] == pytest.approx(0.12, rel=0.10)
    assert both.verdict.status == "good", both.verdict
    alone = fit(line, path, DRUM, scenario="startup", starts=1)
    assert alone.verdict.status == "poor", alone.verdict
    assert alone.at_bound[0] == "low"
    assert any("torque[drum]" in r for r in alone.verdict.reasons), alone.verdict
