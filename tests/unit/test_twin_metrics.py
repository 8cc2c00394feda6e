"""Replay metrics (issue 36 item 9): R² is undefined for a flat signal, not -1e12."""

from __future__ import annotations

import math

import numpy as np

from webline.twin.traces.metrics import one_signal


def test_r2_is_blank_for_a_flat_signal_and_kept_for_a_moving_one() -> None:
    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 10.0, 2001)
    flat = 200.0 + rng.normal(0.0, 0.5, len(t))  # a loadcell at its set point
    m = one_signal(flat + 1e-3, flat)
    assert math.isnan(m["r2"])
    assert abs(m["rms"] - 1e-3) < 1e-9
    ramp = 50.0 * t + rng.normal(0.0, 0.5, len(t))  # a ramp: 500 N against 0.5 N of noise
    m = one_signal(ramp + rng.normal(0.0, 0.5, len(t)), ramp)
    # SSE/SST = 0.25 / var(50 t) = 0.25 / 20833: R² = 1 - 1.2e-5
    assert 0.9999 < m["r2"] < 1.0
