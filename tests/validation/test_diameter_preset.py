"""Diameter preset while running (issue 21 item 9, docs/winder.md W2a): an operator sets the
calculated diameter after a splice or a measurement, and the calculator goes on from there."""

from __future__ import annotations

import numpy as np
import pytest

import webline


def test_a_measured_preset_corrects_a_calculator_that_cannot_correct_itself(hswl):
    """Thickness integration started 10 % high never corrects (docs/winder.md W2); a preset
    to the measured diameter at 2 s makes it right, and it stays right (the true roll grows
    by the same thickness per turn: 1e-6, the strain of the wound web), until a preset to a
    given 0.5 m at 3 s puts it there (to 1e-6 m: one tick's integration after the preset)."""
    line = hswl.replace({"rollers.rewind.diameter": {
        "method": "thickness", "initial": 2 * 1.1 * hswl.rewind.radius,
        "preset": [{"at": "2 s"}, {"at": "3 s", "diameter": "0.5 m"}]}})
    result = webline.simulate(line, 4.0)
    time = result.time
    error = result.control_radius[:, -1] / result.radius[:, -1] - 1.0
    assert error[time < 2.0].min() > 0.0999  # the wrong start, kept
    measured = (time >= 2.0) & (time < 3.0)
    assert np.abs(error[measured]).max() < 1e-6
    at_three = int(np.searchsorted(time, 3.0 - 1e-9))
    assert result.control_radius[at_three, -1] == pytest.approx(0.25, abs=1e-6)
    grown = result.control_radius[-1, -1] - result.control_radius[at_three, -1]
    true_growth = result.radius[-1, -1] - result.radius[at_three, -1]
    assert grown == pytest.approx(true_growth, rel=1e-3)  # it goes on integrating from there
