"""The compiled fixed-step path agrees with the adaptive scipy reference (issue 2)."""

from __future__ import annotations

import numpy as np

import webline

RAMP = {"type": "ramp", "initial": "200 ft/min", "final": "1000 ft/min", "start": 1.0,
        "duration": 5.0}


def test_fast_path_matches_reference_over_60s_ramp(hswl):
    line = hswl.replace(speed=RAMP, disturbances=[
        {"type": "wound_in_ripple", "amplitude": "1 lbf", "frequency": "1 Hz"}])
    fast = webline.simulate(line, 60.0)
    ref = webline.simulate_reference(line, 60.0, method="DOP853", rtol=1e-10, atol=1e-10)
    assert fast.time.shape == ref.time.shape
    error = np.abs(fast.tension - ref.tension) / ref.tension
    # the issue asks for 1e-3 of the reference tension; RK4 at the 1 ms tick gives ~1e-7
    assert error.max() < 1e-3
    assert error.max() < 1e-5, "RK4 accuracy degraded by two orders of magnitude"
    np.testing.assert_allclose(fast.speed, ref.speed, rtol=1e-6)
