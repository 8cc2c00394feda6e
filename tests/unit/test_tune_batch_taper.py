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
