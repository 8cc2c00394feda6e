"""The batched kernel's RMS tension error of a taper rewind's zone is measured against the
tapered reference, as a single run's (``Result.tension_ref``, docs/winder.md W1): tuning
(issue 24) minimises the batched number, so it must be the run's."""

from __future__ import annotations

import math

import numpy as np
import pytest

import webline
from webline.sim.sweep import run_cases


@pytest.mark.parametrize("scenario", ["startup", "flying-splice"])
def test_batched_rms_error_follows_the_taper(scenario: str) -> None:
    line = webline.load_line("converter")  # a 30 % linear taper on the rewind zone
    run = webline.simulate(line, scenario=scenario)
    k = line.spec.spans.index(next(s for s in line.spec.spans if s.name == "rewind_span"))
    single = math.sqrt(float(np.mean((run.tension[:, k] - run.tension_ref[:, k]) ** 2)))
    batched = float(run_cases(line, [{}], scenario=scenario).tension_rms_error.values[0, k])
    # the same records and the same reference: equal to rounding (sums of 2e4 squares)
    assert batched == pytest.approx(single, rel=1e-9)


def test_batched_rms_error_follows_the_tension_ramp() -> None:
    """With a start/stop tension ramp (docs/winder.md R1) every zone's reference is scaled
    by the ramp's factor in a single run; the batch measures against the same."""
    line = webline.load_line("converter").replace(
        {"control.tension_ramp": {"standstill": 0.3, "time": "3 s"}})
    run = webline.simulate(line, scenario="startup")
    ds = run_cases(line, [{}], scenario="startup")
    for k in range(line.n_spans):
        if np.all(np.isfinite(run.tension_ref[:, k])):
            single = math.sqrt(float(np.mean((run.tension[:, k] - run.tension_ref[:, k]) ** 2)))
            assert float(ds.tension_rms_error.values[0, k]) == pytest.approx(single, rel=1e-9)
