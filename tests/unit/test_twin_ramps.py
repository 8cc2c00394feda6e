"""A speed reference reconstructed from a measured speed (issue 36 item 4): the ramps a PLC
commanded are found with their corners, and a profile that is no ramp sequence is said to
be ambiguous."""

from __future__ import annotations

import numpy as np

from webline.twin.traces.ramps import fit_ramps, reconstructed


def test_a_noisy_start_up_ramp_is_found_with_its_corners() -> None:
    """Rest to 1.5 s, a ramp to 5 m/s until 21.5 s, then steady; 2 mm/s noise at 200 Hz.
    The corners come back within 5 ms (a tenth of the 50 ms bins the replay used before) and
    the slope within 0.1 %: least squares over 4000 points of 2 mm/s noise."""
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 30.0, 0.005)
    truth = np.interp(t, [0.0, 1.5, 21.5, 30.0], [0.0, 0.0, 5.0, 5.0])
    found = fit_ramps(t, truth + rng.normal(0.0, 2e-3, len(t)), 2e-3)
    assert found is not None
    knots, values = found
    assert len(knots) == 4
    assert np.allclose(knots[1:3], [1.5, 21.5], atol=5e-3)
    # the rest and the steady speed are holds, exactly flat (a slow noisy ramp there would
    # reach the torques through the inertia compensation)
    assert values[0] == values[1] and values[2] == values[3]
    slope = (values[2] - values[1]) / (knots[2] - knots[1])
    assert abs(slope / 0.25 - 1.0) < 1e-3


def test_a_speed_that_is_no_ramp_sequence_is_called_ambiguous() -> None:
    """A speed swinging 0.5 m/s at 0.7 Hz needs more than the allowed knots: the
    reconstruction smooths it and says so."""
    rng = np.random.default_rng(1)
    t = np.arange(0.0, 20.0, 0.005)
    speed = 3.0 + 0.5 * np.sin(2 * np.pi * 0.7 * t) + rng.normal(0.0, 2e-3, len(t))
    _, values, how = reconstructed(t, speed, 2e-3)  # fit_ramps found none
    assert how.startswith("AMBIGUOUS")
    # the 1 Hz zero-phase low-pass keeps the 0.7 Hz swing's phase: its error is the
    # Butterworth's gain at 0.7 Hz, 1/sqrt(1 + 0.7**4) after filtfilt = 0.81
    assert np.max(np.abs(values - speed)) < 0.25 * 0.5 + 0.01
