"""The compiled fixed-step path agrees with the adaptive scipy reference (issue 2)."""

from __future__ import annotations

import numpy as np
import pytest

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


@pytest.mark.parametrize("hold", ["stall_tension", "zero_speed", "brakes", "off"])
def test_fast_path_matches_reference_through_a_web_break(hold):
    """rockwell's dancer span breaks at 0.1 s; the monitor (loadcell below 20 %) detects it
    and the line ramps to a stop in 0.1 s, then the drives hold (zero speed, brakes, or
    torque off). Both paths apply the break at the same tick, so they must agree through it
    as they do without one."""
    line = webline.load_line("rockwell").replace({"disturbances": [
        {"type": "web_break", "span": "dancer_span", "at": 0.1, "stop_time": 0.1,
         "hold": hold}]})
    fast = webline.simulate(line, 0.3)
    ref = webline.simulate_reference(line, 0.3, method="DOP853", rtol=1e-10, atol=1e-10)
    assert fast.break_monitor == ref.break_monitor == (0.1, 1)  # same tick, by tension
    broken = ref.time >= 0.1
    assert np.all(ref.tension[broken, :2] == 0.0)  # the reference knows the break
    scale = np.abs(ref.tension).max()
    # measured 2.8e-4 N of 141 N (2e-6) through a break at 0.2 s: RK4 at the 1 ms tick. A
    # set brake is static friction (W8): where a roller sticks or slips the right-hand side
    # jumps, which fixed-step RK4 meets to O(h) and DOP853 resolves (measured 0.12 N of
    # 292 N, 4e-4): the 1e-3 of the reference there
    tol = 1e-3 if hold == "brakes" else 2e-5
    assert np.abs(fast.tension - ref.tension).max() < tol * scale
    if hold == "brakes":  # a roller inside the stick band (>= 0.1 rad/s) is held at once: the
        # paths enter it up to a step apart, their speeds then differ by up to r x 0.1 rad/s
        # (rockwell's largest radius, 5 in: 0.0127 m/s; measured 0.0097 m/s, once)
        band = 0.1 * max(r.radius for r in line.spec.rollers)
        assert np.abs(fast.speed - ref.speed).max() < band
    else:
        assert np.abs(fast.speed - ref.speed).max() < tol * np.abs(ref.speed).max()
    held = ref.time > 0.21
    if hold in ("brakes", "off"):
        assert np.all(fast.torque_cmd[held] == 0.0)
    np.testing.assert_array_equal(fast.torque_cmd == 0.0, ref.torque_cmd == 0.0)
