"""Tension ramps at start and stop (issue 21 item 9, docs/winder.md R1): every zone's set
tension runs from a standstill fraction to its running value when the line starts and back
when it stops."""

from __future__ import annotations

import numpy as np
import pytest

import webline
from webline.model.operating_point import operating_point
from webline.model.tension_ramp import ramp_profile

FPM = 0.3048 / 60
#: from rest, 0 -> 500 ft/min from 1 s to 6 s, held to 12 s, down to rest at 17 s
SPEED = {"type": "table", "time": [0, 1, 6, 12, 17],
         "value": ["0 fpm", "0 fpm", "500 fpm", "500 fpm", "0 fpm"]}
RAMP = {"standstill": 0.3, "time": "2 s"}  # below: 0.05 m/s (default)


@pytest.fixture(scope="module")
def ramped():
    line = webline.load_line("hswl").replace({"speed": SPEED, "control.tension_ramp": RAMP})
    return line, webline.simulate(line, 22.0)


def test_the_ramp_starts_and_ends_where_the_speed_reference_crosses_the_standstill_band():
    """By hand: the line passes 0.05 m/s at 1 + 0.05/(500 fpm / 5 s) s on the way up and as
    long before 17 s on the way down; the set tension then takes 2 s from 30 to 100 %."""
    line = webline.load_line("hswl").replace({"speed": SPEED, "control.tension_ramp": RAMP})
    times, factors = ramp_profile(line.spec.speed, line.spec.control.tension_ramp)
    cross = 0.05 / (500 * FPM / 5.0)
    np.testing.assert_allclose(times, [0, 1 + cross, 3 + cross, 17 - cross, 19 - cross],
                               rtol=1e-12)
    np.testing.assert_allclose(factors, [0.3, 0.3, 1.0, 1.0, 0.3], rtol=1e-15)
    # a stop before the ramp is up turns it back from where it is (rate limited both ways)
    short = webline.load_line("hswl").replace({
        "speed": {"type": "table", "time": [0, 1, 2, 3], "value": [0, 0, 1, 0]},
        "control.tension_ramp": RAMP})
    times, factors = ramp_profile(short.spec.speed, short.spec.control.tension_ramp)
    assert factors.max() == pytest.approx(0.3 + 0.35 * 1.9)  # 1.9 s of 2 s up
    assert factors[-1] == pytest.approx(0.3, abs=1e-12)
    assert np.all(np.abs(np.diff(factors)) <= 0.35 * np.diff(times) + 1e-12)  # 0.7 / 2 s


def test_the_line_follows_the_ramped_set_tension_at_start_and_stop(ramped):
    """The run starts at rest in equilibrium at 30 % of the set tension, the set tension
    (Result.tension_ref) is the reference times the ramp, and every loadcell zone holds it:
    exactly at rest before the start, within 1 % from 1 s after each ramp (the 8 rad/s
    tension loops settle in well under a second), 30 % again after the stop."""
    line, result = ramped
    reference = 14.35 * 4.4482216152605
    op = operating_point(line)
    loadcells = [zone.loadcell for zone in line.zones]
    np.testing.assert_allclose(op.tension[loadcells], 0.3 * reference, rtol=1e-12)
    factor = np.interp(result.time, *ramp_profile(line.spec.speed, line.spec.control.tension_ramp))
    np.testing.assert_allclose(result.tension_ref[:, loadcells],
                               reference * factor[:, None] * np.ones(len(loadcells)), rtol=1e-12)
    error = np.abs(result.tension[:, loadcells] / result.tension_ref[:, loadcells] - 1.0)
    time = result.time
    assert error[time < 1.0].max() < 1e-9  # at rest: equilibrium at the standstill tension
    settled = ((time > 4.2) & (time < 16.5)) | (time > 20.0)
    assert error[settled].max() < 0.01
    assert result.tension[-1, loadcells] == pytest.approx(0.3 * reference, rel=0.01)


def test_a_line_that_starts_running_keeps_its_reference(hswl):
    """Limiting case: a line running from t = 0 (hswl's 500 ft/min) never stands, the ramp's
    factor stays 1 and the run is the same, bit for bit."""
    plain = webline.simulate(hswl, 0.5)
    ramped = webline.simulate(hswl.replace({"control.tension_ramp": RAMP}), 0.5)
    np.testing.assert_array_equal(ramped.states, plain.states)
