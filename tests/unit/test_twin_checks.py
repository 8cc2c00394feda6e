"""Model checks of a fit's residuals (issue 36 item 6): white residuals pass; residuals
correlated over a ramp, locally several times the noise, are named with their window; a
torque residual that follows its roller's acceleration is named with its lag."""

from __future__ import annotations

import numpy as np

from webline.twin.fitting.checks import model_checks


def test_white_residuals_raise_no_finding() -> None:
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 10.0, 0.005)
    checks = model_checks(t, {"tension[a]": rng.normal(0.0, 1.0, len(t))}, {})
    assert checks.findings == () and checks.serious == ()
    (row,) = checks.signals
    assert abs(row.rms - 1.0) < 0.05  # 2000 samples: σ of the RMS ~1.6 %
    assert row.correlation_time < 2 * 0.005


def test_a_missed_inertia_shows_as_correlated_residuals_in_its_window() -> None:
    """A drive torque residual of 4 noise levels during a ramp from 2 to 3 s (an inertia the
    model misses: J·α while α ≠ 0), on white noise."""
    rng = np.random.default_rng(1)
    t = np.arange(0.0, 10.0, 0.005)
    speed = np.interp(t, [0.0, 2.0, 3.0, 10.0], [0.0, 0.0, 1.0, 1.0])
    r = rng.normal(0.0, 1.0, len(t)) + 4.0 * ((t >= 2.0) & (t < 3.0))
    checks = model_checks(t, {"torque[drum]": r}, {"speed[drum]": speed})
    (row,) = checks.signals
    assert row.p_white < 1e-10
    assert 1.9 <= row.window[0] <= 2.6 and row.window_rms > 3.0
    assert any("torque[drum]: residuals not white" in f for f in checks.serious)
    # the residual is the roller's acceleration (1 m/s² from 2 to 3 s) times a constant:
    # found at lag 0 within one sample (central differences blur each corner over two)
    found = [f for f in checks.findings if "correlates with its roller's acceleration" in f]
    assert len(found) == 1, checks.findings
    assert any(f"at lag {lag} ms" in found[0] for lag in ("0", "5", "-5")), found
