"""Thesis Sec. 2.5 (Figs 2.11-2.12) against webline's belt step under the thesis's setup
(docs/errata.md E-2.6, E-2.8): the numbers the thesis states, not the model against itself."""

from __future__ import annotations

import numpy as np
import pytest

from webline.analysis.drivetrain import belt
from webline.analysis.drivetrain.params import hswl_unwind_belt_drive
from webline.studies import belt_step_thesis as thesis

BELTS = ("12mm", "24mm", "36mm")


@pytest.fixture(scope="module")
def runs():
    return {(b, label): thesis.setup_run(b, fb, ts, duration=8.0, window=4.0)
            for b in BELTS
            for label, fb, ts in (("motor", "motor", 1e-3), ("listing", "motor", 0.03536),
                                  ("load", "load", 1e-3))}


def test_stated_frequencies_are_2_37_in_rad_per_s_not_hz():
    """Sec. 2.5 states 5.5, 7 and 8.6 Hz from (2.37). (2.37) with the printed data gives
    4.92, 6.96 and 8.53 rad/s (0.78-1.36 Hz): within 1 % of the printed numbers for the 24 and
    36 mm belts whose stiffness follows from the printed 36 mm value, as rad/s; as Hz they are
    6.3x too high. (12 mm: 11 % low, its stiffness is not printed; E-2.6.)"""
    for b, rel in (("24mm", 0.01), ("36mm", 0.01), ("12mm", 0.12)):
        w = belt.natural_frequencies(hswl_unwind_belt_drive(b)).velocity_mode_hz * 2 * np.pi
        assert w == pytest.approx(thesis.THESIS_STATED_237[b], rel=rel)
        assert thesis.THESIS_STATED_237[b] / (w / (2 * np.pi)) > 5.0


def test_motor_feedback_as_stated_settles_far_from_the_thesis_peaks(runs):
    """With the encoder on the motor (Sec. 2.5) and a loop that settles in < 2 s (Fig. 2.10)
    the belt mode is damped and sits at 0.7-1.1 Hz, a fifth of the thesis's FFT peaks."""
    for b in BELTS:
        r = runs[(b, "motor")]
        assert r["mode_real_1_s"] < -0.5
        assert r["mode_Hz"] < 0.25 * thesis.THESIS_PEAK_HZ[b]


def test_load_feedback_sustains_the_oscillation_at_the_thesis_frequency(runs):
    """Load-side feedback makes the belt mode grow (E-2.4) until the torque limit: a sustained
    oscillation at the two-inertia frequency. Its FFT peak is within 5 % of the thesis's
    "approximately 5 Hz" for the 12 mm belt and within 30 % of "near 10 Hz" for 24 and 36 mm
    (7.3 and 9.0 Hz); its amplitude is two decades above the thesis's 5 RPM."""
    for b in BELTS:
        r = runs[(b, "load")]
        torque_mode = belt.natural_frequencies(hswl_unwind_belt_drive(b)).torque_mode_hz
        assert r["mode_real_1_s"] > 1.0
        assert r["fft_peak_Hz"] == pytest.approx(torque_mode, rel=0.03)
        tol = 0.05 if b == "12mm" else 0.3
        assert r["fft_peak_Hz"] == pytest.approx(thesis.THESIS_PEAK_HZ[b], rel=tol)
        assert r["torque_limited_pct"] > 50.0
        assert r["amplitude_rpm"] > 100 * thesis.THESIS_AMPLITUDE_RPM["12mm"]


def test_sampling_at_the_listing_period_destabilises_the_motor_loop(runs):
    """The same motor-side PI sampled at Appendix B's 35.36 ms: a mode beyond the unit circle
    (here at the Nyquist frequency 14.1 Hz) and a torque-limited oscillation."""
    for b in BELTS:
        r = runs[(b, "listing")]
        assert r["mode_real_1_s"] > 10.0
        assert r["mode_Hz"] == pytest.approx(0.5 / 0.03536, rel=1e-6)
        assert r["torque_limited_pct"] > 50.0


def test_thesis_frequencies_need_a_speed_loop_far_too_slow_for_fig_2_10():
    """A lightly damped (zeta < 0.1) belt mode at the thesis's frequencies under motor feedback
    needs kp below ~2.3 N m s: a rigid-loop bandwidth below 0.14 rad/s, a step that takes tens of
    seconds where Fig. 2.10 settles in under 2 s."""
    for b in BELTS:
        kp, hz = thesis.light_damping_limit(b)
        torque_mode = belt.natural_frequencies(hswl_unwind_belt_drive(b)).torque_mode_hz
        assert hz == pytest.approx(torque_mode, rel=0.02)
        assert kp < 2.5
