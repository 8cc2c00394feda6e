"""Out-of-round unwind and rewind rolls (issue 21 item 9, docs/winder.md E1): an
eccentricity e riding on a roll whose radius changes excites its span once per revolution."""

from __future__ import annotations

import math

import numpy as np
import pytest

import webline

E = 1e-3  # eccentricity [m]
LBF = 4.4482216152605


@pytest.fixture(scope="module")
def run(hswl):
    """hswl winding a 1 mm web (the unwind shrinks ~1 mm/s), its unwind 1 mm out of round;
    the unwind and the master roller at the span's two ends made heavy (x100) and the
    unwind's tension loop slow (0.5 rad/s), so that their speeds barely move at the ripple's
    6.7 rad/s: what the span sees is the roll's geometry."""
    line = hswl.replace({
        "web.thickness": "1 mm", "web.modulus": None, "web.ea": hswl.ea,
        "rollers.unwind.inertia": 100 * 7.34, "rollers.master.inertia": 100 * 0.0843,
        "rollers.unwind.controller.tension_bandwidth": "0.5 rad/s",
        "disturbances": [{"type": "eccentric_roller", "roller": "unwind", "eccentricity": E}]})
    return line, webline.simulate(line, 20.0)


def _periods(time, signal):
    """(times, lengths [s]) of the signal's periods between rising crossings of its mean."""
    centred = signal - np.convolve(signal, np.ones(1001) / 1001, mode="same")
    up = np.flatnonzero((centred[:-1] < 0) & (centred[1:] >= 0))[1:-1]
    crossings = time[up] - centred[up] * (time[up + 1] - time[up]) / (
        centred[up + 1] - centred[up])
    return 0.5 * (crossings[1:] + crossings[:-1]), np.diff(crossings)


def test_the_span_sees_the_geometric_ripple(run):
    """E1: with the roll's speed held, L dδT/dt = -(EA - T0) e ω cos θ - v δT, so the span's
    tension swings by (EA - T0) e ω / √(v² + L²ω²) = (EA - T0) e / √(L² + R²) whatever the
    speed (v = R ω): 1.448 N here. 5 %: the heavy roll's speed still moves a little."""
    line, result = run
    window = (result.time > 8.0) & (result.time < 10.0)
    tension = result.tension[window, 0]
    radius = result.radius[window, 0].mean()
    length = line.spec.spans[0].length
    expected = (line.ea - 12 * LBF) * E / math.hypot(length, radius)
    amplitude = 0.5 * (tension.max() - tension.min())
    assert amplitude == pytest.approx(expected, rel=0.05)


def test_the_ripple_rides_on_the_shrinking_radius(run):
    """Once per revolution: the period is 2π R(t) / v, shortening as the unwind empties
    (by ~5 % over the run); 1 %: crossings of a ~1.5 N sine sampled every ms."""
    _, result = run
    when, period = _periods(result.time, result.tension[:, 0])
    steady = when > 3.0
    radius = np.interp(when, result.time, result.radius[:, 0] - E * np.cos(
        result.states[:, result.plan.state_names.index("unwind.angle")]))
    speed = 500 * 0.3048 / 60
    np.testing.assert_allclose(period[steady], 2 * math.pi * radius[steady] / speed, rtol=0.01)
    assert period[steady][0] / period[steady][-1] > 1.03  # faster as the roll empties
